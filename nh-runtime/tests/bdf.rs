//! The BDF integrator (`Bdf`) against closed forms and published
//! references: tolerance proportionality on a stiff linear problem, Van der
//! Pol (VDPOL, ε = 1e-6) and Robertson's kinetics from the stiff test sets,
//! the dense output, a terminal event, and the typed failures.

mod common;

use common::{ROBER_AT_40, Robertson, VDPOL_AT_2, VanDerPolTestSet};
use nalgebra::{Matrix3, Vector1, Vector2, Vector3};
use nh_runtime::{Bdf, Direction, Events, Integrator, OdeJacobian, OdeSystem, Rodas5P, SimError};

/// A stiff linear system with a closed form: `x1' = −x1`,
/// `x2' = −1000 (x2 − x1)` and the Prothero–Robinson equation
/// `x3' = −100 (x3 − cos t) − sin t` (solution `cos t` from 1): decaying
/// modes, so that the global error is the error of the last steps.
struct Linear;

const K: f64 = 1000.0;

impl OdeSystem<f64, 3> for Linear {
    fn rhs(&self, t: f64, x: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            -x[0],
            -K * (x[1] - x[0]),
            -100.0 * (x[2] - t.cos()) - t.sin(),
        )
    }
}

impl OdeJacobian<f64, 3> for Linear {
    fn jacobian(&self, _t: f64, _x: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::new(
            -1.0, 0.0, 0.0, //
            K, -K, 0.0, //
            0.0, 0.0, -100.0,
        )
    }
}

/// The solution of [`Linear`] from `(1, 0, 1)`:
/// `x2 = K/(K−1) (e^(−t) − e^(−K t))`.
fn linear_exact(t: f64) -> Vector3<f64> {
    let x2 = K / (K - 1.0) * ((-t).exp() - (-K * t).exp());
    Vector3::new((-t).exp(), x2, t.cos())
}

/// Measured (atol = rtol, t1 = 3): error/rtol 0.05, 0.73, 0.19, 1.6, 1.6,
/// 1.3, 4.3 for rtol 1e-4 … 1e-10 (93 … 459 steps). The error control is
/// per step, so the global error of the non-decaying mode x1 grows like the
/// number of steps times the tolerance, `rtol^(q/(q+1))` at order q: about
/// 10× over six decades at order 5.
#[test]
fn the_error_on_a_linear_problem_follows_the_tolerance() {
    let x0 = Vector3::new(1.0, 0.0, 1.0);
    let t1 = 3.0;
    let mut errors = Vec::new();
    for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let out = Bdf::new(rtol, rtol)
            .integrate_with_jacobian(&Linear, 0.0, x0, t1)
            .unwrap();
        let err = (out.x - linear_exact(t1)).amax();
        println!(
            "rtol {rtol:.0e}: error {err:.2e} ({:.2}·rtol), {:?}",
            err / rtol,
            out.stats
        );
        assert!(err <= 10.0 * rtol, "rtol {rtol:e}: error {err:e}");
        // A linear system needs its Jacobian once.
        assert_eq!(out.stats.jacobian_evals, 1);
        errors.push(err);
    }
    // Six decades of tolerance buy at least four of error.
    assert!(errors[6] < errors[0] * 1e-4, "{errors:?}");
    for pair in errors.windows(3) {
        assert!(pair[2] < pair[0], "{errors:?}");
    }
}

/// The finite-difference Jacobian gives the same solution as the analytic
/// one to the tolerance, at `D` extra evaluations per Jacobian.
#[test]
fn finite_differences_and_the_analytic_jacobian_agree() {
    let x0 = Vector3::new(1.0, 0.0, 1.0);
    let mut bdf = Bdf::new(1e-8, 1e-8);
    let fd = bdf.integrate(&Linear, 0.0, x0, 3.0).unwrap();
    let an = bdf.integrate_with_jacobian(&Linear, 0.0, x0, 3.0).unwrap();
    assert!((fd.x - linear_exact(3.0)).amax() < 1e-7);
    assert!((fd.x - an.x).amax() < 1e-7);
    assert!(fd.stats.jacobian_evals >= 1);
    assert_eq!(
        fd.stats.rhs_evals,
        fd.stats.newton_iterations + 3 * fd.stats.jacobian_evals + 2,
        "Newton iterations, 3 per Jacobian, f(t0) and the initial-step probe: {:?}",
        fd.stats
    );
}

