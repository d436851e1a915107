use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, a, R }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*(dot(x)^2 + dot(y)^2)/2;
        constraints { dot(x)*dot(y) = 0; }
    }
}

fn main() {}
