//! Automatic stiffness switching: Dormand–Prince while the problem is not
//! stiff, RODAS4 while it is, in one integration.

use nalgebra::{RealField, SMatrix, SVector};

use crate::ScalarTolerance;
use crate::Stats;
use crate::dopri5::Dopri5Stages;
use crate::jacobian::{Analytic, FiniteDifference, Linearised};
use crate::method::{Failure, Method, Pi};
use crate::numeric::c;
use crate::rodas4::rodas4;
use crate::settings::{Settings, adaptive_builders, integrator_impl, jacobian_entry_points};
use crate::step::Poly;
use crate::tolerance::Tolerance;

/// Consecutive accepted explicit steps held at the stability boundary
/// (`|h|·ρ > STIFF_FRACTION · STIFF_LIMIT`, Hairer's estimate of `ρ`) that
/// switch to the implicit member.
const TO_STIFF: usize = 5;
/// Consecutive accepted implicit steps with `|h|·ρ(J)` well inside the
/// explicit member's stability region that switch back.
const TO_NONSTIFF: usize = 5;
/// The share of the explicit member's `STIFF_LIMIT` above which an explicit
/// step counts as limited by stability.
const STIFF_FRACTION: f64 = 0.9;
/// The share of the explicit member's `STIFF_LIMIT` below which an implicit
/// step could as well have been explicit.
const NONSTIFF_FRACTION: f64 = 0.5;
/// The step after a switch to the implicit member is this multiple of the
/// last accepted one (its inverse after a switch back).
const STEP_FACTOR: f64 = 2.0;
/// Power iterations on the Jacobian per accepted implicit step.
const POWER_ITERATIONS: usize = 3;

/// Which member of [`AutoSwitch`] is stepping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Regime {
    /// The explicit member (Dormand–Prince 5(4)).
    NonStiff,
    /// The implicit member (RODAS4).
    Stiff,
}

/// A switch of [`AutoSwitch`]: from the accepted time `t` on, the steps
/// are taken by the member of regime `to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switch<T> {
    /// The time of the switch (the end of an accepted step).
    pub t: T,
    /// The regime switched to.
    pub to: Regime,
}

/// The switches of one run, the first [`AutoSwitch::LOG_CAPACITY`] of
/// them (all are counted in [`Stats`]); a fixed array, so no allocation.
/// Reset at the start of every call (the integrator's entry points reset
/// their further fields); a run over several charts builds its method once
/// per chart segment, and each starts in the regime of the last switch.
#[derive(Debug, Clone, Copy, PartialEq)]
struct SwitchLog<T> {
    entries: [Switch<T>; AutoSwitch::<f64>::LOG_CAPACITY],
    len: usize,
    /// The regime switched to last (also past the capacity).
    regime: Regime,
}

impl<T: RealField + Copy> Default for SwitchLog<T> {
    fn default() -> Self {
        SwitchLog {
            entries: [Switch {
                t: T::zero(),
                to: Regime::NonStiff,
            }; AutoSwitch::<f64>::LOG_CAPACITY],
            len: 0,
            regime: Regime::NonStiff,
        }
    }
}

impl<T: Copy> SwitchLog<T> {
    fn push(&mut self, switch: Switch<T>) {
        self.regime = switch.to;
        if let Some(slot) = self.entries.get_mut(self.len) {
            *slot = switch;
            self.len += 1;
        }
    }

    fn as_slice(&self) -> &[Switch<T>] {
        &self.entries[..self.len]
    }
}

