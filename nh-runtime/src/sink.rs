//! Where accepted steps go: nowhere, an observer, requested output times,
//! a step callback or the events (`events::Tracker`). Each consumer is
//! written once and used both by the integrators of this crate (through the
//! step driver) and by the default methods of [`Integrator`](crate::Integrator).

use nalgebra::{RealField, SVector};

use crate::checks::check_arguments;
use crate::{EventHit, Outcome, SimError, Step};

/// A consumer of accepted steps.
pub(crate) trait Sink<T, const D: usize> {
    /// Whether the step from `t_prev` to `t` will be interpolated inside
    /// (then the driver builds, and checks, its dense output before
    /// accepting it).
    fn wants_dense(&self, _t_prev: T, _t: T) -> bool {
        false
    }

    /// Whether the trial step from `(t_prev, x_prev)` to `(t, x_new)` (its
    /// end before projection) will be interpolated: [`Sink::wants_dense`]
    /// unless the sink needs to see the end (events look at the sign of
    /// their functions there).
    fn wants_dense_at(&mut self, prev: (T, &SVector<T, D>), end: (T, &SVector<T, D>)) -> bool {
        self.wants_dense(prev.0, end.0)
    }

    /// One accepted step.
    fn step(&mut self, step: &Step<'_, T, D>);

    /// One accepted step; `Some` when a terminal event inside it ends the
    /// run there (the driver then stops at the event's time and state).
    fn step_or_stop(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        self.step(step);
        None
    }

    /// A completed trial, with its dense output, whose end the driver
    /// could not accept (its projection failed, or it lies across a
    /// singularity of the chart): `Some` when a terminal event inside it
    /// ends the run before that end, `None` (the default) to let the run
    /// fail.
    fn salvage(&mut self, _step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        None
    }

    /// After an accepted step has been handed over, moves its end `x` to
    /// the centre of its chart where the run is in a free rotation's
    /// canonical coordinates (DESIGN §9.4): `true` if it moved, and the
    /// method then restarts there. `false` (the default) elsewhere.
    fn recentre(&mut self, _x: &mut SVector<T, D>) -> bool {
        false
    }
}

/// Discards every step.
pub(crate) struct Discard;

impl<T, const D: usize> Sink<T, D> for Discard {
    fn step(&mut self, _step: &Step<'_, T, D>) {}
}

/// Hands every step, with its dense output, to a callback.
pub(crate) struct Steps<F>(pub(crate) F);

impl<T, F, const D: usize> Sink<T, D> for Steps<F>
where
    F: FnMut(&Step<'_, T, D>),
{
    fn wants_dense(&self, _t_prev: T, _t: T) -> bool {
        true
    }

    fn step(&mut self, step: &Step<'_, T, D>) {
        (self.0)(step)
    }
}

/// Calls an observer at `t0` (before the first step) and at every step end.
struct Observer<T, const D: usize, F> {
    t0: T,
    x0: SVector<T, D>,
    started: bool,
    observer: F,
}

impl<T, const D: usize, F> Sink<T, D> for Observer<T, D, F>
where
    T: RealField + Copy,
    F: FnMut(T, &SVector<T, D>),
{
    fn step(&mut self, step: &Step<'_, T, D>) {
        if !self.started {
            self.started = true;
            (self.observer)(self.t0, &self.x0);
        }
        (self.observer)(step.t(), step.x());
    }
}

/// The observer protocol of
/// [`Integrator::integrate_with_observer`](crate::Integrator::integrate_with_observer)
/// around `run`, which integrates and feeds the given sink.
pub(crate) fn observe<T, F, const D: usize>(
    t0: T,
    x0: SVector<T, D>,
    observer: F,
    run: impl FnOnce(&mut dyn Sink<T, D>) -> Result<Outcome<T, D>, SimError<T, D>>,
) -> Result<Outcome<T, D>, SimError<T, D>>
where
    T: RealField + Copy,
    F: FnMut(T, &SVector<T, D>),
{
    let mut sink = Observer {
        t0,
        x0,
        started: false,
        observer,
    };
    let result = run(&mut sink);
    // `t0` is reported just before the first step, or after the call if
    // there was none, so that invalid input reports nothing.
    if !sink.started && !matches!(result, Err(SimError::InvalidInput { .. })) {
        (sink.observer)(t0, &x0);
    }
    result
}

/// Samples the steps at requested times by dense output.
struct Outputs<'a, T, F> {
    times: &'a [T],
    i: usize,
    dir: T,
    started: bool,
    on_output: F,
}

impl<T: RealField + Copy, F: FnMut(T, &SVector<T, D>), const D: usize> Sink<T, D>
    for Outputs<'_, T, F>
{
    fn wants_dense(&self, t_prev: T, t: T) -> bool {
        // A time strictly inside the step needs the interpolant (the ends
        // are reported with the exact states).
        let pending = &self.times[self.i.min(self.times.len())..];
        pending
            .iter()
            .find(|&&ti| ti != t_prev)
            .is_some_and(|&ti| (ti - t) * self.dir < T::zero())
    }

    fn step(&mut self, step: &Step<'_, T, D>) {
        self.started = true;
        while self.i < self.times.len() && (self.times[self.i] - step.t()) * self.dir <= T::zero() {
            let ti = self.times[self.i];
            (self.on_output)(ti, &step.interpolate(ti));
            self.i += 1;
        }
    }
}

/// The output-time protocol of
/// [`Integrator::integrate_with_outputs`](crate::Integrator::integrate_with_outputs)
/// around `run`: checks `times`, then integrates and samples.
pub(crate) fn outputs<T, F, const D: usize>(
    (t0, x0, t1): (T, SVector<T, D>, T),
    times: &[T],
    on_output: F,
    run: impl FnOnce(&mut dyn Sink<T, D>) -> Result<Outcome<T, D>, SimError<T, D>>,
) -> Result<Outcome<T, D>, SimError<T, D>>
where
    T: RealField + Copy,
    F: FnMut(T, &SVector<T, D>),
{
    let dir = check_arguments(t0, &x0, t1)?;
    let sort_dir = if dir == T::zero() { T::one() } else { dir };
    if !times.iter().all(|t| t.is_finite()) {
        return Err(SimError::InvalidInput {
            what: "output times must be finite",
        });
    }
    if times
        .windows(2)
        .any(|w| (w[1] - w[0]) * sort_dir < T::zero())
    {
        return Err(SimError::InvalidInput {
            what: "output times must be sorted in the direction of integration",
        });
    }
    // Skip the times before t0.
    let i = times
        .iter()
        .position(|&ti| (ti - t0) * sort_dir >= T::zero())
        .unwrap_or(times.len());
    let mut sink = Outputs {
        times,
        i,
        dir,
        started: false,
        on_output,
    };
    let result = run(&mut sink);
    if !sink.started && !matches!(result, Err(SimError::InvalidInput { .. })) {
        while sink.i < times.len() && times[sink.i] == t0 {
            (sink.on_output)(t0, &x0);
            sink.i += 1;
        }
    }
    result
}
