//! Per-component tolerances: equal entries reproduce the scalar tolerance
//! bit for bit, a rescaled component with a rescaled `atol` gives the same
//! steps, components of very different scales each get their relative
//! accuracy, and invalid tolerances are typed errors.

use core::cell::Cell;

use nalgebra::{Matrix3, SVector, Vector2, Vector3, Vector4};
use nh_runtime::{Dop853, Dopri5, Integrator, OdeJacobian, OdeSystem, Outcome, Rodas4, SimError};

/// Two harmonic oscillators, `ω = 1` in `(x1, x2)` and `ω = 10` in
/// `(x3, x4)`, each component multiplied by `scale[i]`:
/// `x' = S A S⁻¹ x`. With powers of two in `scale`, the right-hand side of
/// the scaled state `S x` is exactly `S f(x)`.
fn oscillators(scale: Vector4<f64>) -> impl Fn(f64, &Vector4<f64>) -> Vector4<f64> {
    let s = scale;
    move |_t, x| {
        Vector4::new(
            (s[0] / s[1]) * x[1],
            -(s[1] / s[0]) * x[0],
            10.0 * (s[2] / s[3]) * x[3],
            -10.0 * (s[3] / s[2]) * x[2],
        )
    }
}

/// The exact solution of [`oscillators`] from `scale ⊙ (1, 0, 1, 0)`.
fn oscillators_exact(scale: Vector4<f64>, t: f64) -> Vector4<f64> {
    let unit = Vector4::new(t.cos(), -t.sin(), (10.0 * t).cos(), -(10.0 * t).sin());
    unit.component_mul(&scale)
}

/// Van der Pol with `μ = 5`, a nonlinear test problem.
fn van_der_pol(_t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(x[1], 5.0 * (1.0 - x[0] * x[0]) * x[1] - x[0])
}

/// Every accepted step `(t, x)` of a run, and its outcome.
type Trace<const D: usize> = (
    Vec<(f64, SVector<f64, D>)>,
    Result<Outcome<f64, D>, SimError<f64, D>>,
);

fn trace<I, S, const D: usize>(mut integrator: I, sys: &S, x0: SVector<f64, D>, t1: f64) -> Trace<D>
where
    I: Integrator<f64>,
    S: OdeSystem<f64, D>,
{
    let mut steps = Vec::new();
    let out = integrator.integrate_with_steps(sys, 0.0, x0, t1, |s| steps.push((s.t(), *s.x())));
    (steps, out)
}

/// `with_tolerances` with equal entries takes exactly the steps of
/// `new(rtol, atol)` (same times, same states, same counters), for every
/// adaptive integrator, including `atol = 0` and an `rtol` below the
/// `10·eps` floor.
#[test]
fn equal_entries_are_bit_identical_to_scalar_tolerances() {
    let x0 = Vector2::new(2.0, 0.0);
    for (rtol, atol) in [(1e-4, 1e-6), (1e-9, 1e-12), (1e-7, 0.0), (1e-18, 1e-20)] {
        let (r, a) = (Vector2::repeat(rtol), Vector2::repeat(atol));
        let cases = [
            (
                trace(Dopri5::new(rtol, atol), &van_der_pol, x0, 8.0),
                trace(
                    Dopri5::new(1.0, 1.0).with_tolerances(r, a),
                    &van_der_pol,
                    x0,
                    8.0,
                ),
            ),
            (
                trace(Dop853::new(rtol, atol), &van_der_pol, x0, 8.0),
                trace(
                    Dop853::new(1.0, 1.0).with_tolerances(r, a),
                    &van_der_pol,
                    x0,
                    8.0,
                ),
            ),
            (
                trace(Rodas4::new(rtol, atol), &van_der_pol, x0, 8.0),
                trace(
                    Rodas4::new(1.0, 1.0).with_tolerances(r, a),
                    &van_der_pol,
                    x0,
                    8.0,
                ),
            ),
        ];
        for (k, (scalar, vector)) in cases.into_iter().enumerate() {
            // below 50·eps the Rosenbrock methods end at once in
            // ToleranceTooTight, given either way
            let too_tight = k == 2 && rtol < 50.0 * f64::EPSILON;
            assert_eq!(
                too_tight,
                scalar.0.is_empty(),
                "case {k}, rtol {rtol}: {:?}",
                scalar.1
            );
            assert!(
                too_tight || scalar.0.len() > 5,
                "case {k}, rtol {rtol}: {:?}",
                scalar.1
            );
            assert_eq!(scalar, vector, "integrator {k}, rtol {rtol}, atol {atol}");
        }
    }
}

