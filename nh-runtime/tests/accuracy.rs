//! Accuracy and work of the integrators on problems with known solutions.

mod common;

use common::{Decay, Oscillator, max_err, oscillator_exact};
use nalgebra::{Vector1, Vector2};
use nh_runtime::{Dopri5, Integrator, Rk4};

#[test]
fn rk4_exponential_decay() {
    let out = Rk4::new(0.05)
        .integrate(&Decay, 0.0, Vector1::new(1.0), 3.0)
        .unwrap();
    assert_eq!(out.t, 3.0);
    assert_eq!(out.stats.steps, 60);
    assert_eq!(out.stats.rhs_evals, 240);
    let err = (out.x[0] - (-3.0f64).exp()).abs();
    assert!(err < 1e-7, "err = {err:e}");
}

#[test]
fn rk4_oscillator() {
    let out = Rk4::new(0.01)
        .integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0)
        .unwrap();
    let err = max_err(&out.x, &oscillator_exact(10.0));
    assert!(err < 1e-9, "err = {err:e}");
}

#[test]
fn rk4_last_step_is_shortened_to_land_on_t1() {
    let mut times = Vec::new();
    let out = Rk4::new(0.3)
        .integrate_with_observer(&Decay, 0.0, Vector1::new(1.0), 1.0, |t, _| times.push(t))
        .unwrap();
    assert_eq!(out.t, 1.0);
    assert_eq!(out.stats.steps, 4);
    assert_eq!(times.len(), 5);
    assert_eq!(*times.last().unwrap(), 1.0);
    assert!((times[3] - 0.9).abs() < 1e-15);
    // The short final step of 0.1 is still accurate.
    assert!((out.x[0] - (-1.0f64).exp()).abs() < 1e-4);
}

#[test]
fn rk4_exact_multiple_has_no_sliver_step() {
    // 2.0 / 0.1 is not exactly 20 in binary; still exactly 20 steps.
    let out = Rk4::new(0.1)
        .integrate(&Decay, 0.0, Vector1::new(1.0), 2.0)
        .unwrap();
    assert_eq!(out.stats.steps, 20);
    let out = Rk4::new(0.1)
        .integrate(&Decay, 0.0, Vector1::new(1.0), 0.3)
        .unwrap();
    assert_eq!(out.stats.steps, 3);
}

#[test]
fn rk4_order_is_four() {
    let x0 = Vector2::new(1.0, 0.0);
    let exact = oscillator_exact(2.0);
    let errs: Vec<f64> = [0.1, 0.05, 0.025]
        .iter()
        .map(|&h| {
            let out = Rk4::new(h).integrate(&Oscillator, 0.0, x0, 2.0).unwrap();
            max_err(&out.x, &exact)
        })
        .collect();
    let p1 = (errs[0] / errs[1]).log2();
    let p2 = (errs[1] / errs[2]).log2();
    println!("rk4 errors {errs:?}, measured orders {p1:.4} {p2:.4}");
    for p in [p1, p2] {
        assert!((p - 4.0).abs() < 0.3, "measured order {p}");
    }
}

#[test]
fn dopri_exponential_decay() {
    let out = Dopri5::new(1e-9, 1e-12)
        .integrate(&Decay, 0.0, Vector1::new(1.0), 5.0)
        .unwrap();
    assert_eq!(out.t, 5.0);
    let rel = (out.x[0] / (-5.0f64).exp() - 1.0).abs();
    assert!(rel < 1e-7, "rel err = {rel:e}");
}

#[test]
fn dopri_oscillator_tolerance_proportionality() {
    let x0 = Vector2::new(1.0, 0.0);
    let exact = oscillator_exact(10.0);
    let mut prev_steps = 0;
    for rtol in [1e-6, 1e-8, 1e-10] {
        let mut dp = Dopri5::new(rtol, rtol * 1e-2);
        let out = dp.integrate(&Oscillator, 0.0, x0, 10.0).unwrap();
        let err = max_err(&out.x, &exact);
        let s = out.stats;
        println!(
            "dopri5 rtol {rtol:e}: err {err:.3e}, steps {}, rejected {}, rhs_evals {}",
            s.steps, s.rejected, s.rhs_evals
        );
        assert_eq!(out.t, 10.0);
        assert!(err < 100.0 * rtol, "err {err:e} vs rtol {rtol:e}");
        assert!(
            err > rtol / 100.0,
            "err {err:e} suspiciously far below rtol {rtol:e}"
        );
        // FSAL: 6 evaluations per attempt, plus f(t0) and the hinit probe.
        assert_eq!(s.rhs_evals, 6 * (s.steps + s.rejected) + 2);
        assert_eq!(s.jacobian_evals, 0);
        assert!(!s.stiffness_detected);
        assert!(
            s.steps > prev_steps,
            "tighter tolerance must need more steps"
        );
        prev_steps = s.steps;
        assert_eq!(dp.last_stats(), s);
    }
}

#[test]
fn dopri_step_count_scales_like_fifth_root() {
    // For a 5th-order method, steps grow like rtol^(-1/5): ×100 in rtol ⇒ ×~2.5 steps.
    let x0 = Vector2::new(1.0, 0.0);
    let steps = |rtol: f64| {
        Dopri5::new(rtol, rtol * 1e-2)
            .integrate(&Oscillator, 0.0, x0, 10.0)
            .unwrap()
            .stats
            .steps as f64
    };
    let ratio = steps(1e-10) / steps(1e-8);
    assert!((1.8..3.5).contains(&ratio), "ratio {ratio}");
}

