//! Dense output ([`Step::interpolate`]), observers and output times.

mod common;

use common::{Oscillator, max_err, oscillator_exact};
use nalgebra::{SVector, Vector2};
use nh_runtime::{Dop853, Dopri5, Integrator, Rk4, Rodas4, Rodas5P, SimError, Stats, Step};

/// Largest interpolation error over 7 interior points of every step, and the
/// number of steps.
fn worst_interpolation_error<I: Integrator<f64>>(i: &mut I, t1: f64) -> (f64, usize) {
    let mut worst: f64 = 0.0;
    let mut n = 0;
    i.integrate_with_steps(&Oscillator, 0.0, Vector2::new(1.0, 0.0), t1, |s| {
        n += 1;
        // The step itself is exact at its ends.
        assert_eq!(s.interpolate(s.t()), *s.x());
        assert_eq!(s.interpolate(s.t_prev()), *s.x_prev());
        for j in 1..8 {
            let tj = s.t_prev() + s.h() * j as f64 / 8.0;
            // Compare with the exact flow from the step's start, so that
            // only the interpolation error (not the global error) counts.
            let (c, sn) = ((tj - s.t_prev()).cos(), (tj - s.t_prev()).sin());
            let x0 = s.x_prev();
            let exact = Vector2::new(c * x0[0] + sn * x0[1], -sn * x0[0] + c * x0[1]);
            worst = worst.max(max_err(&s.interpolate(tj), &exact));
        }
    })
    .unwrap();
    (worst, n)
}

#[test]
fn interpolation_orders() {
    // Local interpolation error of a dense output of order q is O(h^(q+1)):
    // halving h divides it by 2^(q+1).
    let rk4 = |h: f64| worst_interpolation_error(&mut Rk4::new(h), 2.0).0;
    let (e1, e2) = (rk4(0.1), rk4(0.05));
    let q = (e1 / e2).log2();
    println!("rk4 dense: {e1:.3e} {e2:.3e}, local order {q:.3}");
    assert!((q - 4.0).abs() < 0.3, "rk4 dense output local order {q}");

    let dp = |h: f64| {
        worst_interpolation_error(
            &mut Dopri5::new(1.0, 1.0).with_initial_step(h).with_max_step(h),
            2.0,
        )
        .0
    };
    let (e1, e2) = (dp(0.2), dp(0.1));
    let q = (e1 / e2).log2();
    println!("dopri5 dense: {e1:.3e} {e2:.3e}, local order {q:.3}");
    assert!((q - 5.0).abs() < 0.3, "dopri5 dense output local order {q}");

    let d8 =
        |h: f64| worst_interpolation_error(&mut Dop853::new(1.0, 1.0).with_fixed_step(h), 2.0).0;
    let (e1, e2) = (d8(0.4), d8(0.2));
    let q = (e1 / e2).log2();
    println!("dop853 dense: {e1:.3e} {e2:.3e}, local order {q:.3}");
    assert!((q - 8.0).abs() < 0.3, "dop853 dense output local order {q}");

    // RODAS4's dense output is of order 3, Rodas5P's of order 4.
    let rodas4 =
        |h: f64| worst_interpolation_error(&mut Rodas4::new(1.0, 1.0).with_fixed_step(h), 2.0).0;
    let rodas5 =
        |h: f64| worst_interpolation_error(&mut Rodas5P::new(1.0, 1.0).with_fixed_step(h), 2.0).0;
    for (name, f, local) in [
        ("rodas4", &rodas4 as &dyn Fn(f64) -> f64, 4.0),
        ("rodas5p", &rodas5, 5.0),
    ] {
        let (e1, e2) = (f(0.2), f(0.1));
        let q = (e1 / e2).log2();
        println!("{name} dense: {e1:.3e} {e2:.3e}, local order {q:.3}");
        assert!(
            (q - local).abs() < 0.3,
            "{name} dense output local order {q}"
        );
    }
}

#[test]
fn dense_output_accuracy_matches_tolerance() {
    for (name, worst) in [
        (
            "dopri5",
            worst_interpolation_error(&mut Dopri5::new(1e-9, 1e-12), 10.0).0,
        ),
        (
            "dop853",
            worst_interpolation_error(&mut Dop853::new(1e-9, 1e-12), 10.0).0,
        ),
    ] {
        println!("{name}: worst interpolation error {worst:.3e} at rtol 1e-9");
        assert!(worst < 1e-8, "{name}: {worst:e}");
    }
}

