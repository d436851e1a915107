use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m*dot(x)^2/(2*x - x - x);
    }
}

fn main() {}
