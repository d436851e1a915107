use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m*v^2/2 + J*dot(theta)^2/2;
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
    }
}

fn main() {}
