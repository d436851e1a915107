use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, a, R }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*(dot(x)^2 + dot(y)^2)/2;
        constraints {
            dot(x) + a*dot(theta) = 0;
            2*dot(x) + 2*a*dot(theta) + dot(y) = 0;
        }
        dependent { x, theta }
    }
}

fn main() {}
