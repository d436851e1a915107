use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A missing `;` between two items.
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m*dot(x)^2/2
        let E = m;
    }
}

fn main() {}