/// Measured (rtol = atol): error/rtol 5.5, 7.5, 3.8, 8.1, 19, 22 at rtol
/// 1e-4 … 1e-9 (637 … 3,605 steps, 1,315 … 5,658 right-hand sides and 54 …
/// 65 Jacobians). The error at t = 2 is mostly the error in the time of the
/// last jump (at t ≈ 1.6), where local errors made on the slow branch
/// before it are amplified; the error control is per step, so it grows with
/// the number of steps. AutoSwitch, whose Rodas4 member overestimates
/// its error, stays within 10·rtol.
#[test]
fn van_der_pol_matches_the_test_set() {
    let y0 = Vector2::new(2.0, 0.0);
    let reference = Vector2::from(VDPOL_AT_2);
    for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9] {
        let out = Bdf::new(rtol, rtol)
            .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
            .unwrap();
        let error = (out.x - reference).amax();
        println!(
            "VDPOL rtol {rtol:.0e}: error {error:.2e} ({:.2}·rtol), {:?}",
            error / rtol,
            out.stats
        );
        assert!(error <= 30.0 * rtol, "rtol {rtol:e}: {error:e}");
        assert!(out.stats.steps < 5000, "{:?}", out.stats);
    }
}

/// ROBER at t = 40 (Hairer & Wanner, *Solving ODEs II*, IV.10, 7 digits)
/// and, far into the slow regime, against Rodas5P at rtol 1e-12 (an
/// independent method) at t = 4e10.
#[test]
fn robertson_matches_the_published_values() {
    let y0 = Vector3::new(1.0, 0.0, 0.0);
    let published = Vector3::from(ROBER_AT_40);
    for rtol in [1e-6, 1e-8] {
        let mut bdf = Bdf::new(rtol, 1e-6 * rtol);
        let out = bdf
            .integrate_with_jacobian(&Robertson, 0.0, y0, 40.0)
            .unwrap();
        println!(
            "ROBER t = 40, rtol {rtol:.0e}: {:?} {:?}",
            out.x.as_slice(),
            out.stats
        );
        let relative = (out.x - published).component_div(&published).amax();
        // The published values have 7 digits: relative rounding ≤ 6e-7.
        assert!(
            relative <= 10.0 * rtol + 1e-6,
            "rtol {rtol:e}: {relative:e}"
        );
        // The linear invariant y1 + y2 + y3 = 1 holds for any linear
        // multistep method, up to the Newton iteration's residue.
        assert!((out.x.sum() - 1.0).abs() < 10.0 * rtol);
        // The fast reaction needs its Jacobian rarely.
        assert!(
            out.stats.jacobian_evals * 10 < out.stats.steps,
            "{:?}",
            out.stats
        );
    }
    let reference = Rodas5P::new(1e-12, 1e-20)
        .integrate_with_jacobian(&Robertson, 0.0, y0, 4e10)
        .unwrap()
        .x;
    let rtol = 1e-6;
    let out = Bdf::new(rtol, 1e-20)
        .integrate_with_jacobian(&Robertson, 0.0, y0, 4e10)
        .unwrap();
    println!(
        "ROBER t = 4e10: {:?} vs {:?}, {:?}",
        out.x.as_slice(),
        reference.as_slice(),
        out.stats
    );
    let relative = (out.x - reference).component_div(&reference).amax();
    assert!(relative <= 10.0 * rtol, "{relative:e}");
    assert!(out.stats.steps < 2000, "{:?}", out.stats);
}

/// The dense output is the interpolating polynomial of each step: on the
/// linear problem its error between the step ends is of the order of the
/// tolerance, and it is continuous from step to step.
#[test]
fn the_dense_output_interpolates_within_the_tolerance() {
    let x0 = Vector3::new(1.0, 0.0, 1.0);
    let rtol = 1e-8;
    let mut worst: f64 = 0.0;
    let mut steps = 0;
    Bdf::new(rtol, rtol)
        .integrate_with_jacobian_and_steps(&Linear, 0.0, x0, 3.0, |s| {
            steps += 1;
            for theta in [0.25, 0.5, 0.75] {
                let t = s.t_prev() + theta * s.h();
                worst = worst.max((s.interpolate(t) - linear_exact(t)).amax());
            }
        })
        .unwrap();
    println!("dense output: worst error {worst:.2e} over {steps} steps");
    assert!(worst < 10.0 * rtol, "{worst:e}");
}

/// A terminal event on `x' = −x` at `x = 1/2` ends the run at `t = ln 2`.
#[test]
fn a_terminal_event_is_located_on_the_dense_output() {
    let decay = |_t: f64, x: &Vector1<f64>| -x;
    let events = Events::new(|_t: f64, x: &Vector1<f64>| Vector1::new(x[0] - 0.5))
        .direction([Direction::Falling])
        .terminal([true]);
    let mut seen = Vec::new();
    let out = Bdf::new(1e-12, 1e-14)
        .integrate_with_events(&decay, 0.0, Vector1::new(1.0), 5.0, &events, |h| {
            seen.push(*h)
        })
        .unwrap();
    let hit = out.event.expect("the run ends at the event");
    println!(
        "event at {:.16} (ln 2 = {:.16}), {:?}",
        hit.t,
        2f64.ln(),
        out.stats
    );
    assert!((hit.t - 2f64.ln()).abs() < 1e-10, "{}", hit.t);
    assert!((hit.x[0] - 0.5).abs() < 1e-10);
    assert_eq!(out.t, hit.t);
    assert_eq!(seen.len(), 1);
}