/// Outputs at 0, 0.01, …, 10 and the run without outputs.
fn outputs_vs_plain<I: Integrator<f64>>(name: &str, mut make: impl FnMut() -> I, tol: f64) {
    let x0 = Vector2::new(1.0, 0.0);
    let times: Vec<f64> = (0..=1000).map(|i| 0.01 * i as f64).collect();
    let mut plain_ends = Vec::new();
    let plain = make()
        .integrate_with_observer(&Oscillator, 0.0, x0, 10.0, |t, _| plain_ends.push(t))
        .unwrap();
    let mut samples = Vec::new();
    let mut i = make();
    let with = i
        .integrate_with_outputs(&Oscillator, 0.0, x0, 10.0, &times, |t, x| {
            samples.push((t, *x))
        })
        .unwrap();
    let mut step_ends = vec![0.0];
    make()
        .integrate_with_steps(&Oscillator, 0.0, x0, 10.0, |s| step_ends.push(s.t()))
        .unwrap();
    // Identical step sequence, result and work (Dop853's lazily computed
    // dense stages aside, which are counted only when used).
    assert_eq!(plain_ends, step_ends, "{name}");
    assert_eq!(plain.x, with.x, "{name}");
    let Stats { rhs_evals, .. } = with.stats;
    assert_eq!(
        Stats {
            rhs_evals: plain.stats.rhs_evals,
            ..with.stats
        },
        plain.stats,
        "{name}"
    );
    assert!(rhs_evals >= plain.stats.rhs_evals);
    // Every time reported once, in order, accurately.
    assert_eq!(samples.len(), times.len(), "{name}");
    assert_eq!(samples[0], (0.0, x0), "{name}: t0 is reported with x0");
    assert_eq!(
        samples.last().unwrap(),
        &(10.0, with.x),
        "{name}: t1 exactly"
    );
    let worst = samples
        .iter()
        .map(|(t, x)| max_err(x, &oscillator_exact(*t)))
        .fold(0.0, f64::max);
    println!(
        "{name}: {} steps, {} outputs, worst output error {worst:.2e}",
        plain.stats.steps,
        samples.len()
    );
    assert!(worst < tol, "{name}: worst output error {worst:e}");
    for (w, t) in samples.windows(2).zip(&times[1..]) {
        assert!(w[1].0 > w[0].0);
        assert_eq!(w[1].0, *t);
    }
}

#[test]
fn output_times_do_not_change_the_steps() {
    use nh_runtime::GaussLegendre4;
    outputs_vs_plain("rk4", || Rk4::new(0.07), 1e-5);
    outputs_vs_plain("dopri5", || Dopri5::new(1e-9, 1e-12), 1e-8);
    outputs_vs_plain("dop853", || Dop853::new(1e-9, 1e-12), 1e-8);
    outputs_vs_plain("rodas4", || Rodas4::new(1e-7, 1e-10), 1e-5);
    outputs_vs_plain("rodas5p", || Rodas5P::new(1e-7, 1e-10), 1e-5);
    outputs_vs_plain("gauss4", || GaussLegendre4::new(0.05), 1e-5);
}

