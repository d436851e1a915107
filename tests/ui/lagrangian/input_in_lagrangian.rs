use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        inputs { F }
        lagrangian = m*dot(x)^2/2 + F*x;
    }
}

fn main() {}
