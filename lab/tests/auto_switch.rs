//! Automatic stiffness switching on the demo discs: the thesis's disc is
//! never stiff, the stiff disc (k = 1e6 on the lean) is, at moderate
//! tolerances, from its first hundredths of a second on.
use nh_lab::systems::{StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;

fn state(q: [f64; 5], rdot: [f64; 3]) -> SVector<f64, 8> {
    SVector::<f64, 8>::from_fn(|i, _| if i < 5 { q[i] } else { rdot[i - 5] })
}

/// The initial state of the reports' disc scenes.
fn x0() -> SVector<f64, 8> {
    state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5])
}

/// The stiff disc of the work-precision report: critically damped lean
/// spring, eigenvalues near −2000 (double).
fn stiff_disc() -> StiffDisc<f64> {
    let (m, r, k): (f64, f64, f64) = (1.7, 0.35, 1e6);
    let inertia = 1.25 * m * r * r;
    StiffDisc::new(m, r, 9.81, k, 2.0 * (k * inertia).sqrt(), 0.2)
}

fn work(s: Stats) -> usize {
    s.rhs_evals + s.jacobian_evals
}

#[test]
fn the_thesis_disc_never_switches_and_costs_what_dormand_prince_costs() {
    let sys = ThesisDisc::new(1.7, 0.35, 9.81);
    for rtol in [1e-1, 1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        let atol = rtol * 1e-2;
        let mut auto = AutoSwitch::new(rtol, atol);
        let a = auto.integrate(&sys, 0.0, x0(), 5.0).unwrap();
        let d = Dopri5::new(rtol, atol)
            .integrate(&sys, 0.0, x0(), 5.0)
            .unwrap();
        assert!(auto.last_switches().is_empty(), "rtol {rtol:e}");
        // The same steps, bit for bit: the switching test only reads what
        // Dormand–Prince computes anyway.
        assert_eq!(a.x, d.x);
        assert_eq!(a.stats, d.stats);
    }
}

#[test]
fn the_stiff_disc_switches_early_and_costs_what_rosenbrock_costs() {
    let sys = stiff_disc();
    // Independent of both members: DOP853 at a tight tolerance (where the
    // stiff disc costs it a few thousand steps).
    let reference = Dop853::new(1e-13, 1e-15)
        .integrate(&sys, 0.0, x0(), 1.0)
        .unwrap()
        .x;
    for rtol in [1e-4, 1e-5, 1e-6] {
        let atol = rtol * 1e-2;
        let mut auto = AutoSwitch::new(rtol, atol);
        let a = auto.integrate_with_jacobian(&sys, 0.0, x0(), 1.0).unwrap();
        let switches = auto.last_switches().to_vec();
        let fd = auto.integrate(&sys, 0.0, x0(), 1.0).unwrap();
        let mut ros = Rodas4::new(rtol, atol);
        let r = ros.integrate_with_jacobian(&sys, 0.0, x0(), 1.0).unwrap();
        let r_fd = ros.integrate(&sys, 0.0, x0(), 1.0).unwrap();
        let (error, ros_error) = ((a.x - reference).amax(), (r.x - reference).amax());
        println!(
            "rtol {rtol:e}: {switches:?}\n  auto {} + {} J (fd {}), error {error:.1e}\n  Rodas4 {} + {} J (fd {}), error {ros_error:.1e}",
            a.stats.rhs_evals,
            a.stats.jacobian_evals,
            fd.stats.rhs_evals,
            r.stats.rhs_evals,
            r.stats.jacobian_evals,
            r_fd.stats.rhs_evals
        );
        // Once, early (measured t = 0.022 … 0.025 of 1 s), for good.
        assert_eq!(switches.len(), 1);
        assert_eq!(switches[0].to, Regime::Stiff);
        assert!(switches[0].t < 0.05, "{switches:?}");
        assert_eq!(a.stats.switches_to_nonstiff, 0);
        assert!(a.stats.stiff_steps > a.stats.steps / 2);
        // Work (RHS + Jacobians) within 5 % of Rodas4's alone, with the
        // analytic and with finite-difference Jacobians (measured: 721 vs
        // 742, 1749 + 217 vs 1963 + 326; fd 1211 vs 1477).
        assert!(20 * work(a.stats) < 21 * work(r.stats), "{:?}", r.stats);
        assert!(20 * work(fd.stats) < 21 * work(r_fd.stats));
        // Within the tolerance (measured 0.07·rtol; Rodas4 alone is
        // more accurate than asked here, 0.003·rtol).
        assert!(error < rtol, "{error:e}");
    }
}

#[test]
fn at_tight_tolerances_the_stiff_disc_is_not_stiff() {
    // At rtol ≤ 1e-8 Dormand–Prince's steps are limited by accuracy below
    // its stability bound (3.3 / 2000 s): no switch, the same run as
    // Dormand–Prince alone (which then costs less than Rodas4).
    let sys = stiff_disc();
    for rtol in [1e-8, 1e-9] {
        let atol = rtol * 1e-2;
        let mut auto = AutoSwitch::new(rtol, atol);
        let a = auto.integrate_with_jacobian(&sys, 0.0, x0(), 1.0).unwrap();
        let d = Dopri5::new(rtol, atol)
            .integrate(&sys, 0.0, x0(), 1.0)
            .unwrap();
        let r = Rodas4::new(rtol, atol)
            .integrate_with_jacobian(&sys, 0.0, x0(), 1.0)
            .unwrap();
        assert!(auto.last_switches().is_empty());
        assert_eq!((a.x, a.stats), (d.x, d.stats));
        assert!(work(a.stats) < work(r.stats));
    }
}
