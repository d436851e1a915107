//! Event location: the sign changes of a user function `g(t, x)`, found on
//! the dense output of the accepted steps ([`Events`], [`EventHit`],
//! [`Integrator::integrate_with_events`](crate::Integrator::integrate_with_events)).

use core::cmp::Ordering;

use nalgebra::{RealField, SVector};

use crate::numeric::{c, machine_epsilon};
use crate::sink::Sink;
use crate::{ChartSwitches, Direction, EventHit, Outcome, SimError, Stats, Step};

/// `N` event functions `g(t, x)`, evaluated together (one call returns all
/// `N` values), each with a [`Direction`] filter and a terminal flag.
///
/// Event `i` happens where `g(t, x(t))[i]` changes sign in the chosen
/// direction. The integrators look at the sign of `g` at the end of every
/// accepted step; a step across which it changes is interpolated by its
/// dense output ([`Step::interpolate`]) and the time of the zero is located
/// there by the Anderson–Björck method to within the time tolerance
/// ([`Events::with_tolerance`], default `4·eps·max(|t|, |h|)` for a step
/// `h`). A non-terminal event is reported and the run goes on; a terminal
/// one ends it there, at the located time with the dense output's state.
///
/// Two sign changes of the same `g_i` within one step cancel and go
/// unnoticed (cap the step with `with_max_step` if `g` oscillates faster
/// than the solution). A zero of `g_i` exactly at `t0` is not an event; nor
/// is a non-finite value of `g`.
///
/// # Non-finite values of `g`
///
/// * NaN has no sign. A NaN of `g_i` is never an event, but neither does it
///   hide one: the sign of `g_i` is compared between the last value that
///   had one and the next (across any number of steps whose ends gave
///   NaN), and a change is located in the step where `g_i` has a sign
///   again, on its dense output, where NaN counts as "not yet crossed".
///   The reported time is where `g_i` is first seen on the far side (or
///   zero): the end of the NaN window, or the zero after it, to within the
///   time tolerance.
/// * `±∞` have a sign, but a pole is not a root: a sign change located
///   where `g_i` is infinite, or towards which `|g_i|` grows on both sides
///   beyond its values at the ends of the bracket (`g = 1/(t − a)` at
///   `t = a`), is not an event, and the run goes on. A root next to a pole
///   is still found when it is the only sign change between two values of
///   `g_i` with a sign (a root and a pole within one step cancel like two
///   roots).
///
/// # Example
///
/// ```rust
/// use nalgebra::{Vector1, Vector2};
/// use nh_runtime::{Direction, Dopri5, Events, Integrator};
///
/// // A ball thrown up at 10 m/s: (height, velocity).
/// let ball = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -9.81);
/// // It lands (falling through height 0): terminal.
/// let landing = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]))
///     .direction([Direction::Falling])
///     .terminal([true]);
/// let out = Dopri5::new(1e-10, 1e-12)
///     .integrate_with_events(&ball, 0.0, Vector2::new(0.0, 10.0), 5.0, &landing, |_| {})
///     .unwrap();
/// let hit = out.event.expect("the ball lands");
/// assert_eq!((hit.index, hit.t), (0, out.t));
/// assert!((out.t - 20.0 / 9.81).abs() < 1e-12);
/// assert!(out.x[0].abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Events<T, G, const N: usize> {
    g: G,
    direction: [Direction; N],
    terminal: [bool; N],
    tolerance: Option<T>,
}

impl<T: RealField + Copy, G, const N: usize> Events<T, G, N> {
    /// The events `g(t, x) = 0` (all `N` at once): every direction, none
    /// terminal, the default time tolerance.
    pub fn new<const D: usize>(g: G) -> Self
    where
        G: Fn(T, &SVector<T, D>) -> SVector<T, N>,
    {
        Events {
            g,
            direction: [Direction::Either; N],
            terminal: [false; N],
            tolerance: None,
        }
    }

    /// The direction filter of each event.
    pub fn direction(mut self, direction: [Direction; N]) -> Self {
        self.direction = direction;
        self
    }

    /// Which events end the run.
    pub fn terminal(mut self, terminal: [bool; N]) -> Self {
        self.terminal = terminal;
        self
    }

    /// Locates the times of the events to within `tol` (a time, > 0)
    /// instead of the default `4·eps·max(|t|, |h|)` (a few ulps of `t` or
    /// of the step `h`). A non-positive or non-finite `tol` keeps the
    /// default.
    pub fn with_tolerance(mut self, tol: T) -> Self {
        self.tolerance = (tol.is_finite() && tol > T::zero()).then_some(tol);
        self
    }

