//! Event location against closed forms: a ball thrown up,
//! `x(t) = v t − g t²/2`, crossing heights at known times (every
//! integrator, to 1e-12), the direction filter, several events in one step,
//! non-terminal events in order, no event at `t0`, the terminal state equal
//! to the dense output, backwards integration, the default body of the
//! trait, and a terminal event before a chart singularity.
mod common;

use common::Oscillator;
use nalgebra::{SVector, Vector1, Vector2, Vector3};
use nh_runtime::{
    Direction, Dop853, Dopri5, EventHit, Events, GaussLegendre4, Integrator, OdeSystem, Outcome,
    ProjectionFailure, Rk4, Rodas4, SimError, Step,
};

const G: f64 = 9.81;
const V: f64 = 10.0;

/// `(height, velocity)` of a ball under gravity.
fn ball(_t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(x[1], -G)
}

/// The times the ball thrown up at `V` from 0 passes height `h`: up, down.
fn passes(h: f64) -> (f64, f64) {
    let root = (V * V - 2.0 * G * h).sqrt();
    ((V - root) / G, (V + root) / G)
}

/// Runs `integrator` with `events`, collecting every hit.
fn hits<I, E, const N: usize>(
    integrator: &mut I,
    (t0, x0, t1): (f64, Vector2<f64>, f64),
    events: &Events<f64, E, N>,
) -> (Outcome<f64, 2>, Vec<EventHit<f64, 2>>)
where
    I: Integrator<f64>,
    E: Fn(f64, &Vector2<f64>) -> SVector<f64, N>,
{
    let mut seen = Vec::new();
    let out = integrator
        .integrate_with_events(&ball, t0, x0, t1, events, |h| seen.push(*h))
        .expect("the ball integrates");
    (out, seen)
}

/// Every integrator of the crate, at settings where the ball is exact to
/// rounding (its solution is a quadratic, which every method and dense
/// output here reproduces).
fn each(mut f: impl FnMut(&str, &mut dyn FnMut(&Events3) -> Run)) {
    let span = (0.0, Vector2::new(0.0, V), 2.5);
    f("Rk4", &mut |e| hits(&mut Rk4::new(0.1), span, e));
    f("Dopri5", &mut |e| {
        hits(&mut Dopri5::new(1e-8, 1e-10), span, e)
    });
    f("Dop853", &mut |e| {
        hits(&mut Dop853::new(1e-8, 1e-10), span, e)
    });
    f("Rodas4", &mut |e| {
        hits(&mut Rodas4::new(1e-8, 1e-10), span, e)
    });
    f("GaussLegendre4", &mut |e| {
        hits(&mut GaussLegendre4::new(0.1), span, e)
    });
}

type Events3 = Events<f64, fn(f64, &Vector2<f64>) -> Vector3<f64>, 3>;
type Run = (Outcome<f64, 2>, Vec<EventHit<f64, 2>>);

/// Heights 3, 1 and 2 (in that order of the indices).
fn heights(_t: f64, x: &Vector2<f64>) -> Vector3<f64> {
    Vector3::new(x[0] - 3.0, x[0] - 1.0, x[0] - 2.0)
}

#[test]
fn crossings_of_a_height_are_located_to_1e_12_with_every_integrator() {
    let events: Events3 = Events::new(heights as fn(_, &_) -> _);
    each(|name, run| {
        let (out, seen) = run(&events);
        assert_eq!(out.t, 2.5, "{name}: no terminal event, the run ends at t1");
        assert!(out.event.is_none());
        // Up through 1, 2, 3, then down through 3, 2, 1.
        let order: Vec<usize> = seen.iter().map(|h| h.index).collect();
        assert_eq!(order, [1, 2, 0, 0, 2, 1], "{name}");
        let mut worst = 0.0_f64;
        for hit in &seen {
            let height = [3.0, 1.0, 2.0][hit.index];
            let (up, down) = passes(height);
            let (want, way) = if hit.t < V / G {
                (up, Direction::Rising)
            } else {
                (down, Direction::Falling)
            };
            assert_eq!(hit.direction, way, "{name}");
            assert!(!hit.terminal);
            worst = worst.max((hit.t - want).abs());
            assert!((hit.x[0] - height).abs() < 1e-12, "{name}: {}", hit.x[0]);
            assert!((hit.x[1] - (V - G * want)).abs() < 1e-12, "{name}");
        }
        eprintln!(
            "{name}: 6 crossings, worst time error {worst:.1e}; {} steps, {} evaluations of g",
            out.stats.steps, out.stats.event_evals
        );
        assert!(worst <= 1e-12, "{name}: {worst:e}");
    });
}

