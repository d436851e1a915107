//! Switching charts at run time (DESIGN §6.7). A system whose atlas has
//! several charts ([`OdeSystem::charts`]) is integrated in *segments*: each
//! is one run of the step driver over one chart ([`InChart`]), which ends
//! at the last good state when that chart's regularity falls below the
//! switching threshold ([`RunSettings::chart_floor`]). [`run`] then moves
//! the state to the chart that is best there and starts the next segment,
//! and hands everything to the caller in chart 0's layout ([`Charted`]).

use core::cell::Cell;

use nalgebra::{RealField, SMatrix, SVector, Vector3};

use crate::checks::check_arguments;
use crate::driver::{Control, Record, RunSettings, drive};
use crate::jacobian::{FiniteDifference, JacobianSource};
use crate::lie::Frame;
use crate::method::Method;
use crate::numeric::{all_finite, c, machine_epsilon};
use crate::sink::Sink;
use crate::step::Step;
use crate::{
    ChartSwitch, ChartSwitches, EventHit, OdeJacobian, OdeSystem, Outcome, ProjectionFailure,
    SimError, Singularity, Stats,
};

/// The hysteresis: the run moves to another chart only where that chart's
/// regularity exceeds the current one's by this factor.
pub(crate) const HYSTERESIS: f64 = 2.0;

/// Segments in a row that end where they started (no accepted step)
/// before the run gives up (`Singular { cause: Chart }`).
const MAX_STALLS: usize = 2;

/// The system seen in one chart of its atlas: an [`OdeSystem`] (and an
/// [`OdeJacobian`] when the system is one) whose equations and hooks are
/// the chart's (`*_in_chart`, `*_in`), or, with a frame, those of its free
/// rotation's canonical coordinates about the frame's base ([`Frame`]).
pub(crate) struct InChart<'s, S: ?Sized, T> {
    sys: &'s S,
    chart: usize,
    frame: Option<&'s Frame<T>>,
    /// Right-hand sides evaluated by the finite differences taken where
    /// the system has no Jacobian of the chart (counted after the segment).
    extra_evals: Cell<usize>,
}

impl<'s, S: ?Sized, T> InChart<'s, S, T> {
    fn new(sys: &'s S, chart: usize, frame: Option<&'s Frame<T>>) -> Self {
        InChart {
            sys,
            chart,
            frame,
            extra_evals: Cell::new(0),
        }
    }
}

impl<T, S, const D: usize> OdeSystem<T, D> for InChart<'_, S, T>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        match self.frame {
            Some(frame) => frame.rhs(self.sys, t, x),
            None => self.sys.rhs_in_chart(self.chart, t, x),
        }
    }

    #[inline]
    fn chart_regularity(&self, t: T, x: &SVector<T, D>) -> Option<T> {
        match self.frame {
            Some(frame) => frame.regularity(self.sys, t, x),
            None => self.sys.chart_regularity_in(self.chart, t, x),
        }
    }

    #[inline]
    fn crossed_pole(
        &self,
        t0: T,
        x0: &SVector<T, D>,
        t1: T,
        x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        let Some(frame) = self.frame else {
            return self.sys.crossed_pole_in(self.chart, t0, x0, t1, x1);
        };
        frame.in_chart(self.sys, x1, |chart, x1| {
            let x0 = frame.to_chart(self.sys, chart, x0, None);
            self.sys.crossed_pole_in(chart, t0, &x0, t1, x1)
        })
    }

    #[inline]
    fn constraint_residual(&self, t: T, x: &SVector<T, D>) -> Option<T> {
        match self.frame {
            Some(frame) => frame.in_chart(self.sys, x, |chart, x| {
                self.sys.constraint_residual_in(chart, t, x)
            }),
            None => self.sys.constraint_residual_in(self.chart, t, x),
        }
    }

    #[inline]
    fn project(&self, t: T, x: &mut SVector<T, D>) -> Result<bool, ProjectionFailure<T>> {
        match self.frame {
            Some(frame) => frame.project(self.sys, t, x),
            None => self.sys.project_in(self.chart, t, x),
        }
    }

    #[inline]
    fn is_autonomous(&self) -> bool {
        self.sys.is_autonomous()
    }
}