/// Multiplying component `i` of the state by `s_i` (a power of two) and
/// its absolute tolerance by `s_i` changes nothing but the units: the
/// explicit methods take the same steps and land on exactly the scaled
/// states. With one scalar `atol` the same rescaling changes the steps.
#[test]
fn a_rescaled_component_with_a_rescaled_atol_takes_the_same_steps() {
    let unit = Vector4::repeat(1.0);
    let scale = Vector4::new(2f64.powi(20), 2f64.powi(20), 2f64.powi(-20), 2f64.powi(-20));
    let (rtol, atol) = (Vector4::repeat(1e-8), Vector4::repeat(1e-10));
    let x0 = Vector4::new(1.0, 0.0, 1.0, 0.0);
    let (sys, scaled_sys) = (oscillators(unit), oscillators(scale));
    let runs = [
        (
            trace(Dopri5::new(1e-8, 1e-10), &sys, x0, 5.0),
            trace(
                Dopri5::new(1e-8, 1e-10).with_tolerances(rtol, atol.component_mul(&scale)),
                &scaled_sys,
                x0.component_mul(&scale),
                5.0,
            ),
            trace(
                Dopri5::new(1e-8, 1e-10 * scale.max()),
                &scaled_sys,
                x0.component_mul(&scale),
                5.0,
            ),
        ),
        (
            trace(Dop853::new(1e-8, 1e-10), &sys, x0, 5.0),
            trace(
                Dop853::new(1e-8, 1e-10).with_tolerances(rtol, atol.component_mul(&scale)),
                &scaled_sys,
                x0.component_mul(&scale),
                5.0,
            ),
            trace(
                Dop853::new(1e-8, 1e-10 * scale.max()),
                &scaled_sys,
                x0.component_mul(&scale),
                5.0,
            ),
        ),
    ];
    for (k, ((steps, out), (scaled_steps, scaled_out), (scalar_steps, _))) in
        runs.into_iter().enumerate()
    {
        let (out, scaled_out) = (out.unwrap(), scaled_out.unwrap());
        assert_eq!(out.stats, scaled_out.stats, "integrator {k}");
        assert_eq!(steps.len(), scaled_steps.len());
        for ((t, x), (ts, xs)) in steps.iter().zip(&scaled_steps) {
            assert_eq!(t, ts, "integrator {k}");
            assert_eq!(x.component_mul(&scale), *xs, "integrator {k} at t = {t}");
        }
        // One scalar atol (suited to the large components) is not
        // invariant: the small components no longer limit the step.
        assert!(
            scalar_steps.len() < steps.len(),
            "integrator {k}: {} vs {}",
            scalar_steps.len(),
            steps.len()
        );
    }
}

/// The largest error of each component over the output times, relative
/// to the component's amplitude.
fn relative_errors<I: Integrator<f64>>(mut integrator: I, scale: Vector4<f64>) -> Vector4<f64> {
    let sys = oscillators(scale);
    let x0 = Vector4::new(1.0, 0.0, 1.0, 0.0).component_mul(&scale);
    let times: Vec<f64> = (1..=40).map(|k| 0.25 * k as f64).collect();
    let mut worst = Vector4::zeros();
    integrator
        .integrate_with_outputs(&sys, 0.0, x0, 10.0, &times, |t, x| {
            let e = (x - oscillators_exact(scale, t))
                .component_div(&scale)
                .abs();
            worst = worst.sup(&e);
        })
        .unwrap();
    worst
}

