//! The settings every integrator carries (tolerances, step limits,
//! projection, the record of its last call) and, written once for all of
//! them, the builder methods and `Integrator` entry points that set and use
//! them: the macros `adaptive_builders!`, `fixed_builders!`,
//! `integrator_impl!` and `jacobian_entry_points!`. A call resolves the
//! settings for the state's dimension ([`Settings::run_settings`]) and hands
//! them to the step driver ([`drive`]).

use nalgebra::{RealField, SVector};

use crate::charts::{InChart, Segment};
use crate::driver::{Control, Record, RunSettings, drive};
use crate::method::Method;
use crate::numeric::{c, machine_epsilon};
use crate::sink::Sink;
use crate::{ChartSwitches, ErrorTolerance, OdeSystem, Outcome, ScalarTolerance, SimError};

/// The default step budget of the adaptive integrators (attempts).
pub(crate) const ADAPTIVE_MAX_STEPS: usize = 100_000;
/// The default step budget of the fixed-step integrators (steps).
pub(crate) const FIXED_MAX_STEPS: usize = 1_000_000;

/// The settings and bookkeeping every integrator has (tolerances, step
/// limits, projection, the counters of the last call): an adaptive one's
/// from [`Settings::new`], with the builder methods of [`adaptive_builders`];
/// a fixed-step one's from [`Settings::fixed`], with those of
/// [`fixed_builders`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Settings<T, Tol = ScalarTolerance<T>> {
    pub(crate) tol: Tol,
    pub(crate) max_steps: usize,
    pub(crate) initial_step: Option<T>,
    pub(crate) max_step: Option<T>,
    pub(crate) fixed_step: Option<T>,
    pub(crate) project: bool,
    /// Whether a system with several charts switches between them
    /// (DESIGN §6.7; `with_chart_switching`).
    pub(crate) chart_switching: bool,
    /// Whether a one-step method advances a free rotation in its canonical
    /// coordinates (DESIGN §9.4; `with_lie_step`) rather than switching
    /// sequences.
    pub(crate) lie_step: bool,
    pub(crate) record: Record<T>,
    /// The chart switches of the last call over several charts (`None`
    /// after a call that ran on one chart: cheaper to make and clear than
    /// an empty record).
    pub(crate) switches: Option<ChartSwitches<T>>,
}

impl<T: RealField + Copy> Settings<T> {
    /// Tolerances `rtol`, `atol`; at most 100 000 step attempts.
    pub(crate) fn new(rtol: T, atol: T) -> Self {
        Settings {
            tol: ScalarTolerance::new(rtol, atol),
            max_steps: ADAPTIVE_MAX_STEPS,
            initial_step: None,
            max_step: None,
            fixed_step: None,
            project: true,
            chart_switching: true,
            lie_step: true,
            record: Record::default(),
            switches: None,
        }
    }

    /// The settings of a fixed-step integrator: step `h`, at most
    /// [`FIXED_MAX_STEPS`] steps (the tolerances are not used).
    pub(crate) fn fixed(h: T) -> Self {
        Settings {
            max_steps: FIXED_MAX_STEPS,
            fixed_step: Some(h),
            ..Settings::new(T::one(), T::one())
        }
    }
}

impl<T: RealField + Copy, Tol: ErrorTolerance<T>> Settings<T, Tol> {
    /// These settings with the tolerance `tol` instead.
    pub(crate) fn with_tolerance<U: ErrorTolerance<T>>(self, tol: U) -> Settings<T, U> {
        Settings {
            tol,
            max_steps: self.max_steps,
            initial_step: self.initial_step,
            max_step: self.max_step,
            fixed_step: self.fixed_step,
            project: self.project,
            chart_switching: self.chart_switching,
            lie_step: self.lie_step,
            record: self.record,
            switches: self.switches,
        }
    }