/// Dormand–Prince 5(4) while the problem is not stiff, the L-stable
/// Rosenbrock method RODAS4 while it is, switching automatically in both
/// directions within one integration (the way LSODA switches between Adams
/// and BDF, or DifferentialEquations.jl's `AutoTsit5(Rosenbrock23())`).
///
/// * Non-stiff → stiff: after every accepted Dormand–Prince step, Hairer's
///   estimate `ρ ≈ ‖k7 − k6‖/‖x7 − x6‖` of the dominant eigenvalue (the
///   test behind [`Stats::stiffness_detected`] of [`Dopri5`](crate::Dopri5))
///   is taken; when `|h|·ρ` exceeds 0.9 × 3.25 (the step is held at the
///   method's stability boundary) on 5 consecutive accepted steps, RODAS4
///   takes over with twice the last step.
/// * Stiff → non-stiff: after every accepted RODAS4 step, the spectral
///   radius `ρ(J)` of the Jacobian it has just evaluated for its next step
///   is estimated by 3 power iterations (continued from step to step); when
///   `|h|·ρ(J)` stays below 0.5 × 3.25, well inside Dormand–Prince's
///   stability region, on 5 consecutive accepted steps, Dormand–Prince takes
///   over with half the last step.
/// * At a switch the step-size controller restarts with the new member's
///   (that of [`Dopri5`](crate::Dopri5) or
///   [`Rodas4`](crate::Rodas4)); each member keeps its own error
///   estimate, dense output and work per step. The run starts explicit.
/// * Jacobian: by forward differences with [`Integrator`](crate::Integrator)'s
///   methods, analytic with [`AutoSwitch::integrate_with_jacobian`]; only
///   the implicit member evaluates it.
/// * [`Stats::switches_to_stiff`], [`Stats::switches_to_nonstiff`] and
///   [`Stats::stiff_steps`] count the switches and the implicit steps
///   (the first switch to stiff also sets [`Stats::stiffness_detected`]);
///   [`AutoSwitch::last_switches`] gives the time and direction of each
///   switch of the most recent call.
///
/// A problem that is never stiff costs what [`Dopri5`](crate::Dopri5)
/// costs (the test reads values the method computes anyway); a stiff one
/// costs a few explicit steps more than [`Rodas4`](crate::Rodas4).
/// Tolerances, step budget and failure modes are those of the two members
/// and the shared step driver.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{AutoSwitch, Integrator, Regime};
///
/// // A slow mode relaxing onto a fast one that becomes stiff at t = 1:
/// // x1' = −x1, x2' = −k(t) (x2 − x1) with k rising from 1 to 1e5.
/// let sys = |t: f64, x: &Vector2<f64>| {
///     let k = if t < 1.0 { 1.0 } else { 1e5 };
///     Vector2::new(-x[0], -k * (x[1] - x[0]))
/// };
/// let mut auto = AutoSwitch::new(1e-6, 1e-9);
/// let out = auto.integrate(&sys, 0.0, Vector2::new(1.0, 0.0), 10.0).unwrap();
/// assert!((out.x[0] - (-10.0f64).exp()).abs() < 1e-8);
/// assert_eq!(out.stats.switches_to_stiff, 1);
/// let switch = auto.last_switches()[0];
/// assert_eq!(switch.to, Regime::Stiff);
/// assert!(switch.t > 1.0 && switch.t < 1.1);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutoSwitch<T, Tol = ScalarTolerance<T>> {
    a: Settings<T, Tol>,
    log: SwitchLog<T>,
}

adaptive_builders!(AutoSwitch, log);
integrator_impl!(AutoSwitch<T, Tol>, a, |sys, log| Switching::new(
    Dopri5Stages::new(sys),
    rodas4(FiniteDifference(sys)),
    log
));

/// AutoSwitch is a one-step method.
impl<T, Tol> crate::settings::OneStep for AutoSwitch<T, Tol> {
    const ONE_STEP: bool = true;
}

jacobian_entry_points! {
    AutoSwitch<T, Tol>, a, |sys, log| Switching::new(Dopri5Stages::new(sys), rodas4(Analytic(sys)), log),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but the
    /// implicit member uses the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of
    /// finite differences.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{AutoSwitch, OdeJacobian, OdeSystem};
    ///
    /// /// A stiff linear system with eigenvalues −1 and −1e4.
    /// struct TwoScales;
    /// impl OdeSystem<f64, 2> for TwoScales {
    ///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    ///         Vector2::new(-x[0], -1e4 * (x[1] - x[0]))
    ///     }
    /// }
    /// impl OdeJacobian<f64, 2> for TwoScales {
    ///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
    ///         Matrix2::new(-1.0, 0.0, 1e4, -1e4)
    ///     }
    /// }
    ///
    /// let mut auto = AutoSwitch::new(1e-8, 1e-10);
    /// let out = auto.integrate_with_jacobian(&TwoScales, 0.0, Vector2::new(1.0, 0.0), 5.0).unwrap();
    /// assert!((out.x[0] - (-5.0f64).exp()).abs() < 1e-8);
    /// // Explicit through the transient, then implicit to the end.
    /// assert_eq!(out.stats.switches_to_stiff, 1);
    /// assert_eq!(out.stats.switches_to_nonstiff, 0);
    /// assert!(out.stats.stiff_steps > out.stats.steps / 2);
    /// ```
    integrate_with_jacobian;
    /// Like [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps),
    /// but the implicit member uses the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of
    /// finite differences.
    integrate_with_jacobian_and_steps;
}

