//! The one step driver shared by every integrator.
//!
//! A [`Method`] supplies the stages of one step, its error estimate and its
//! dense output; [`drive`] owns everything else: argument checks, the step
//! layout (a fixed step, or the PI controller of Hairer's codes),
//! acceptance and rejection, step budgets, stiffness detection, handing
//! accepted steps to a [`Sink`] (observers, output times, step callbacks,
//! events, which may end the run) and the typed failures ([`SimError`]).

use nalgebra::{RealField, SVector};

use crate::checks::{check_arguments, check_positive};
use crate::method::{Failure, Method, Pi};
use crate::numeric::{all_finite, c, machine_epsilon};
use crate::sink::Sink;
use crate::step::Poly;
use crate::step_size::{initial_step, min_step};
use crate::tolerance::Tolerance;
use crate::{ChartSwitches, EventHit, OdeSystem, Outcome, SimError, Singularity, Stats, Step};

/// How steps are placed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Control<T> {
    /// Every step has the magnitude `h`; step `k` ends at `t0 + k·h`, the
    /// last one lands on `t1`.
    Fixed(T),
    /// Error control with the method's step-size controller
    /// ([`Method::pi`], by default the constant [`Method::PI`], so that it
    /// folds into the loop).
    Adaptive,
}

/// Everything [`drive`] needs besides the method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RunSettings<T, const D: usize> {
    pub(crate) control: Control<T>,
    pub(crate) tol: Tolerance<T, D>,
    /// The first trial step (magnitude) instead of Hairer's `hinit`.
    pub(crate) initial_step: Option<T>,
    /// The largest step magnitude (default `|t1 − t0|`).
    pub(crate) max_step: Option<T>,
    /// Step attempts allowed (accepted plus rejected).
    pub(crate) max_steps: usize,
    /// Whether accepted states are projected onto the system's holonomic
    /// constraints ([`OdeSystem::project`]).
    pub(crate) project: bool,
    /// The chart regularity below which (in magnitude) the run ends in
    /// `Singular { cause: Chart }` at the last good state, when it is above
    /// `√eps`: the switching threshold of a segment of a run over several
    /// charts (`charts::run`). `None`: `√eps`.
    pub(crate) chart_floor: Option<T>,
}

/// The bookkeeping of one run, kept also when it fails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Record<T> {
    pub(crate) stats: Stats,
    /// The step size proposed after the last accepted step.
    pub(crate) last_step: Option<T>,
    /// The largest holonomic-constraint residual seen so far.
    pub(crate) max_residual: Option<T>,
}

impl<T> Default for Record<T> {
    fn default() -> Self {
        Record {
            stats: Stats::default(),
            last_step: None,
            max_residual: None,
        }
    }
}

/// Accepted steps between routine stiffness tests (Hairer's `NSTIFF`).
const NSTIFF: usize = 1000;
/// Stiff tests needed to flag stiffness.
const STIFF_COUNT: usize = 15;
/// Consecutive non-stiff tests that reset the stiff counter.
const NONSTIFF_RESET: usize = 6;
/// Consecutive singular iteration matrices tolerated (step halved each time).
const MAX_SINGULAR: usize = 5;
/// Iterations of the symmetric projection's shift before the step fails
/// (each contracts the constraint residual by a factor of order h).
const SYMMETRIC_ITERATIONS: usize = 20;
/// Bisections locating a pole inside a step (the bracket reaches adjacent
/// numbers long before).
const MAX_BISECTIONS: usize = 128;

/// The state of one run: the accepted point, the system's chart and
/// manifold hooks, and the counters.
struct Run<'r, T, H: ?Sized, const D: usize> {
    t: T,
    x: SVector<T, D>,
    t1: T,
    dir: T,
    eps: T,
    sys: &'r H,
    project: bool,
    /// The switching threshold of a segment ([`RunSettings::chart_floor`]).
    chart_floor: Option<T>,
    /// The chart regularity at the accepted point (`None`: no chart test).
    chart: Option<T>,
    rec: &'r mut Record<T>,
    /// The terminal event that ended the run, if one did.
    event: Option<EventHit<T, D>>,
    /// The signed size of the last trial step (0 before the first), for
    /// explaining a failure by a pole it crosses.
    h_try: T,
}

