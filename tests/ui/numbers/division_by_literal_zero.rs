use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - x/0;
    }
}

fn main() {}
