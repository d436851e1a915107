use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Three independent mistakes, reported in one compilation.
    pub struct Slide {
        parameters { m k }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^^2;
        constraints { dot(x) = ; }
    }
}

fn main() {}