/// Integrates `sys` from `(t0, x0)` to `t1` with `method` (which evaluates
/// `sys`), reporting every accepted step to `sink`; the work counters end up
/// in `rec`.
pub(crate) fn drive<T, M, H, K, const D: usize>(
    method: &mut M,
    sys: &H,
    settings: &RunSettings<T, D>,
    (t0, x0, t1): (T, SVector<T, D>, T),
    sink: &mut K,
    rec: &mut Record<T>,
) -> Result<Outcome<T, D>, SimError<T, D>>
where
    T: RealField + Copy,
    M: Method<T, D>,
    H: OdeSystem<T, D> + ?Sized,
    K: Sink<T, D> + ?Sized,
{
    *rec = Record::default();
    let dir = check_arguments(t0, &x0, t1)?;
    check_settings(settings)?;
    let eps = machine_epsilon::<T>();
    let mut run = Run {
        t: t0,
        x: x0,
        t1,
        dir,
        eps,
        sys,
        project: settings.project,
        chart_floor: settings.chart_floor,
        chart: None,
        rec,
        event: None,
        h_try: T::zero(),
    };
    run.chart = run.regular_chart(t0, &x0)?;
    run.rec.max_residual = sys.constraint_residual(t0, &x0);
    if dir == T::zero() {
        return Ok(run.outcome());
    }
    if (t1 - t0).abs() < min_step(eps, t0, t1) {
        let result = run.tiny_span(method, sink);
        return result.map_err(|e| run.explain(e));
    }
    let result = method
        .start(t0, &x0, &mut run.rec.stats)
        .map_err(|f| f.at(t0, x0, t1 - t0))
        .and_then(|()| match settings.control {
            Control::Fixed(h) => run.fixed(method, settings, h, sink),
            Control::Adaptive => run.adaptive(method, settings, sink),
        });
    result.map_err(|e| run.explain(e))
}

/// `InvalidInput` unless the tolerances and step settings are usable.
fn check_settings<T: RealField + Copy, const D: usize>(
    s: &RunSettings<T, D>,
) -> Result<(), SimError<T, D>> {
    s.tol.check()?;
    if let Control::Fixed(h) = s.control {
        check_positive(h, "step size h must be positive and finite")?;
    }
    if let Some(h) = s.initial_step {
        check_positive(h, "initial step must be positive and finite")?;
    }
    if let Some(h) = s.max_step {
        check_positive(h, "max step must be positive and finite")?;
    }
    Ok(())
}

/// The state of the step-size controller between attempts.
struct Controller<T> {
    pi: Pi,
    facold: T,
    /// The previous accepted step and its error (Gustafsson).
    hacc: Option<(T, T)>,
    /// Whether the last attempt was rejected.
    reject: bool,
}

impl<T: RealField + Copy> Controller<T> {
    /// A controller with no history.
    fn new(pi: Pi) -> Self {
        Controller {
            pi,
            facold: c(1e-4),
            hacc: None,
            reject: false,
        }
    }

    /// Whether `err` is acceptable, and the next step after `h`.
    #[inline(always)]
    fn propose(&self, err: T, h: T) -> (bool, T) {
        let p = &self.pi;
        // (`expo = 0`: a method that proposes its own steps, no `powf`.)
        let fac11 = root(err, p.expo);
        if err > T::one() {
            return (false, h / (fac11 / c(p.safe)).min(c(p.fac_hi)));
        }
        // (`β = 0` skips a `powf` per step: DOP853 and RODAS have no PI term.)
        let errold = if p.beta == 0.0 {
            T::one()
        } else {
            self.facold.powf(c(p.beta))
        };
        let fac = (fac11 / errold / c(p.safe))
            .min(c(p.fac_hi))
            .max(c(p.fac_lo));
        let mut h_new = h / fac;
        if let (true, Some((hacc, erracc))) = (p.gustafsson, self.hacc) {
            let facgus = ((hacc / h) * root(err * err / erracc, p.expo) / c(p.safe))
                .min(c(p.fac_hi))
                .max(c(p.fac_lo));
            h_new = h / fac.max(facgus);
        }
        (true, h_new)
    }

    /// Records an accepted step `h` with error `err`; returns the next step
    /// from the proposal `h_new`, capped at `hmax` and, after a rejection,
    /// at `|h|`.
    fn accepted(&mut self, err: T, h: T, h_new: T, hmax: T, dir: T) -> T {
        self.facold = err.max(c(1e-4));
        self.hacc = Some((h, err.max(c(1e-2))));
        let mut h_new = h_new.abs().min(hmax);
        if self.reject {
            h_new = h_new.min(h.abs());
        }
        self.reject = false;
        h_new * dir
    }
}

