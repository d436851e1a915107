use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - a*sqrt(-1)*x^2;
    }
}

fn main() {}
