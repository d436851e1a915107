//! Results of an integration: [`Outcome`], [`Stats`] and [`SimError`].

use core::fmt;

use nalgebra::{RealField, SVector};

use crate::EventHit;

/// Work counters of one integration call.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Integrator, Rk4};
///
/// let decay = |_t: f64, x: &Vector1<f64>| -x;
/// let out = Rk4::new(0.25).integrate(&decay, 0.0, Vector1::new(1.0), 1.0).unwrap();
/// assert_eq!(out.stats.steps, 4);
/// assert_eq!(out.stats.rhs_evals, 16);
/// assert_eq!(out.stats.rejected, 0);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Stats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected step attempts (error too large, or a non-finite trial state).
    pub rejected: usize,
    /// Evaluations of [`OdeSystem::rhs`](crate::OdeSystem::rhs).
    pub rhs_evals: usize,
    /// Jacobian evaluations of the implicit methods: calls of
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) when the
    /// analytic Jacobian is used, finite-difference Jacobians otherwise (whose
    /// `D` (+1) right-hand side evaluations are also counted in
    /// [`Stats::rhs_evals`]). Always 0 for the explicit methods.
    pub jacobian_evals: usize,
    /// Whether the integrator's stiffness test fired (only
    /// [`Dopri5`](crate::Dopri5) and [`Dop853`](crate::Dop853)
    /// perform one, and only under error control, not with
    /// `with_fixed_step`). The integration still continues; a stiff problem
    /// is merely slow for an explicit method. [`AutoSwitch`](crate::AutoSwitch)
    /// sets it at its first switch to the implicit member.
    pub stiffness_detected: bool,
    /// Newton iterations (implicit Runge–Kutta methods such as
    /// [`GaussLegendre4`](crate::GaussLegendre4); 0 for the others).
    pub newton_iterations: usize,
    /// LU decompositions of iteration matrices (implicit methods; 0 for the
    /// explicit ones).
    pub lu_decompositions: usize,
    /// Evaluations of the event functions
    /// ([`Integrator::integrate_with_events`](crate::Integrator::integrate_with_events);
    /// 0 for the other entry points).
    pub event_evals: usize,
    /// Switches from the explicit to the implicit member of
    /// [`AutoSwitch`](crate::AutoSwitch) (0 for the other integrators).
    pub switches_to_stiff: usize,
    /// Switches from the implicit back to the explicit member of
    /// [`AutoSwitch`](crate::AutoSwitch).
    pub switches_to_nonstiff: usize,
    /// Accepted steps taken by the implicit member of
    /// [`AutoSwitch`](crate::AutoSwitch); the explicit member took
    /// `steps − stiff_steps`.
    pub stiff_steps: usize,
    /// Switches from one chart of the system's atlas to another
    /// ([`OdeSystem::charts`](crate::OdeSystem::charts), DESIGN §6.7): all
    /// of them, also past the capacity of [`Outcome::switches`]. 0 for a
    /// system with one chart.
    pub chart_switches: usize,
}

impl Stats {
    /// Adds the counters of `other` (a later segment of the same run, see
    /// DESIGN §6.7) to these; stiffness counts as detected if either saw
    /// it. [`Stats::chart_switches`] is the run's, not a segment's: kept.
    pub(crate) fn add(&mut self, other: &Stats) {
        self.steps += other.steps;
        self.rejected += other.rejected;
        self.rhs_evals += other.rhs_evals;
        self.jacobian_evals += other.jacobian_evals;
        self.stiffness_detected |= other.stiffness_detected;
        self.newton_iterations += other.newton_iterations;
        self.lu_decompositions += other.lu_decompositions;
        self.event_evals += other.event_evals;
        self.switches_to_stiff += other.switches_to_stiff;
        self.switches_to_nonstiff += other.switches_to_nonstiff;
        self.stiff_steps += other.stiff_steps;
    }
}