/// `v^expo`: by square roots for the exponents 1/2, 1/4 and 1/8 of DOP853 and
/// RODAS4's controllers (a few instructions instead of a `powf`; within an
/// ulp or two of it), 1 for the exponent 0 of a method that proposes its own
/// steps, by `powf` otherwise. `expo` is a constant of the method, so the
/// choice folds away.
#[inline(always)]
fn root<T: RealField + Copy>(v: T, expo: f64) -> T {
    if expo == 0.0 {
        T::one()
    } else if expo == 0.5 {
        v.sqrt()
    } else if expo == 0.25 {
        v.sqrt().sqrt()
    } else if expo == 0.125 {
        v.sqrt().sqrt().sqrt()
    } else {
        v.powf(c(expo))
    }
}

/// Hairer's stiffness test: counts steps at the stability boundary.
struct Stiffness<T> {
    hlamb: Option<T>,
    iasti: usize,
    nonsti: usize,
}

impl<T: RealField + Copy> Stiffness<T> {
    /// Tests after accepted step number `steps` (of size `h`); `true` once
    /// stiffness is detected.
    fn test<M: Method<T, D>, const D: usize>(&mut self, m: &M, steps: usize, h: T) -> bool {
        let Some(limit) = M::STIFF_LIMIT else {
            return false;
        };
        if !(steps.is_multiple_of(NSTIFF) || self.iasti > 0) {
            return false;
        }
        if let Some(r) = m.stiffness_ratio() {
            self.hlamb = Some(h.abs() * r);
        }
        if self.hlamb.is_some_and(|hl| hl > c(limit)) {
            self.nonsti = 0;
            self.iasti += 1;
            self.iasti >= STIFF_COUNT
        } else {
            self.nonsti += 1;
            if self.nonsti == NONSTIFF_RESET {
                self.iasti = 0;
            }
            false
        }
    }
}

