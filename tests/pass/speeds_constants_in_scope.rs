//! A system in generalized speeds among constants named like the identifiers
//! its generated code introduces (the argument `speeds`, the names derived
//! from the speeds, the others of `constants_in_scope.rs`): its results equal
//! the closed form of the sled.
#![allow(non_upper_case_globals, non_camel_case_types, dead_code)]
use nonholonomic::prelude::*;

const speeds: f64 = 1.0;
const speed_v: f64 = 1.0;
const speed_omega: f64 = 1.0;
const t: f64 = 1.0;
static q: f64 = 1.0;
const u: i32 = 3;
struct x;
const v: u8 = 0;
const omega: f64 = 2.0;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, a }
        coordinates { x, y, theta }
        inputs { tau }
        lagrangian = J*dot(theta)^2/2
            + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        forces { theta: tau; }
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        outputs { energy, reaction_forces, jacobian, linearization, mass_matrix }
    }
}

fn main() {
    let (m, j, a) = (2.0_f64, 0.3_f64, 0.5_f64);
    let s = Sled::new(m, j, a);
    let q0 = SVector::<f64, 3>::new(0.1, 0.2, 0.3);
    let u0 = SVector::<f64, 2>::new(0.4, 0.9);
    let tau = SVector::<f64, 1>::new(0.25);
    let ud = s.accelerations(0.0, &q0, &u0, &tau);
    assert!((ud[0] - a * 0.81).abs() < 1e-15);
    assert!((ud[1] - (0.25 - m * a * 0.36) / (j + m * a * a)).abs() < 1e-15);
    let x0 = SVector::<f64, 5>::new(0.1, 0.2, 0.3, 0.4, 0.9);
    let (jac, _) = s.linearization(0.0, &x0, &tau);
    assert_eq!(jac, s.jacobian(0.0, &x0, &tau));
    assert!(s.energy(&q0, &u0) > 0.0);
}
