//! The pole hook `OdeSystem::crossed_pole`: a step across a pole of the
//! equations ends every integrator in `SimError::Singular` with
//! `Singularity::Pole` and the last good state (adaptive, fixed-step and
//! tiny-span paths, with a system with inputs and with sensitivities); a run
//! that stays away from the pole is the run without the hook, bit for bit;
//! a terminal event before the pole still ends the run at the event.
use std::f64::consts::FRAC_PI_2;

use nalgebra::{Matrix2, SMatrix, SVector, Vector1, Vector2};
use nh_runtime::{
    AutoSwitch, Bdf, ControlledSystem, Dop853, Dopri5, Driven, Events, GaussLegendre4, Integrator,
    OdeJacobian, OdeSystem, Outcome, ParameterJacobian, Rk4, Rodas4, Rodas5P, Sensitivities,
    SimError, Singularity, Step,
};

const TAN: &str = "tan(theta)";

/// x = [θ, v]: θ' = 1, v' = tan θ (v = −ln cos θ), a pole at θ = π/2,
/// with its guard cos θ checked by hand.
struct Tangent;

/// The same equations without the hook.
struct Unguarded;

fn tangent_rhs(x: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(1.0, x[0].tan())
}

/// The guard cos θ changed sign or reached zero, or is not finite at the end.
fn crosses_tan(x0: &Vector2<f64>, x1: &Vector2<f64>) -> Option<&'static str> {
    let (g0, g1) = (x0[0].cos(), x1[0].cos());
    (g0 * g1 <= 0.0 || !g1.is_finite()).then_some(TAN)
}

impl OdeSystem<f64, 2> for Tangent {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        tangent_rhs(x)
    }

    fn crossed_pole(
        &self,
        _t0: f64,
        x0: &Vector2<f64>,
        _t1: f64,
        x1: &Vector2<f64>,
    ) -> Option<&'static str> {
        crosses_tan(x0, x1)
    }
}

impl OdeSystem<f64, 2> for Unguarded {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        tangent_rhs(x)
    }
}

fn tangent_jacobian(x: &Vector2<f64>) -> Matrix2<f64> {
    let c = x[0].cos();
    Matrix2::new(0.0, 0.0, 1.0 / (c * c), 0.0)
}

impl OdeJacobian<f64, 2> for Tangent {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        tangent_jacobian(x)
    }
}

impl OdeJacobian<f64, 2> for Unguarded {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        tangent_jacobian(x)
    }
}

type Run = Result<Outcome<f64, 2>, SimError<f64, 2>>;

/// Every integrator of the crate on `sys` from `x0` at `t0` to `t1`; for
/// each, the result of `integrate` and the step ends `(t, x)` of
/// `integrate_with_steps` (starting with `(t0, x0)`).
#[allow(clippy::type_complexity)]
fn every_integrator<S: OdeJacobian<f64, 2>>(
    sys: &S,
    t0: f64,
    x0: Vector2<f64>,
    t1: f64,
) -> Vec<(&'static str, Run, Vec<(f64, Vector2<f64>)>)> {
    let mut out = Vec::new();
    let mut add =
        |name: &'static str, run: &mut dyn FnMut(bool, &mut Vec<(f64, Vector2<f64>)>) -> Run| {
            let plain = run(false, &mut Vec::new());
            let mut ends = vec![(t0, x0)];
            run(true, &mut ends).ok();
            out.push((name, plain, ends));
        };
    macro_rules! runs {
        ($integrator:expr, $call:ident, $steps:ident) => {
            &mut |with_steps: bool, ends: &mut Vec<(f64, Vector2<f64>)>| {
                if with_steps {
                    $integrator.$steps(sys, t0, x0, t1, |s: &Step<'_, f64, 2>| {
                        ends.push((s.t(), *s.x()))
                    })
                } else {
                    $integrator.$call(sys, t0, x0, t1)
                }
            }
        };
    }
    add(
        "Rk4",
        runs!(Rk4::new(0.01), integrate, integrate_with_steps),
    );
    add(
        "Rk4 coarse",
        runs!(Rk4::new(0.25), integrate, integrate_with_steps),
    );
    add(
        "Dopri5",
        runs!(Dopri5::new(1e-8, 1e-10), integrate, integrate_with_steps),
    );
    add(
        "Dopri5 fixed step",
        runs!(
            Dopri5::new(1e-8, 1e-10).with_fixed_step(0.3),
            integrate,
            integrate_with_steps
        ),
    );
    add(
        "Dop853",
        runs!(Dop853::new(1e-10, 1e-12), integrate, integrate_with_steps),
    );
    add(
        "Rodas4",
        runs!(
            Rodas4::new(1e-6, 1e-8),
            integrate_with_jacobian,
            integrate_with_jacobian_and_steps
        ),
    );
    add(
        "Rodas4 (finite differences)",
        runs!(Rodas4::new(1e-6, 1e-8), integrate, integrate_with_steps),
    );
    add(
        "Rodas5P",
        runs!(
            Rodas5P::new(1e-7, 1e-9),
            integrate_with_jacobian,
            integrate_with_jacobian_and_steps
        ),
    );
    add(
        "Bdf",
        runs!(
            Bdf::new(1e-7, 1e-9),
            integrate_with_jacobian,
            integrate_with_jacobian_and_steps
        ),
    );
    add(
        "Bdf (finite differences)",
        runs!(Bdf::new(1e-7, 1e-9), integrate, integrate_with_steps),
    );
    add(
        "GaussLegendre4",
        runs!(GaussLegendre4::new(0.05), integrate, integrate_with_steps),
    );
    add(
        "GaussLegendre4 coarse",
        runs!(GaussLegendre4::new(0.3), integrate, integrate_with_steps),
    );
    add(
        "AutoSwitch",
        runs!(
            AutoSwitch::new(1e-8, 1e-10),
            integrate,
            integrate_with_steps
        ),
    );
    out
}

