use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, x }
        coordinates { x, y, y }
        lagrangian = m*dot(x)^2/2 + m*dot(y)^2/2;
    }
}

fn main() {}