/// A successful integration: the final time and state, plus work counters.
///
/// `t` equals the requested end time exactly, unless a terminal event
/// ([`Integrator::integrate_with_events`](crate::Integrator::integrate_with_events))
/// ended the run earlier: then `t` and `x` are the event's, and
/// [`Outcome::event`] says which.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Dopri5, Integrator};
///
/// let decay = |_t: f64, x: &Vector1<f64>| -x;
/// let out = Dopri5::new(1e-9, 1e-12)
///     .integrate(&decay, 0.0, Vector1::new(1.0), 1.0)
///     .unwrap();
/// assert_eq!(out.t, 1.0);
/// assert!((out.x[0] - (-1.0f64).exp()).abs() < 1e-8);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome<T, const D: usize> {
    /// Final time: the requested `t1`, or the time of the terminal event
    /// that ended the run.
    pub t: T,
    /// State at `t`.
    pub x: SVector<T, D>,
    /// Work counters.
    pub stats: Stats,
    /// The largest holonomic-constraint residual
    /// ([`OdeSystem::constraint_residual`](crate::OdeSystem::constraint_residual))
    /// over the initial state and every accepted state (after projection,
    /// when it is on); `None` for a system without holonomic constraints.
    pub max_residual: Option<T>,
    /// The terminal event that ended the run before `t1`, if one did.
    pub event: Option<EventHit<T, D>>,
    /// The switches between the charts of the system's atlas, in order
    /// (empty for a system with one chart); see [`ChartSwitches`].
    pub switches: ChartSwitches<T>,
}

/// One switch of chart during a run: from time `t` on the integrator
/// worked in chart `to` instead of chart `from` (see
/// [`OdeSystem::charts`](crate::OdeSystem::charts)).
///
/// # Example
///
/// ```rust
/// use nh_runtime::ChartSwitch;
///
/// let s = ChartSwitch { t: 1.2, from: 0, to: 1 };
/// assert_eq!((s.from, s.to), (0, 1));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChartSwitch<T> {
    /// The time of the switch: the last good state of the chart left.
    pub t: T,
    /// The chart left.
    pub from: usize,
    /// The chart taken.
    pub to: usize,
}

/// The chart switches of one run: the first
/// [`ChartSwitches::CAPACITY`] (32) of them in order, and how many there
/// were in all. A fixed array (`Copy`, no allocation), so that an
/// [`Outcome`] stays on the stack.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Dopri5, Integrator};
///
/// // A system with one chart never switches.
/// let decay = |_t: f64, x: &Vector1<f64>| -x;
/// let out = Dopri5::new(1e-8, 1e-10).integrate(&decay, 0.0, Vector1::new(1.0), 1.0).unwrap();
/// assert!(out.switches.is_empty());
/// assert_eq!((out.switches.len(), out.switches.total()), (0, 0));
/// assert_eq!(out.switches.iter().count(), 0);
/// ```
#[derive(Clone, Copy)]
pub struct ChartSwitches<T> {
    entries: [ChartSwitch<T>; CAPACITY],
    total: usize,
}

/// [`ChartSwitches::CAPACITY`].
const CAPACITY: usize = 32;

impl<T: RealField + Copy> ChartSwitches<T> {
    /// No switches.
    pub fn new() -> Self {
        ChartSwitches {
            entries: [ChartSwitch {
                t: T::zero(),
                from: 0,
                to: 0,
            }; CAPACITY],
            total: 0,
        }
    }
}

impl<T: RealField + Copy> Default for ChartSwitches<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T> ChartSwitches<T> {
    /// How many switches are recorded (at most 32); [`ChartSwitches::total`]
    /// counts them all.
    pub const CAPACITY: usize = CAPACITY;

    /// The number of recorded switches, `min(total, CAPACITY)`.
    pub fn len(&self) -> usize {
        self.total.min(CAPACITY)
    }

    /// Whether the run switched no chart.
    pub fn is_empty(&self) -> bool {
        self.total == 0
    }

    /// The number of switches of the run, also those past the capacity.
    pub fn total(&self) -> usize {
        self.total
    }

    /// The recorded switches, in order.
    pub fn as_slice(&self) -> &[ChartSwitch<T>] {
        &self.entries[..self.len()]
    }

    /// The recorded switches, in order.
    pub fn iter(&self) -> core::slice::Iter<'_, ChartSwitch<T>> {
        self.as_slice().iter()
    }

    /// Records a switch (counted also past the capacity).
    pub(crate) fn push(&mut self, switch: ChartSwitch<T>) {
        if let Some(slot) = self.entries.get_mut(self.total) {
            *slot = switch;
        }
        self.total += 1;
    }

    /// Forgets every switch.
    pub(crate) fn clear(&mut self) {
        self.total = 0;
    }
}