/// `Singular { cause: Pole(TAN) }` with the last good state: finite, before
/// the pole, and a state the same run accepted (the end of a step reported
/// to `integrate_with_steps`, or `(t0, x0)`).
fn assert_pole(name: &str, r: &Run, ends: &[(f64, Vector2<f64>)]) {
    let Err(SimError::Singular { t, x, cause }) = *r else {
        panic!("{name}: expected a pole, got {r:?}");
    };
    assert_eq!(cause, Singularity::Pole(TAN), "{name}");
    assert!(x.iter().all(|v| v.is_finite()), "{name}: {x}");
    assert!(
        t < FRAC_PI_2 && x[0] < FRAC_PI_2,
        "{name}: t = {t}, θ = {}",
        x[0]
    );
    assert!(t > 1.2, "{name}: t = {t}");
    let last = ends.last().expect("t0 at least");
    assert_eq!((t, x), *last, "{name}: not the last accepted state");
    println!(
        "{name}: pole after t = {t:.6} (π/2 − t = {:.1e})",
        FRAC_PI_2 - t
    );
}

#[test]
fn a_step_across_a_pole_ends_every_integrator_with_the_last_good_state() {
    let runs = every_integrator(&Tangent, 0.0, Vector2::zeros(), 3.0);
    assert_eq!(runs.len(), 13);
    for (name, r, ends) in &runs {
        assert_pole(name, r, ends);
    }
    // The message names the expression.
    let err = runs[0].1.unwrap_err();
    assert!(err.to_string().contains("`tan(theta)`"), "{err}");
}

/// Smooth equations θ' = 1, v' = θ with a pole reported at θ = 1 (a
/// removable one, say): every integrator steps across it unhindered, so
/// the accepted step that crosses it ends the run (no failure to explain).
struct Removable;

const REMOVABLE: &str = "(theta - 1)/(theta - 1)";

impl OdeSystem<f64, 2> for Removable {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(1.0, x[0])
    }

    fn crossed_pole(
        &self,
        _t0: f64,
        x0: &Vector2<f64>,
        _t1: f64,
        x1: &Vector2<f64>,
    ) -> Option<&'static str> {
        ((x0[0] - 1.0) * (x1[0] - 1.0) <= 0.0).then_some(REMOVABLE)
    }
}

impl OdeJacobian<f64, 2> for Removable {
    fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(0.0, 0.0, 1.0, 0.0)
    }
}

#[test]
fn the_accepted_step_across_a_pole_ends_every_integrator() {
    for (name, r, ends) in every_integrator(&Removable, 0.0, Vector2::zeros(), 3.0) {
        let Err(SimError::Singular { t, x, cause }) = r else {
            panic!("{name}: expected a pole, got {r:?}");
        };
        assert_eq!(cause, Singularity::Pole(REMOVABLE), "{name}");
        // (θ is the guard's variable; t may round to 1 on a fixed step.)
        assert!(x[0] < 1.0 && t <= 1.0, "{name}: t = {t}, θ = {}", x[0]);
        assert!(t > 0.0, "{name}: {t}");
        // The last good state is the last step end the same run accepted.
        assert_eq!((t, x), *ends.last().unwrap(), "{name}");
    }
}

