#![allow(deprecated)] // the constraints are integrable, and the macro says so
//! p = n − 1: a single independent coordinate.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Wheel {
        parameters { m, R }
        coordinates { theta, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2;
        constraints {
            dot(x) = R*dot(theta);
            dot(y) = 0;
        }
    }
}

#[allow(deprecated)]
fn main() {
    assert_eq!(Wheel::<f64>::INDEPENDENT, [0]);
    assert_eq!(Wheel::<f64>::DEPENDENT, [1, 2]);
    let w: Wheel = Wheel::new(2.0, 0.5);
    let a = w.accelerations(0.0, &SVector::from([0.0, 0.0, 0.0]), &SVector::from([3.0]));
    assert_eq!(a[0], 0.0);
    assert_eq!(w.dependent_velocities(&SVector::from([0.0, 0.0, 0.0]), &SVector::from([3.0])), SVector::<f64, 2>::from([1.5, 0.0]));
}