    /// The settings of a run in dimension `D`: the tolerances per
    /// component, each positive `rtol_i` below `10·eps` (the smallest
    /// relative error the scalar can resolve in a step) raised to `10·eps`;
    /// tolerances for another dimension are `InvalidInput` (and clear the
    /// counters of the previous run).
    pub(crate) fn run_settings<const D: usize>(
        &mut self,
    ) -> Result<RunSettings<T, D>, SimError<T, D>> {
        let Some(tol) = self.tol.for_dimension::<D>() else {
            self.record = Record::default();
            return Err(SimError::InvalidInput {
                what: "the per-component tolerances have another dimension than the state",
            });
        };
        Ok(RunSettings {
            control: match self.fixed_step {
                Some(h) => Control::Fixed(h),
                None => Control::Adaptive,
            },
            tol: tol.floored(c::<T>(10.0) * machine_epsilon::<T>()),
            initial_step: self.initial_step,
            max_step: self.max_step,
            max_steps: self.max_steps,
            project: self.project,
            chart_floor: None,
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
        self.switches = None;
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
        let settings = self.run_settings()?;
        drive(method, sys, &settings, span, sink, &mut self.record)
    }

    /// Whether a run of `sys` goes over the charts of its atlas: chart
    /// switching is on and `sys` has more than one chart (otherwise
    /// [`Settings::run`] runs it as it is).
    #[inline(always)]
    pub(crate) fn switches_charts<S, const D: usize>(&self, sys: &S) -> bool
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        self.chart_switching && sys.charts() > 1
    }

    /// Runs `sys` over the charts of its atlas (`charts::run`, DESIGN
    /// §6.7): `segment` runs the integrator's method on one chart's view;
    /// `one_step` when that method is a one-step method ([`OneStep`]).
    pub(crate) fn run_charts<S, K, F, const D: usize>(
        &mut self,
        sys: &S,
        (span, one_step): ((T, SVector<T, D>, T), bool),
        sink: &mut K,
        segment: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        K: Sink<T, D> + ?Sized,
        F: FnMut(&InChart<'_, S, T>, Segment<'_, T, D>) -> Result<Outcome<T, D>, SimError<T, D>>,
    {
        self.switches = Some(ChartSwitches::new());
        let settings = self.run_settings()?;
        let rtol = match self.fixed_step {
            Some(_) => None,
            None => self.tol.for_dimension::<D>().and_then(|raw| {
                let positive = raw.rtol.iter().copied().filter(|&r| r > T::zero());
                positive.reduce(|a, b| a.min(b))
            }),
        };
        let switches = self.switches.get_or_insert_with(ChartSwitches::new);
        let rec = (&mut self.record, switches);
        crate::charts::run(sys, (&settings, rtol, one_step), span, sink, rec, segment)
    }
}

/// Whether an integrator's method is a one-step method, which advances a
/// free rotation in its canonical coordinates re-centred after every step
/// (DESIGN §9.4), rather than a multistep one, whose history a re-centring
/// would void.
pub(crate) trait OneStep {
    /// `true` for a one-step method.
    const ONE_STEP: bool;
}

/// The body of an entry point: resets the integrator's further fields
/// (`$extra`, to their `Default`), then runs `$method` (built for `$sys`)
/// from `$span` into `$sink`, over the charts of `$sys`'s atlas when it has
/// several and chart switching is on ([`Settings::run_charts`], the method
/// built again for each chart's view), else as it is ([`Settings::run`]).
macro_rules! run_entry {
    ($this:ident, $field:ident, [$($extra:ident),*], $sys:ident, $method:expr, $span:expr, $sink:expr) => {{
        $($this.$extra = Default::default();)*
        let span = $span;
        if $this.$field.switches_charts($sys) {
            $(let $extra = &mut $this.$extra;)*
            let one_step = <Self as crate::settings::OneStep>::ONE_STEP && $this.$field.lie_step;
            $this.$field.run_charts($sys, (span, one_step), $sink, |$sys, segment| segment.drive(&mut $method, $sys))
        } else {
            $(let $extra = &mut $this.$extra;)*
            $this.$field.run(&mut $method, $sys, span, $sink)
        }
    }};
}
pub(crate) use run_entry;

/// The builder and query methods shared by the adaptive integrators (their
/// settings live in a [`Settings`] field named `a`; further fields, listed
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
                    a: crate::settings::Settings::new(rtol, atol),
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
/// (their settings live in a [`Settings`] field named `f`, made by
/// [`Settings::fixed`]), written once.
macro_rules! fixed_builders {
    ($ty:ident) => {
        impl<T: nalgebra::RealField + Copy> $ty<T> {
            /// A fixed-step integrator with step size `h` (> 0).
            pub fn new(h: T) -> Self {
                Self {
                    f: crate::settings::Settings::fixed(h),
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
/// whose settings live in `$field` (a [`Settings`]) and whose
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

            /// Turns the switching between the charts of a system's atlas
            /// on or off (default on; systems with one chart are
            /// unaffected). With it on, a system with several charts
            /// ([`OdeSystem::charts`](crate::OdeSystem::charts)) moves to a
            /// better chart wherever the current one degrades (DESIGN
            /// §6.7); off, the run stays in chart 0 and ends in
            /// [`SimError::Singular`](crate::SimError::Singular) with cause
            /// [`Singularity::Chart`](crate::Singularity::Chart) at its
            /// singularity. See [`OdeSystem::charts`](crate::OdeSystem::charts)
            /// for an example.
            pub fn with_chart_switching(mut self, on: bool) -> Self {
                self.$field.chart_switching = on;
                self
            }

            /// Turns the Lie-group step of a free rotation on or off
            /// (default on; it has no effect on `Bdf`, which switches
            /// sequences, nor on systems without a free rotation,
            /// [`OdeSystem::free_rotation`](crate::OdeSystem::free_rotation)).
            /// On, a one-step method advances the rotation in its canonical
            /// coordinates about the orientation at the start of each step
            /// (DESIGN §9.4); off, it switches between the Euler sequences
            /// of the system's charts as it does for other atlases.
            ///
            /// # Example
            ///
            /// ```rust
            /// use nh_runtime::Dop853;
            ///
            /// // the sequences, for a comparison
            /// let _switching = Dop853::<f64>::new(1e-10, 1e-12).with_lie_step(false);
            /// ```
            pub fn with_lie_step(mut self, on: bool) -> Self {
                self.$field.lie_step = on;
                self
            }

            /// Work counters of the most recent call to `integrate*`, whether
            /// it succeeded or failed (useful to read
            /// [`Stats::stiffness_detected`](crate::Stats::stiffness_detected)
            /// after [`SimError::MaxSteps`](crate::SimError::MaxSteps)).
            pub fn last_stats(&self) -> crate::Stats {
                self.$field.record.stats
            }

            /// The chart switches of the most recent call to `integrate*`,
            /// whether it succeeded or failed (of a successful one they
            /// are also [`Outcome::switches`](crate::Outcome::switches));
            /// empty for a system with one chart.
            pub fn last_chart_switches(&self) -> crate::ChartSwitches<T> {
                self.$field.switches.unwrap_or_default()
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
                crate::settings::run_entry!(self, $field, [$($extra),*], $sys, $method, (t0, x0, t1), sink)
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
                let sink = &mut crate::sink::Discard;
                crate::settings::run_entry!(self, $field, [$($extra),*], $sys, $method, (t0, x0, t1), sink)
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
                let sink = &mut crate::sink::Steps(on_step);
                crate::settings::run_entry!(self, $field, [$($extra),*], $sys, $method, (t0, x0, t1), sink)
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
                let sink = &mut tracker;
                let result = crate::settings::run_entry!(self, $field, [$($extra),*], $sys, $method, (t0, x0, t1), sink);
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
    use crate::PerComponentTolerance;
    use nalgebra::Vector2;

    /// An adaptive integrator's shell: the settings and one further field.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Adaptive<T, Tol = ScalarTolerance<T>> {
        a: Settings<T, Tol>,
        extra: u8,
    }
    adaptive_builders!(Adaptive, extra);

    /// A fixed-step integrator's shell.
    struct Fixed<T> {
        f: Settings<T>,
    }
    fixed_builders!(Fixed);

    #[test]
    fn adaptive_defaults() {
        let s = Settings::new(1e-6, 1e-9);
        assert_eq!(s.tol, ScalarTolerance::new(1e-6, 1e-9));
        assert_eq!(s.max_steps, 100_000);
        assert_eq!(
            (s.initial_step, s.max_step, s.fixed_step),
            (None, None, None)
        );
        assert!(s.project);
        assert_eq!(s.record, Record::default());
    }

    #[test]
    fn adaptive_builders_set_their_fields() {
        let mut i = Adaptive::new(1e-6, 1e-9)
            .with_max_steps(7)
            .with_initial_step(0.1)
            .with_max_step(0.5)
            .with_fixed_step(0.01);
        assert_eq!(i.extra, 0);
        i.extra = 3;
        assert_eq!(i.a.max_steps, 7);
        assert_eq!(i.a.initial_step, Some(0.1));
        assert_eq!(i.a.max_step, Some(0.5));
        assert_eq!(i.a.fixed_step, Some(0.01));
        assert_eq!(i.last_step(), None);
        i.a.record.last_step = Some(0.25);
        assert_eq!(i.last_step(), Some(0.25));
        // Per-component tolerances replace the scalar pair and keep the rest.
        let (rtol, atol) = (Vector2::new(1e-6, 1e-8), Vector2::new(0.0, 1e-12));
        let p = i.with_tolerances(rtol, atol);
        assert_eq!(p.a.tol, PerComponentTolerance::new(rtol, atol));
        assert_eq!((p.a.max_steps, p.a.fixed_step, p.extra), (7, Some(0.01), 3));
        assert_eq!(p.last_step(), Some(0.25));
    }

    #[test]
    fn fixed_builders_set_the_step_and_budget() {
        let i = Fixed::new(0.125);
        assert_eq!(i.step_size(), 0.125);
        assert_eq!(i.f.max_steps, 1_000_000);
        assert_eq!(i.f.fixed_step, Some(0.125));
        assert_eq!(Fixed::new(0.5).with_max_steps(3).f.max_steps, 3);
    }

    #[test]
    fn run_settings_resolve_the_control_and_floor_rtol() {
        let mut s = Settings::new(1e-20, 1e-9);
        let run = s.run_settings::<2>().unwrap();
        assert_eq!(run.control, Control::Adaptive);
        let floor = 10.0 * f64::EPSILON;
        assert_eq!(run.tol.rtol, Vector2::repeat(floor));
        assert_eq!(run.tol.atol, Vector2::repeat(1e-9));
        assert_eq!(run.max_steps, 100_000);
        assert!(run.project);
        // A tolerance above the floor is kept; a fixed step is a fixed step.
        let mut f = Settings::fixed(0.5);
        f.initial_step = Some(0.1);
        let run = f.run_settings::<1>().unwrap();
        assert_eq!(run.control, Control::Fixed(0.5));
        assert_eq!(run.tol.rtol[0], 1.0);
        assert_eq!((run.initial_step, run.max_steps), (Some(0.1), 1_000_000));
    }

    #[test]
    fn run_settings_of_another_dimension_are_invalid_and_clear_the_record() {
        let tol = PerComponentTolerance::new(Vector2::repeat(1e-6), Vector2::repeat(1e-9));
        let mut s = Settings::new(1e-6, 1e-9).with_tolerance(tol);
        s.record.stats.steps = 5;
        assert_eq!(
            s.run_settings::<3>(),
            Err(SimError::InvalidInput {
                what: "the per-component tolerances have another dimension than the state",
            })
        );
        assert_eq!(s.record, Record::default());
        assert!(s.run_settings::<2>().is_ok());
    }
}
