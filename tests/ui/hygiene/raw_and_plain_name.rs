use nonholonomic::prelude::*;

nonholonomic_system! {
    /// `r#x` and `x` are one name to Rust, so they are one name here: declaring both is a duplicate.
    pub struct Slide {
        parameters { m, k }
        coordinates { r#x, x }
        lagrangian = m/2*dot(x)^2 - k/2*x^2;
    }
}

fn main() {
    let s: Slide = Slide::new(1.0, 2.0);
    let _ = s.accelerations(0.0, &SVector::from([0.1, 0.2]), &SVector::from([0.0, 0.0]));
}