#[test]
fn the_direction_filter_keeps_the_chosen_crossings() {
    for (way, want) in [
        (Direction::Rising, passes(2.0).0),
        (Direction::Falling, passes(2.0).1),
    ] {
        let events =
            Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 2.0)).direction([way]);
        let span = (0.0, Vector2::new(0.0, V), 2.5);
        let (_, seen) = hits(&mut Dopri5::new(1e-8, 1e-10), span, &events);
        assert_eq!(seen.len(), 1, "{way:?}");
        assert_eq!(seen[0].direction, way);
        assert!((seen[0].t - want).abs() <= 1e-12, "{way:?}");
    }
}

#[test]
fn several_events_in_one_step_come_in_time_order() {
    // One Rk4 step over [0, 1] crosses the heights 1, 2 and 3 on the way up.
    let events: Events3 = Events::new(heights as fn(_, &_) -> _);
    let (out, seen) = hits(
        &mut Rk4::new(1.0),
        (0.0, Vector2::new(0.0, V), 1.0),
        &events,
    );
    assert_eq!(out.stats.steps, 1);
    let order: Vec<usize> = seen.iter().map(|h| h.index).collect();
    assert_eq!(order, [1, 2, 0]);
    for hit in &seen {
        let want = passes([3.0, 1.0, 2.0][hit.index]).0;
        assert!((hit.t - want).abs() <= 1e-12, "{}: {}", hit.index, hit.t);
    }
    // A terminal event in the middle of the step ends it there: the
    // earlier event is reported, the later one is not.
    let events: Events3 = Events::new(heights as fn(_, &_) -> _).terminal([false, false, true]);
    let (out, seen) = hits(
        &mut Rk4::new(1.0),
        (0.0, Vector2::new(0.0, V), 1.0),
        &events,
    );
    let order: Vec<usize> = seen.iter().map(|h| h.index).collect();
    assert_eq!(order, [1, 2]);
    assert_eq!(out.event, Some(seen[1]));
    assert_eq!(out.t, seen[1].t);
    assert!((out.t - passes(2.0).0).abs() <= 1e-12);
}

#[test]
fn non_terminal_zeros_of_the_oscillator_are_all_reported_in_order() {
    let zero = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]));
    let mut seen: Vec<EventHit<f64, 2>> = Vec::new();
    let x0 = Vector2::new(1.0, 0.0);
    let out = Dopri5::new(1e-11, 1e-13)
        .integrate_with_events(&Oscillator, 0.0, x0, 20.0, &zero, |h| seen.push(*h))
        .unwrap();
    assert_eq!(out.t, 20.0);
    assert_eq!(seen.len(), 6);
    for (k, hit) in seen.iter().enumerate() {
        let want = (k as f64 + 0.5) * std::f64::consts::PI;
        assert!((hit.t - want).abs() < 1e-9, "zero {k}: {} vs {want}", hit.t);
        let way = if k % 2 == 0 {
            Direction::Falling
        } else {
            Direction::Rising
        };
        assert_eq!(hit.direction, way);
    }
}