#[test]
fn output_time_conventions() {
    let x0 = Vector2::new(1.0, 0.0);
    let collect = |t0: f64, t1: f64, times: &[f64]| {
        let mut v = Vec::new();
        let r = Dopri5::new(1e-10, 1e-12).integrate_with_outputs(
            &Oscillator,
            t0,
            x0,
            t1,
            times,
            |t, x: &SVector<f64, 2>| v.push((t, *x)),
        );
        (r, v)
    };
    // Outside [t0, t1]: ignored; repeated times: reported repeatedly.
    let (r, v) = collect(0.0, 1.0, &[-1.0, 0.0, 0.5, 0.5, 1.0, 2.0]);
    r.unwrap();
    let ts: Vec<f64> = v.iter().map(|p| p.0).collect();
    assert_eq!(ts, [0.0, 0.5, 0.5, 1.0]);
    assert_eq!(v[0].1, x0);
    assert!(max_err(&v[1].1, &oscillator_exact(0.5)) < 1e-9);
    // Unsorted or non-finite times: InvalidInput, nothing integrated.
    for bad in [&[0.5, 0.2][..], &[0.1, f64::NAN]] {
        let (r, v) = collect(0.0, 1.0, bad);
        assert!(matches!(r, Err(SimError::InvalidInput { .. })), "{r:?}");
        assert!(v.is_empty());
    }
    // Backwards: times must decrease.
    let (r, v) = collect(1.0, 0.0, &[1.0, 0.75, 0.25, 0.0, -0.5]);
    let out = r.unwrap();
    let ts: Vec<f64> = v.iter().map(|p| p.0).collect();
    assert_eq!(ts, [1.0, 0.75, 0.25, 0.0]);
    assert_eq!(v[3].1, out.x);
    assert!(matches!(
        collect(1.0, 0.0, &[0.25, 0.75]).0,
        Err(SimError::InvalidInput { .. })
    ));
    // Empty interval: only times equal to t0, with x0.
    let (r, v) = collect(3.0, 3.0, &[2.0, 3.0, 3.0, 4.0]);
    r.unwrap();
    assert_eq!(v, [(3.0, x0), (3.0, x0)]);
    // On error, the outputs before the failure have been delivered.
    let mut v = Vec::new();
    let e = Dopri5::new(1e-8, 1e-10)
        .with_max_steps(10)
        .integrate_with_outputs(&Oscillator, 0.0, x0, 100.0, &[0.0, 1e-3, 50.0], |t, _| {
            v.push(t)
        })
        .unwrap_err();
    assert!(matches!(e, SimError::MaxSteps { .. }));
    assert_eq!(v, [0.0, 1e-3]);
}

#[test]
fn observer_is_silent_on_invalid_input() {
    let mut calls = 0;
    let r = Dopri5::new(-1.0, 1e-8).integrate_with_observer(
        &Oscillator,
        0.0,
        Vector2::new(1.0, 0.0),
        1.0,
        |_, _: &SVector<f64, 2>| calls += 1,
    );
    assert!(matches!(r, Err(SimError::InvalidInput { .. })));
    assert_eq!(calls, 0);
}

#[test]
fn dop853_dense_stages_only_where_interpolated() {
    // The three extra stages of DOP853's dense output are computed (and
    // checked) before a step is accepted, and only for steps that are
    // interpolated: every step handed to `integrate_with_steps`, and only
    // the steps with an output time inside for `integrate_with_outputs`.
    let x0 = Vector2::new(1.0, 0.0);
    let mut d = Dop853::new(1e-9, 1e-12);
    let plain = d.integrate(&Oscillator, 0.0, x0, 10.0).unwrap().stats;
    let mut ends = vec![0.0];
    let steps = d
        .integrate_with_steps(&Oscillator, 0.0, x0, 10.0, |s: &Step<'_, f64, 2>| {
            ends.push(s.t())
        })
        .unwrap()
        .stats;
    assert_eq!(steps.steps, plain.steps);
    assert_eq!(steps.rhs_evals, plain.rhs_evals + 3 * plain.steps);
    // Output times in the second half only (and one exactly at a step end,
    // which needs no interpolant).
    let times = [ends[1], 6.0, 6.01, 7.5, 9.0];
    let inside = ends
        .windows(2)
        .filter(|w| times.iter().any(|&t| w[0] < t && t < w[1]))
        .count();
    assert_eq!(inside, 3);
    let outputs = d
        .integrate_with_outputs(&Oscillator, 0.0, x0, 10.0, &times, |_, _| {})
        .unwrap()
        .stats;
    assert_eq!(outputs.steps, plain.steps);
    assert_eq!(outputs.rhs_evals, plain.rhs_evals + 3 * inside);
}

/// `x' = x`: from `x0 = 1e305` it stays below the largest `f64` until
/// `t ≈ 7.5`, but DOP853's dense output (weights up to 527 on stages of
/// that size) overflows from `x ≈ 3e305` on.
fn growth(_t: f64, x: &SVector<f64, 1>) -> SVector<f64, 1> {
    *x
}

/// `θ' = sqrt(2 (cos θ − cos 1))`: the pendulum's angle rising to its
/// turning point θ = 1, where the square root's argument reaches zero; the
/// extra stages of DOP853's dense output land beyond it (NaN) on some
/// steps whose own stages do not.
fn to_the_turning_point(_t: f64, x: &SVector<f64, 1>) -> SVector<f64, 1> {
    SVector::<f64, 1>::new((2.0 * (x[0].cos() - 1.0f64.cos())).sqrt())
}

