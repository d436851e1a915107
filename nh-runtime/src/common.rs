//! Numeric helpers shared by all integrators (one place, no duplication).

use nalgebra::{RealField, SVector};

use crate::driver::{Control, Method, Record, Settings, Tolerance, drive};
use crate::sink::Sink;
pub(crate) use crate::tolerance::{error_norm, scaled};
use crate::{ErrorTolerance, OdeSystem, Outcome, ScalarTolerance, SimError, Stats};

/// Converts an `f64` constant to `T`.
#[inline(always)]
pub(crate) fn c<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert::<f64, T>(x)
}

/// Machine epsilon of `T`: the smallest power of two `e` with `1 + e > 1`.
///
/// Computed rather than looked up, because `RealField` does not expose it.
pub(crate) fn machine_epsilon<T: RealField + Copy>() -> T {
    let one = T::one();
    let half = c::<T>(0.5);
    let mut eps = one;
    // The iteration cap only matters for exotic number types.
    for _ in 0..2048 {
        let next = eps * half;
        if one + next <= one {
            break;
        }
        eps = next;
    }
    eps
}

/// Whether every component of `x` is finite, without a branch per
/// component (`0·v` is `0` for a finite `v` and NaN otherwise).
#[inline]
pub(crate) fn all_finite<T: RealField + Copy, const D: usize>(x: &SVector<T, D>) -> bool {
    x.iter().fold(T::zero(), |zero, &v| zero + v * T::zero()) == T::zero()
}

/// `x + (Σ_j a_j·k_{s_j})·h` for the stages and weights `terms = [(s_j,
/// a_j)]` of an explicit Runge–Kutta step, summed left to right as in the
/// formulas of Hairer's codes, component by component (no temporary vector
/// per term; the same rounding as the vector expression).
#[inline(always)]
pub(crate) fn stage_point<T: RealField + Copy, const D: usize, const M: usize, const N: usize>(
    x: &SVector<T, D>,
    k: &[SVector<T, D>; M],
    terms: [(usize, f64); N],
    h: T,
) -> SVector<T, D> {
    let mut point = *x;
    for (i, p) in point.iter_mut().enumerate() {
        let mut sum = k[terms[0].0][i] * c::<T>(terms[0].1);
        for &(s, a) in &terms[1..] {
            sum += k[s][i] * c::<T>(a);
        }
        *p += sum * h;
    }
    point
}

/// Whether every component of every vector in `vs` is finite, without a
/// branch per component: `0·v` is `0` for a finite `v` and NaN otherwise,
/// so the sum of `0·v_i` over the vectors is zero exactly when all of them
/// are finite (the stage checks of every step go through here).
#[inline]
pub(crate) fn all_finite_in<T: RealField + Copy, const D: usize>(vs: &[SVector<T, D>]) -> bool {
    let mut zero = SVector::<T, D>::zeros();
    for v in vs {
        zero += v * T::zero();
    }
    all_finite(&zero)
}

/// Validates the arguments common to every integrator and returns the
/// direction of integration (`+1` or `-1`, or `0` when `t1 == t0`).
pub(crate) fn check_arguments<T: RealField + Copy, const D: usize>(
    t0: T,
    x0: &SVector<T, D>,
    t1: T,
) -> Result<T, SimError<T, D>> {
    if !t0.is_finite() {
        return Err(SimError::InvalidInput {
            what: "t0 must be finite",
        });
    }
    if !t1.is_finite() {
        return Err(SimError::InvalidInput {
            what: "t1 must be finite",
        });
    }
    if !all_finite(x0) {
        return Err(SimError::InvalidInput {
            what: "x0 must be finite",
        });
    }
    Ok(if t1 > t0 {
        T::one()
    } else if t1 < t0 {
        -T::one()
    } else {
        T::zero()
    })
}

/// Returns `Ok(())` if `v` is finite and positive, else `InvalidInput`.
pub(crate) fn check_positive<T: RealField + Copy, const D: usize>(
    v: T,
    what: &'static str,
) -> Result<(), SimError<T, D>> {
    if v.is_finite() && v > T::zero() {
        Ok(())
    } else {
        Err(SimError::InvalidInput { what })
    }
}

/// The smallest step magnitude an adaptive method may take at `t`:
/// `10·eps·|t|` (the resolution of `t`, as in Hairer's codes), floored at
/// `10·eps²·|t1|` so that it stays positive near `t = 0` without stopping
/// short initial transients of long integrations, and at
/// `1 / (eps·T::MAX)` (about 2.5e-293 in `f64`) so that it never underflows
/// and `1/h` stays finite. A span below it is covered in one Euler step.
pub(crate) fn min_step<T: RealField + Copy>(eps: T, t: T, t1: T) -> T {
    let floor = T::max_value().map_or(T::zero(), |max| T::one() / (max * eps));
    (c::<T>(10.0) * eps * t.abs().max(eps * t1.abs())).max(floor)
}