#[test]
fn without_the_hook_the_pole_is_stepped_over_or_fails_otherwise() {
    // What the hook prevents: the unguarded equations either integrate
    // straight through θ = π/2 (ending Ok with a meaningless v) or fail
    // with another error; none of them reports the pole.
    let runs = every_integrator(&Unguarded, 0.0, Vector2::zeros(), 3.0);
    let through = runs.iter().filter(|(_, r, _)| r.is_ok()).count();
    for (name, r, _) in &runs {
        println!("{name} unguarded: {:?}", r.as_ref().map(|o| o.x));
        assert!(
            !matches!(
                r,
                Err(SimError::Singular {
                    cause: Singularity::Pole(_),
                    ..
                })
            ),
            "{name}: {r:?}"
        );
    }
    assert!(through > 0, "some integrator steps over the pole unguarded");
}

#[test]
fn away_from_the_pole_the_hook_changes_nothing() {
    let x0 = Vector2::new(-1.0, 0.0);
    let guarded = every_integrator(&Tangent, 0.0, x0, 2.2);
    let plain = every_integrator(&Unguarded, 0.0, x0, 2.2);
    for ((name, a, ends_a), (_, b, ends_b)) in guarded.iter().zip(&plain) {
        let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
        assert_eq!(a.x, b.x, "{name}");
        assert_eq!(a.stats, b.stats, "{name}");
        assert_eq!(ends_a, ends_b, "{name}");
        assert_eq!(a.t, 2.2);
        // v = ln cos(−1) − ln cos θ
        let exact = (-1.0f64).cos().ln() - 1.2f64.cos().ln();
        assert!(
            (a.x[1] - exact).abs() < 1e-3,
            "{name}: {} vs {exact}",
            a.x[1]
        );
    }
}

#[test]
fn a_tiny_span_across_the_pole_is_refused_too() {
    // A span below the resolution of t (one explicit Euler step) across
    // θ = π/2.
    let t0 = 1000.0;
    let x0 = Vector2::new(FRAC_PI_2 - 1e-13, 0.0);
    let t1 = t0 + 1e-12;
    let err = Dopri5::new(1e-8, 1e-10)
        .integrate(&Tangent, t0, x0, t1)
        .unwrap_err();
    assert_eq!(
        err,
        SimError::Singular {
            t: t0,
            x: x0,
            cause: Singularity::Pole(TAN)
        }
    );
    // Short of the pole, the same span is fine.
    let x0 = Vector2::new(FRAC_PI_2 - 1e-11, 0.0);
    let out = Dopri5::new(1e-8, 1e-10)
        .integrate(&Tangent, t0, x0, t1)
        .unwrap();
    assert_eq!((out.t, out.stats.steps), (t1, 1));
}

#[test]
fn a_terminal_event_before_the_pole_ends_the_run_at_the_event() {
    // θ = 1.55 < π/2: the event lies before the pole, in the step that
    // crosses it for the coarse fixed steps (the step [1.5, 1.75]).
    let events =
        Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 1.55)).terminal([true]);
    let x0 = Vector2::zeros();
    let check = |name: &str, r: Run| {
        let out = r.unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let hit = out.event.expect("the event");
        assert!((hit.t - 1.55).abs() < 1e-9, "{name}: {}", hit.t);
        assert_eq!((out.t, out.x), (hit.t, hit.x), "{name}");
        assert!(out.x[0] < FRAC_PI_2);
    };
    let on = |_: &_| {};
    check(
        "Rk4 coarse",
        Rk4::new(0.25).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "GaussLegendre4 coarse",
        GaussLegendre4::new(0.25).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Dopri5 fixed step",
        Dopri5::new(1e-8, 1e-10)
            .with_fixed_step(0.25)
            .integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Dopri5",
        Dopri5::new(1e-8, 1e-10).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Dop853",
        Dop853::new(1e-8, 1e-10).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Rodas4",
        Rodas4::new(1e-6, 1e-8)
            .integrate_with_jacobian_and_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Rodas5P",
        Rodas5P::new(1e-6, 1e-8).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "Bdf",
        Bdf::new(1e-7, 1e-9).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    check(
        "AutoSwitch",
        AutoSwitch::new(1e-8, 1e-10).integrate_with_events(&Tangent, 0.0, x0, 3.0, &events, on),
    );
    // The same coarse fixed step whose end lies across the pole, with the
    // event after the pole: the pole ends the run.
    let late = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 1.6)).terminal([true]);
    let err = Rk4::new(0.25)
        .integrate_with_events(&Tangent, 0.0, x0, 3.0, &late, on)
        .unwrap_err();
    assert_eq!(
        err,
        SimError::Singular {
            t: 1.5,
            x: Rk4::new(0.25).integrate(&Tangent, 0.0, x0, 1.5).unwrap().x,
            cause: Singularity::Pole(TAN)
        }
    );
}

