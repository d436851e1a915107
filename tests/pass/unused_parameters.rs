//! Parameters that appear nowhere are kept as fields.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, colour, mu }
        coordinates { x }
        lagrangian = m*dot(x)^2/2;
    }
}

fn main() {
    let s: Slide = Slide::new(1.0, 7.0, 0.3);
    assert_eq!(s.colour, 7.0);
    assert_eq!(s.accelerations(0.0, &SVector::from([1.0]), &SVector::from([2.0]))[0], 0.0);
}