/// The chart's Jacobian where the system gives it
/// ([`OdeJacobian::jacobian_in_chart`]), forward differences otherwise
/// (and in a free rotation's canonical coordinates).
impl<T, S, const D: usize> OdeJacobian<T, D> for InChart<'_, S, T>
where
    T: RealField + Copy,
    S: OdeJacobian<T, D> + ?Sized,
{
    fn jacobian(&self, t: T, x: &SVector<T, D>) -> SMatrix<T, D, D> {
        if self.frame.is_none()
            && let Some(j) = self.sys.jacobian_in_chart(self.chart, t, x)
        {
            return j;
        }
        let f0 = self.rhs(t, x);
        let mut j = SMatrix::<T, D, D>::zeros();
        let mut stats = Stats::default();
        let fd = FiniteDifference(self);
        JacobianSource::jacobian(&fd, t, x, &f0, j.as_mut_slice(), &mut stats);
        let evals = self.extra_evals.get() + 1 + stats.rhs_evals;
        self.extra_evals.set(evals);
        j
    }

    /// Chart 0's own `∂f/∂t`; in the other charts the implicit methods
    /// difference `f` in `t`.
    fn time_derivative(&self, t: T, x: &SVector<T, D>) -> Option<SVector<T, D>> {
        if self.chart == 0 && self.frame.is_none() {
            self.sys.time_derivative(t, x)
        } else {
            None
        }
    }
}

/// A sink seen from a segment in chart `chart`: the steps (their ends and
/// every interpolated point) and the trial ends are mapped to chart 0
/// before they reach `inner`; in chart 0 they pass as they are.
struct Charted<'k, 's, K: ?Sized, S: ?Sized, T, const D: usize> {
    inner: &'k mut K,
    sys: &'s S,
    chart: usize,
    /// The frame of a free rotation's canonical coordinates, when the run
    /// is in them (then `chart` is not used).
    frame: Option<&'s Frame<T>>,
    /// The last state handed to `inner` (chart 0's layout): each mapped
    /// state is the representative nearest it
    /// ([`OdeSystem::change_chart_near`]), so that angles do not jump by
    /// whole turns where the run is in another chart.
    near: Cell<SVector<T, D>>,
    /// With a frame, the canonical coordinates of `near`, from which the
    /// next state's angles are followed ([`Frame::follow`]).
    near_theta: Cell<Vector3<T>>,
}

impl<K: ?Sized, S, T, const D: usize> Charted<'_, '_, K, S, T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    /// `x` of the current chart in chart 0's layout, nearest the last state
    /// handed out, which it becomes.
    fn to_chart_0(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        let trail = (&self.near, &self.near_theta);
        written_in_chart_0(self.sys, (self.chart, self.frame), trail, t, x)
    }

    /// Whether the steps reach the inner sink as they are.
    fn direct(&self) -> bool {
        self.chart == 0 && self.frame.is_none()
    }
}

/// `x` at `t`, in the chart or the frame `at`, written in chart 0's layout
/// nearest the last state handed out, `trail.0` (with a frame, followed
/// from it, whose canonical coordinates are `trail.1`), which it becomes.
fn written_in_chart_0<T, S, const D: usize>(
    sys: &S,
    at: (usize, Option<&Frame<T>>),
    (near, theta): (&Cell<SVector<T, D>>, &Cell<Vector3<T>>),
    t: T,
    x: &SVector<T, D>,
) -> SVector<T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    let y = match at {
        (_, Some(frame)) => {
            let y = frame.follow(sys, x, (&near.get(), &theta.get()));
            theta.set(frame.canonical(x));
            y
        }
        (0, None) => *x,
        (chart, None) => sys.change_chart_near(chart, 0, t, x, &near.get()),
    };
    near.set(y);
    y
}

