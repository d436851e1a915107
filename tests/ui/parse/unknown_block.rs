use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x, y }
        lagrangian = m*dot(x)^2/2 + m*dot(y)^2/2;
        constraint { dot(y) = x*dot(x); }
    }
}

fn main() {}