/// The step ends of a run without dense output (observer), with every step
/// interpolated (`integrate_with_steps`) and with output times at 1 %
/// of the span: identical, and every sample finite.
fn sampling_changes_nothing(
    name: &str,
    sys: fn(f64, &SVector<f64, 1>) -> SVector<f64, 1>,
    x0: f64,
    t1: f64,
    make: impl Fn() -> Dop853<f64>,
) -> Vec<(f64, f64)> {
    let x0 = SVector::<f64, 1>::new(x0);
    let mut plain_ends = Vec::new();
    let plain =
        make().integrate_with_observer(&sys, 0.0, x0, t1, |t, x| plain_ends.push((t, x[0])));
    let plain = plain.unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let mut step_ends = vec![(0.0, x0[0])];
    let mut interpolated = Vec::new();
    let steps = make()
        .integrate_with_steps(&sys, 0.0, x0, t1, |s| {
            step_ends.push((s.t(), s.x()[0]));
            interpolated.push(s.interpolate(s.t_prev() + 0.5 * s.h())[0]);
        })
        .unwrap_or_else(|e| panic!("{name}, steps: {e:?}"));
    let times: Vec<f64> = (0..=100).map(|k| t1 * k as f64 / 100.0).collect();
    let mut samples = Vec::new();
    let outputs = make()
        .integrate_with_outputs(&sys, 0.0, x0, t1, &times, |t, x| samples.push((t, x[0])))
        .unwrap_or_else(|e| panic!("{name}, outputs: {e:?}"));
    assert_eq!(step_ends, plain_ends, "{name}");
    for out in [steps, outputs] {
        assert_eq!((out.t, out.x), (plain.t, plain.x), "{name}");
        assert_eq!(
            (out.stats.steps, out.stats.rejected),
            (plain.stats.steps, plain.stats.rejected),
            "{name}"
        );
    }
    assert_eq!(samples.len(), times.len(), "{name}");
    assert!(interpolated.iter().all(|v| v.is_finite()), "{name}");
    assert!(samples.iter().all(|(_, v)| v.is_finite()), "{name}");
    samples
}

#[test]
fn dop853_sampling_never_changes_the_steps_where_its_dense_output_fails() {
    // Before: with output times the run ended in NonFinite at t = 1.2201
    // (rtol 1e-10) where the plain run succeeds (x = 3.43e305 at t1 after
    // 6 steps): a dense output that overflowed rejected the step.
    for rtol in [1e-6, 1e-10, 1e-12] {
        let samples = sampling_changes_nothing("growth", growth, 1e305, 1.23125, || {
            Dop853::new(rtol, rtol * 1e-2)
        });
        // Where the order-7 interpolant overflows, the cubic Hermite one
        // takes over: still close to 1e305·e^t.
        let worst = samples
            .iter()
            .map(|&(t, x)| (x / (1e305 * t.exp()) - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-4, "rtol {rtol:e}: {worst:e}");
    }
    // Before: 37 steps and 33 rejections with every step interpolated
    // against 33 and 28 plain (the extra stages' NaN rejected steps).
    for (t1, rtol) in [(2.73, 0.1), (3.38, 0.1), (3.38, 0.03)] {
        let samples =
            sampling_changes_nothing("turning point", to_the_turning_point, 0.0, t1, || {
                Dop853::new(rtol, rtol)
            });
        assert!(samples.iter().all(|&(_, x)| (0.0..=1.0).contains(&x)));
    }
}

#[test]
fn dop853_fixed_steps_are_not_failed_by_their_dense_output() {
    // With a fixed step a non-finite dense output used to end the run in
    // NonFinite at once, a step before the plain run's own failure: the
    // stiff problem below blows up (h·λ far beyond the stability
    // boundary); both now fail at the same step.
    let stiff = |t: f64, x: &SVector<f64, 1>| SVector::<f64, 1>::new(-1e6 * (x[0] - t.cos()));
    let x0 = SVector::<f64, 1>::new(0.5);
    let h = 0.01 / 37.0;
    let make = || Dop853::new(1e-6, 1e-8).with_fixed_step(h);
    let plain = make().integrate(&stiff, 0.0, x0, 0.01).unwrap_err();
    let times: Vec<f64> = (0..=200).map(|k| 0.01 * k as f64 / 200.0).collect();
    let mut finite = true;
    let with = make()
        .integrate_with_outputs(&stiff, 0.0, x0, 0.01, &times, |_, x| {
            finite &= x[0].is_finite()
        })
        .unwrap_err();
    assert!(matches!(plain, SimError::NonFinite { .. }), "{plain:?}");
    assert_eq!(with, plain);
    assert!(finite);
}