#[test]
fn a_zero_at_t0_is_not_an_event() {
    // The ball starts on the ground: g = height is 0 at t0; only the
    // landing counts.
    let ground = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]));
    let span = (0.0, Vector2::new(0.0, V), 2.5);
    let (_, seen) = hits(&mut Dop853::new(1e-8, 1e-10), span, &ground);
    assert_eq!(seen.len(), 1);
    assert!((seen[0].t - 2.0 * V / G).abs() <= 1e-12);
    assert_eq!(seen[0].direction, Direction::Falling);
}

#[test]
fn the_terminal_state_is_the_dense_output_there() {
    let half = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 0.5))
        .direction([Direction::Falling])
        .terminal([true]);
    let x0 = Vector2::new(1.0, 0.0);
    let make = || Dop853::new(1e-6, 1e-9);
    let out = make()
        .integrate_with_events(&Oscillator, 0.0, x0, 5.0, &half, |_| {})
        .unwrap();
    let hit = out.event.expect("a terminal event");
    let error = (out.t - std::f64::consts::FRAC_PI_3).abs();
    assert!(error < 1e-5, "{error:e}");
    assert_eq!((hit.t, hit.x), (out.t, out.x));
    // The same steps without events: the one containing the event's time
    // interpolates to exactly the event's state.
    let mut at_event = None;
    make()
        .integrate_with_steps(&Oscillator, 0.0, x0, 5.0, |s: &Step<'_, f64, 2>| {
            if at_event.is_none() && s.t() >= out.t {
                at_event = Some(s.interpolate(out.t));
            }
        })
        .unwrap();
    assert_eq!(at_event, Some(out.x));
    // g is past zero (or zero) at the reported state.
    assert!(out.x[0] - 0.5 <= 0.0);
}

#[test]
fn events_do_not_change_the_steps_and_need_dense_output_only_across_a_sign_change() {
    // Dop853 builds its dense output (3 more right-hand sides) only for
    // steps that are interpolated: an event that never happens costs no
    // right-hand side, only evaluations of g.
    let never = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 5.0));
    let once = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 0.5));
    let x0 = Vector2::new(1.0, 0.0);
    let plain = Dop853::new(1e-8, 1e-10)
        .integrate(&Oscillator, 0.0, x0, 1.5)
        .unwrap();
    fn with<E: Fn(f64, &Vector2<f64>) -> Vector1<f64>>(e: &Events<f64, E, 1>) -> Outcome<f64, 2> {
        Dop853::new(1e-8, 1e-10)
            .integrate_with_events(&Oscillator, 0.0, Vector2::new(1.0, 0.0), 1.5, e, |_| {})
            .unwrap()
    }
    let (quiet, crossing) = (with(&never), with(&once));
    for out in [quiet, crossing] {
        assert_eq!((out.t, out.x), (plain.t, plain.x));
        assert_eq!(out.stats.steps, plain.stats.steps);
    }
    assert_eq!(quiet.stats.rhs_evals, plain.stats.rhs_evals);
    assert_eq!(quiet.stats.event_evals, plain.stats.steps + 1);
    assert_eq!(crossing.stats.rhs_evals, plain.stats.rhs_evals + 3);
    let search = crossing.stats.event_evals - (plain.stats.steps + 1);
    eprintln!(
        "Dop853, one crossing: {} steps, {search} evaluations of g to locate it",
        plain.stats.steps
    );
    assert!(search <= 12, "{search}");
    assert_eq!(plain.stats.event_evals, 0);
}

#[test]
fn a_looser_tolerance_takes_fewer_evaluations() {
    let make = |tol: Option<f64>| {
        let e = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new((x[0] / 4.0).sin() - 0.5));
        match tol {
            Some(tol) => e.with_tolerance(tol),
            None => e,
        }
    };
    let span = (0.0, Vector2::new(0.0, V), 1.0);
    let (tight, seen_tight) = hits(&mut Rk4::new(0.5), span, &make(None));
    let (loose, seen_loose) = hits(&mut Rk4::new(0.5), span, &make(Some(1e-3)));
    // sin(x/4) = 1/2 at x = 2π/3.
    let want = {
        let h = 4.0 * std::f64::consts::FRAC_PI_6;
        (V - (V * V - 2.0 * G * h).sqrt()) / G
    };
    assert!((seen_tight[0].t - want).abs() <= 1e-14);
    assert!((seen_loose[0].t - want).abs() <= 1e-3);
    assert!(loose.stats.event_evals < tight.stats.event_evals);
}

