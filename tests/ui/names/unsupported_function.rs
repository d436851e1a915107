use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { theta }
        lagrangian = m*l^2*dot(theta)^2/2 + m*g*l*sech(theta);
    }
}

fn main() {}