impl<T: RealField + Copy, Tol> AutoSwitch<T, Tol> {
    /// How many switches [`AutoSwitch::last_switches`] records per call
    /// (further ones are only counted in [`Stats`]).
    pub const LOG_CAPACITY: usize = 64;

    /// The switches of the most recent call, in order (also of a call that
    /// failed, up to its failure).
    ///
    /// ```rust
    /// use nalgebra::Vector1;
    /// use nh_runtime::{AutoSwitch, Integrator};
    ///
    /// let decay = |_t: f64, x: &Vector1<f64>| -x;
    /// let mut auto = AutoSwitch::new(1e-6, 1e-9);
    /// auto.integrate(&decay, 0.0, Vector1::new(1.0), 1.0).unwrap();
    /// assert!(auto.last_switches().is_empty());
    /// ```
    pub fn last_switches(&self) -> &[Switch<T>] {
        self.log.as_slice()
    }
}

/// The switching method: an explicit member `E` and an implicit member
/// `I`, one of which steps at a time.
struct Switching<'l, E, I, T, const D: usize> {
    explicit: E,
    implicit: I,
    stiff: bool,
    /// Consecutive accepted steps that voted for the other regime.
    votes: usize,
    /// The size of the last trial step.
    h: T,
    /// The power iteration's vector (kept from step to step).
    probe: SVector<T, D>,
    /// The step factor of a switch at the last accepted point.
    switched: Option<f64>,
    log: &'l mut SwitchLog<T>,
}

impl<'l, E, I, T, const D: usize> Switching<'l, E, I, T, D>
where
    T: RealField + Copy,
    E: Method<T, D>,
    I: Linearised<T, D>,
{
    /// The switching method, starting in the regime `log` switched to last
    /// (a fresh log: the explicit member).
    fn new(explicit: E, implicit: I, log: &'l mut SwitchLog<T>) -> Self {
        Switching {
            explicit,
            implicit,
            stiff: log.regime == Regime::Stiff,
            votes: 0,
            h: T::zero(),
            probe: first_probe(),
            switched: None,
            log,
        }
    }

    /// Counts a vote for the other regime (`yes`) or resets the count;
    /// `true` once `needed` consecutive votes are in.
    fn vote(&mut self, yes: bool, needed: usize) -> bool {
        self.votes = if yes { self.votes + 1 } else { 0 };
        self.votes >= needed
    }

    /// Records a switch at `t` to `to`, with the next step `factor` times
    /// the last one.
    fn switch(&mut self, t: T, to: Regime, factor: f64) {
        self.stiff = to == Regime::Stiff;
        self.votes = 0;
        self.switched = Some(factor);
        self.log.push(Switch { t, to });
    }

    /// After an accepted explicit step: switches to the implicit member at
    /// `(t, x)` if the step was held at the stability boundary long enough
    /// (and stays explicit if the implicit member cannot start there).
    fn consider_stiff(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) {
        let Some(limit) = E::STIFF_LIMIT else { return };
        let bound = c::<T>(STIFF_FRACTION * limit);
        let held = (self.explicit.stiffness_ratio()).is_some_and(|r| self.h.abs() * r > bound);
        if self.vote(held, TO_STIFF) && self.implicit.start(t, x, stats).is_ok() {
            stats.switches_to_stiff += 1;
            stats.stiffness_detected = true;
            self.switch(t, Regime::Stiff, STEP_FACTOR);
        }
    }

    /// After an accepted implicit step: switches to the explicit member at
    /// `(t, x)` if its steps were well inside the explicit stability region
    /// long enough.
    fn consider_nonstiff(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        let Some(limit) = E::STIFF_LIMIT else {
            return Ok(());
        };
        let rho = spectral_radius(self.implicit.jacobian(), &mut self.probe);
        let inside = self.h.abs() * rho < c(NONSTIFF_FRACTION * limit);
        if self.vote(inside, TO_NONSTIFF) {
            self.explicit.start(t, x, stats)?;
            stats.switches_to_nonstiff += 1;
            self.switch(t, Regime::NonStiff, 1.0 / STEP_FACTOR);
        }
        Ok(())
    }
}

