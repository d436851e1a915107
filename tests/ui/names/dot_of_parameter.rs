use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 + dot(m)*x;
    }
}

fn main() {}