/// Components of amplitude 1e6 and 1e-6 (two oscillators): with an
/// absolute tolerance per component, `rtol` times the component's scale,
/// every component is accurate to its own scale; one scalar `atol` suited
/// to the large components lets the small ones drift by a large fraction
/// of their size.
#[test]
fn per_component_atol_gives_each_component_its_relative_accuracy() {
    let scale = Vector4::new(1e6, 1e6, 1e-6, 1e-6);
    let rtol = 1e-7;
    let (r, a) = (Vector4::repeat(rtol), scale * rtol);
    let big_atol = rtol * 1e6;
    let cases = [
        (
            "Dopri5",
            relative_errors(Dopri5::new(rtol, 0.0).with_tolerances(r, a), scale),
            relative_errors(Dopri5::new(rtol, big_atol), scale),
        ),
        (
            "Dop853",
            relative_errors(Dop853::new(rtol, 0.0).with_tolerances(r, a), scale),
            relative_errors(Dop853::new(rtol, big_atol), scale),
        ),
        (
            "Rodas4",
            relative_errors(Rodas4::new(rtol, 0.0).with_tolerances(r, a), scale),
            relative_errors(Rodas4::new(rtol, big_atol), scale),
        ),
    ];
    for (name, per_component, scalar) in cases {
        eprintln!(
            "{name}: per component {:?}, scalar {:?}",
            per_component.as_slice(),
            scalar.as_slice()
        );
        // Each component within 100·rtol of its amplitude …
        assert!(
            per_component.max() < 100.0 * rtol,
            "{name}: {per_component:?}"
        );
        // … while the scalar atol leaves the small ones far less accurate.
        for i in 2..4 {
            assert!(
                scalar[i] > 1e3 * per_component[i],
                "{name} x{i}: {scalar:?}"
            );
        }
    }
}

/// A non-finite, negative or zero entry is `InvalidInput` before the
/// system is evaluated, as for the scalar tolerances.
#[test]
fn invalid_per_component_tolerances_are_invalid_input() {
    let calls = Cell::new(0usize);
    let sys = |_t: f64, x: &Vector2<f64>| {
        calls.set(calls.get() + 1);
        -x
    };
    let x0 = Vector2::new(1.0, 1e-3);
    let good = Vector2::new(1e-6, 1e-8);
    let bad_rtol = [0.0, -1e-6, f64::NAN, f64::INFINITY];
    let bad_atol = [-1e-8, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    let expect = |r: Result<Outcome<f64, 2>, SimError<f64, 2>>, what: &str| match r {
        Err(SimError::InvalidInput { what: w }) => assert_eq!(w, what),
        other => panic!("{other:?}"),
    };
    for v in bad_rtol {
        let rtol = Vector2::new(1e-6, v);
        let rtol_what = "rtol must be positive and finite";
        let mut dp = Dopri5::new(1e-6, 1e-8).with_tolerances(rtol, good);
        expect(dp.integrate(&sys, 0.0, x0, 1.0), rtol_what);
        let mut dop = Dop853::new(1e-6, 1e-8).with_tolerances(rtol, good);
        expect(dop.integrate(&sys, 0.0, x0, 1.0), rtol_what);
        let mut ros = Rodas4::new(1e-6, 1e-8).with_tolerances(rtol, good);
        expect(ros.integrate(&sys, 0.0, x0, 1.0), rtol_what);
    }
    for v in bad_atol {
        let atol = Vector2::new(v, 1e-8);
        let atol_what = "atol must be non-negative and finite";
        let mut dp = Dopri5::new(1e-6, 1e-8).with_tolerances(good, atol);
        expect(dp.integrate(&sys, 0.0, x0, 1.0), atol_what);
        let mut dop = Dop853::new(1e-6, 1e-8).with_tolerances(good, atol);
        expect(dop.integrate(&sys, 0.0, x0, 1.0), atol_what);
        let mut ros = Rodas4::new(1e-6, 1e-8).with_tolerances(good, atol);
        expect(ros.integrate(&sys, 0.0, x0, 1.0), atol_what);
    }
    assert_eq!(calls.get(), 0);
    // A zero atol entry is allowed (pure relative control of that component).
    let mut dp = Dopri5::new(1e-6, 1e-8).with_tolerances(good, Vector2::new(0.0, 1e-9));
    assert!(dp.integrate(&sys, 0.0, x0, 1.0).is_ok());
}

/// `x' = -x` in three dimensions with its Jacobian, counting evaluations.
struct Linear3<'a>(&'a Cell<usize>);

