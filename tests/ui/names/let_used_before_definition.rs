use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, k }
        coordinates { x }
        let T = m*dot(x)^2/2;
        let L = T - V;
        let V = k*x^2/2;
        lagrangian = L;
    }
}

fn main() {}