    /// The event functions at `(t, x)`.
    pub fn values<const D: usize>(&self, t: T, x: &SVector<T, D>) -> SVector<T, N>
    where
        G: Fn(T, &SVector<T, D>) -> SVector<T, N>,
    {
        (self.g)(t, x)
    }
}

/// The events' view of a run: `g` at the last accepted point, the
/// candidate step end, the count of evaluations.
pub(crate) struct Tracker<'e, T, G, F, const D: usize, const N: usize> {
    events: &'e Events<T, G, N>,
    on_event: F,
    /// `g` at the last accepted point (`None` before the first step).
    g_prev: Option<SVector<T, N>>,
    /// The last value of each `g_i` with a sign (not NaN) at an accepted
    /// point (NaN while there has been none: `g` at `t0`). Crossings are
    /// sign changes from these.
    g_signed: SVector<T, N>,
    /// `g` at the end of the trial the driver asked about.
    candidate: Option<(T, SVector<T, D>, SVector<T, N>)>,
    /// Evaluations of `g`.
    pub(crate) evals: usize,
}

impl<'e, T, G, F, const D: usize, const N: usize> Tracker<'e, T, G, F, D, N>
where
    T: RealField + Copy,
    G: Fn(T, &SVector<T, D>) -> SVector<T, N>,
    F: FnMut(&EventHit<T, D>),
{
    pub(crate) fn new(events: &'e Events<T, G, N>, on_event: F) -> Self {
        Tracker {
            events,
            on_event,
            g_prev: None,
            g_signed: SVector::zeros(),
            candidate: None,
            evals: 0,
        }
    }

    fn g(&mut self, t: T, x: &SVector<T, D>) -> SVector<T, N> {
        self.evals += 1;
        (self.events.g)(t, x)
    }

    /// `g` at the start of a step from `(t, x)` (evaluated once, at `t0`).
    fn start(&mut self, t: T, x: &SVector<T, D>) -> SVector<T, N> {
        match self.g_prev {
            Some(g) => g,
            None => {
                let g = self.g(t, x);
                self.g_prev = Some(g);
                self.g_signed = g;
                g
            }
        }
    }

    /// Whether a step `(t_prev, x_prev) → (t, x_new)` has a sign change of
    /// some `g_i` in its direction; `g` at the end is kept for
    /// [`Tracker::step`].
    pub(crate) fn crosses(
        &mut self,
        (t_prev, x_prev): (T, &SVector<T, D>),
        (t, x_new): (T, &SVector<T, D>),
    ) -> bool {
        self.start(t_prev, x_prev);
        let g_new = self.g(t, x_new);
        self.candidate = Some((t, *x_new, g_new));
        self.any_crossing(&g_new)
    }

    /// Whether some `g_i` changed sign, in its direction, from its last
    /// value with a sign to `g_new`.
    fn any_crossing(&self, g_new: &SVector<T, N>) -> bool {
        (0..N).any(|i| self.events.direction[i].crossed(self.g_signed[i], g_new[i]))
    }

    /// `g` at the end of an accepted step: the value kept by
    /// [`Tracker::crosses`] if the end is the same point.
    fn at_end(&mut self, step: &Step<'_, T, D>) -> SVector<T, N> {
        match self.candidate.take() {
            Some((t, x, g)) if t == step.t() && x == *step.x() => g,
            _ => self.g(step.t(), step.x()),
        }
    }

    /// Reports the events inside an accepted step, in time order, up to and
    /// including the first terminal one, which it returns.
    pub(crate) fn step(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        let g_prev = self.start(step.t_prev(), step.x_prev());
        let g_new = self.at_end(step);
        let found = if self.any_crossing(&g_new) {
            Some(self.locate_all(step, &g_prev, &g_new))
        } else {
            None
        };
        self.g_prev = Some(g_new);
        for (signed, &g) in self.g_signed.iter_mut().zip(g_new.iter()) {
            if has_sign(g) {
                *signed = g;
            }
        }
        self.report(step, &found?)
    }

    /// A step that the driver could not accept (its end could not be
    /// settled): if a terminal event lies inside, reports the events up to
    /// it and returns it; otherwise reports nothing.
    pub(crate) fn salvage(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        let g_prev = self.start(step.t_prev(), step.x_prev());
        let g_new = self.at_end(step);
        if !self.any_crossing(&g_new) {
            return None;
        }
        let found = self.locate_all(step, &g_prev, &g_new);
        let terminal = |&(_, i, _): &(T, usize, Direction)| self.events.terminal[i];
        if found.iter().flatten().any(terminal) {
            self.report(step, &found)
        } else {
            None
        }
    }

    /// The located crossings `(t, index, direction)` (poles left out),
    /// sorted in the direction of integration (ties by index); `None`
    /// entries last.
    fn locate_all(
        &mut self,
        step: &Step<'_, T, D>,
        g_prev: &SVector<T, N>,
        g_new: &SVector<T, N>,
    ) -> [Option<Crossing<T>>; N] {
        let mut found = [None; N];
        for (i, slot) in found.iter_mut().enumerate() {
            let side = self.g_signed[i];
            if self.events.direction[i].crossed(side, g_new[i]) {
                let way = if side < T::zero() {
                    Direction::Rising
                } else {
                    Direction::Falling
                };
                *slot = self
                    .locate(step, i, (g_prev[i], side), g_new[i])
                    .map(|t| (t, i, way));
            }
        }
        let dir = if step.h() < T::zero() {
            -T::one()
        } else {
            T::one()
        };
        let key = |e: &Option<Crossing<T>>| e.map(|(t, i, _)| (t * dir, i));
        found.sort_unstable_by(|a, b| match (key(a), key(b)) {
            (Some((ta, ia)), Some((tb, ib))) => ta
                .partial_cmp(&tb)
                .unwrap_or(Ordering::Equal)
                .then(ia.cmp(&ib)),
            (Some(_), None) => Ordering::Less,
            (None, Some(_)) => Ordering::Greater,
            (None, None) => Ordering::Equal,
        });
        found
    }

    /// Calls back the located events in order, up to and including the
    /// first terminal one, which is returned.
    fn report(
        &mut self,
        step: &Step<'_, T, D>,
        found: &[Option<Crossing<T>>; N],
    ) -> Option<EventHit<T, D>> {
        for &(t, index, direction) in found.iter().flatten() {
            let hit = EventHit {
                index,
                t,
                x: step.interpolate(t),
                direction,
                terminal: self.events.terminal[index],
            };
            (self.on_event)(&hit);
            if hit.terminal {
                return Some(hit);
            }
        }
        None
    }

    /// The time where `g_i` crosses zero inside `step`, from the value
    /// `g0` at its start (NaN, or the last value with a sign, `side`) to
    /// `g1` at its end (zero or of the other sign), by the Anderson–Björck
    /// method on the dense output: the end of the final bracket on the far
    /// side of the zero (where `g_i` has crossed, or is zero), within the
    /// time tolerance of the zero. NaN counts as "not yet crossed", so a
    /// sign change across NaN is placed where `g_i` is first seen on the
    /// far side; a trial point or end with a non-finite value is bisected
    /// away from. `None` when the sign change is a pole, not a root: `g_i`
    /// is infinite at the final bracket, or its magnitude there exceeds its
    /// magnitudes at the ends of the first bracket on both sides.
    fn locate(&mut self, step: &Step<'_, T, D>, i: usize, (g0, side): (T, T), g1: T) -> Option<T> {
        let h = step.h();
        let tol = self.events.tolerance.unwrap_or_else(|| {
            let scale = step.t_prev().abs().max(step.t().abs()).max(h.abs());
            c::<T>(4.0) * machine_epsilon::<T>() * scale
        });
        // Whether `g_i` has crossed at the value `v` (false for NaN).
        let rising = side < T::zero();
        let past = |v: T| {
            if rising {
                v >= T::zero()
            } else {
                v <= T::zero()
            }
        };
        // The bracket: `(b, fb)` the latest point, `(a, fa)` the end kept
        // (`fa` scaled by Anderson–Björck, `ga` its value); one of them has
        // crossed, the other not.
        let (mut a, mut fa, mut ga) = (step.t_prev(), g0, g0);
        let (mut b, mut fb) = (step.t(), g1);
        let (mut slow, mut kept) = (0, 0);
        for _ in 0..MAX_ITERATIONS {
            let width = (b - a).abs();
            if fb == T::zero() || width <= tol {
                break;
            }
            let secant = b - fb * (b - a) / (fb - fa);
            let (lo, hi) = (a.min(b), a.max(b));
            let inside = secant >= lo && secant <= hi;
            let finite = fa.is_finite() && fb.is_finite();
            let t = if slow >= SLOW || !inside || !finite {
                (a + b) * c(0.5)
            } else {
                secant
            };
            // At least half the tolerance from either end, so that the
            // bracket closes on the zero from both sides.
            let least = tol * c(0.5);
            let t = t.max(lo + least).min(hi - least);
            if t == a || t == b {
                break; // the bracket is down to adjacent numbers
            }
            let v = self.g(t, &step.interpolate(t))[i];
            if past(v) == past(fb) {
                // `a` stays: Anderson–Björck's factor shrinks its value,
                // halved (Illinois) when `a` stays again, so that the
                // iterates soon land on its side too.
                kept += 1;
                let m = T::one() - v / fb;
                fa *= if m > T::zero() && kept < 2 { m } else { c(0.5) };
            } else {
                kept = 0;
                (a, fa, ga) = (b, fb, fb);
            }
            (b, fb) = (t, v);
            slow = if (b - a).abs() > width * c(0.5) {
                slow + 1
            } else {
                0
            };
        }
        let ((t_far, g_far), g_near) = if past(fb) {
            ((b, fb), ga)
        } else {
            ((a, ga), fb)
        };
        let pole = has_sign(g_near)
            && (!g_near.is_finite()
                || !g_far.is_finite()
                || (g_near.abs() > side.abs() && g_far.abs() > g1.abs()));
        (!pole).then_some(t_far)
    }
}