/// Hairer's `hinit`: a first step magnitude for a method of order `order`
/// from `f0 = f(t, x)` and one explicit Euler probe step (one evaluation of
/// the right-hand side, counted in `stats`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<T, S, const D: usize>(
    sys: &S,
    stats: &mut Stats,
    t: T,
    x: &SVector<T, D>,
    f0: &SVector<T, D>,
    dir: T,
    hmax: T,
    tol: &Tolerance<T, D>,
    order: u32,
) -> T
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    let sk = tol.weights_at(x);
    let ratio = |v: &SVector<T, D>| v.zip_map(&sk, scaled).norm_squared();
    let (dnf, dny) = (ratio(f0), ratio(x));
    let tiny = c::<T>(1e-10);
    let mut h = if dnf <= tiny || dny <= tiny || !(dnf / dny).is_finite() {
        c::<T>(1e-6)
    } else {
        (dny / dnf).sqrt() * c::<T>(0.01)
    };
    h = h.min(hmax);
    // One explicit Euler step to estimate the second derivative.
    let x1 = x + f0 * (h * dir);
    let f1 = sys.rhs(t + h * dir, &x1);
    stats.rhs_evals += 1;
    let der2 = ratio(&(f1 - f0)).sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if !(der2.is_finite() && der12.is_finite()) {
        // The probe step produced garbage: stay cautious.
        h * c::<T>(1e-3)
    } else if der12 <= c::<T>(1e-15) {
        c::<T>(1e-6).max(h * c::<T>(1e-3))
    } else {
        (c::<T>(0.01) / der12).powf(T::one() / c::<T>(f64::from(order)))
    };
    (h * c::<T>(100.0)).min(h1).min(hmax)
}

/// The default step budget of the adaptive integrators (attempts).
pub(crate) const ADAPTIVE_MAX_STEPS: usize = 100_000;
/// The default step budget of the fixed-step integrators (steps).
pub(crate) const FIXED_MAX_STEPS: usize = 1_000_000;

/// The settings and bookkeeping every adaptive integrator has (tolerances,
/// step limits, the counters of the last call); see the builder methods that
/// [`adaptive_builders`] gives each of them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Adaptive<T, Tol = ScalarTolerance<T>> {
    pub(crate) tol: Tol,
    pub(crate) max_steps: usize,
    pub(crate) initial_step: Option<T>,
    pub(crate) max_step: Option<T>,
    pub(crate) fixed_step: Option<T>,
    pub(crate) project: bool,
    pub(crate) record: Record<T>,
}

impl<T: RealField + Copy> Adaptive<T> {
    /// Tolerances `rtol`, `atol`; at most 100 000 step attempts.
    pub(crate) fn new(rtol: T, atol: T) -> Self {
        Adaptive {
            tol: ScalarTolerance::new(rtol, atol),
            max_steps: ADAPTIVE_MAX_STEPS,
            initial_step: None,
            max_step: None,
            fixed_step: None,
            project: true,
            record: Record::default(),
        }
    }

    /// The settings of a fixed-step integrator: step `h`, at most
    /// [`FIXED_MAX_STEPS`] steps (the tolerances are not used).
    pub(crate) fn fixed(h: T) -> Self {
        Adaptive {
            max_steps: FIXED_MAX_STEPS,
            fixed_step: Some(h),
            ..Adaptive::new(T::one(), T::one())
        }
    }
}

impl<T: RealField + Copy, Tol: ErrorTolerance<T>> Adaptive<T, Tol> {
    /// These settings with the tolerance `tol` instead.
    pub(crate) fn with_tolerance<U: ErrorTolerance<T>>(self, tol: U) -> Adaptive<T, U> {
        Adaptive {
            tol,
            max_steps: self.max_steps,
            initial_step: self.initial_step,
            max_step: self.max_step,
            fixed_step: self.fixed_step,
            project: self.project,
            record: self.record,
        }
    }