#[test]
fn backwards_the_crossings_come_in_the_order_of_integration() {
    // From the landing back to the throw: down through 2 m first, which is
    // g = x − 2 rising as t decreases, then up through 2 m.
    let events = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0] - 2.0));
    let t_land = 2.0 * V / G;
    let span = (t_land, Vector2::new(0.0, -V), 0.0);
    let (out, seen) = hits(&mut Dopri5::new(1e-8, 1e-10), span, &events);
    assert_eq!(out.t, 0.0);
    let (up, down) = passes(2.0);
    assert_eq!(seen.len(), 2);
    assert!((seen[0].t - down).abs() <= 1e-12);
    assert_eq!(seen[0].direction, Direction::Rising);
    assert!((seen[1].t - up).abs() <= 1e-12);
    assert_eq!(seen[1].direction, Direction::Falling);
    // A terminal one stops the backward run there.
    let stop = events.terminal([true]);
    let (out, _) = hits(&mut GaussLegendre4::new(0.1), span, &stop);
    assert!((out.t - down).abs() <= 1e-12);
}

/// An integrator from outside the crate: only `integrate_with_steps`.
struct Outside(Dopri5<f64>);

impl Integrator<f64> for Outside {
    fn integrate_with_steps<S, F, const D: usize>(
        &mut self,
        sys: &S,
        t0: f64,
        x0: SVector<f64, D>,
        t1: f64,
        on_step: F,
    ) -> Result<Outcome<f64, D>, SimError<f64, D>>
    where
        S: OdeSystem<f64, D> + ?Sized,
        F: FnMut(&Step<'_, f64, D>),
    {
        self.0.integrate_with_steps(sys, t0, x0, t1, on_step)
    }
}

#[test]
fn the_default_body_finds_the_same_terminal_event() {
    let landing = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]))
        .direction([Direction::Falling])
        .terminal([true]);
    let span = (0.0, Vector2::new(0.0, V), 5.0);
    let (own, _) = hits(&mut Dopri5::new(1e-8, 1e-10), span, &landing);
    let (outside, seen) = hits(&mut Outside(Dopri5::new(1e-8, 1e-10)), span, &landing);
    assert_eq!(seen.len(), 1);
    assert_eq!((outside.t, outside.x), (own.t, own.x));
    assert_eq!(outside.event, own.event);
    assert!((own.t - 2.0 * V / G).abs() <= 1e-12);
}

/// `x' = 1` on a chart that is singular at `x = 1` (and flips beyond).
struct Chart;

impl OdeSystem<f64, 1> for Chart {
    fn rhs(&self, _t: f64, _x: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(1.0)
    }

    fn chart_regularity(&self, _t: f64, x: &Vector1<f64>) -> Option<f64> {
        Some(1.0 - x[0])
    }
}

#[test]
fn a_terminal_event_before_a_chart_singularity_ends_the_run_there() {
    let near = |terminal| {
        Events::new(|_t: f64, x: &Vector1<f64>| Vector1::new(x[0] - 0.999)).terminal([terminal])
    };
    let run = |e: &Events<f64, _, 1>| {
        Dopri5::new(1e-8, 1e-10).integrate_with_events(
            &Chart,
            0.0,
            Vector1::new(0.0),
            2.0,
            e,
            |_| {},
        )
    };
    // One step from 0 to 2 ends across the singularity.
    let out = run(&near(true)).expect("the event ends the run first");
    assert!((out.t - 0.999).abs() <= 1e-12, "{}", out.t);
    assert_eq!(out.event.map(|h| h.index), Some(0));
    // Without a terminal event the run ends at the singularity, typed.
    let err = run(&near(false)).unwrap_err();
    assert!(matches!(err, SimError::Singular { .. }), "{err}");
}

