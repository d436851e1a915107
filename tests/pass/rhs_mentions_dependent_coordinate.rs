#![allow(deprecated)] // integrable, and the macro says so
//! A constraint coefficient may depend on the dependent coordinate itself (A = A(r, s)).
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Growth {
        parameters { m }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2);
        constraints { dot(y) = y*dot(x); }
        outputs { curvature }
    }
}

#[allow(deprecated)]
fn main() {
    // y = C e^x: integrable, and the curvature term through ∂A/∂s cancels
    const { assert!(Growth::<f64>::INTEGRABLE) };
    let g: Growth = Growth::new(1.0);
    let v = g.dependent_velocities(&SVector::from([0.0, 2.0]), &SVector::from([3.0]));
    assert_eq!(v[0], 6.0);
}