/// The power iteration's first vector: no special direction.
fn first_probe<T: RealField + Copy, const D: usize>() -> SVector<T, D> {
    SVector::from_fn(|i, _| c::<T>(if i % 2 == 0 { 1.0 } else { -0.5 } + 0.1 * i as f64))
}

/// An estimate of the spectral radius of `jac`: the largest `‖J v‖/‖v‖`
/// over [`POWER_ITERATIONS`] steps of the power iteration from `v`, which
/// is left at the last iterate. (The largest ratio, because around a
/// complex pair the ratios oscillate about `|λ|` instead of converging.)
fn spectral_radius<T: RealField + Copy, const D: usize>(
    jac: &SMatrix<T, D, D>,
    v: &mut SVector<T, D>,
) -> T {
    let mut rho = T::zero();
    for _ in 0..POWER_ITERATIONS {
        let norm = v.norm();
        if !(norm > T::zero() && norm.is_finite()) {
            *v = first_probe();
            continue;
        }
        *v = jac * (*v / norm);
        rho = rho.max(v.norm());
    }
    rho
}

impl<E, I, T, const D: usize> Method<T, D> for Switching<'_, E, I, T, D>
where
    T: RealField + Copy,
    E: Method<T, D>,
    I: Linearised<T, D>,
{
    const ORDER: u32 = E::ORDER;
    const PI: Pi = E::PI;

    fn pi(&self) -> Pi {
        if self.stiff { I::PI } else { E::PI }
    }

    fn switched(&self) -> Option<f64> {
        self.switched
    }

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.explicit.rhs(t, x)
    }

    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        if self.stiff {
            self.implicit.start(t, x, stats)
        } else {
            self.explicit.start(t, x, stats)
        }
    }

    fn slope(&self) -> Option<&SVector<T, D>> {
        if self.stiff {
            self.implicit.slope()
        } else {
            self.explicit.slope()
        }
    }

    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        self.h = h;
        if self.stiff {
            self.implicit.attempt(t, x, h, t_new, tol, stats)
        } else {
            self.explicit.attempt(t, x, h, t_new, tol, stats)
        }
    }

    /// Completes the trial; an implicit one counts as a stiff step (taken
    /// back if its dense output fails).
    fn complete(&mut self, t_new: T, stats: &mut Stats) -> Result<(), Failure> {
        if self.stiff {
            self.implicit.complete(t_new, stats)?;
            stats.stiff_steps += 1;
            Ok(())
        } else {
            self.explicit.complete(t_new, stats)
        }
    }

    fn x_new(&self) -> &SVector<T, D> {
        if self.stiff {
            self.implicit.x_new()
        } else {
            self.explicit.x_new()
        }
    }

    fn build_dense(&mut self, t: T, x: &SVector<T, D>, h: T, stats: &mut Stats) -> bool {
        if !self.stiff {
            return self.explicit.build_dense(t, x, h, stats);
        }
        let ok = self.implicit.build_dense(t, x, h, stats);
        if !ok {
            stats.stiff_steps = stats.stiff_steps.saturating_sub(1);
        }
        ok
    }

    fn dense(&self) -> &Poly<T, D> {
        if self.stiff {
            self.implicit.dense()
        } else {
            self.explicit.dense()
        }
    }

    fn advance(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        self.switched = None;
        if self.stiff {
            self.implicit.advance(t, x, last, stats)?;
            if !last {
                self.consider_nonstiff(t, x, stats)?;
            }
        } else {
            self.explicit.advance(t, x, last, stats)?;
            if !last {
                self.consider_stiff(t, x, stats);
            }
        }
        Ok(())
    }
}
