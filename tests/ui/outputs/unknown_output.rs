use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m*dot(x)^2/2;
        outputs { energie, multipliers }
    }
}

fn main() {}
