use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { t, m }
        coordinates { x, sin }
        inputs { pi }
        lagrangian = m*dot(x)^2/2;
    }
}

fn main() {}
