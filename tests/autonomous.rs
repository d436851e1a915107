//! A generated system that does not depend on t says so, and the implicit
//! methods then skip the finite difference for ∂f/∂t: the same steps,
//! bit for bit, with one right-hand side less per Jacobian.

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The thesis disc with a stiff spring-damper on the lean.
    pub struct StiffDisc {
        parameters { m, R, g, k, c }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4) - m*g*Z;
        forces { psi: -k*(psi - 1/5) - c*dot(psi); }
        constraints { dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }
    }
}

nonholonomic_system! {
    /// A stiff oscillator driven by a force that varies in time.
    pub struct Forced {
        parameters { m, k, c }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        forces { x: sin(t) - c*dot(x); }
    }
}

fn x0() -> SVector<f64, 8> {
    SVector::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5])
}

/// (outcome of the system, outcome of the same right-hand side as a
/// closure, which does not say it is autonomous).
fn both<S: OdeSystem<f64, D>, const D: usize>(
    sys: &S,
    x0: SVector<f64, D>,
) -> (Outcome<f64, D>, Outcome<f64, D>) {
    let mut r = Rodas4::new(1e-6, 1e-9);
    let own = r.integrate(sys, 0.0, x0, 1.0).unwrap();
    let closure = |t: f64, x: &SVector<f64, D>| sys.rhs(t, x);
    let plain = r.integrate(&closure, 0.0, x0, 1.0).unwrap();
    (own, plain)
}

#[test]
fn an_autonomous_system_skips_the_time_difference() {
    let sys = StiffDisc::new(1.7, 0.35, 9.81, 1e4, 50.0);
    assert!(sys.is_autonomous());
    let (own, plain) = both(&sys, x0());
    assert_eq!(own.x, plain.x, "the same steps, bit for bit");
    assert_eq!(own.stats.steps, plain.stats.steps);
    assert!(own.stats.jacobian_evals > 0);
    assert_eq!(
        plain.stats.rhs_evals - own.stats.rhs_evals,
        own.stats.jacobian_evals,
        "one right-hand side less per Jacobian"
    );
    eprintln!(
        "stiff disc, Rodas4 rtol 1e-6: {} steps, {} → {} right-hand sides ({} Jacobians)",
        own.stats.steps, plain.stats.rhs_evals, own.stats.rhs_evals, own.stats.jacobian_evals
    );
}

#[test]
fn a_system_with_time_keeps_the_time_difference() {
    let sys = Forced::new(1.0, 1e4, 50.0);
    assert!(!sys.is_autonomous());
    let (own, plain) = both(&sys, SVector::from([0.1, 0.0]));
    assert!(own.stats.jacobian_evals > 0);
    assert_eq!(own.x, plain.x);
    assert_eq!(own.stats.rhs_evals, plain.stats.rhs_evals);
}

nonholonomic_system! {
    /// A cart pushed by an input u.
    pub struct Cart {
        parameters { m, c }
        coordinates { x }
        inputs { u }
        lagrangian = m*dot(x)^2/2;
        forces { x: u - c*dot(x); }
    }
}

#[test]
fn a_held_input_keeps_the_answer() {
    let cart = Cart::new(2.0, 0.5);
    assert!(cart.is_autonomous());
    let u = SVector::<f64, 1>::from([1.0]);
    assert!(Driven::new(&cart, u).is_autonomous());
}