/// Whether `v` has a sign (is not NaN).
fn has_sign<T: RealField + Copy>(v: T) -> bool {
    v.partial_cmp(&T::zero()).is_some()
}

/// A located crossing: its time, its event, the way it went.
type Crossing<T> = (T, usize, Direction);

/// Consecutive iterations that do not halve the bracket before the root
/// finder bisects it.
const SLOW: usize = 4;

/// Iterations of the root finder per event (bisection alone would reach
/// the resolution of `f64` in about 60).
const MAX_ITERATIONS: usize = 200;

/// The events as a consumer of the driver's steps: the dense output of a
/// trial is built only when some `g_i` changes sign across it.
impl<T, G, F, const D: usize, const N: usize> Sink<T, D> for Tracker<'_, T, G, F, D, N>
where
    T: RealField + Copy,
    G: Fn(T, &SVector<T, D>) -> SVector<T, N>,
    F: FnMut(&EventHit<T, D>),
{
    fn wants_dense_at(&mut self, prev: (T, &SVector<T, D>), end: (T, &SVector<T, D>)) -> bool {
        self.crosses(prev, end)
    }

    fn step(&mut self, step: &Step<'_, T, D>) {
        Tracker::step(self, step);
    }

    fn step_or_stop(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        Tracker::step(self, step)
    }

    fn salvage(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        Tracker::salvage(self, step)
    }
}