    /// The settings of a run in dimension `D`: the tolerances per
    /// component, each positive `rtol_i` below `10·eps` (the smallest
    /// relative error the scalar can resolve in a step) raised to `10·eps`;
    /// tolerances for another dimension are `InvalidInput` (and clear the
    /// counters of the previous run).
    pub(crate) fn settings<const D: usize>(&mut self) -> Result<Settings<T, D>, SimError<T, D>> {
        let Some(tol) = self.tol.for_dimension::<D>() else {
            self.record = Record::default();
            return Err(SimError::InvalidInput {
                what: "the per-component tolerances have another dimension than the state",
            });
        };
        Ok(Settings {
            control: match self.fixed_step {
                Some(h) => Control::Fixed(h),
                None => Control::Adaptive,
            },
            tol: tol.floored(c::<T>(10.0) * machine_epsilon::<T>()),
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            project: self.project,
        })
    }

    /// Runs `method` under these settings with its step-size controller
    /// (or the fixed step of `with_fixed_step`). A positive `rtol`
    /// below the method's [`Method::MIN_RTOL_EPS`] ends the run in
    /// `ToleranceTooTight`; otherwise one below `10·eps` is raised to
    /// `10·eps`, the smallest relative error the scalar can resolve in a step.
    pub(crate) fn run<M, H, K, const D: usize>(
        &mut self,
        method: &mut M,
        sys: &H,
        span: (T, SVector<T, D>, T),
        sink: &mut K,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        M: Method<T, D>,
        H: OdeSystem<T, D> + ?Sized,
        K: Sink<T, D> + ?Sized,
    {
        if let (Some(units), None) = (M::MIN_RTOL_EPS, self.fixed_step) {
            let rtol_min = c::<T>(units) * machine_epsilon::<T>();
            let too_tight = self
                .tol
                .for_dimension::<D>()
                .is_some_and(|raw| raw.rtol.iter().any(|&r| r > T::zero() && r < rtol_min));
            if too_tight {
                let (t, x, _) = span;
                return Err(SimError::ToleranceTooTight { t, x, rtol_min });
            }
        }
        let settings = self.settings()?;
        drive(method, sys, &settings, span, sink, &mut self.record)
    }
}

/// The builder and query methods shared by the adaptive integrators (their
/// settings live in an [`Adaptive`] field named `a`; further fields, listed
/// after the type, start as their `Default`), written once.
macro_rules! adaptive_builders {
    ($ty:ident $(, $extra:ident)*) => {
        impl<T: nalgebra::RealField + Copy> $ty<T> {
            /// An adaptive integrator with relative tolerance `rtol` (> 0)
            /// and absolute tolerance `atol` (≥ 0), applied to every
            /// component (see [`Self::with_tolerances`] for a pair per
            /// component).
            pub fn new(rtol: T, atol: T) -> Self {
                Self {
                    a: crate::common::Adaptive::new(rtol, atol),
                    $($extra: Default::default(),)*
                }
            }
        }

        impl<T: nalgebra::RealField + Copy, Tol: crate::ErrorTolerance<T>> $ty<T, Tol> {
            /// The same integrator with a relative tolerance `rtol[i]`
            /// (> 0) and an absolute tolerance `atol[i]` (≥ 0) for each
            /// component `i` of the state (whose dimension must be `N`),
            /// replacing the tolerances given so far; see
            /// [`PerComponentTolerance`](crate::PerComponentTolerance).
            /// Equal entries give exactly the steps of `new(rtol, atol)`.
            pub fn with_tolerances<const N: usize>(
                self,
                rtol: nalgebra::SVector<T, N>,
                atol: nalgebra::SVector<T, N>,
            ) -> $ty<T, crate::PerComponentTolerance<T, N>> {
                let tol = crate::PerComponentTolerance::new(rtol, atol);
                $ty {
                    a: self.a.with_tolerance(tol),
                    $($extra: self.$extra,)*
                }
            }

            /// Sets the maximum number of step attempts, accepted plus
            /// rejected (default 100 000); more ends the run with
            /// [`SimError::MaxSteps`](crate::SimError::MaxSteps).
            pub fn with_max_steps(mut self, n: usize) -> Self {
                self.a.max_steps = n;
                self
            }

            /// Uses `h` (a magnitude, > 0) as the first trial step instead
            /// of the automatic estimate. It is still capped by the maximal
            /// step.
            pub fn with_initial_step(mut self, h: T) -> Self {
                self.a.initial_step = Some(h);
                self
            }

            /// Caps the step size magnitude at `h` (> 0). Default: `|t1 − t0|`.
            pub fn with_max_step(mut self, h: T) -> Self {
                self.a.max_step = Some(h);
                self
            }

            /// Switches the error control off: the steps are laid out as for
            /// [`Rk4`](crate::Rk4) (step `k` ends at `t0 + k·h`, the last
            /// one lands on `t1`), as for measuring the method's order of
            /// convergence. A non-finite step then ends the run with
            /// [`SimError::NonFinite`](crate::SimError::NonFinite); the step
            /// budget stays that of [`Self::with_max_steps`].
            pub fn with_fixed_step(mut self, h: T) -> Self {
                self.a.fixed_step = Some(h);
                self
            }

            /// Magnitude of the step size the controller proposed after the
            /// last accepted step of the most recent call (`None` if no step
            /// was accepted); handy as the initial step when continuing an
            /// integration.
            pub fn last_step(&self) -> Option<T> {
                self.a.record.last_step
            }
        }
    };
}
pub(crate) use adaptive_builders;

/// The builder and query methods shared by the fixed-step integrators
/// (their settings live in an [`Adaptive`] field named `f`, made by
/// [`Adaptive::fixed`]), written once.
macro_rules! fixed_builders {
    ($ty:ident) => {
        impl<T: nalgebra::RealField + Copy> $ty<T> {
            /// A fixed-step integrator with step size `h` (> 0).
            pub fn new(h: T) -> Self {
                Self {
                    f: crate::common::Adaptive::fixed(h),
                }
            }

            /// Sets the maximum number of steps (default 1 000 000);
            /// exceeding it returns [`SimError::MaxSteps`](crate::SimError::MaxSteps).
            pub fn with_max_steps(mut self, n: usize) -> Self {
                self.f.max_steps = n;
                self
            }

            /// The step size.
            pub fn step_size(&self) -> T {
                self.f.fixed_step.unwrap_or_else(T::zero)
            }
        }
    };
}
pub(crate) use fixed_builders;

/// The [`Integrator`](crate::Integrator) implementation of an integrator
/// whose settings live in `$field` (an [`Adaptive`]) and whose
/// method for a system `$sys` is `$method` (which may borrow the further
/// fields named after `$sys` mutably): every entry point goes through the
/// step driver with the matching [`Sink`].
macro_rules! integrator_impl {
    ($ty:ident $(<T, $tol:ident>)?, $field:ident, |$sys:ident $(, $extra:ident)*| $method:expr) => {
        impl<T: nalgebra::RealField + Copy $(, $tol: crate::ErrorTolerance<T>)?> $ty<T $(, $tol)?> {
            /// Turns the projection of accepted states onto the system's
            /// holonomic constraints ([`OdeSystem::project`](crate::OdeSystem::project))
            /// on or off (default on; systems without holonomic constraints
            /// are unaffected). The largest residual is reported in
            /// [`Outcome::max_residual`](crate::Outcome::max_residual) either way.
            pub fn with_projection(mut self, on: bool) -> Self {
                self.$field.project = on;
                self
            }

            /// Work counters of the most recent call to `integrate*`, whether
            /// it succeeded or failed (useful to read
            /// [`Stats::stiffness_detected`](crate::Stats::stiffness_detected)
            /// after [`SimError::MaxSteps`](crate::SimError::MaxSteps)).
            pub fn last_stats(&self) -> crate::Stats {
                self.$field.record.stats
            }

            /// Integrates `sys` and reports the accepted steps to `sink`.
            fn run<S, K, const D: usize>(
                &mut self,
                $sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                sink: &mut K,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeSystem<T, D> + ?Sized,
                K: crate::sink::Sink<T, D> + ?Sized,
            {
                $(let $extra = &mut self.$extra;)*
                self.$field.run(&mut $method, $sys, (t0, x0, t1), sink)
            }
        }

        impl<T: nalgebra::RealField + Copy $(, $tol: crate::ErrorTolerance<T>)?> crate::Integrator<T>
            for $ty<T $(, $tol)?>
        {
            fn integrate_with_steps<S, F, const D: usize>(
                &mut self,
                sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                on_step: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeSystem<T, D> + ?Sized,
                F: FnMut(&crate::Step<'_, T, D>),
            {
                self.run(sys, t0, x0, t1, &mut crate::sink::Steps(on_step))
            }

            fn integrate<S: crate::OdeSystem<T, D> + ?Sized, const D: usize>(
                &mut self,
                sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>> {
                self.run(sys, t0, x0, t1, &mut crate::sink::Discard)
            }

            fn integrate_with_observer<S, F, const D: usize>(
                &mut self,
                sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                observer: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeSystem<T, D> + ?Sized,
                F: FnMut(T, &nalgebra::SVector<T, D>),
            {
                crate::sink::observe(t0, x0, observer, |k| self.run(sys, t0, x0, t1, k))
            }

            fn integrate_with_outputs<S, F, const D: usize>(
                &mut self,
                sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                times: &[T],
                on_output: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeSystem<T, D> + ?Sized,
                F: FnMut(T, &nalgebra::SVector<T, D>),
            {
                let span = (t0, x0, t1);
                crate::sink::outputs(span, times, on_output, |k| self.run(sys, t0, x0, t1, k))
            }

            fn integrate_with_events<S, G, F, const D: usize, const N: usize>(
                &mut self,
                sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                events: &crate::Events<T, G, N>,
                on_event: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeSystem<T, D> + ?Sized,
                G: Fn(T, &nalgebra::SVector<T, D>) -> nalgebra::SVector<T, N>,
                F: FnMut(&crate::EventHit<T, D>),
            {
                let mut tracker = crate::events::Tracker::new(events, on_event);
                let result = self.run(sys, t0, x0, t1, &mut tracker);
                let record = &mut self.$field.record.stats;
                crate::events::counted(result, tracker.evals, record)
            }
        }
    };
}
pub(crate) use integrator_impl;

/// `integrate_with_jacobian` and `integrate_with_jacobian_and_steps` of an
/// implicit integrator whose method for an [`OdeJacobian`](crate::OdeJacobian)
/// system `$sys` is `$method` (documented by the given attributes; further
/// fields as in [`integrator_impl`]).
macro_rules! jacobian_entry_points {
    (
        $ty:ident $(<T, $tol:ident>)?, $field:ident, |$sys:ident $(, $extra:ident)*| $method:expr,
        $(#[$plain:meta])* integrate_with_jacobian;
        $(#[$steps:meta])* integrate_with_jacobian_and_steps;
    ) => {
        impl<T: nalgebra::RealField + Copy $(, $tol: crate::ErrorTolerance<T>)?> $ty<T $(, $tol)?> {
            $(#[$plain])*
            pub fn integrate_with_jacobian<S, const D: usize>(
                &mut self,
                $sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeJacobian<T, D> + ?Sized,
            {
                $(let $extra = &mut self.$extra;)*
                self.$field
                    .run(&mut $method, $sys, (t0, x0, t1), &mut crate::sink::Discard)
            }

            $(#[$steps])*
            pub fn integrate_with_jacobian_and_steps<S, F, const D: usize>(
                &mut self,
                $sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                on_step: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeJacobian<T, D> + ?Sized,
                F: FnMut(&crate::Step<'_, T, D>),
            {
                let mut sink = crate::sink::Steps(on_step);
                $(let $extra = &mut self.$extra;)*
                self.$field.run(&mut $method, $sys, (t0, x0, t1), &mut sink)
            }

            /// Like [`Integrator::integrate_with_events`](crate::Integrator::integrate_with_events),
            /// but with the analytic Jacobian
            /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
            pub fn integrate_with_jacobian_and_events<S, G, F, const D: usize, const N: usize>(
                &mut self,
                $sys: &S,
                t0: T,
                x0: nalgebra::SVector<T, D>,
                t1: T,
                events: &crate::Events<T, G, N>,
                on_event: F,
            ) -> Result<crate::Outcome<T, D>, crate::SimError<T, D>>
            where
                S: crate::OdeJacobian<T, D> + ?Sized,
                G: Fn(T, &nalgebra::SVector<T, D>) -> nalgebra::SVector<T, N>,
                F: FnMut(&crate::EventHit<T, D>),
            {
                let mut tracker = crate::events::Tracker::new(events, on_event);
                let span = (t0, x0, t1);
                $(let $extra = &mut self.$extra;)*
                let result = self.$field.run(&mut $method, $sys, span, &mut tracker);
                let record = &mut self.$field.record.stats;
                crate::events::counted(result, tracker.evals, record)
            }
        }
    };
}
pub(crate) use jacobian_entry_points;

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn machine_epsilon_matches_std() {
        assert_eq!(machine_epsilon::<f64>(), f64::EPSILON);
        assert_eq!(machine_epsilon::<f32>(), f32::EPSILON);
    }

    #[test]
    fn arguments_are_validated() {
        let ok = Vector2::new(1.0, 2.0);
        assert_eq!(check_arguments(0.0, &ok, 1.0), Ok(1.0));
        assert_eq!(check_arguments(1.0, &ok, 0.0), Ok(-1.0));
        assert_eq!(check_arguments(1.0, &ok, 1.0), Ok(0.0));
        assert!(check_arguments(f64::NAN, &ok, 1.0).is_err());
        assert!(check_arguments(0.0, &ok, f64::INFINITY).is_err());
        assert!(check_arguments(0.0, &Vector2::new(1.0, f64::NAN), 1.0).is_err());
        assert!(check_positive::<f64, 2>(0.0, "x").is_err());
        assert!(check_positive::<f64, 2>(f64::NAN, "x").is_err());
        assert!(check_positive::<f64, 2>(1e-300, "x").is_ok());
    }
}
