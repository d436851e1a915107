use nonholonomic::prelude::*;

nonholonomic_system! {
    pub fn Slide {
        coordinates { x }
        lagrangian = dot(x)^2;
    }
}

fn main() {}