/// The result of a run with events: the evaluations of `g` counted in the
/// outcome and in the integrator's record of the call.
pub(crate) fn counted<T, const D: usize>(
    result: Result<Outcome<T, D>, SimError<T, D>>,
    evals: usize,
    record: &mut Stats,
) -> Result<Outcome<T, D>, SimError<T, D>> {
    record.event_evals = evals;
    result.map(|mut out| {
        out.stats.event_evals = evals;
        out
    })
}

/// The default [`Integrator::integrate_with_events`](crate::Integrator::integrate_with_events)
/// of an integrator that only has `integrate_with_steps`: the result of a
/// run to `t1` whose steps went through the events until a terminal one,
/// which then ends it (a failure after the event does not count; the work
/// counters are then those of the run, zero if it failed).
pub(crate) fn after_the_fact<T: RealField + Copy, const D: usize>(
    result: Result<Outcome<T, D>, SimError<T, D>>,
    hit: Option<EventHit<T, D>>,
    evals: usize,
) -> Result<Outcome<T, D>, SimError<T, D>> {
    let out = match (result, hit) {
        (Ok(out), Some(hit)) => Ok(Outcome {
            t: hit.t,
            x: hit.x,
            event: Some(hit),
            ..out
        }),
        (Err(_), Some(hit)) => Ok(Outcome {
            t: hit.t,
            x: hit.x,
            stats: Stats::default(),
            max_residual: None,
            event: Some(hit),
            switches: ChartSwitches::new(),
        }),
        (result, None) => result,
    };
    counted(out, evals, &mut Stats::default())
}
