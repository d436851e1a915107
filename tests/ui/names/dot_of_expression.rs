use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, R }
        coordinates { x }
        lagrangian = m*dot(R*x)^2/2;
    }
}

fn main() {}
