use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x }
        let K = m*dot(x)^2/2;
        lagrangian = K + dot(K);
    }
}

fn main() {}