impl<T: RealField + Copy, H: OdeSystem<T, D> + ?Sized, const D: usize> Run<'_, T, H, D> {
    fn outcome(&self) -> Outcome<T, D> {
        Outcome {
            t: self.t,
            x: self.x,
            stats: self.rec.stats,
            max_residual: self.rec.max_residual,
            event: self.event,
            switches: ChartSwitches::new(),
        }
    }

    /// The chart regularity at `(t, x)` if the chart is regular there (above
    /// `√eps` in magnitude, and above the segment's switching threshold if
    /// it has one) and on the same side of its singularities as the
    /// accepted point; otherwise `Singular` at the accepted point.
    fn regular_chart(&self, t: T, x: &SVector<T, D>) -> Result<Option<T>, SimError<T, D>> {
        let Some(rho) = self.sys.chart_regularity(t, x) else {
            return Ok(None);
        };
        let floor = self.eps.sqrt();
        let floor = self.chart_floor.map_or(floor, |f| f.max(floor));
        let flipped = self.chart.is_some_and(|prev| prev * rho < T::zero());
        if rho.abs() > floor && !flipped {
            Ok(Some(rho))
        } else {
            Err(self.chart_singular())
        }
    }

    fn chart_singular(&self) -> SimError<T, D> {
        SimError::Singular {
            t: self.t,
            x: self.x,
            cause: Singularity::Chart,
        }
    }

    /// A failure within `eps^(1/4)` of a chart singularity is reported as
    /// the singularity that caused it; so is a stage solve that failed on a
    /// step whose explicit Euler predictor x + h f(t, x) lies across one
    /// (an implicit method's fixed step reaching the singularity). Failing
    /// that, a failure on a step whose explicit Euler predictor crosses a
    /// pole of the equations ([`OdeSystem::crossed_pole`]) is reported as
    /// the pole.
    fn explain(&self, e: SimError<T, D>) -> SimError<T, D> {
        let near = |rho: T| rho.abs() <= self.eps.sqrt().sqrt();
        if let SimError::NoConvergence { h, .. } = e
            && let Some(rho) = self.sys.chart_regularity(self.t, &self.x)
        {
            let predictor = self.x + self.sys.rhs(self.t, &self.x) * h;
            let across = self
                .sys
                .chart_regularity(self.t + h, &predictor)
                .is_some_and(|next| next * rho <= T::zero() || !next.is_finite());
            if across {
                return self.chart_singular();
            }
        }
        match e {
            SimError::NonFinite { .. }
            | SimError::StepSizeTooSmall { .. }
            | SimError::NoConvergence { .. }
                if self.sys.chart_regularity(self.t, &self.x).is_some_and(near) =>
            {
                self.chart_singular()
            }
            SimError::NoConvergence { .. } => self.pole_ahead(false).unwrap_or(e),
            SimError::NonFinite { .. } | SimError::StepSizeTooSmall { .. } => {
                self.pole_ahead(true).unwrap_or(e)
            }
            e => e,
        }
    }

    /// `Singular` at the accepted point with the pole that the explicit
    /// Euler predictor `x + h f(t, x)` crosses, if it crosses one: over the
    /// last trial step and, when the step `collapsed` (a step size too
    /// small, non-finite trials halved away), also over `√eps·max(|t|,
    /// |t1|)` (at most to `t1`), since an adaptive method's steps shrink
    /// with the distance to a singularity of the solution and stall short
    /// of the pole.
    fn pole_ahead(&self, collapsed: bool) -> Option<SimError<T, D>> {
        let f = self.sys.rhs(self.t, &self.x);
        let reach = self.eps.sqrt() * self.t.abs().max(self.t1.abs());
        let horizon = reach.min((self.t1 - self.t).abs()) * self.dir;
        let spans = [Some(self.h_try), collapsed.then_some(horizon)];
        spans.into_iter().flatten().find_map(|h| {
            let predictor = self.x + f * h;
            if h == T::zero() || !all_finite(&predictor) {
                return None;
            }
            let expr = self
                .sys
                .crossed_pole(self.t, &self.x, self.t + h, &predictor)?;
            Some(self.pole_singular(expr))
        })
    }

    /// The last point of the step's dense output before the pole that its
    /// end lies across (bisection on [`OdeSystem::crossed_pole`] from the
    /// step's start), so that the events of the step are looked for only
    /// before the pole: `(t, x(t))`.
    fn before_pole(&self, step: &Step<'_, T, D>) -> (T, SVector<T, D>) {
        let (mut lo, mut hi) = (step.t_prev(), step.t());
        for _ in 0..MAX_BISECTIONS {
            let mid = (lo + hi) * c(0.5);
            if mid == lo || mid == hi {
                break;
            }
            let x = step.interpolate(mid);
            let across =
                !all_finite(&x) || self.sys.crossed_pole(self.t, &self.x, mid, &x).is_some();
            if across {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        (lo, step.interpolate(lo))
    }

    fn pole_singular(&self, expr: &'static str) -> SimError<T, D> {
        SimError::Singular {
            t: self.t,
            x: self.x,
            cause: Singularity::Pole(expr),
        }
    }

    /// The end `x_new` of an accepted step at `t_new`, projected onto the
    /// holonomic constraints when projection is on, its chart checked, the
    /// step checked for a pole of the equations between its ends, and its
    /// residual recorded; `true` if the projection moved it.
    fn settle(&mut self, t_new: T, x_new: &mut SVector<T, D>) -> Result<bool, SimError<T, D>> {
        let moved = if self.project {
            self.sys
                .project(t_new, x_new)
                .map_err(|f| SimError::ProjectionFailed {
                    t: self.t,
                    x: self.x,
                    residual: f.residual,
                })?
        } else {
            false
        };
        if moved && !all_finite(x_new) {
            return Err(SimError::NonFinite {
                t: self.t,
                x: self.x,
            });
        }
        let chart = self.regular_chart(t_new, x_new)?;
        if let Some(expr) = self.sys.crossed_pole(self.t, &self.x, t_new, x_new) {
            return Err(self.pole_singular(expr));
        }
        self.chart = chart;
        if let Some(r) = self.sys.constraint_residual(t_new, x_new) {
            let worst = self.rec.max_residual.map_or(r, |m| m.max(r));
            self.rec.max_residual = Some(worst);
        }
        Ok(moved)
    }

    /// Whether the end of a symmetric method's step (just attempted) from
    /// the accepted point was moved by Hairer's symmetric projection
    /// (Geometric Numerical Integration, §V.4.1), which replaces the
    /// method's end ([`Method::replace_end`]): the step starts from x + σ
    /// and its end is shifted by the same σ, σ ← σ + d/2 with d the
    /// projection's correction of that end, until the end lies on the
    /// holonomic constraints. The map x ↦ end is then as symmetric as the
    /// method (the projection of a generated system moves the dependent
    /// coordinates alone, a fixed direction: the step back from the end with
    /// −σ lands on x). `false`, and nothing more done, when the projection
    /// does not move the plain step's end (no holonomic constraints). A
    /// projection that fails within the iteration ends the step as
    /// `NoConvergence`.
    #[inline(never)]
    fn symmetric_end<M: Method<T, D>>(
        &mut self,
        m: &mut M,
        h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
    ) -> Result<bool, Failure> {
        let (t, x, eps) = (self.t, self.x, self.eps);
        let stats = &mut self.rec.stats;
        let mut shift = SVector::<T, D>::zeros();
        for _ in 0..SYMMETRIC_ITERATIONS {
            let mut end = *m.x_new() + shift;
            let before = end;
            let project = self.sys.project(t_new, &mut end);
            let moved = project.map_err(|_| Failure::NoConvergence)?;
            let d = end - before;
            if !moved || d.amax() <= c::<T>(4.0) * eps * (T::one() + end.amax()) {
                let shifted = shift != SVector::<T, D>::zeros();
                if shifted {
                    m.replace_end(&end);
                }
                return Ok(shifted);
            }
            shift += d * c::<T>(0.5);
            let start = x + shift;
            m.start(t, &start, stats)?;
            m.attempt(t, &start, h, t_new, tol, stats)?;
        }
        Err(Failure::NoConvergence)
    }

    /// A span below the resolution of `t`: one explicit Euler step to `t1`.
    fn tiny_span<M, K>(&mut self, m: &mut M, sink: &mut K) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        M: Method<T, D>,
        K: Sink<T, D> + ?Sized,
    {
        let (t, x) = (self.t, self.x);
        self.h_try = self.t1 - t;
        let f = m.rhs(t, &x);
        self.rec.stats.rhs_evals += 1;
        let mut x_new = x + f * (self.t1 - t);
        if !(all_finite(&f) && all_finite(&x_new)) {
            return Err(SimError::NonFinite { t, x });
        }
        self.settle(self.t1, &mut x_new)?;
        self.rec.stats.steps += 1;
        let line = Poly::from_monomial(&[x, x_new - x]);
        let stop = sink.step_or_stop(&Step::new(t, &x, self.t1, &x_new, Some(&line)));
        self.t = self.t1;
        self.x = x_new;
        self.stop_at(stop);
        Ok(self.outcome())
    }

    /// Completes an acceptable trial from `(t, x)` of size `h`: `complete`,
    /// and the dense output if the sink needs it; `true` if it was built
    /// and is finite. A dense output that is not finite (a method's extra
    /// stages outside the domain of `f`, an overflow) does not reject the
    /// trial, since asking for it must not change the steps: the step is
    /// then interpolated on its chord ([`Step::interpolate`] without a
    /// dense output).
    fn finish<M, K>(&mut self, m: &mut M, sink: &mut K, h: T, t_new: T) -> Result<bool, Failure>
    where
        M: Method<T, D>,
        K: Sink<T, D> + ?Sized,
    {
        let stats = &mut self.rec.stats;
        m.complete(t_new, stats)?;
        let dense = sink.wants_dense_at((self.t, &self.x), (t_new, m.x_new()));
        Ok(dense && m.build_dense(self.t, &self.x, h, stats))
    }

    /// Settles the end of the accepted step (projection, symmetric for a
    /// symmetric method's fixed step `symmetric` = (h, tolerance); chart;
    /// residual), hands the step to the sink and moves to its end; the method restarts
    /// there if the projection moved the state. `true` when a terminal
    /// event inside the step ended the run (at the event), also one found
    /// before an end that could not be settled.
    fn accept<M, K>(
        &mut self,
        m: &mut M,
        sink: &mut K,
        (t_new, symmetric): (T, Option<(T, &Tolerance<T, D>)>),
        dense: bool,
        last: bool,
    ) -> Result<bool, SimError<T, D>>
    where
        M: Method<T, D>,
        K: Sink<T, D> + ?Sized,
    {
        // a symmetric method's fixed step: its end projected symmetrically
        let shifted = match symmetric {
            Some((h, tol)) if self.project => self
                .symmetric_end(m, h, t_new, tol)
                .map_err(|f| f.at(self.t, self.x, h))?,
            _ => false,
        };
        let mut x_new = *m.x_new();
        let moved = match self.settle(t_new, &mut x_new) {
            Ok(moved) => moved || shifted,
            Err(e) if dense => {
                let step = Step::new(self.t, &self.x, t_new, m.x_new(), Some(m.dense()));
                let stop = if let SimError::Singular {
                    cause: Singularity::Pole(_),
                    ..
                } = e
                {
                    // Only the part of the step before the pole.
                    let (t_pole, x_pole) = self.before_pole(&step);
                    sink.salvage(&step.truncated(t_pole, &x_pole))
                } else {
                    sink.salvage(&step)
                };
                return if self.stop_at(stop) { Ok(true) } else { Err(e) };
            }
            Err(e) => return Err(e),
        };
        let poly = if dense { Some(m.dense()) } else { None };
        let stop = sink.step_or_stop(&Step::new(self.t, &self.x, t_new, &x_new, poly));
        if self.stop_at(stop) {
            return Ok(true);
        }
        self.t = t_new;
        self.x = x_new;
        let moved = sink.recentre(&mut self.x) || moved;
        let stats = &mut self.rec.stats;
        let next = if moved {
            m.advance_projected(t_new, &self.x, last, stats)
        } else {
            m.advance(t_new, &self.x, last, stats)
        };
        next.map(|()| false)
            .map_err(|f| f.at(t_new, self.x, T::zero()))
    }

    /// Ends the run at the terminal event `stop`, if there is one.
    fn stop_at(&mut self, stop: Option<EventHit<T, D>>) -> bool {
        let Some(hit) = stop else {
            return false;
        };
        (self.t, self.x, self.event) = (hit.t, hit.x, Some(hit));
        true
    }

    /// The fixed-step loop: step `k` ends at `t0 + k·h`, a remainder below a
    /// few ulps of `t` is merged into the last step; any failure ends the run.
    fn fixed<M, K>(
        &mut self,
        m: &mut M,
        s: &RunSettings<T, D>,
        h_abs: T,
        sink: &mut K,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        M: Method<T, D>,
        K: Sink<T, D> + ?Sized,
    {
        let (t0, t1, dir) = (self.t, self.t1, self.dir);
        let h = h_abs * dir;
        let tol = (c::<T>(64.0) * self.eps * (t0.abs() + t1.abs() + h_abs)).min(h_abs * c(0.5));
        let mut k: usize = 0;
        loop {
            let stats = &mut self.rec.stats;
            if stats.steps >= s.max_steps {
                return Err(self.max_steps());
            }
            k += 1;
            let mut t_new = t0 + h * c::<T>(k as f64);
            let last = (t1 - t_new) * dir <= tol;
            if last {
                t_new = t1;
            }
            let hk = t_new - self.t;
            if hk * dir <= T::zero() {
                return Err(SimError::StepSizeTooSmall {
                    t: self.t,
                    x: self.x,
                    h,
                });
            }
            self.h_try = hk;
            let fail = |f: Failure, r: &Self| f.at(r.t, r.x, hk);
            m.attempt(self.t, &self.x, hk, t_new, &s.tol, stats)
                .map_err(|f| fail(f, self))?;
            let dense = self.finish(m, sink, hk, t_new).map_err(|f| fail(f, self))?;
            self.rec.stats.steps += 1;
            self.rec.last_step = Some(h_abs);
            let symmetric = M::SYMMETRIC.then_some((hk, &s.tol));
            if self.accept(m, sink, (t_new, symmetric), dense, last)? || last {
                return Ok(self.outcome());
            }
        }
    }

    fn max_steps(&self) -> SimError<T, D> {
        SimError::MaxSteps {
            t: self.t,
            x: self.x,
            steps: self.rec.stats.steps + self.rec.stats.rejected,
        }
    }

    /// The first trial step of an adaptive run (signed): `initial` (capped
    /// at `hmax`) or Hairer's `hinit` from the method's derivative at `t0`.
    fn first_step<M: Method<T, D>>(&mut self, m: &M, s: &RunSettings<T, D>, hmax: T) -> T {
        let h = match (s.initial_step, m.slope()) {
            (Some(h0), _) => h0.min(hmax),
            (None, Some(f0)) => {
                let rhs = |t: T, x: &SVector<T, D>| m.rhs(t, x);
                let (tol, order) = (&s.tol, M::ORDER);
                let stats = &mut self.rec.stats;
                let (t, x, dir) = (self.t, &self.x, self.dir);
                initial_step(&rhs, stats, t, x, f0, dir, hmax, tol, order)
            }
            (None, None) => hmax,
        };
        h * self.dir
    }

    /// Where a trial of size `h` ends: `(h, t_new, last)`, stretched (by up
    /// to 1 %) or rounded onto `t1` when it would reach it.
    fn place(&self, h: T) -> (T, T, bool) {
        let (t, t1, dir) = (self.t, self.t1, self.dir);
        if (t + h * c::<T>(1.01) - t1) * dir > T::zero() || (t + h - t1) * dir >= T::zero() {
            (t1 - t, t1, true)
        } else {
            (h, t + h, false)
        }
    }

    /// The adaptive loop: PI control, rejections, budget and stiffness.
    fn adaptive<M, K>(
        &mut self,
        m: &mut M,
        s: &RunSettings<T, D>,
        sink: &mut K,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        M: Method<T, D>,
        K: Sink<T, D> + ?Sized,
    {
        let hmax = s.max_step.unwrap_or((self.t1 - self.t).abs());
        let mut h = self.first_step(m, s, hmax);
        let mut ctl = Controller::new(m.pi());
        let mut stiff = Stiffness {
            hlamb: None,
            iasti: 0,
            nonsti: 0,
        };
        let (mut nonfinite, mut singular) = (false, 0usize);
        loop {
            if self.rec.stats.steps + self.rec.stats.rejected >= s.max_steps {
                return Err(self.max_steps());
            }
            if !h.is_finite() || h.abs() < min_step(self.eps, self.t, self.t1) {
                return Err(if nonfinite {
                    SimError::NonFinite {
                        t: self.t,
                        x: self.x,
                    }
                } else {
                    SimError::StepSizeTooSmall {
                        t: self.t,
                        x: self.x,
                        h,
                    }
                });
            }
            let (hs, t_new, last) = self.place(h);
            h = hs;
            self.h_try = h;
            let stats = &mut self.rec.stats;
            let trial = m
                .attempt(self.t, &self.x, h, t_new, &s.tol, stats)
                .and_then(|err| {
                    if err.partial_cmp(&T::zero()).is_none() {
                        Err(Failure::NonFinite)
                    } else {
                        Ok(err)
                    }
                });
            singular = if trial == Err(Failure::Singular) {
                singular + 1
            } else {
                0
            };
            let outcome = trial.and_then(|err| {
                let (ok, h_new) = ctl.propose(err, h);
                if !ok {
                    return Ok((err, h_new, None));
                }
                self.finish(m, sink, h, t_new)
                    .map(|d| (err, h_new, Some(d)))
            });
            let (err, h_new, dense) = match outcome {
                Ok(v) => v,
                Err(Failure::Singular) if singular >= MAX_SINGULAR => {
                    return Err(Failure::Singular.at(self.t, self.x, h));
                }
                Err(f) => {
                    // A failed trial is retried with half the step.
                    nonfinite = f == Failure::NonFinite;
                    self.rec.stats.rejected += 1;
                    ctl.reject = true;
                    h *= c(0.5);
                    continue;
                }
            };
            nonfinite = false;
            let Some(dense) = dense else {
                self.rec.stats.rejected += 1;
                ctl.reject = true;
                h = m.proposed_step().unwrap_or(h_new);
                continue;
            };
            self.rec.stats.steps += 1;
            if stiff.test(m, self.rec.stats.steps, h) {
                self.rec.stats.stiffness_detected = true;
            }
            let h_accepted = h.abs();
            h = ctl.accepted(err, h, h_new, hmax, self.dir);
            self.rec.last_step = Some(h.abs());
            if self.accept(m, sink, (t_new, None), dense, last)? || last {
                return Ok(self.outcome());
            }
            if let Some(proposed) = m.proposed_step() {
                h = proposed.abs().min(hmax) * self.dir;
                self.rec.last_step = Some(h.abs());
            }
            if let Some(factor) = m.switched() {
                ctl = Controller::new(m.pi());
                h = (h_accepted * c(factor)).min(hmax) * self.dir;
                self.rec.last_step = Some(h.abs());
            }
        }
    }
}