/// The pole through the input adapter: v' = u tan θ.
struct SteeredTangent;

impl ControlledSystem<f64, 2, 1> for SteeredTangent {
    fn rhs_with_input(&self, _t: f64, x: &Vector2<f64>, u: &Vector1<f64>) -> Vector2<f64> {
        Vector2::new(1.0, u[0] * x[0].tan())
    }

    fn crossed_pole(
        &self,
        _t0: f64,
        x0: &Vector2<f64>,
        _t1: f64,
        x1: &Vector2<f64>,
    ) -> Option<&'static str> {
        crosses_tan(x0, x1)
    }
}

#[test]
fn the_input_adapter_forwards_the_pole() {
    let driven = Driven::new(&SteeredTangent, Vector1::new(2.0));
    assert_eq!(
        driven.crossed_pole(0.0, &Vector2::new(1.5, 0.0), 0.1, &Vector2::new(1.6, 0.0)),
        Some(TAN)
    );
    assert_eq!(
        driven.crossed_pole(0.0, &Vector2::new(1.4, 0.0), 0.1, &Vector2::new(1.5, 0.0)),
        None
    );
    let r = Dopri5::new(1e-8, 1e-10).integrate(&driven, 0.0, Vector2::zeros(), 3.0);
    let mut ends = vec![(0.0, Vector2::zeros())];
    Dopri5::new(1e-8, 1e-10)
        .integrate_with_steps(&driven, 0.0, Vector2::zeros(), 3.0, |s| {
            ends.push((s.t(), *s.x()))
        })
        .ok();
    assert_pole("Driven", &r, &ends);
}

/// θ' = 1, v' = p tan θ with the parameter p, for sensitivities.
struct ScaledTangent {
    p: f64,
}

impl OdeSystem<f64, 2> for ScaledTangent {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(1.0, self.p * x[0].tan())
    }

    fn crossed_pole(
        &self,
        _t0: f64,
        x0: &Vector2<f64>,
        _t1: f64,
        x1: &Vector2<f64>,
    ) -> Option<&'static str> {
        crosses_tan(x0, x1)
    }
}

impl OdeJacobian<f64, 2> for ScaledTangent {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        tangent_jacobian(x) * self.p
    }
}

impl ParameterJacobian<f64, 2, 1> for ScaledTangent {
    fn parameter_jacobian(&self, _t: f64, x: &Vector2<f64>) -> SMatrix<f64, 2, 1> {
        SMatrix::<f64, 2, 1>::new(0.0, x[0].tan())
    }
}

#[test]
fn the_sensitivities_forward_the_pole_of_the_state() {
    let sys = ScaledTangent { p: 1.0 };
    let sens = Sensitivities::<_, 2, 1, 8>::new(&sys);
    let a0 = sens.initial_state(&Vector2::zeros());
    // Only the state part counts: the sensitivities may be anything.
    let mut a1 = a0;
    a1[0] = 1.6;
    a1[5] = f64::MAX;
    assert_eq!(sens.crossed_pole(0.0, &a0, 1.6, &a1), Some(TAN));
    let err = Dopri5::new(1e-8, 1e-10)
        .integrate(&sens, 0.0, a0, 3.0)
        .unwrap_err();
    let SimError::Singular { t, x, cause } = err else {
        panic!("{err:?}");
    };
    assert_eq!(cause, Singularity::Pole(TAN));
    assert!(t < FRAC_PI_2 && x[0] < FRAC_PI_2, "{t}");
    assert!(x.iter().all(|v| v.is_finite()));
    let _: SVector<f64, 8> = x;
}
