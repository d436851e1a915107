use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, b }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2;
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta) + b*t;
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        outputs { energy }
    }
}

fn main() {}
