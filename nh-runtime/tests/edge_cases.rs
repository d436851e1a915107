//! Edge cases settled once in the step driver, for every integrator: step
//! budgets of fixed-step methods, non-finite dense output, finite-difference
//! Jacobians of huge states, tolerances below the scalar's resolution, spans
//! too short to take a step, landing on `t1` by rounding, and the stack use
//! of `GaussLegendre4`.

mod common;

use common::{Decay, Oscillator};
use nalgebra::{SVector, Vector1, Vector2};
use nh_runtime::{
    Dop853, Dopri5, GaussLegendre4, Integrator, OdeSystem, Outcome, Rk4, Rodas4, Rodas5P, SimError,
};

type Run<const D: usize> = Result<Outcome<f64, D>, SimError<f64, D>>;

/// Runs `sys` from `(t0, x0)` to `t1` with all five integrators.
fn all_five<S: OdeSystem<f64, D>, const D: usize>(
    sys: &S,
    t0: f64,
    x0: SVector<f64, D>,
    t1: f64,
) -> [(&'static str, Run<D>); 5] {
    [
        ("rk4", Rk4::new(1e-3).integrate(sys, t0, x0, t1)),
        (
            "dopri5",
            Dopri5::new(1e-8, 1e-10).integrate(sys, t0, x0, t1),
        ),
        (
            "dop853",
            Dop853::new(1e-8, 1e-10).integrate(sys, t0, x0, t1),
        ),
        (
            "rodas4",
            Rodas4::new(1e-8, 1e-10).integrate(sys, t0, x0, t1),
        ),
        (
            "gauss4",
            GaussLegendre4::new(1e-3).integrate(sys, t0, x0, t1),
        ),
    ]
}

#[test]
fn fixed_step_methods_have_a_finite_default_budget() {
    // 1e12 steps would be needed: the default budget of 1e6 steps ends the
    // run with MaxSteps instead of running for hours.
    let x0 = Vector1::new(1.0);
    let e = Rk4::new(1e-3).integrate(&Decay, 0.0, x0, 1e9).unwrap_err();
    let SimError::MaxSteps { t, steps, .. } = e else {
        panic!("{e:?}")
    };
    assert_eq!(steps, 1_000_000);
    assert!((t - 1e3).abs() < 1e-6, "t = {t}");
    let e = GaussLegendre4::new(1e-3)
        .integrate(&Decay, 0.0, x0, 1e9)
        .unwrap_err();
    assert!(
        matches!(
            e,
            SimError::MaxSteps {
                steps: 1_000_000,
                ..
            }
        ),
        "{e:?}"
    );
    // The budget can be raised (and lowered).
    let out = Rk4::new(1e-3)
        .with_max_steps(1_500_000)
        .integrate(&Decay, 0.0, x0, 1.2e3)
        .unwrap();
    assert_eq!(out.stats.steps, 1_200_000);
    let e = GaussLegendre4::new(1e-3)
        .with_max_steps(10)
        .integrate(&Decay, 0.0, x0, 1.0)
        .unwrap_err();
    assert!(matches!(e, SimError::MaxSteps { steps: 10, .. }), "{e:?}");
    // `with_fixed_step` of the adaptive methods keeps their budget.
    let e = Dop853::new(1e-6, 1e-6)
        .with_fixed_step(1e-3)
        .integrate(&Decay, 0.0, x0, 1e9)
        .unwrap_err();
    assert!(
        matches!(e, SimError::MaxSteps { steps: 100_000, .. }),
        "{e:?}"
    );
}

/// The oscillator, but NaN for `0.376 < t < 0.380`: with steps of 0.1 from
/// 0, no stage of DOP853 falls there, only the stage 16 of its dense
/// output on the step `[0.3, 0.4]` (at `0.3 + 0.0778`).
struct NanWindow;

impl OdeSystem<f64, 2> for NanWindow {
    fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        if t > 0.376 && t < 0.380 {
            Vector2::repeat(f64::NAN)
        } else {
            Vector2::new(x[1], -x[0])
        }
    }
}