/// Rotation on the unit circle, projected back onto it after every step.
struct Circle;

impl OdeSystem<f64, 2> for Circle {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(-x[1], x[0])
    }

    fn constraint_residual(&self, _t: f64, x: &Vector2<f64>) -> Option<f64> {
        Some((x.norm() - 1.0).abs())
    }

    fn project(&self, _t: f64, x: &mut Vector2<f64>) -> Result<bool, ProjectionFailure<f64>> {
        let projected = *x / x.norm();
        let moved = projected != *x;
        *x = projected;
        Ok(moved)
    }
}

#[test]
fn with_projection_events_are_located_on_the_dense_output_of_the_step() {
    // (cos t, sin t) passes y = 1/2 at π/6 and 5π/6.
    let half = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[1] - 0.5));
    let mut seen = Vec::new();
    let out = Dopri5::new(1e-10, 1e-12)
        .integrate_with_events(&Circle, 0.0, Vector2::new(1.0, 0.0), 3.0, &half, |h| {
            seen.push(*h)
        })
        .unwrap();
    assert!(out.max_residual.unwrap() <= 2.0 * f64::EPSILON);
    let pi = std::f64::consts::PI;
    assert_eq!(seen.len(), 2);
    for (hit, want) in seen.iter().zip([pi / 6.0, 5.0 * pi / 6.0]) {
        assert!((hit.t - want).abs() < 1e-9, "{} vs {want}", hit.t);
        assert!((hit.x[1] - 0.5).abs() < 1e-14);
    }
    // g at the end of a step whose state the projection moved is
    // evaluated again there: at most two evaluations per step besides the
    // search.
    assert!(out.stats.event_evals <= 2 * out.stats.steps + 1 + 2 * 12);
}

/// The ball with its (constant) Jacobian.
struct Ball;

impl OdeSystem<f64, 2> for Ball {
    fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        ball(t, x)
    }
}

impl nh_runtime::OdeJacobian<f64, 2> for Ball {
    fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(0.0, 1.0, 0.0, 0.0)
    }
}

#[test]
fn the_implicit_methods_locate_events_with_the_analytic_jacobian_too() {
    let landing = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]))
        .direction([Direction::Falling])
        .terminal([true]);
    let x0 = Vector2::new(0.0, V);
    let want = 2.0 * V / G;
    let ros = Rodas4::new(1e-8, 1e-10)
        .integrate_with_jacobian_and_events(&Ball, 0.0, x0, 5.0, &landing, |_| {})
        .unwrap();
    let gauss = GaussLegendre4::new(0.1)
        .integrate_with_jacobian_and_events(&Ball, 0.0, x0, 5.0, &landing, |_| {})
        .unwrap();
    for out in [ros, gauss] {
        assert!((out.t - want).abs() <= 1e-12, "{}", out.t);
        assert_eq!(out.event.map(|h| h.index), Some(0));
        assert!(out.stats.jacobian_evals > 0 && out.stats.event_evals > 0);
    }
}

#[test]
fn events_work_in_single_precision() {
    let ball32 = |_t: f32, x: &Vector2<f32>| Vector2::new(x[1], -9.81);
    let landing = Events::new(|_t: f32, x: &Vector2<f32>| Vector1::new(x[0])).terminal([true]);
    let out = Dopri5::new(1e-5f32, 1e-7)
        .integrate_with_events(&ball32, 0.0, Vector2::new(0.0, 10.0), 5.0, &landing, |_| {})
        .unwrap();
    // 20/9.81 to the resolution of f32.
    assert!(
        (out.t - 20.0 / 9.81).abs() <= 4.0 * f32::EPSILON * 2.1,
        "{}",
        out.t
    );
}
