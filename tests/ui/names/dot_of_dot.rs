use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 + m*x*dot(dot(x));
    }
}

fn main() {}
