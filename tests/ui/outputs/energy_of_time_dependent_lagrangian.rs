use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, k, w }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*cos(w*t)*x^2/2;
        outputs { energy }
    }
}

fn main() {}
