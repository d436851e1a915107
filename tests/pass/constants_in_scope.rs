//! Constants, statics and unit structs in the user's scope named like the
//! identifiers the generated code introduces (its argument names `t`, `q`,
//! `rdot`, `x`, `u`, the names derived from the user's names, temporaries,
//! the cache) or like the parameters do not change the generated code: the
//! results equal those of the same system defined without them.
#![allow(non_upper_case_globals, non_camel_case_types, dead_code)]
use nonholonomic::prelude::*;

const p_m: f64 = 1.0;
const q_x: f64 = 1.0;
const dot_x: f64 = 1.0;
const u_F: f64 = 1.0;
const time: f64 = 1.0;
const t: f64 = 1.0;
static q: f64 = 1.0;
struct x;
const rdot: u8 = 0;
const u: i32 = 3;
const m: i32 = 3;
const R: f64 = 3.0;
const t0: f64 = 0.0;
const v1: f64 = 0.0;
const v2: f64 = 0.0;
const vals: f64 = 0.0;
const c: f64 = 0.0;
const s: f64 = 0.0;
const b: f64 = 0.0;
const sq: f64 = 0.0;
const __c: f64 = 0.0;
const __cache: f64 = 0.0;
struct T;

macro_rules! disc {
    ($name:ident) => {
        nonholonomic_system! {
            pub struct $name {
                parameters { m, R, g, k }
                coordinates { theta, phi, psi, x, y }
                inputs { F }
                let X = x - R*sin(phi)*sin(psi);
                let Y = y + R*cos(phi)*sin(psi);
                let Z = R*cos(psi);
                lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                           + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                           - m*g*Z;
                constraints {
                    dot(x) = R*cos(phi)*dot(theta);
                    dot(y) = R*sin(phi)*dot(theta);
                }
                forces { psi: F - k*dot(psi)^4; }
                outputs { energy, multipliers, curvature, constraint_matrix, mass_matrix, jacobian, linearization, routes }
            }
        }
    };
}

disc!(Crowded);

mod clean {
    use nonholonomic::prelude::*;
    disc!(Clean);
}

fn main() {
    let (a, b_) = (Crowded::new(1.7, 0.35, 9.81, 0.1), clean::Clean::new(1.7, 0.35, 9.81, 0.1));
    let q0 = SVector::<f64, 5>::from([0.1, 0.2, 0.3, 0.4, 0.5]);
    let r0 = SVector::<f64, 3>::from([6.0, 20.0, 0.5]);
    let u0 = SVector::<f64, 1>::from([0.7]);
    let x0 = SVector::<f64, 8>::from([0.1, 0.2, 0.3, 0.4, 0.5, 6.0, 20.0, 0.5]);
    assert_eq!(a.accelerations(0.3, &q0, &r0, &u0), b_.accelerations(0.3, &q0, &r0, &u0));
    assert_eq!(a.accelerations_multiplier_route(0.3, &q0, &r0, &u0), b_.accelerations_multiplier_route(0.3, &q0, &r0, &u0));
    assert_eq!(a.multipliers(0.3, &q0, &r0, &u0), b_.multipliers(0.3, &q0, &r0, &u0));
    assert_eq!(a.curvature(&q0), b_.curvature(&q0));
    assert_eq!(a.energy(&q0, &r0), b_.energy(&q0, &r0));
    assert_eq!(a.mass_matrix(&q0), b_.mass_matrix(&q0));
    assert_eq!(a.constraint_matrix(&q0), b_.constraint_matrix(&q0));
    assert_eq!(a.jacobian(0.3, &x0, &u0), b_.jacobian(0.3, &x0, &u0));
    assert_eq!(a.linearization(0.3, &x0, &u0), b_.linearization(0.3, &x0, &u0));
    assert_eq!(a.rhs_with_input(0.3, &x0, &u0), b_.rhs_with_input(0.3, &x0, &u0));
    assert_eq!(a.dependent_velocities(&q0, &r0), b_.dependent_velocities(&q0, &r0));
    // the thesis's closed form (6.60)–(6.62) at F = 0, k = 0
    let d = Crowded::new(1.0, 0.5, 9.81, 0.0);
    let acc = d.accelerations(0.0, &q0, &r0, &SVector::from([0.0]));
    let (psi, thd, phd, psd, r, g) = (0.3_f64, 6.0, 20.0, 0.5, 0.5, 9.81);
    let den = 4.0 * psi.sin().powi(2) + 3.0;
    let expect = [
        4.0 * psi.cos() * phd * psd / den,
        -4.0 * (2.0 * psi).sin() * phd * psd / den,
        4.0 * (r * (psi.sin() * phd - thd) * psi.cos() * phd + g * psi.sin()) / (5.0 * r),
    ];
    for i in 0..3 {
        assert!((acc[i] - expect[i]).abs() < 1e-12 * expect[i].abs().max(1.0), "{acc} vs {expect:?}");
    }
}