#[test]
fn non_finite_dense_output_is_never_sampled_and_changes_no_step() {
    let x0 = Vector2::new(1.0, 0.0);
    let times = [0.05, 0.15, 0.25, 0.35, 0.45];
    let exact = |t: f64| Vector2::new(t.cos(), -t.sin());
    // Without output times the window is never evaluated: Ok.
    let fixed = || Dop853::new(1.0, 1.0).with_fixed_step(0.1);
    let plain = fixed().integrate(&NanWindow, 0.0, x0, 0.5).unwrap();
    // With them, the order-7 interpolant of [0.3, 0.4] is not finite (its
    // stage 16 falls into the window). It used to end the fixed-step run in
    // NonFinite at 0.3; now the step stands and is interpolated by the
    // cubic Hermite interpolant of its ends: the same run, finite samples.
    let mut samples = Vec::new();
    let with = fixed()
        .integrate_with_outputs(&NanWindow, 0.0, x0, 0.5, &times, |t, x| {
            samples.push((t, *x))
        })
        .unwrap();
    assert_eq!(
        (with.t, with.x, with.stats.steps),
        (plain.t, plain.x, plain.stats.steps)
    );
    assert_eq!(samples.len(), 5);
    for (t, x) in &samples {
        // order 7 on the other steps, the cubic Hermite one (h⁴/384) on [0.3, 0.4]
        let bound = if *t == 0.35 { 1e-6 } else { 1e-9 };
        assert!((x - exact(*t)).amax() < bound, "{t}: {x}");
    }
    // The same through integrate_with_steps.
    let steps = fixed()
        .integrate_with_steps(&NanWindow, 0.0, x0, 0.5, |s| {
            let mid = s.t_prev() + 0.5 * s.h();
            assert!((s.interpolate(mid) - exact(mid)).amax() < 1e-6);
        })
        .unwrap();
    assert_eq!(steps.x, plain.x);
    // Adaptively, the step is not rejected either: the run with outputs is
    // the run without.
    let adaptive = || {
        Dop853::new(1e-6, 1e-8)
            .with_initial_step(0.1)
            .with_max_step(0.1)
    };
    let plain = adaptive().integrate(&NanWindow, 0.0, x0, 0.5).unwrap();
    let mut samples = Vec::new();
    let with = adaptive()
        .integrate_with_outputs(&NanWindow, 0.0, x0, 0.5, &times, |t, x| {
            samples.push((t, *x))
        })
        .unwrap();
    assert_eq!(
        (with.x, with.stats.steps, with.stats.rejected),
        (plain.x, plain.stats.steps, plain.stats.rejected)
    );
    assert_eq!(samples.len(), 5);
    assert!(samples.iter().all(|(t, x)| (x - exact(*t)).amax() < 1e-6));
}

#[test]
fn finite_difference_jacobians_resolve_huge_states() {
    // x' = −x from 1e17 (f64) and 1e10 (f32): Hairer's increment
    // sqrt(eps·|x|) is below the spacing of the numbers there.
    for x0 in [1e17, 1e200, -1e17] {
        let out = Rodas4::new(1e-8, 1e-10)
            .integrate(&Decay, 0.0, Vector1::new(x0), 1.0)
            .unwrap();
        assert!(
            (out.x[0] / x0 - (-1.0f64).exp()).abs() < 1e-7,
            "{x0:e}: {out:?}"
        );
        let out = GaussLegendre4::new(1e-2)
            .integrate(&Decay, 0.0, Vector1::new(x0), 1.0)
            .unwrap();
        assert!(
            (out.x[0] / x0 - (-1.0f64).exp()).abs() < 1e-8,
            "{x0:e}: {out:?}"
        );
    }
    let decay32 = |_t: f32, x: &Vector1<f32>| -x;
    let out = Rodas4::new(1e-4f32, 1e-6)
        .integrate(&decay32, 0.0, Vector1::new(1e10f32), 1.0)
        .unwrap();
    assert!((out.x[0] / 1e10 - (-1.0f32).exp()).abs() < 1e-3, "{out:?}");
    let out = GaussLegendre4::new(1e-2f32)
        .integrate(&decay32, 0.0, Vector1::new(1e10f32), 1.0)
        .unwrap();
    assert!((out.x[0] / 1e10 - (-1.0f32).exp()).abs() < 1e-4, "{out:?}");
    // The time derivative too: t0 = 1e17.
    let out = Rodas4::new(1e-8, 1e-10)
        .integrate(&Decay, 1e17, Vector1::new(1.0), 1e17 + 64.0)
        .unwrap();
    assert_eq!(out.t, 1e17 + 64.0);
}

