use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        let x = 2*m;
        lagrangian = m*dot(x)^2/2;
    }
}

fn main() {}
