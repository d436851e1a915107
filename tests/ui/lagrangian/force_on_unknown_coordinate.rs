use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, c }
        coordinates { x }
        lagrangian = m*dot(x)^2/2;
        forces { y: -c*dot(x); }
    }
}

fn main() {}
