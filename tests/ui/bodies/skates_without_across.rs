use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, y, theta }
        body sled { mass: m, centre: [x, y, 0], orientation: rot_z(theta), inertia: diag(m, m, m) }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { skates(sled, at: [-1, 0, 0]); }
    }
}

fn main() {}
