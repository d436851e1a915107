use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { mass, k }
        coordinates { x }
        lagrangian = mas*dot(x)^2/2 - k*x^2/2;
    }
}

fn main() {}