#[test]
fn dopri_explicit_initial_step_and_max_step() {
    let x0 = Vector2::new(1.0, 0.0);
    let mut dp = Dopri5::new(1e-8, 1e-10)
        .with_initial_step(1e-3)
        .with_max_step(0.05);
    let mut max_h: f64 = 0.0;
    let mut prev = 0.0;
    let out = dp
        .integrate_with_observer(&Oscillator, 0.0, x0, 10.0, |t, _| {
            max_h = max_h.max(t - prev);
            prev = t;
        })
        .unwrap();
    assert!(max_h <= 0.05 + 1e-12, "max step {max_h}");
    assert!(out.stats.steps >= 200);
    // No hinit probe when the initial step is given.
    let s = out.stats;
    assert_eq!(s.rhs_evals, 6 * (s.steps + s.rejected) + 1);
    assert!(max_err(&out.x, &oscillator_exact(10.0)) < 1e-6);
    assert!(dp.last_step().unwrap() <= 0.05);
}

#[test]
fn observer_sees_t0_and_every_accepted_step() {
    let x0 = Vector2::new(1.0, 0.0);
    let mut n = 0usize;
    let mut first = None;
    let mut last_t = 0.0;
    let mut monotone = true;
    let out = Dopri5::new(1e-7, 1e-9)
        .integrate_with_observer(&Oscillator, 0.0, x0, 5.0, |t, x| {
            if first.is_none() {
                first = Some((t, *x));
            } else if t <= last_t {
                monotone = false;
            }
            last_t = t;
            n += 1;
        })
        .unwrap();
    assert_eq!(first, Some((0.0, x0)));
    assert_eq!(n, out.stats.steps + 1);
    assert_eq!(last_t, 5.0);
    assert!(monotone);
}

#[test]
fn backward_integration() {
    // x' = -x backwards from x(1) = e^-1 to t = 0 gives x(0) = 1.
    let x1 = Vector1::new((-1.0f64).exp());
    let out = Rk4::new(0.01).integrate(&Decay, 1.0, x1, 0.0).unwrap();
    assert_eq!(out.t, 0.0);
    assert_eq!(out.stats.steps, 100);
    assert!((out.x[0] - 1.0).abs() < 1e-9);

    let mut times = Vec::new();
    let out = Dopri5::new(1e-10, 1e-12)
        .integrate_with_observer(&Decay, 1.0, x1, 0.0, |t, _| times.push(t))
        .unwrap();
    assert_eq!(out.t, 0.0);
    assert!((out.x[0] - 1.0).abs() < 1e-9);
    assert!(times.windows(2).all(|w| w[1] < w[0]), "time must decrease");

    // Oscillator there and back again.
    let x0 = Vector2::new(1.0, 0.0);
    let mut dp = Dopri5::new(1e-10, 1e-12);
    let fwd = dp.integrate(&Oscillator, 0.0, x0, 7.0).unwrap();
    let back = dp.integrate(&Oscillator, 7.0, fwd.x, 0.0).unwrap();
    assert!(max_err(&back.x, &x0) < 1e-8);
}

#[test]
fn zero_length_interval() {
    let x0 = Vector2::new(1.0, 2.0);
    let mut calls = 0;
    let out = Dopri5::new(1e-6, 1e-9)
        .integrate_with_observer(&Oscillator, 3.0, x0, 3.0, |_, _| calls += 1)
        .unwrap();
    assert_eq!((out.t, out.x), (3.0, x0));
    assert_eq!(out.stats, Default::default());
    assert_eq!(calls, 1);
    let out = Rk4::new(0.1).integrate(&Oscillator, 3.0, x0, 3.0).unwrap();
    assert_eq!((out.t, out.x, out.stats.steps), (3.0, x0, 0));
}

#[test]
fn works_in_f32() {
    let x0 = Vector2::new(1.0f32, 0.0);
    let exact = Vector2::new(5.0f32.cos(), -5.0f32.sin());

    let out = Dopri5::new(1e-5f32, 1e-7)
        .integrate(&Oscillator, 0.0f32, x0, 5.0)
        .unwrap();
    assert_eq!(out.t, 5.0f32);
    let err = (out.x - exact).amax();
    assert!(err < 1e-3, "dopri5 f32 err {err:e}");

    let out = Rk4::new(0.01f32)
        .integrate(&Oscillator, 0.0f32, x0, 5.0)
        .unwrap();
    assert_eq!(out.t, 5.0f32);
    let err = (out.x - exact).amax();
    assert!(err < 1e-4, "rk4 f32 err {err:e}");
}

#[test]
fn driven_system_with_held_input() {
    use nalgebra::Vector1 as U;
    use nh_runtime::{ControlledSystem, Driven};

    /// Damped cart with force input.
    struct Cart;
    impl ControlledSystem<f64, 2, 1> for Cart {
        fn rhs_with_input(&self, _t: f64, x: &Vector2<f64>, u: &U<f64>) -> Vector2<f64> {
            Vector2::new(x[1], u[0] - x[1])
        }
    }
    // v' = u - v from rest: v = u (1 - e^-t).
    let driven = Driven::new(&Cart, U::new(3.0));
    let out = Dopri5::new(1e-10, 1e-12)
        .integrate(&driven, 0.0, Vector2::zeros(), 2.0)
        .unwrap();
    let v = 3.0 * (1.0 - (-2.0f64).exp());
    let q = 3.0 * (2.0 - (1.0 - (-2.0f64).exp()));
    assert!((out.x[1] - v).abs() < 1e-9);
    assert!((out.x[0] - q).abs() < 1e-9);
}
