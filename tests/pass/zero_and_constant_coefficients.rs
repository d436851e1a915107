//! Constraint coefficients that are zero or constant.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, theta, y, z }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2 + dot(z)^2) + J/2*dot(theta)^2;
        constraints {
            dot(y) = tan(theta)*dot(x) + 0*dot(theta);
            dot(z) = 3/2*dot(theta) - 0*dot(x);
        }
        outputs { constraint_matrix, curvature }
    }
}

fn main() {
    let s: Sled = Sled::new(2.0, 0.3);
    let q = SVector::<f64, 4>::from([0.0, 0.4, 0.0, 0.0]);
    let a = s.constraint_matrix(&q);
    assert_eq!(a[(0, 1)], 0.0);
    assert_eq!(a[(1, 0)], 0.0);
    assert_eq!(a[(1, 1)], -1.5);
    assert!((a[(0, 0)] + 0.4f64.tan()).abs() < 1e-15);
    // only the first constraint is nonholonomic
    let b = s.curvature(&q);
    assert!(b[0][(0, 1)] != 0.0);
    assert_eq!(b[1][(0, 1)], 0.0);
    const { assert!(!Sled::<f64>::INTEGRABLE) };
}
