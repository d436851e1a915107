//! A system without constraints: the reduced equations are the Euler–Lagrange equations.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { theta }
        lagrangian = m*l^2*dot(theta)^2/2 + m*g*l*cos(theta);
        outputs { energy, curvature, multipliers }
    }
}

fn main() {
    let p: Pendulum = Pendulum::new(1.0, 2.0, 9.81);
    let a = p.accelerations(0.0, &SVector::from([0.5]), &SVector::from([0.0]));
    assert!((a[0] + 9.81 / 2.0 * 0.5f64.sin()).abs() < 1e-14);
    assert_eq!(Pendulum::<f64>::P, 0);
    assert_eq!(p.multipliers(0.0, &SVector::from([0.5]), &SVector::from([0.0])).len(), 0);
    assert_eq!(p.curvature(&SVector::from([0.5])).len(), 0);
    const { assert!(Pendulum::<f64>::INTEGRABLE) };
}