/// `f` on the inner sink of `charted` and `step` in chart 0's layout.
fn pass<T, K, S, R, const D: usize>(
    charted: &mut Charted<'_, '_, K, S, T, D>,
    step: &Step<'_, T, D>,
    f: impl FnOnce(&mut K, &Step<'_, T, D>) -> R,
) -> R
where
    T: RealField + Copy,
    K: Sink<T, D> + ?Sized,
    S: OdeSystem<T, D> + ?Sized,
{
    if charted.direct() {
        charted.near.set(*step.x());
        return f(charted.inner, step);
    }
    let x_prev = charted.to_chart_0(step.t_prev(), step.x_prev());
    let start = (charted.near.get(), charted.near_theta.get());
    let x = charted.to_chart_0(step.t(), step.x());
    let end = (charted.near.get(), charted.near_theta.get());
    let Charted {
        inner,
        sys,
        chart,
        frame,
        near,
        near_theta,
    } = charted;
    let out = if frame.is_some() {
        // interpolated points followed from the step's start, each from
        // the one before
        near.set(start.0);
        near_theta.set(start.1);
        let trail = (&*near, &*near_theta);
        let map = |t: T, x: &SVector<T, D>| written_in_chart_0(*sys, (*chart, *frame), trail, t, x);
        f(inner, &step.mapped(&x_prev, &x, &map))
    } else {
        // interpolated points nearest the step's end
        let map = |t: T, x: &SVector<T, D>| sys.change_chart_near(*chart, 0, t, x, &end.0);
        f(inner, &step.mapped(&x_prev, &x, &map))
    };
    near.set(end.0);
    near_theta.set(end.1);
    out
}

impl<T, K, S, const D: usize> Sink<T, D> for Charted<'_, '_, K, S, T, D>
where
    T: RealField + Copy,
    K: Sink<T, D> + ?Sized,
    S: OdeSystem<T, D> + ?Sized,
{
    fn wants_dense(&self, t_prev: T, t: T) -> bool {
        self.inner.wants_dense(t_prev, t)
    }

    fn wants_dense_at(&mut self, prev: (T, &SVector<T, D>), end: (T, &SVector<T, D>)) -> bool {
        if self.direct() {
            return self.inner.wants_dense_at(prev, end);
        }
        let x_prev = self.to_chart_0(prev.0, prev.1);
        let x = self.to_chart_0(end.0, end.1);
        self.inner.wants_dense_at((prev.0, &x_prev), (end.0, &x))
    }

    fn step(&mut self, step: &Step<'_, T, D>) {
        pass(self, step, |k, s| k.step(s));
    }

    fn step_or_stop(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        pass(self, step, |k, s| k.step_or_stop(s))
    }

    fn salvage(&mut self, step: &Step<'_, T, D>) -> Option<EventHit<T, D>> {
        pass(self, step, |k, s| k.salvage(s))
    }

    fn recentre(&mut self, x: &mut SVector<T, D>) -> bool {
        let moved = self.frame.is_some_and(|frame| frame.recentre(x));
        if moved {
            // the last state handed out is the step's end, now the centre
            self.near_theta.set(Vector3::zeros());
        }
        moved
    }
}

/// One segment to integrate: what the step driver needs, handed to the
/// integrator's closure that builds its method for the chart's view.
pub(crate) struct Segment<'g, T, const D: usize> {
    settings: &'g RunSettings<T, D>,
    /// The smallest positive relative tolerance asked for (`None` with a
    /// fixed step), held against the method's [`Method::MIN_RTOL_EPS`].
    rtol: Option<T>,
    span: (T, SVector<T, D>, T),
    sink: &'g mut dyn Sink<T, D>,
    rec: &'g mut Record<T>,
}

impl<T: RealField + Copy, const D: usize> Segment<'_, T, D> {
    /// Integrates the segment with `method` (built for `sys`, the chart's
    /// view): `ToleranceTooTight` as `Settings::run` would say it, else
    /// the step driver.
    pub(crate) fn drive<M, H>(
        self,
        method: &mut M,
        sys: &H,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        M: Method<T, D>,
        H: OdeSystem<T, D> + ?Sized,
    {
        if let (Some(units), Some(rtol)) = (M::MIN_RTOL_EPS, self.rtol) {
            let rtol_min = c::<T>(units) * machine_epsilon::<T>();
            if rtol < rtol_min {
                let (t, x, _) = self.span;
                return Err(SimError::ToleranceTooTight { t, x, rtol_min });
            }
        }
        drive(method, sys, self.settings, self.span, self.sink, self.rec)
    }
}