#[test]
fn tolerances_below_resolution_are_raised_to_ten_eps() {
    // rtol below 10·eps is raised to 10·eps (documented floor); atol may be
    // as small as it likes (it only matters where x is tiny).
    let x0 = Vector2::new(1.0, 0.0);
    let floor = 10.0 * f64::EPSILON;
    for rtol in [1e-300, 1e-20] {
        let same = |a: Run<2>, b: Run<2>| {
            let (a, b) = (a.unwrap(), b.unwrap());
            assert_eq!((a.x, a.stats), (b.x, b.stats));
            a
        };
        let out = same(
            Dopri5::new(rtol, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
            Dopri5::new(floor, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
        );
        assert!((out.x[0] - 1.0f64.cos()).abs() < 1e-13, "{out:?}");
        let out = same(
            Dop853::new(rtol, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
            Dop853::new(floor, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
        );
        assert!((out.x[0] - 1.0f64.cos()).abs() < 1e-13, "{out:?}");
        // The Rosenbrock methods say so instead: below 50·eps rounding in
        // their stage combinations, not the tolerance, would set the error.
        let rtol_min = 50.0 * f64::EPSILON;
        let too_tight = Err(SimError::ToleranceTooTight {
            t: 0.0,
            x: x0,
            rtol_min,
        });
        assert_eq!(
            Rodas4::new(rtol, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
            too_tight
        );
        assert_eq!(
            Rodas5P::new(rtol, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0),
            too_tight
        );
    }
    for rtol in [50.0 * f64::EPSILON, floor] {
        let tight = Rodas4::new(rtol, 1e-300).integrate(&Oscillator, 0.0, x0, 1.0);
        assert_eq!(
            tight.is_ok(),
            rtol >= 50.0 * f64::EPSILON,
            "{rtol:e}: {tight:?}"
        );
    }
    let out = Rodas5P::new(50.0 * f64::EPSILON, 1e-300)
        .integrate(&Oscillator, 0.0, x0, 1.0)
        .unwrap();
    assert!((out.x[0] - 1.0f64.cos()).abs() < 1e-13, "{out:?}");
    // In f32 the floor is 10·eps(f32).
    let osc32 = |_t: f32, x: &Vector2<f32>| Vector2::new(x[1], -x[0]);
    let out = Dop853::new(1e-30f32, 1e-30)
        .integrate(&osc32, 0.0, Vector2::new(1.0, 0.0), 1.0)
        .unwrap();
    assert!((out.x[0] - 1.0f32.cos()).abs() < 1e-5, "{out:?}");
}

#[test]
fn spans_too_short_for_a_step_end_ok_at_t1() {
    let x0 = Vector1::new(1.0);
    // 5e-324 (the smallest subnormal), 1e-300 from 0, and one ulp at 1.
    for (t0, t1) in [
        (0.0, 5e-324),
        (0.0, 1e-300),
        (1e-300, 2e-300),
        (1.0, 1.0 + f64::EPSILON),
        (1.0 + f64::EPSILON, 1.0),
    ] {
        for (name, r) in all_five(&Decay, t0, x0, t1) {
            let out = r.unwrap_or_else(|e| panic!("{name} [{t0:e}, {t1:e}]: {e:?}"));
            assert_eq!(out.t, t1, "{name}");
            assert!(
                (out.x[0] - 1.0).abs() <= 4.0 * f64::EPSILON,
                "{name}: {out:?}"
            );
            assert_eq!(
                out.stats.steps, 1,
                "{name} [{t0:e}, {t1:e}]: {:?}",
                out.stats
            );
        }
    }
    // Observers and output times see t0 and t1.
    let mut seen = Vec::new();
    Dopri5::new(1e-6, 1e-9)
        .integrate_with_outputs(&Decay, 0.0, x0, 1e-300, &[0.0, 5e-301, 1e-300], |t, x| {
            seen.push((t, x[0]))
        })
        .unwrap();
    assert_eq!(seen, [(0.0, 1.0), (5e-301, 1.0), (1e-300, 1.0)]);
}

#[test]
fn a_step_that_rounds_onto_t1_ends_the_run() {
    // From t = 1, a step of 11.6 ulps rounds onto t1 = 1 + 12 ulps while
    // t + 1.01·h does not exceed t1: the run must end there, Ok, instead
    // of trying a step of length 0 (StepSizeTooSmall with h = 0, or
    // Singular for Rodas4).
    let ulp = f64::EPSILON;
    let (t0, t1) = (1.0, 1.0 + 12.0 * ulp);
    let h0 = 11.6 * ulp;
    assert_eq!(t0 + h0, t1);
    let x0 = Vector1::new(1.0);
    let runs = [
        (
            "rodas4",
            Rodas4::new(1e-6, 1e-9)
                .with_initial_step(h0)
                .integrate(&Decay, t0, x0, t1),
        ),
        (
            "dopri5",
            Dopri5::new(1e-6, 1e-9)
                .with_initial_step(h0)
                .integrate(&Decay, t0, x0, t1),
        ),
        (
            "dop853",
            Dop853::new(1e-6, 1e-9)
                .with_initial_step(h0)
                .integrate(&Decay, t0, x0, t1),
        ),
    ];
    for (name, r) in runs {
        let out = r.unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert_eq!(out.t, t1, "{name}");
        assert_eq!(out.stats.steps, 1, "{name}: {:?}", out.stats);
    }
}

/// 75 uncoupled oscillators: dimension 150.
struct Oscillators150;

impl OdeSystem<f64, 150> for Oscillators150 {
    fn rhs(&self, _t: f64, x: &SVector<f64, 150>) -> SVector<f64, 150> {
        SVector::from_fn(|i, _| {
            let w = 1.0 + (i / 2) as f64 * 0.01;
            if i % 2 == 0 {
                x[i + 1]
            } else {
                -w * w * x[i - 1]
            }
        })
    }
}

#[test]
fn gauss_at_dimension_150_fits_a_small_thread_stack() {
    // The 150×150 Jacobian and LU live in a heap workspace: a thread with
    // a 256 KiB stack is enough (the stack version needed 3.2 MiB in
    // release, 10 MiB in debug).
    let worker = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(|| {
            let x0 = SVector::<f64, 150>::from_fn(|i, _| if i % 2 == 0 { 1.0 } else { 0.0 });
            let out = GaussLegendre4::new(0.05)
                .integrate(&Oscillators150, 0.0, x0, 0.5)
                .unwrap();
            (out.x[0], out.stats)
        })
        .unwrap();
    let (q, stats) = worker
        .join()
        .expect("the Gauss thread overflowed its stack");
    assert_eq!(stats.steps, 10);
    assert!((q - 0.5f64.cos()).abs() < 1e-6, "{q}");
}

#[test]
fn no_step_is_accepted_without_progress() {
    // A huge derivative on spans near the bottom of the exponent range:
    // the step size used to underflow to 0 at t = 0, and 99,931 accepted
    // steps of length 0 passed before MaxSteps. Now every accepted step
    // advances t, and a span below the smallest step is one Euler step.
    let big = |_t: f64, x: &Vector2<f64>| Vector2::new(1e300 * x[1], -x[0]);
    let x0 = Vector2::new(1.0, 1.0);
    for t1 in [5e-324, 1e-300, 1e-295, 1e-290] {
        let check = |name: &str, r: Run<2>, steps: usize| {
            println!("{name} [0, {t1:e}]: {steps} steps, {r:?}");
            match r {
                Ok(out) => assert_eq!(out.t, t1),
                Err(e) => assert!(
                    matches!(
                        e,
                        SimError::StepSizeTooSmall { .. } | SimError::NonFinite { .. }
                    ),
                    "{name}: {e:?}"
                ),
            }
            assert!(steps < 1000, "{name}: {steps} steps");
        };
        let forward = |s: &nh_runtime::Step<'_, f64, 2>| assert!(s.t() > s.t_prev(), "{s:?}");
        let mut n = 0;
        let r = Dopri5::new(1e-8, 1e-10).integrate_with_steps(&big, 0.0, x0, t1, |s| {
            forward(s);
            n += 1
        });
        check("dopri5", r, n);
        let mut n = 0;
        let r = Dop853::new(1e-8, 1e-10).integrate_with_steps(&big, 0.0, x0, t1, |s| {
            forward(s);
            n += 1
        });
        check("dop853", r, n);
        let mut n = 0;
        let r = Rodas4::new(1e-8, 1e-10).integrate_with_steps(&big, 0.0, x0, t1, |s| {
            forward(s);
            n += 1
        });
        check("rodas4", r, n);
    }
}