impl<'a, T> IntoIterator for &'a ChartSwitches<T> {
    type Item = &'a ChartSwitch<T>;
    type IntoIter = core::slice::Iter<'a, ChartSwitch<T>>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// Equal when the same switches are recorded and as many were made.
impl<T: PartialEq> PartialEq for ChartSwitches<T> {
    fn eq(&self, other: &Self) -> bool {
        self.total == other.total && self.as_slice() == other.as_slice()
    }
}

impl<T: fmt::Debug> fmt::Debug for ChartSwitches<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ChartSwitches")
            .field("total", &self.total)
            .field("recorded", &self.as_slice())
            .finish()
    }
}

/// What was singular when a run ended in [`SimError::Singular`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Singularity {
    /// The iteration matrix of an implicit method (Newton or Rosenbrock)
    /// is singular to working precision.
    IterationMatrix,
    /// The chart of the equations is singular: the system's
    /// [`chart_regularity`](crate::OdeSystem::chart_regularity) vanished or
    /// changed sign (a dependent-velocity block or a reduced mass matrix
    /// lost rank). Choose other dependent coordinates or other speeds.
    Chart,
    /// A pole or domain edge of the system's equations lies inside the step: the
    /// expression (as written in the system) whose guard changed sign or reached zero.
    ///
    /// Reported by the system's
    /// [`crossed_pole`](crate::OdeSystem::crossed_pole) after a step, or for
    /// a run that failed otherwise on a step whose explicit Euler predictor
    /// crosses the pole; the error's state is the last one before it.
    Pole(&'static str),
}

/// Why an integration failed.
///
/// Every variant that happens after integration started carries the last
/// *good* (finite, accepted) time and state, so a caller can inspect or
/// restart from there; see [`SimError::time`] and [`SimError::state`].
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Integrator, Rk4, SimError};
///
/// // x' = x^2, x(0) = 1 blows up at t = 1.
/// let blow_up = |_t: f64, x: &Vector1<f64>| x.component_mul(x);
/// let err = Rk4::new(0.01).integrate(&blow_up, 0.0, Vector1::new(1.0), 2.0).unwrap_err();
/// assert!(matches!(err, SimError::NonFinite { .. }));
/// assert!(err.state().unwrap()[0].is_finite());
/// assert!(err.time().unwrap() > 0.9);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimError<T, const D: usize> {
    /// The right-hand side or the state became NaN or infinite and the
    /// integrator could not recover. `x` is the last good state, at `t`.
    NonFinite {
        /// Time of the last good state.
        t: T,
        /// Last good state.
        x: SVector<T, D>,
    },
    /// The adaptive step size fell below the resolution of `t` (about
    /// `10 * eps * |t|`, at least `10 * eps² * |t1|`), or a fixed step no
    /// longer advances `t`.
    StepSizeTooSmall {
        /// Time of the last good state.
        t: T,
        /// Last good state.
        x: SVector<T, D>,
        /// The step size that was too small.
        h: T,
    },
    /// The step budget (`with_max_steps`) was used up before reaching `t1`.
    MaxSteps {
        /// Time of the last good state.
        t: T,
        /// Last good state.
        x: SVector<T, D>,
        /// Step attempts made (accepted plus rejected).
        steps: usize,
    },
    /// The Newton iteration for the stages of an implicit method
    /// ([`GaussLegendre4`](crate::GaussLegendre4)) did not converge, even
    /// with a fresh Jacobian: the fixed step `h` is too large for the
    /// problem at `t`. Reduce `h`.
    NoConvergence {
        /// Time of the last good state.
        t: T,
        /// Last good state.
        x: SVector<T, D>,
        /// The step whose stage equations could not be solved.
        h: T,
    },
    /// A linear system could not be solved, or the equations are not
    /// defined: an implicit method's iteration matrix, the system's own
    /// equations at a singularity of their chart, or a pole or domain edge
    /// of the equations that the next step would cross (see `cause`).
    Singular {
        /// Time of the last good state.
        t: T,
        /// Last good state.
        x: SVector<T, D>,
        /// What was singular.
        cause: Singularity,
    },
    /// Projecting an accepted state onto the holonomic constraints
    /// ([`OdeSystem::project`](crate::OdeSystem::project)) did not converge.
    ProjectionFailed {
        /// Time of the last good state.
        t: T,
        /// Last good state (before the step whose end could not be projected).
        x: SVector<T, D>,
        /// The constraint residual the projection reached.
        residual: T,
    },
    /// The relative tolerance is below what the method can deliver in the
    /// scalar type (rounding, not truncation, would set the error); nothing
    /// was integrated. `t` and `x` are the start; rerun with
    /// `rtol ≥ rtol_min`.
    ToleranceTooTight {
        /// The start time.
        t: T,
        /// The start state.
        x: SVector<T, D>,
        /// The smallest relative tolerance the method accepts.
        rtol_min: T,
    },
    /// The arguments or the integrator's settings are invalid; nothing was
    /// integrated. `what` names the offending value.
    InvalidInput {
        /// Human-readable description of the invalid value.
        what: &'static str,
    },
}