/// The magnitude of chart `chart`'s regularity at `(t, x)` (in its
/// layout): 1 for a chart without singularities, 0 where it is not finite.
fn magnitude<T, S, const D: usize>(sys: &S, chart: usize, t: T, x: &SVector<T, D>) -> T
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    match sys.chart_regularity_in(chart, t, x) {
        None => T::one(),
        Some(rho) if rho.is_finite() => rho.abs(),
        Some(_) => T::zero(),
    }
}

/// The chart to move to from `(t, x)` in chart `from`, with the state
/// there: the one whose regularity is largest, if it exceeds `√eps` and
/// [`HYSTERESIS`] times `from`'s.
fn better<T, S, const D: usize>(
    sys: &S,
    from: usize,
    t: T,
    x: &SVector<T, D>,
) -> Option<(usize, SVector<T, D>)>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    let least = machine_epsilon::<T>()
        .sqrt()
        .max(c::<T>(HYSTERESIS) * magnitude(sys, from, t, x));
    let mut best: Option<(usize, SVector<T, D>, T)> = None;
    for to in (0..sys.charts()).filter(|&to| to != from) {
        let y = sys.change_chart(from, to, t, x);
        if !all_finite(&y) {
            continue;
        }
        let rho = magnitude(sys, to, t, &y);
        if rho > least && best.as_ref().is_none_or(|b| rho > b.2) {
            best = Some((to, y, rho));
        }
    }
    best.map(|(to, y, _)| (to, y))
}

/// The switching threshold of a segment that starts where its chart's
/// regularity is `rho`, after `stalls` segments that ended where they
/// started: `min(τ, |ρ|/2)`, divided by 4 for each stall, τ the chart's
/// [`OdeSystem::chart_switch_below`] (`|ρ|/2` so that a segment that starts
/// poorly still goes on).
fn threshold<T: RealField + Copy>(tau: f64, rho: T, stalls: usize) -> T {
    let mut floor = c::<T>(tau).min(rho.abs() * c(0.5));
    for _ in 0..stalls {
        floor *= c(0.25);
    }
    floor
}

/// Adds a segment's record to the run's.
fn add<T: RealField + Copy>(run: &mut Record<T>, segment: &Record<T>) {
    run.stats.add(&segment.stats);
    run.last_step = segment.last_step.or(run.last_step);
    run.max_residual = match (run.max_residual, segment.max_residual) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    };
}

/// The step attempts counted against the budget: accepted plus rejected
/// (adaptive), accepted (fixed step).
fn attempts<T, const D: usize>(stats: &Stats, settings: &RunSettings<T, D>) -> usize {
    match settings.control {
        Control::Fixed(_) => stats.steps,
        Control::Adaptive => stats.steps + stats.rejected,
    }
}

/// Where a run over several charts is: the chart, and the state in its
/// layout.
struct At<T, const D: usize> {
    chart: usize,
    t: T,
    x: SVector<T, D>,
}

/// The switching threshold of a free rotation's canonical coordinates,
/// whose regularity `1 − |θ|/2π` starts every step at 1: a segment ends
/// where one step turns the body by more than 3/4 of a turn.
const FRAME_SWITCH_BELOW: f64 = 0.25;

/// Where a run over the charts of `sys` starts from `(t0, x0)` (chart 0):
/// in canonical coordinates about the rotation at `x0` with a `frame`; in
/// a better chart when chart 0 is poor there (recorded in `switches`);
/// else in chart 0.
fn start<T, S, const D: usize>(
    sys: &S,
    frame: Option<&Frame<T>>,
    (t0, x0, t1): (T, SVector<T, D>, T),
    switches: &mut ChartSwitches<T>,
) -> At<T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    if let Some(frame) = frame {
        let x = frame.enter(sys, 0, &x0);
        return At { chart: 0, t: t0, x };
    }
    let moving = check_arguments(t0, &x0, t1).is_ok_and(|dir| dir != T::zero());
    if moving
        && magnitude(sys, 0, t0, &x0) < c(sys.chart_switch_below(0))
        && let Some((to, x)) = better(sys, 0, t0, &x0)
    {
        switches.push(ChartSwitch { t: t0, from: 0, to });
        return At {
            chart: to,
            t: t0,
            x,
        };
    }
    At {
        chart: 0,
        t: t0,
        x: x0,
    }
}

