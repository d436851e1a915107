use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, y, theta }
        body sled { mass: m, centre: [x, y, 0] }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { skates(sled, across: [0, 1, 0]); }
    }
}

fn main() {}
