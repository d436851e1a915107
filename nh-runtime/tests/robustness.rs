//! Failure modes: blow-up, non-finite right-hand sides, stiffness, step
//! budgets and invalid input.

mod common;

use common::{BlowUp, Decay, Oscillator, Stiff};
use nalgebra::{Vector1, Vector2};
use nh_runtime::{Dopri5, Integrator, OdeSystem, Rk4, SimError};

#[test]
fn dopri_blow_up_stops_at_singularity() {
    // The numerical solution blows up at 1 + O(rtol) (relative errors of
    // early steps shift the pole), so the stopping time is compared with
    // that band; at rtol 1e-10 it is strictly below the exact pole.
    for (rtol, band) in [(1e-6, 1e-5), (1e-10, 0.0)] {
        let mut dp = Dopri5::new(rtol, rtol * 1e-2);
        let err = dp
            .integrate(&BlowUp, 0.0, Vector1::new(1.0), 2.0)
            .unwrap_err();
        println!(
            "dopri5 blow-up, rtol {rtol:e}: {err} ({err:?}), {:?}",
            dp.last_stats()
        );
        assert!(matches!(
            err,
            SimError::StepSizeTooSmall { .. } | SimError::NonFinite { .. }
        ));
        let t = err.time().unwrap();
        assert!(t > 0.99 && t < 1.0 + band, "t = {t}");
        let x = err.state().unwrap()[0];
        assert!(x.is_finite() && x > 1e6, "x = {x}");
    }
}

#[test]
fn rk4_blow_up_never_panics() {
    let result = Rk4::new(0.01).integrate(&BlowUp, 0.0, Vector1::new(1.0), 2.0);
    match result {
        Err(e) => {
            assert!(matches!(e, SimError::NonFinite { .. }), "{e:?}");
            let x = e.state().unwrap();
            assert!(x[0].is_finite());
            assert!(e.time().unwrap().is_finite());
        }
        Ok(out) => assert!(out.x[0].is_finite()),
    }
}

/// `x' = -x`, but the right-hand side returns NaN after `t = 0.5`.
struct NanAfterHalf;

impl OdeSystem<f64, 1> for NanAfterHalf {
    fn rhs(&self, t: f64, x: &Vector1<f64>) -> Vector1<f64> {
        if t > 0.5 { Vector1::new(f64::NAN) } else { -x }
    }
}