/// Integrates `sys` over the charts of its atlas from `(t0, x0)` (chart 0)
/// to `t1`, each segment by `segment` (the integrator's method for the
/// chart's view, run by [`Segment::drive`]), handing `sink` chart 0's
/// layout, with the run's settings `base` and smallest relative tolerance
/// `rtol`. The records of the segments add up in `rec`; the switches go to
/// `switches`. With `one_step` (the method is a one-step method) a system
/// whose charts are those of a free rotation is run in its canonical
/// coordinates instead ([`Frame`]), re-centred after every step and at the
/// end of every segment.
pub(crate) fn run<T, S, K, F, const D: usize>(
    sys: &S,
    (base, rtol, one_step): (&RunSettings<T, D>, Option<T>, bool),
    (t0, x0, t1): (T, SVector<T, D>, T),
    sink: &mut K,
    (rec, switches): (&mut Record<T>, &mut ChartSwitches<T>),
    mut segment: F,
) -> Result<Outcome<T, D>, SimError<T, D>>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
    K: Sink<T, D> + ?Sized,
    F: FnMut(&InChart<'_, S, T>, Segment<'_, T, D>) -> Result<Outcome<T, D>, SimError<T, D>>,
{
    *rec = Record::default();
    switches.clear();
    let frame = if one_step { Frame::of(sys) } else { None };
    let frame = frame.as_ref();
    let mut at = start(sys, frame, (t0, x0, t1), switches);
    let mut sink = Charted {
        inner: sink,
        sys,
        chart: 0,
        frame,
        near: Cell::new(x0),
        near_theta: Cell::new(Vector3::zeros()),
    };
    let (mut h, mut stalls) = (base.initial_step, 0);
    loop {
        let view = InChart::new(sys, at.chart, frame);
        let mut settings = *base;
        settings.initial_step = h;
        settings.max_steps = base.max_steps.saturating_sub(attempts(&rec.stats, base));
        let tau = match frame {
            Some(_) => FRAME_SWITCH_BELOW,
            None => sys.chart_switch_below(at.chart),
        };
        let rho = view.chart_regularity(at.t, &at.x);
        settings.chart_floor = rho.map(|rho| threshold(tau, rho, stalls));
        if let Some(cap) = frame.and_then(|f| f.step_cap(&at.x)) {
            settings.max_step = Some(base.max_step.map_or(cap, |m| m.min(cap)));
        }
        sink.chart = at.chart;
        let mut seg = Record::default();
        let result = segment(
            &view,
            Segment {
                settings: &settings,
                rtol,
                span: (at.t, at.x, t1),
                sink: &mut sink,
                rec: &mut seg,
            },
        );
        seg.stats.rhs_evals += view.extra_evals.get();
        add(rec, &seg);
        rec.stats.chart_switches = switches.total();
        let (t, mut x) = match result {
            Ok(out) => return Ok(finished(&sink, out, rec, switches)),
            Err(SimError::Singular {
                t,
                x,
                cause: Singularity::Chart,
            }) => (t, x),
            Err(e) => return Err(in_chart_0(&sink, e, (t0, x0), rec)),
        };
        stalls = if t == at.t { stalls + 1 } else { 0 };
        h = if stalls > 0 {
            h.map(|h| h * c(0.25))
        } else {
            seg.last_step.or(h)
        };
        let moved = match frame {
            // a trial that turned too far, or constraints that degrade:
            // again from the centre of the canonical coordinates (the step
            // shrinks if it ends where it started)
            Some(frame) => {
                frame.recentre(&mut x);
                let floor = machine_epsilon::<T>().sqrt();
                stalls <= MAX_STALLS && view.chart_regularity(t, &x).is_none_or(|r| r > floor)
            }
            None => switch(&sink, (t, &mut x), &mut at.chart, stalls, switches),
        };
        if !moved {
            let x = sink.to_chart_0(t, &x);
            let cause = Singularity::Chart;
            return Err(SimError::Singular { t, x, cause });
        }
        rec.stats.chart_switches = switches.total();
        (at.t, at.x) = (t, x);
    }
}

