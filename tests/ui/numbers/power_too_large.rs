use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - a*2^(10^9)*x;
    }
}

fn main() {}
