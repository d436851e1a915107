use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - a*(-8)^(1/3)*x;
    }
}

fn main() {}