/// Moves the state `x` at `t` of the segment that ended in `chart` to the
/// chart that is best there (`chart` and `x` updated, the switch recorded),
/// or keeps it in `chart` if it is still regular there (the next segment
/// then has a lower threshold); `false` where the run cannot go on: no
/// chart is better and `chart` is singular, or too many segments ended
/// where they started (`stalls`).
fn switch<T, K, S, const D: usize>(
    sink: &Charted<'_, '_, K, S, T, D>,
    (t, x): (T, &mut SVector<T, D>),
    chart: &mut usize,
    stalls: usize,
    switches: &mut ChartSwitches<T>,
) -> bool
where
    T: RealField + Copy,
    K: ?Sized,
    S: OdeSystem<T, D> + ?Sized,
{
    let sys = sink.sys;
    let next = better(sys, *chart, t, x);
    let regular = magnitude(sys, *chart, t, x) > machine_epsilon::<T>().sqrt();
    if stalls > MAX_STALLS || (next.is_none() && !regular) {
        return false;
    }
    if let Some((to, mut y)) = next {
        if to == 0 {
            // back in the layout the caller sees: continuous with it
            y = sink.to_chart_0(t, x);
        }
        switches.push(ChartSwitch {
            t,
            from: *chart,
            to,
        });
        (*chart, *x) = (to, y);
    }
    true
}

/// The outcome of the last segment, in the chart of `sink`, as the run's:
/// its state in chart 0's layout (a terminal event's already is), the
/// run's record and switches.
fn finished<T, K, S, const D: usize>(
    sink: &Charted<'_, '_, K, S, T, D>,
    out: Outcome<T, D>,
    rec: &Record<T>,
    switches: &ChartSwitches<T>,
) -> Outcome<T, D>
where
    T: RealField + Copy,
    K: ?Sized,
    S: OdeSystem<T, D> + ?Sized,
{
    let x = if out.event.is_some() {
        out.x
    } else {
        sink.to_chart_0(out.t, &out.x)
    };
    Outcome {
        x,
        stats: rec.stats,
        max_residual: rec.max_residual,
        switches: *switches,
        ..out
    }
}

/// The failure `e` of a segment in the chart of `sink` as the run's: its
/// state in chart 0's layout, a tolerance too tight at the run's start
/// `(t0, x0)`, the step attempts of the whole run.
fn in_chart_0<T, K, S, const D: usize>(
    sink: &Charted<'_, '_, K, S, T, D>,
    e: SimError<T, D>,
    (t0, x0): (T, SVector<T, D>),
    rec: &Record<T>,
) -> SimError<T, D>
where
    T: RealField + Copy,
    K: ?Sized,
    S: OdeSystem<T, D> + ?Sized,
{
    let map = |t: T, x: SVector<T, D>| sink.to_chart_0(t, &x);
    match e {
        SimError::NonFinite { t, x } => SimError::NonFinite { t, x: map(t, x) },
        SimError::StepSizeTooSmall { t, x, h } => SimError::StepSizeTooSmall { t, x: map(t, x), h },
        SimError::MaxSteps { t, x, .. } => SimError::MaxSteps {
            t,
            x: map(t, x),
            steps: rec.stats.steps + rec.stats.rejected,
        },
        SimError::NoConvergence { t, x, h } => SimError::NoConvergence { t, x: map(t, x), h },
        SimError::Singular { t, x, cause } => SimError::Singular {
            t,
            x: map(t, x),
            cause,
        },
        SimError::ProjectionFailed { t, x, residual } => SimError::ProjectionFailed {
            t,
            x: map(t, x),
            residual,
        },
        SimError::ToleranceTooTight { rtol_min, .. } => SimError::ToleranceTooTight {
            t: t0,
            x: x0,
            rtol_min,
        },
        e @ SimError::InvalidInput { .. } => e,
    }
}
