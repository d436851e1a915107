use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Other keywords work as raw identifiers (`r#type`); written plain they are an error that says so.
    pub struct Slide {
        parameters { m, type }
        coordinates { x }
        lagrangian = m/2*dot(x)^2 - type*x^2;
    }
}

fn main() {
    let s: Slide = Slide::new(1.0, 2.0);
    let _ = s.accelerations(0.0, &SVector::from([0.1]), &SVector::from([0.0]));
}
