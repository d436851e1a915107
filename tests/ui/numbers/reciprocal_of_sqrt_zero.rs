use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - 1/sqrt(0)*x;
    }
}

fn main() {}