/// Failures are typed: a right-hand side that becomes NaN beyond `x = 2`
/// ends in `NonFinite` with the last good state, and a step budget in
/// `MaxSteps`.
#[test]
fn failures_are_typed_values() {
    let blow_up =
        |_t: f64, x: &Vector1<f64>| Vector1::new(if x[0] < 2.0 { x[0] * x[0] } else { f64::NAN });
    let e = Bdf::new(1e-6, 1e-9)
        .integrate(&blow_up, 0.0, Vector1::new(1.0), 2.0)
        .unwrap_err();
    match e {
        SimError::NonFinite { t, x } | SimError::StepSizeTooSmall { t, x, .. } => {
            assert!(t < 0.5 && x[0] < 2.0 && x[0] > 1.0, "{e:?}");
        }
        e => panic!("{e:?}"),
    }
    let e = Bdf::new(1e-6, 1e-9)
        .with_max_steps(10)
        .integrate_with_jacobian(&VanDerPolTestSet, 0.0, Vector2::new(2.0, 0.0), 2.0)
        .unwrap_err();
    assert!(matches!(e, SimError::MaxSteps { steps: 10, .. }), "{e:?}");
}

/// Backwards in time, per-component tolerances and a fixed step: the same
/// driver features as the other adaptive methods.
#[test]
fn backwards_per_component_and_fixed_step() {
    // Backwards from t = 2 to 0 on an oscillator, x = (cos t, −sin t).
    let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
    let at = |t: f64| Vector2::new(t.cos(), -t.sin());
    let out = Bdf::new(1e-10, 1e-10)
        .integrate(&oscillator, 2.0, at(2.0), 0.0)
        .unwrap();
    println!("backwards: {:?}", out.stats);
    assert_eq!(out.t, 0.0);
    assert!((out.x - at(0.0)).amax() < 1e-8, "{}", out.x);

    // Per-component tolerances: equal entries give the scalar run exactly.
    let x0 = Vector3::new(1.0, 0.0, 1.0);
    let scalar = Bdf::new(1e-7, 1e-9)
        .integrate_with_jacobian(&Linear, 0.0, x0, 3.0)
        .unwrap();
    let mut per = Bdf::new(1.0, 1.0).with_tolerances(Vector3::repeat(1e-7), Vector3::repeat(1e-9));
    let same = per.integrate_with_jacobian(&Linear, 0.0, x0, 3.0).unwrap();
    assert_eq!(scalar, same);
    // A looser tolerance on x2 alone takes fewer steps.
    let mut loose = Bdf::new(1.0, 1.0).with_tolerances(
        Vector3::new(1e-7, 1e-3, 1e-7),
        Vector3::new(1e-9, 1e-3, 1e-9),
    );
    let fewer = loose
        .integrate_with_jacobian(&Linear, 0.0, x0, 3.0)
        .unwrap();
    assert!(fewer.stats.steps < scalar.stats.steps, "{:?}", fewer.stats);

    // A fixed step of 1e-3, the order still rising from 1 (implicit Euler
    // throughout would end ~1e-4 off; the first low-order steps set the
    // error: 4.1e-8 measured).
    let fixed = Bdf::new(1e-6, 1e-6)
        .with_fixed_step(1e-3)
        .integrate_with_jacobian(&Linear, 0.0, x0, 3.0)
        .unwrap();
    assert_eq!(fixed.stats.steps, 3000);
    let err = (fixed.x - linear_exact(3.0)).amax();
    println!("fixed step 1e-3: error {err:.2e}");
    assert!(err < 1e-6, "{err:e}");
}

/// No outlier on a ladder of tolerances (quarter decades, rtol 1e-4 …
/// 1e-9, atol = rtol and rtol/100): measured error/rtol 0.10 … 23.6,
/// growing slowly as rtol falls. (With the error weighed against the
/// prediction instead of the solution, one rung ended 340·rtol off: a
/// prediction far off at a jump had loosened the error test.)
#[test]
fn van_der_pol_has_no_outlier_on_a_ladder_of_tolerances() {
    let y0 = Vector2::new(2.0, 0.0);
    let reference = Vector2::from(VDPOL_AT_2);
    let mut worst: f64 = 0.0;
    for k in 0..=20 {
        let rtol = 10f64.powf(-4.0 - k as f64 / 4.0);
        for atol in [rtol, rtol * 1e-2] {
            let out = Bdf::new(rtol, atol)
                .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
                .unwrap();
            let ratio = (out.x - reference).amax() / rtol;
            assert!(ratio <= 30.0, "rtol {rtol:e}, atol {atol:e}: {ratio}");
            worst = worst.max(ratio);
        }
    }
    println!("VDPOL ladder: worst error/rtol {worst:.1}");
}
