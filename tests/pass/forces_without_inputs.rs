//! Generalized forces without inputs: damping and a spring outside L.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Damped {
        parameters { m, k, c }
        coordinates { x }
        lagrangian = m*dot(x)^2/2;
        forces { x: -k*x - c*dot(x); }
    }
}

fn main() {
    let d: Damped = Damped::new(2.0, 8.0, 0.5);
    let a = d.accelerations(0.0, &SVector::from([0.5]), &SVector::from([1.0]));
    assert!((a[0] - (-8.0 * 0.5 - 0.5) / 2.0).abs() < 1e-15);
}