#[test]
fn non_finite_rhs_returns_last_good_state() {
    let mut dp = Dopri5::new(1e-8, 1e-10);
    let e = dp
        .integrate(&NanAfterHalf, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    let SimError::NonFinite { t, x } = e else {
        panic!("expected NonFinite, got {e:?}")
    };
    assert!(t <= 0.5 && t > 0.49, "t = {t}");
    assert!((x[0] - (-t).exp()).abs() < 1e-7);
    assert!(dp.last_stats().rejected > 10, "halving retries were made");

    let e = Rk4::new(0.1)
        .integrate(&NanAfterHalf, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    let SimError::NonFinite { t, x } = e else {
        panic!("expected NonFinite, got {e:?}")
    };
    // The step from 0.4 samples t = 0.45 and 0.5 (fine), but the one from
    // 0.5 samples 0.55: the last good state is at 0.5.
    assert!((t - 0.5).abs() < 1e-12, "t = {t}");
    assert!((x[0] - (-0.5f64).exp()).abs() < 1e-6);
}

#[test]
fn non_finite_derivative_at_start() {
    let nan = |_t: f64, _x: &Vector1<f64>| Vector1::new(f64::NAN);
    let e = Dopri5::new(1e-6, 1e-8)
        .integrate(&nan, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    assert_eq!(
        e,
        SimError::NonFinite {
            t: 0.0,
            x: Vector1::new(1.0)
        }
    );
    let e = Rk4::new(0.1)
        .integrate(&nan, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    assert_eq!(e.time(), Some(0.0));
}

#[test]
fn stiff_problem_is_detected() {
    // The stability limit forces |h| ≈ 3.3e-6, so [0, 0.01] takes ~3000
    // steps: the routine test at step 1000 fires and repeats until flagged.
    let mut dp = Dopri5::new(1e-6, 1e-8);
    let out = dp.integrate(&Stiff, 0.0, Vector1::new(0.0), 0.01).unwrap();
    println!("stiff: {:?}", out.stats);
    assert!(out.stats.stiffness_detected);
    assert!(out.stats.steps > 2000, "explicit method is step-limited");
    assert!((out.x[0] - 0.01f64.cos()).abs() < 1e-5);

    // The same problem with a small step budget fails with MaxSteps; the
    // stiffness flag is still available from last_stats().
    let mut dp = Dopri5::new(1e-6, 1e-8).with_max_steps(2000);
    let e = dp
        .integrate(&Stiff, 0.0, Vector1::new(0.0), 1.0)
        .unwrap_err();
    assert!(matches!(e, SimError::MaxSteps { steps: 2000, .. }), "{e:?}");
    assert!(e.time().unwrap() < 0.01);
    assert!(dp.last_stats().stiffness_detected);

    // A non-stiff problem run as long is not flagged.
    let out = Dopri5::new(1e-6, 1e-8)
        .with_max_step(1e-3)
        .integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0)
        .unwrap();
    assert!(out.stats.steps > 2000);
    assert!(!out.stats.stiffness_detected);
}

#[test]
fn max_steps() {
    let e = Rk4::new(0.01)
        .with_max_steps(10)
        .integrate(&Decay, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    let SimError::MaxSteps { t, x, steps } = e else {
        panic!("{e:?}")
    };
    assert_eq!(steps, 10);
    assert!((t - 0.1).abs() < 1e-15);
    assert!((x[0] - (-0.1f64).exp()).abs() < 1e-10);

    let e = Dopri5::new(1e-10, 1e-12)
        .with_max_steps(5)
        .integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0)
        .unwrap_err();
    assert!(matches!(e, SimError::MaxSteps { steps: 5, .. }), "{e:?}");
}

#[test]
fn invalid_input() {
    let x0 = Vector1::new(1.0);
    let bad_x0 = Vector1::new(f64::NAN);
    let invalid = |r: Result<_, SimError<f64, 1>>| matches!(r, Err(SimError::InvalidInput { .. }));

    assert!(invalid(Rk4::new(0.1).integrate(&Decay, 0.0, bad_x0, 1.0)));
    assert!(invalid(
        Dopri5::new(1e-6, 1e-8).integrate(&Decay, 0.0, bad_x0, 1.0)
    ));
    assert!(invalid(Dopri5::new(1e-6, 1e-8).integrate(
        &Decay,
        0.0,
        Vector1::new(f64::INFINITY),
        1.0
    )));
    assert!(invalid(Rk4::new(0.1).integrate(&Decay, f64::NAN, x0, 1.0)));
    assert!(invalid(Dopri5::new(1e-6, 1e-8).integrate(
        &Decay,
        0.0,
        x0,
        f64::INFINITY
    )));
    for rtol in [0.0, -1e-6, f64::NAN, f64::INFINITY] {
        assert!(invalid(
            Dopri5::new(rtol, 1e-8).integrate(&Decay, 0.0, x0, 1.0)
        ));
    }
    for atol in [-1e-8, f64::NAN] {
        assert!(invalid(
            Dopri5::new(1e-6, atol).integrate(&Decay, 0.0, x0, 1.0)
        ));
    }
    // atol = 0 is allowed (pure relative control).
    assert!(
        Dopri5::new(1e-6, 0.0)
            .integrate(&Decay, 0.0, x0, 1.0)
            .is_ok()
    );
    for h in [0.0, -0.1, f64::NAN] {
        assert!(invalid(Rk4::new(h).integrate(&Decay, 0.0, x0, 1.0)));
        assert!(invalid(
            Dopri5::new(1e-6, 1e-8)
                .with_initial_step(h)
                .integrate(&Decay, 0.0, x0, 1.0)
        ));
        assert!(invalid(
            Dopri5::new(1e-6, 1e-8)
                .with_max_step(h)
                .integrate(&Decay, 0.0, x0, 1.0)
        ));
    }
    // Invalid input is reported even on an empty interval, and evaluates nothing.
    let mut dp = Dopri5::new(-1.0, 1e-8);
    assert!(invalid(dp.integrate(&Decay, 0.0, x0, 0.0)));
    assert_eq!(dp.last_stats().rhs_evals, 0);
}

#[test]
fn rk4_step_too_small_to_advance_time() {
    let e = Rk4::new(1e-20)
        .integrate(&Decay, 1.0, Vector1::new(1.0), 2.0)
        .unwrap_err();
    assert!(matches!(e, SimError::StepSizeTooSmall { .. }), "{e:?}");
    assert_eq!(e.time(), Some(1.0));
}

#[test]
fn error_display_and_std_error() {
    let e: SimError<f64, 1> = SimError::StepSizeTooSmall {
        t: 0.5,
        x: Vector1::new(2.0),
        h: 1e-16,
    };
    assert_eq!(
        e.to_string(),
        "step size 0.0000000000000001 too small at t = 0.5"
    );
    let boxed: Box<dyn std::error::Error> = Box::new(e);
    assert!(boxed.to_string().contains("too small"));
    let e: SimError<f64, 1> = SimError::InvalidInput {
        what: "x0 must be finite",
    };
    assert_eq!(e.to_string(), "invalid input: x0 must be finite");
    assert_eq!(e.time(), None);
    assert_eq!(e.state(), None);
}

/// A pendulum whose angle has turned `turns` times before the start.
fn turned_pendulum(turns: f64, steps: usize) -> Result<Vector2<f64>, SimError<f64, 2>> {
    let pendulum = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0].sin());
    let x0 = Vector2::new(0.5 + turns * std::f64::consts::TAU, 0.3);
    let h = 0.1;
    nh_runtime::GaussLegendre4::new(h)
        .integrate(&pendulum, 0.0, x0, steps as f64 * h)
        .map(|o| o.x - Vector2::new(turns * std::f64::consts::TAU, 0.0))
}

#[test]
fn gauss_legendre_runs_on_an_angle_that_has_turned_many_times() {
    // x + Z rounds the angle to ε|θ| ≈ 7e-12 at 10⁴ turns, more than the
    // stage iteration's round-off floor at order-one states: the iteration
    // stalls there, which is convergence, not failure (the Suslov problem
    // stopped after 6.3·10³ periods for this reason)
    let near = turned_pendulum(0.0, 2000).expect("θ ≈ 0.5");
    for turns in [1e3, 1e4, 1e5] {
        let far = turned_pendulum(turns, 2000).unwrap_or_else(|e| panic!("{turns} turns: {e}"));
        let diff = (far - near).amax();
        println!("pendulum after {turns:e} turns: differs by {diff:.1e} from the one at 0.5 rad");
        // the angle's rounding, ε·θ per step, accumulated over 2000 steps
        assert!(diff < 2e3 * f64::EPSILON * turns * 7.0, "{diff:e}");
    }
}