impl<T: Copy, const D: usize> SimError<T, D> {
    /// Time of the last good state, or `None` for [`SimError::InvalidInput`].
    pub fn time(&self) -> Option<T> {
        match self {
            Self::NonFinite { t, .. }
            | Self::StepSizeTooSmall { t, .. }
            | Self::MaxSteps { t, .. }
            | Self::NoConvergence { t, .. }
            | Self::Singular { t, .. }
            | Self::ProjectionFailed { t, .. }
            | Self::ToleranceTooTight { t, .. } => Some(*t),
            Self::InvalidInput { .. } => None,
        }
    }

    /// Last good state, or `None` for [`SimError::InvalidInput`].
    pub fn state(&self) -> Option<&SVector<T, D>> {
        match self {
            Self::NonFinite { x, .. }
            | Self::StepSizeTooSmall { x, .. }
            | Self::MaxSteps { x, .. }
            | Self::NoConvergence { x, .. }
            | Self::Singular { x, .. }
            | Self::ProjectionFailed { x, .. }
            | Self::ToleranceTooTight { x, .. } => Some(x),
            Self::InvalidInput { .. } => None,
        }
    }
}

impl<T: fmt::Display, const D: usize> fmt::Display for SimError<T, D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite { t, .. } => {
                write!(f, "state or derivative became non-finite after t = {t}")
            }
            Self::StepSizeTooSmall { t, h, .. } => {
                write!(f, "step size {h} too small at t = {t}")
            }
            Self::MaxSteps { t, steps, .. } => {
                write!(f, "maximum number of steps ({steps}) reached at t = {t}")
            }
            Self::NoConvergence { t, h, .. } => write!(
                f,
                "the Newton iteration for the implicit stages did not converge at t = {t}: \
                 the step h = {h} is too large for this problem; reduce h"
            ),
            Self::Singular {
                t,
                cause: Singularity::IterationMatrix,
                ..
            } => write!(f, "singular iteration matrix at t = {t}"),
            Self::Singular {
                t,
                cause: Singularity::Chart,
                ..
            } => write!(
                f,
                "the equations' chart is singular after t = {t}: the dependent velocities \
                 or the reduced mass matrix lose rank there; choose other dependent \
                 coordinates or other speeds"
            ),
            Self::Singular {
                t,
                cause: Singularity::Pole(expr),
                ..
            } => write!(
                f,
                "the step after t = {t} crosses a pole or domain edge of the equations: \
                 `{expr}` is undefined there"
            ),
            Self::ProjectionFailed { t, residual, .. } => write!(
                f,
                "projection onto the holonomic constraints did not converge after t = {t} \
                 (residual {residual})"
            ),
            Self::ToleranceTooTight { rtol_min, .. } => write!(
                f,
                "the relative tolerance is below what this method resolves in this scalar \
                 type (rounding would dominate the error); use rtol >= {rtol_min}"
            ),
            Self::InvalidInput { what } => write!(f, "invalid input: {what}"),
        }
    }
}

#[cfg(feature = "std")]
impl<T: fmt::Debug + fmt::Display, const D: usize> std::error::Error for SimError<T, D> {}