impl OdeSystem<f64, 3> for Linear3<'_> {
    fn rhs(&self, _t: f64, x: &Vector3<f64>) -> Vector3<f64> {
        self.0.set(self.0.get() + 1);
        -x
    }
}

impl OdeJacobian<f64, 3> for Linear3<'_> {
    fn jacobian(&self, _t: f64, _x: &Vector3<f64>) -> Matrix3<f64> {
        self.0.set(self.0.get() + 1);
        -Matrix3::identity()
    }
}

/// Tolerances for another dimension than the state's are `InvalidInput`
/// (nothing evaluated, the counters of the previous run cleared).
#[test]
fn a_dimension_mismatch_is_invalid_input() {
    let calls = Cell::new(0usize);
    let sys3 = |_t: f64, x: &Vector3<f64>| {
        calls.set(calls.get() + 1);
        -x
    };
    let what = "the per-component tolerances have another dimension than the state";
    let mut dp =
        Dopri5::new(1.0, 1.0).with_tolerances(Vector2::repeat(1e-6), Vector2::repeat(1e-8));
    // A run in the right dimension first, so that there are counters to clear.
    dp.integrate(
        &|_t: f64, x: &Vector2<f64>| -x,
        0.0,
        Vector2::new(1.0, 2.0),
        1.0,
    )
    .unwrap();
    assert!(dp.last_stats().steps > 0);
    let r = dp.integrate(&sys3, 0.0, Vector3::new(1.0, 2.0, 3.0), 1.0);
    assert_eq!(r, Err(SimError::InvalidInput { what }));
    assert_eq!(dp.last_stats(), nh_runtime::Stats::default());

    let mut dop = Dop853::new(1.0, 1.0).with_tolerances(Vector4::repeat(1e-6), Vector4::zeros());
    let r = dop.integrate(&sys3, 0.0, Vector3::new(1.0, 2.0, 3.0), 1.0);
    assert_eq!(r, Err(SimError::InvalidInput { what }));
    let mut ros =
        Rodas4::new(1.0, 1.0).with_tolerances(Vector2::repeat(1e-6), Vector2::repeat(1e-8));
    let r = ros.integrate(&sys3, 0.0, Vector3::new(1.0, 2.0, 3.0), 1.0);
    assert_eq!(r, Err(SimError::InvalidInput { what }));
    let r = ros.integrate_with_jacobian(&Linear3(&calls), 0.0, Vector3::new(1.0, 2.0, 3.0), 1.0);
    assert_eq!(r, Err(SimError::InvalidInput { what }));
    assert_eq!(calls.get(), 0);
}

/// The `10·eps` floor applies per component: an entry below it behaves as
/// `10·eps`, the other entries are untouched.
#[test]
fn the_rtol_floor_applies_per_component() {
    let floor = 10.0 * f64::EPSILON;
    let x0 = Vector2::new(2.0, 0.0);
    let atol = Vector2::new(1e-14, 1e-14);
    let below = trace(
        Dop853::new(1.0, 1.0).with_tolerances(Vector2::new(1e-300, 1e-9), atol),
        &van_der_pol,
        x0,
        2.0,
    );
    let at = trace(
        Dop853::new(1.0, 1.0).with_tolerances(Vector2::new(floor, 1e-9), atol),
        &van_der_pol,
        x0,
        2.0,
    );
    let looser = trace(
        Dop853::new(1.0, 1.0).with_tolerances(Vector2::new(1e-9, 1e-9), atol),
        &van_der_pol,
        x0,
        2.0,
    );
    assert_eq!(below, at);
    assert!(
        at.0.len() > looser.0.len(),
        "{} vs {}",
        at.0.len(),
        looser.0.len()
    );
}
