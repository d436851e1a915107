use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        let T = m*dot(x)^2/2;
    }
}

fn main() {}
