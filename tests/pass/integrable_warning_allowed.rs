//! The integrability warning is the lint `deprecated` (its message says
//! so): `#[allow(deprecated)]` on the struct silences it, even under
//! `deny(deprecated)` for the crate, and the system is there.
#![deny(deprecated)]
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// x = R θ: rolling on a line is integrable.
    #[allow(deprecated)]
    pub struct LineWheel {
        parameters { m, R }
        coordinates { theta, x }
        lagrangian = m/2*dot(x)^2 + m*R^2/4*dot(theta)^2;
        constraints { dot(x) = R*dot(theta); }
    }
}

fn main() {
    const { assert!(LineWheel::<f64>::INTEGRABLE) };
    let w = LineWheel::new(2.0, 0.5);
    let v = w.dependent_velocities(&SVector::from([0.0, 0.0]), &SVector::from([4.0]));
    assert_eq!(v[0], 2.0);
}
