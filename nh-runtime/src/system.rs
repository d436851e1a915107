//! The traits a system implements to be integrated, and the [`Driven`] adapter.

use core::fmt;

use nalgebra::{RealField, SMatrix, SVector};

use crate::{EventHit, Events, Outcome, SimError, Step};

/// The default regularity below which a run leaves a chart (DESIGN §6.7):
/// [`OdeSystem::chart_switch_below`].
const SWITCH_BELOW: f64 = 0.1;

/// An autonomous or time-dependent first-order ODE `x' = f(t, x)` with a
/// state of fixed dimension `D`.
///
/// Every closure `Fn(T, &SVector<T, D>) -> SVector<T, D>` is an `OdeSystem`
/// too, which is handy for small problems and tests.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::OdeSystem;
///
/// /// Harmonic oscillator `q'' = -q` written as `(q, p)' = (p, -q)`.
/// struct Oscillator;
///
/// impl OdeSystem<f64, 2> for Oscillator {
///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], -x[0])
///     }
/// }
///
/// assert_eq!(Oscillator.rhs(0.0, &Vector2::new(1.0, 0.0)), Vector2::new(0.0, -1.0));
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not an `OdeSystem<{T}, {D}>`: the integrators take an ODE x' = f(t, x) with {D} states of type `{T}`",
    label = "not an `OdeSystem<{T}, {D}>`",
    note = "a generated system without inputs implements `OdeSystem<T, STATE_DIM>`; a system with `inputs` implements `ControlledSystem` instead: hold its input with `Driven::new(&system, u)` to integrate it",
    note = "check that the state has STATE_DIM = n + k entries and the scalar type of the system"
)]
pub trait OdeSystem<T, const D: usize> {
    /// The right-hand side `f(t, x)`.
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D>;

    /// How far `(t, x)` lies from a singularity of the coordinates the
    /// equations are written in (their *chart*): a number in `[-1, 1]`
    /// whose sign is constant on a chart and which is 0 where the chart is
    /// singular, or `None` (the default) for equations regular everywhere.
    ///
    /// For a generated system with general constraints it is the
    /// Hadamard ratio of the dependent-velocity block, `det C_s / Π ‖row‖`.
    /// The integrators evaluate it after every accepted step and end the
    /// run in [`SimError::Singular`] (cause [`Singularity::Chart`](crate::Singularity::Chart)),
    /// with the last good state, when it falls below `√eps` in magnitude or
    /// changes sign; a run that fails otherwise (a non-finite value, a step
    /// size too small, an unconverged Newton iteration) within `eps^(1/4)`
    /// of a chart singularity reports the singularity instead.
    #[inline]
    fn chart_regularity(&self, _t: T, _x: &SVector<T, D>) -> Option<T> {
        None
    }

    /// The first expression of the system's equations with a pole or a
    /// domain edge that lies between `(t0, x0)` and `(t1, x1)`: its guard
    /// (a denominator, the argument of `ln` or `sqrt`, `1 − a²` for `asin`
    /// and `acos`, ...) changed sign or reached zero between the two states
    /// (or is non-finite at `(t1, x1)`). Returns the expression's source
    /// text. Default: `None` (no poles).
    ///
    /// The integrators ask after every accepted step, from its start to its
    /// end (after projection, the state that would be accepted), and end
    /// the run in [`SimError::Singular`] with cause
    /// [`Singularity::Pole`](crate::Singularity::Pole) and the last good
    /// state, the step's start, when it answers. A terminal event inside
    /// that step still ends the run at the event. A run that fails
    /// otherwise (a non-finite value, a step size too small, an unconverged
    /// Newton iteration) on a step whose explicit Euler predictor
    /// `x + h f(t, x)` crosses a pole reports the pole. A generated system
    /// implements it when its equations divide by a state-dependent
    /// expression or use a function with a pole or a domain edge; the
    /// default costs nothing.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::Vector2;
    /// use nh_runtime::{Dopri5, Integrator, OdeSystem, SimError, Singularity};
    ///
    /// /// θ' = 1, v' = tan θ: a pole at θ = π/2.
    /// struct Tangent;
    ///
    /// impl OdeSystem<f64, 2> for Tangent {
    ///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    ///         Vector2::new(1.0, x[0].tan())
    ///     }
    ///
    ///     fn crossed_pole(&self, _t0: f64, x0: &Vector2<f64>, _t1: f64, x1: &Vector2<f64>) -> Option<&'static str> {
    ///         // the guard of tan θ is cos θ
    ///         let (g0, g1) = (x0[0].cos(), x1[0].cos());
    ///         (g0 * g1 <= 0.0 || !g1.is_finite()).then_some("tan(theta)")
    ///     }
    /// }
    ///
    /// let err = Dopri5::new(1e-8, 1e-10)
    ///     .integrate(&Tangent, 0.0, Vector2::zeros(), 3.0)
    ///     .unwrap_err();
    /// let SimError::Singular { t, x, cause } = err else { panic!("{err:?}") };
    /// assert_eq!(cause, Singularity::Pole("tan(theta)"));
    /// assert!(t < std::f64::consts::FRAC_PI_2 && x[0] < std::f64::consts::FRAC_PI_2);
    /// assert!(err.to_string().contains("tan(theta)"));
    /// ```
    #[inline]
    fn crossed_pole(
        &self,
        _t0: T,
        _x0: &SVector<T, D>,
        _t1: T,
        _x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        None
    }

    /// The largest residual `|f_i(q, t)|` of the system's holonomic
    /// constraints at `(t, x)`, or `None` (the default) for a system without
    /// holonomic constraints. Reported as
    /// [`Outcome::max_residual`](crate::Outcome::max_residual).
    #[inline]
    fn constraint_residual(&self, _t: T, _x: &SVector<T, D>) -> Option<T> {
        None
    }

    /// Moves `x` back onto the holonomic constraints at time `t` (for a
    /// generated system: Newton's method on the dependent coordinates) and
    /// returns whether it changed `x`. The default does nothing. The
    /// integrators call it after every accepted step unless projection is
    /// turned off (`with_projection(false)`).
    #[inline]
    fn project(&self, _t: T, _x: &mut SVector<T, D>) -> Result<bool, ProjectionFailure<T>> {
        Ok(false)
    }

    /// Whether `f` depends on `t` only through `x` (an autonomous system):
    /// then `∂f/∂t = 0`, and the implicit methods skip its finite difference
    /// (one right-hand side per Jacobian less for `Rodas4`). `false` by
    /// default; a generated system answers `true` when nothing in its
    /// definition depends on `t`.
    #[inline]
    fn is_autonomous(&self) -> bool {
        false
    }

    /// How many charts the system's atlas has (1: the system has one chart,
    /// the default).
    ///
    /// A system whose constraints are solved for dependent velocities has
    /// a *chart*: its state is `[q, ṙ]`, the positions and the independent
    /// velocities, and the chart is singular where the block solved for
    /// the dependent velocities is ([`OdeSystem::chart_regularity`]). An
    /// *atlas* is several such charts, all with the same dimension `D` and
    /// the same positions `q`: only the meaning of the last entries (which
    /// velocities are state) differs. Chart 0 is the system's own, the
    /// layout of [`OdeSystem::rhs`] and of everything the integrators hand
    /// back. With more than one chart the integrators move to a better
    /// chart when the current one degrades (DESIGN §6.7): the hooks
    /// `*_in` and [`OdeSystem::rhs_in_chart`] give the equations in each
    /// chart, [`OdeSystem::change_chart`] maps states between them.
    ///
    /// # Example
    ///
    /// A point running round the unit circle, `x ẋ + y ẏ = 0`: chart 0
    /// keeps `ẋ` (state `[x, y, ẋ]`, `ẏ = −x ẋ/y`, singular where `y = 0`),
    /// chart 1 keeps `ẏ` (state `[x, y, ẏ]`, singular where `x = 0`).
    ///
    /// ```rust
    /// use nalgebra::Vector3;
    /// use nh_runtime::{Dopri5, Integrator, OdeSystem, SimError, Singularity};
    ///
    /// struct Circle;
    ///
    /// impl Circle {
    ///     /// (ẋ, ẏ) from the state of `chart`.
    ///     fn velocity(chart: usize, s: &Vector3<f64>) -> (f64, f64) {
    ///         let (x, y) = (s[0], s[1]);
    ///         if chart == 0 { (s[2], -x * s[2] / y) } else { (-y * s[2] / x, s[2]) }
    ///     }
    /// }
    ///
    /// impl OdeSystem<f64, 3> for Circle {
    ///     fn rhs(&self, t: f64, s: &Vector3<f64>) -> Vector3<f64> {
    ///         self.rhs_in_chart(0, t, s)
    ///     }
    ///     fn chart_regularity(&self, t: f64, s: &Vector3<f64>) -> Option<f64> {
    ///         self.chart_regularity_in(0, t, s)
    ///     }
    ///     fn charts(&self) -> usize {
    ///         2
    ///     }
    ///     fn chart_name(&self, chart: usize) -> &'static str {
    ///         ["solved for y", "solved for x"][chart]
    ///     }
    ///     fn rhs_in_chart(&self, chart: usize, _t: f64, s: &Vector3<f64>) -> Vector3<f64> {
    ///         let (vx, vy) = Self::velocity(chart, s);
    ///         let w2 = (vx * vx + vy * vy) / (s[0] * s[0] + s[1] * s[1]);
    ///         // uniform motion on the circle: the acceleration is −ω² (x, y)
    ///         let a = if chart == 0 { -w2 * s[0] } else { -w2 * s[1] };
    ///         Vector3::new(vx, vy, a)
    ///     }
    ///     fn chart_regularity_in(&self, chart: usize, _t: f64, s: &Vector3<f64>) -> Option<f64> {
    ///         let r = (s[0] * s[0] + s[1] * s[1]).sqrt();
    ///         Some(if chart == 0 { s[1] / r } else { s[0] / r })
    ///     }
    ///     fn change_chart(&self, from: usize, to: usize, _t: f64, s: &Vector3<f64>) -> Vector3<f64> {
    ///         let (vx, vy) = Self::velocity(from, s);
    ///         Vector3::new(s[0], s[1], if to == 0 { vx } else { vy })
    ///     }
    /// }
    ///
    /// // Ten radians round the circle from the angle 0.5, at unit speed.
    /// let x0 = Vector3::new(0.5f64.cos(), 0.5f64.sin(), -0.5f64.sin());
    /// let out = Dopri5::new(1e-10, 1e-12).integrate(&Circle, 0.0, x0, 10.0).unwrap();
    /// // Chart 0's layout, [x, y, ẋ], and the closed form.
    /// let exact = Vector3::new(10.5f64.cos(), 10.5f64.sin(), -10.5f64.sin());
    /// assert!((out.x - exact).amax() < 1e-7, "{}", out.x - exact);
    /// // Near the angles π, 2π, 3π (y = 0) and 3π/2, 5π/2 (x = 0); at π/2
    /// // the run is in chart 0, which is regular there.
    /// assert_eq!(out.switches.total(), 5);
    /// assert_eq!(out.stats.chart_switches, 5);
    /// let first = out.switches.iter().next().unwrap();
    /// assert_eq!((first.from, first.to), (0, 1));
    /// assert!((first.t + 0.5 - std::f64::consts::PI).abs() < 0.15);
    ///
    /// // Held in chart 0, the run ends where y = 0.
    /// let err = Dopri5::new(1e-10, 1e-12)
    ///     .with_chart_switching(false)
    ///     .integrate(&Circle, 0.0, x0, 10.0)
    ///     .unwrap_err();
    /// assert!(matches!(err, SimError::Singular { cause: Singularity::Chart, .. }));
    /// assert!(err.time().unwrap() < std::f64::consts::PI - 0.5);
    /// ```
    #[inline]
    fn charts(&self) -> usize {
        1
    }

    /// A short description of chart `chart` for reports, e.g. `"solved
    /// for y"`; `""` by default.
    #[inline]
    fn chart_name(&self, _chart: usize) -> &'static str {
        ""
    }

    /// `f(t, x)` with `x` in the layout of chart `chart` (`[q, the chart's
    /// independent velocities]`, see [`OdeSystem::charts`]); chart 0 is
    /// [`OdeSystem::rhs`], which is the default for every chart.
    #[inline]
    fn rhs_in_chart(&self, _chart: usize, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.rhs(t, x)
    }

    /// [`OdeSystem::chart_regularity`] of chart `chart` at `x` in that
    /// chart's layout; the integrators switch to the chart where it is
    /// largest in magnitude (DESIGN §6.7). Default: chart 0's.
    #[inline]
    fn chart_regularity_in(&self, _chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.chart_regularity(t, x)
    }

    /// [`OdeSystem::crossed_pole`] of the equations of chart `chart`, the
    /// states in that chart's layout. Default: chart 0's.
    #[inline]
    fn crossed_pole_in(
        &self,
        _chart: usize,
        t0: T,
        x0: &SVector<T, D>,
        t1: T,
        x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        self.crossed_pole(t0, x0, t1, x1)
    }

    /// [`OdeSystem::constraint_residual`] at `x` in the layout of chart
    /// `chart`. Default: chart 0's.
    #[inline]
    fn constraint_residual_in(&self, _chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.constraint_residual(t, x)
    }

    /// [`OdeSystem::project`] of `x` in the layout of chart `chart`.
    /// Default: chart 0's.
    #[inline]
    fn project_in(
        &self,
        _chart: usize,
        t: T,
        x: &mut SVector<T, D>,
    ) -> Result<bool, ProjectionFailure<T>> {
        self.project(t, x)
    }

    /// The state `x` of chart `from` written in chart `to`: the same
    /// positions, and `to`'s independent velocities read off the full
    /// velocity `q̇` that chart `from` gives at `(t, x)`. Finite wherever
    /// chart `from` is regular (chart `to` may be singular there).
    /// Identity by default. See [`OdeSystem::charts`].
    #[inline]
    fn change_chart(&self, _from: usize, _to: usize, _t: T, x: &SVector<T, D>) -> SVector<T, D>
    where
        T: Copy,
    {
        *x
    }

    /// The regularity below which a run leaves chart `chart` for a better
    /// one (DESIGN §6.7): `0.1` by default, the threshold for the charts of
    /// constraints, whose regularity can be well below 1 on the whole of a
    /// good chart. The charts of a free rotation take `0.4`: one of the two
    /// sequences always has `|cos β| ≥ 1/√2`, and the cost of the angles
    /// grows as `1/cos β` long before the pole.
    #[inline]
    fn chart_switch_below(&self, chart: usize) -> f64 {
        let _ = chart;
        SWITCH_BELOW
    }

    /// Where the state holds a free rotation in chart `chart` (DESIGN
    /// §9.4): its Euler sequence, the slots of its angles and of their
    /// rates, and the components in which the system writes its angular
    /// velocity; `None` by default. A run of a system all of whose charts
    /// are those of one free rotation goes, with a one-step integrator, in
    /// the rotation's canonical coordinates about the orientation at the
    /// start of each step (a Lie-group step: the rotation advanced, not
    /// its angles, exact for a constant angular velocity), the equations
    /// evaluated in the chart that is regular there; with `Bdf` it
    /// switches charts. Either way the caller sees chart 0's angles.
    #[inline]
    fn free_rotation(&self, chart: usize) -> Option<crate::FreeRotation> {
        let _ = chart;
        None
    }

    /// [`OdeSystem::change_chart`] where chart `to`'s positions are one of
    /// several that describe the same configuration (the angles of a
    /// rotation, which are defined up to whole turns, and a rotation's two
    /// sets of Euler angles): the one nearest `near`, a state in chart
    /// `to`'s layout. The integrators pass the last state they reported, so
    /// that what the caller sees is continuous across switches. Default:
    /// [`OdeSystem::change_chart`].
    #[inline]
    fn change_chart_near(
        &self,
        from: usize,
        to: usize,
        t: T,
        x: &SVector<T, D>,
        near: &SVector<T, D>,
    ) -> SVector<T, D>
    where
        T: Copy,
    {
        let _ = near;
        self.change_chart(from, to, t, x)
    }
}

/// A projection onto holonomic constraints that did not converge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectionFailure<T> {
    /// The largest constraint residual after the last iteration.
    pub residual: T,
}

impl<T, const D: usize, F> OdeSystem<T, D> for F
where
    F: Fn(T, &SVector<T, D>) -> SVector<T, D>,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self(t, x)
    }
}

/// An [`OdeSystem`] that can also provide its Jacobian `∂f/∂x`, for implicit
/// methods.
///
/// # Example
///
/// ```rust
/// use nalgebra::{Matrix2, Vector2};
/// use nh_runtime::{OdeJacobian, OdeSystem};
///
/// struct Oscillator;
///
/// impl OdeSystem<f64, 2> for Oscillator {
///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], -x[0])
///     }
/// }
///
/// impl OdeJacobian<f64, 2> for Oscillator {
///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
///         Matrix2::new(0.0, 1.0, -1.0, 0.0)
///     }
/// }
///
/// let j = Oscillator.jacobian(0.0, &Vector2::zeros());
/// assert_eq!(j * Vector2::new(1.0, 0.0), Vector2::new(0.0, -1.0));
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no analytic Jacobian: it does not implement `OdeJacobian`",
    label = "no `OdeJacobian`",
    note = "a generated system implements `OdeJacobian` (with inputs: `ControlledJacobian`, which `Driven` turns into `OdeJacobian`) when its definition asks for it: add `outputs {{ jacobian }}`",
    note = "or integrate without the analytic Jacobian (`integrate`, `integrate_with_steps`, ...): the implicit methods then use finite differences"
)]
pub trait OdeJacobian<T, const D: usize>: OdeSystem<T, D> {
    /// The Jacobian `∂f/∂x` evaluated at `(t, x)`.
    fn jacobian(&self, t: T, x: &SVector<T, D>) -> SMatrix<T, D, D>;

    /// The partial derivative `∂f/∂t` at `(t, x)` (at fixed `x`), if the
    /// system can give it; `None` (the default) lets the implicit methods
    /// difference `f` in `t` instead (one right-hand side per Jacobian for
    /// [`Rodas4`](crate::Rodas4)). Not asked for when the system
    /// [is autonomous](OdeSystem::is_autonomous). A generated system with
    /// `outputs { jacobian }` whose definition depends on `t` gives it,
    /// derived symbolically.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{Integrator, OdeJacobian, OdeSystem, Rodas4};
    ///
    /// /// A stiff oscillator forced by cos t: x'' = −100 x − 20 x' + cos t.
    /// struct Forced;
    /// impl OdeSystem<f64, 2> for Forced {
    ///     fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    ///         Vector2::new(x[1], -100.0 * x[0] - 20.0 * x[1] + t.cos())
    ///     }
    /// }
    /// impl OdeJacobian<f64, 2> for Forced {
    ///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
    ///         Matrix2::new(0.0, 1.0, -100.0, -20.0)
    ///     }
    ///     fn time_derivative(&self, t: f64, _x: &Vector2<f64>) -> Option<Vector2<f64>> {
    ///         Some(Vector2::new(0.0, -t.sin()))
    ///     }
    /// }
    ///
    /// /// The same system without its ∂f/∂t.
    /// struct Differenced;
    /// impl OdeSystem<f64, 2> for Differenced {
    ///     fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> { Forced.rhs(t, x) }
    /// }
    /// impl OdeJacobian<f64, 2> for Differenced {
    ///     fn jacobian(&self, t: f64, x: &Vector2<f64>) -> Matrix2<f64> { Forced.jacobian(t, x) }
    /// }
    ///
    /// let mut rodas = Rodas4::new(1e-8, 1e-10);
    /// let own = rodas.integrate_with_jacobian(&Forced, 0.0, Vector2::zeros(), 1.0).unwrap();
    /// let differenced = rodas.integrate_with_jacobian(&Differenced, 0.0, Vector2::zeros(), 1.0).unwrap();
    /// // one right-hand side fewer per Jacobian, at the same accuracy
    /// assert_eq!(differenced.stats.rhs_evals - own.stats.rhs_evals, own.stats.jacobian_evals);
    /// assert!((own.x - differenced.x).amax() < 1e-9);
    /// ```
    #[inline]
    fn time_derivative(&self, _t: T, _x: &SVector<T, D>) -> Option<SVector<T, D>> {
        None
    }

    /// The Jacobian `∂f/∂x` of the equations of chart `chart`
    /// ([`OdeSystem::rhs_in_chart`]) at `x` in that chart's layout, if the
    /// system gives it: by default [`OdeJacobian::jacobian`] for chart 0
    /// and `None` for the others, where the implicit methods then take
    /// finite differences (as for a system without a Jacobian).
    #[inline]
    fn jacobian_in_chart(&self, chart: usize, t: T, x: &SVector<T, D>) -> Option<SMatrix<T, D, D>> {
        (chart == 0).then(|| self.jacobian(t, x))
    }
}

/// A system with `M` control inputs `u`: `x' = f(t, x, u)`.
///
/// Hold the input fixed with [`Driven`] to obtain an [`OdeSystem`].
///
/// # Example
///
/// ```rust
/// use nalgebra::{Vector1, Vector2};
/// use nh_runtime::ControlledSystem;
///
/// /// A double integrator pushed by a force `u`.
/// struct Cart;
///
/// impl ControlledSystem<f64, 2, 1> for Cart {
///     fn rhs_with_input(&self, _t: f64, x: &Vector2<f64>, u: &Vector1<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], u[0])
///     }
/// }
///
/// let dx = Cart.rhs_with_input(0.0, &Vector2::new(0.0, 1.0), &Vector1::new(2.0));
/// assert_eq!(dx, Vector2::new(1.0, 2.0));
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` is not a `ControlledSystem<{T}, {D}, {M}>`: a system with {M} inputs and {D} states of type `{T}`",
    label = "not a `ControlledSystem<{T}, {D}, {M}>`",
    note = "a generated system implements `ControlledSystem<T, STATE_DIM, m>` when it declares `inputs {{ .. }}` (m of them); without inputs it is an `OdeSystem` and needs no `Driven`"
)]
pub trait ControlledSystem<T, const D: usize, const M: usize> {
    /// The right-hand side `f(t, x, u)`.
    fn rhs_with_input(&self, t: T, x: &SVector<T, D>, u: &SVector<T, M>) -> SVector<T, D>;

    /// [`OdeSystem::chart_regularity`]; the input does not enter it.
    #[inline]
    fn chart_regularity(&self, _t: T, _x: &SVector<T, D>) -> Option<T> {
        None
    }

    /// [`OdeSystem::crossed_pole`]; the input does not enter it.
    #[inline]
    fn crossed_pole(
        &self,
        _t0: T,
        _x0: &SVector<T, D>,
        _t1: T,
        _x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        None
    }

    /// [`OdeSystem::constraint_residual`].
    #[inline]
    fn constraint_residual(&self, _t: T, _x: &SVector<T, D>) -> Option<T> {
        None
    }

    /// [`OdeSystem::project`].
    #[inline]
    fn project(&self, _t: T, _x: &mut SVector<T, D>) -> Result<bool, ProjectionFailure<T>> {
        Ok(false)
    }

    /// [`OdeSystem::is_autonomous`], for every fixed input: `f(t, x, u)`
    /// depends on `t` only through `x` and `u`.
    #[inline]
    fn is_autonomous(&self) -> bool {
        false
    }

    /// [`OdeSystem::charts`]: the number of charts of the atlas (1 by
    /// default); the input does not enter the charts.
    #[inline]
    fn charts(&self) -> usize {
        1
    }

    /// [`OdeSystem::chart_name`].
    #[inline]
    fn chart_name(&self, _chart: usize) -> &'static str {
        ""
    }

    /// [`OdeSystem::rhs_in_chart`] at the input `u`: `f(t, x, u)` with `x`
    /// in the layout of chart `chart`; chart 0 is
    /// [`ControlledSystem::rhs_with_input`], the default.
    #[inline]
    fn rhs_with_input_in_chart(
        &self,
        _chart: usize,
        t: T,
        x: &SVector<T, D>,
        u: &SVector<T, M>,
    ) -> SVector<T, D> {
        self.rhs_with_input(t, x, u)
    }

    /// [`OdeSystem::chart_regularity_in`]; the input does not enter it.
    #[inline]
    fn chart_regularity_in(&self, _chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.chart_regularity(t, x)
    }

    /// [`OdeSystem::crossed_pole_in`]; the input does not enter it.
    #[inline]
    fn crossed_pole_in(
        &self,
        _chart: usize,
        t0: T,
        x0: &SVector<T, D>,
        t1: T,
        x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        self.crossed_pole(t0, x0, t1, x1)
    }

    /// [`OdeSystem::constraint_residual_in`].
    #[inline]
    fn constraint_residual_in(&self, _chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.constraint_residual(t, x)
    }

    /// [`OdeSystem::project_in`].
    #[inline]
    fn project_in(
        &self,
        _chart: usize,
        t: T,
        x: &mut SVector<T, D>,
    ) -> Result<bool, ProjectionFailure<T>> {
        self.project(t, x)
    }

    /// [`OdeSystem::change_chart`]; the input does not enter it (the
    /// constraints have no inputs). Identity by default.
    #[inline]
    fn change_chart(&self, _from: usize, _to: usize, _t: T, x: &SVector<T, D>) -> SVector<T, D>
    where
        T: Copy,
    {
        *x
    }

    /// [`OdeSystem::chart_switch_below`]: `0.1` by default.
    #[inline]
    fn chart_switch_below(&self, chart: usize) -> f64 {
        let _ = chart;
        SWITCH_BELOW
    }

    /// [`OdeSystem::free_rotation`]; the input does not enter it.
    #[inline]
    fn free_rotation(&self, chart: usize) -> Option<crate::FreeRotation> {
        let _ = chart;
        None
    }

    /// [`OdeSystem::change_chart_near`]; the input does not enter it.
    /// Default: [`ControlledSystem::change_chart`].
    #[inline]
    fn change_chart_near(
        &self,
        from: usize,
        to: usize,
        t: T,
        x: &SVector<T, D>,
        near: &SVector<T, D>,
    ) -> SVector<T, D>
    where
        T: Copy,
    {
        let _ = near;
        self.change_chart(from, to, t, x)
    }
}

/// A [`ControlledSystem`] that can also provide the Jacobian `∂f/∂x` of
/// `f(t, x, u)` at a given input: with [`Driven`], whose
/// [`OdeJacobian::jacobian`] it is at the held input, a system with inputs
/// runs on the implicit methods with its analytic Jacobian.
///
/// A generated system with `inputs` and `outputs { jacobian }` implements
/// it with its generated `jacobian(t, x, u)`.
///
/// # Example
///
/// ```rust
/// use nalgebra::{Matrix2, Vector1, Vector2};
/// use nh_runtime::{ControlledJacobian, ControlledSystem, Driven, Integrator, OdeJacobian, Rodas4};
///
/// /// A damped cart pushed by a force `u`: ẍ = u − 50 ẋ.
/// struct Cart;
///
/// impl ControlledSystem<f64, 2, 1> for Cart {
///     fn rhs_with_input(&self, _t: f64, x: &Vector2<f64>, u: &Vector1<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], u[0] - 50.0 * x[1])
///     }
/// }
///
/// impl ControlledJacobian<f64, 2, 1> for Cart {
///     fn jacobian_with_input(&self, _t: f64, _x: &Vector2<f64>, _u: &Vector1<f64>) -> Matrix2<f64> {
///         Matrix2::new(0.0, 1.0, 0.0, -50.0)
///     }
/// }
///
/// let driven = Driven::new(&Cart, Vector1::new(5.0));
/// assert_eq!(driven.jacobian(0.0, &Vector2::zeros())[(1, 1)], -50.0);
/// let out = Rodas4::new(1e-8, 1e-10)
///     .integrate_with_jacobian(&driven, 0.0, Vector2::zeros(), 1.0)
///     .unwrap();
/// assert!((out.x[1] - 0.1).abs() < 1e-8); // the terminal velocity u/50
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` has no analytic Jacobian: it does not implement `ControlledJacobian`",
    label = "no `ControlledJacobian`",
    note = "a generated system with inputs implements `ControlledJacobian` when its definition asks for the Jacobian: add `outputs {{ jacobian }}`",
    note = "or integrate without the analytic Jacobian (`integrate`, `integrate_with_steps`, ...): the implicit methods then use finite differences"
)]
pub trait ControlledJacobian<T, const D: usize, const M: usize>: ControlledSystem<T, D, M> {
    /// The Jacobian `∂f/∂x` of `f(t, x, u)` evaluated at `(t, x, u)`.
    fn jacobian_with_input(&self, t: T, x: &SVector<T, D>, u: &SVector<T, M>) -> SMatrix<T, D, D>;

    /// [`OdeJacobian::time_derivative`] at the input `u`: `∂f/∂t` at fixed
    /// `x` and `u`, or `None` (the default).
    #[inline]
    fn time_derivative_with_input(
        &self,
        _t: T,
        _x: &SVector<T, D>,
        _u: &SVector<T, M>,
    ) -> Option<SVector<T, D>> {
        None
    }

    /// [`OdeJacobian::jacobian_in_chart`] at the input `u`: by default
    /// [`ControlledJacobian::jacobian_with_input`] for chart 0 and `None`
    /// (finite differences) for the others.
    #[inline]
    fn jacobian_with_input_in_chart(
        &self,
        chart: usize,
        t: T,
        x: &SVector<T, D>,
        u: &SVector<T, M>,
    ) -> Option<SMatrix<T, D, D>> {
        (chart == 0).then(|| self.jacobian_with_input(t, x, u))
    }
}

/// Adapter: a [`ControlledSystem`] with a held (zero-order-hold) input `u`
/// is an [`OdeSystem`], and an [`OdeJacobian`] when the system is a
/// [`ControlledJacobian`].
///
/// Typical use is a control loop that integrates one sampling period at a
/// time with the input computed at the start of the period.
///
/// # Example
///
/// ```rust
/// use nalgebra::{Vector1, Vector2};
/// use nh_runtime::{ControlledSystem, Driven, Integrator, Rk4};
///
/// struct Cart;
///
/// impl ControlledSystem<f64, 2, 1> for Cart {
///     fn rhs_with_input(&self, _t: f64, x: &Vector2<f64>, u: &Vector1<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], u[0])
///     }
/// }
///
/// // Constant acceleration 2 for one second from rest: position 1, velocity 2.
/// let driven = Driven::new(&Cart, Vector1::new(2.0));
/// let out = Rk4::new(0.1).integrate(&driven, 0.0, Vector2::zeros(), 1.0).unwrap();
/// assert!((out.x[0] - 1.0).abs() < 1e-12);
/// assert!((out.x[1] - 2.0).abs() < 1e-12);
/// ```
pub struct Driven<'a, S: ?Sized, T, const M: usize> {
    /// The controlled system.
    pub system: &'a S,
    /// The input held constant during integration.
    pub u: SVector<T, M>,
}

impl<'a, S: ?Sized, T, const M: usize> Driven<'a, S, T, M> {
    /// Holds the input `u` for `system`.
    pub fn new(system: &'a S, u: SVector<T, M>) -> Self {
        Self { system, u }
    }
}

impl<S: ?Sized, T: Clone, const M: usize> Clone for Driven<'_, S, T, M> {
    fn clone(&self) -> Self {
        Self {
            system: self.system,
            u: self.u.clone(),
        }
    }
}

impl<S: ?Sized, T: Copy, const M: usize> Copy for Driven<'_, S, T, M> {}

impl<S: ?Sized + fmt::Debug, T: fmt::Debug, const M: usize> fmt::Debug for Driven<'_, S, T, M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Driven")
            .field("system", &self.system)
            .field("u", &self.u)
            .finish()
    }
}

impl<S, T, const D: usize, const M: usize> OdeSystem<T, D> for Driven<'_, S, T, M>
where
    S: ControlledSystem<T, D, M> + ?Sized,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.system.rhs_with_input(t, x, &self.u)
    }

    #[inline]
    fn chart_regularity(&self, t: T, x: &SVector<T, D>) -> Option<T> {
        self.system.chart_regularity(t, x)
    }

    #[inline]
    fn crossed_pole(
        &self,
        t0: T,
        x0: &SVector<T, D>,
        t1: T,
        x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        self.system.crossed_pole(t0, x0, t1, x1)
    }

    #[inline]
    fn constraint_residual(&self, t: T, x: &SVector<T, D>) -> Option<T> {
        self.system.constraint_residual(t, x)
    }

    #[inline]
    fn project(&self, t: T, x: &mut SVector<T, D>) -> Result<bool, ProjectionFailure<T>> {
        self.system.project(t, x)
    }

    /// The input is held, so the system's own answer holds.
    #[inline]
    fn is_autonomous(&self) -> bool {
        self.system.is_autonomous()
    }

    #[inline]
    fn charts(&self) -> usize {
        self.system.charts()
    }

    #[inline]
    fn chart_name(&self, chart: usize) -> &'static str {
        self.system.chart_name(chart)
    }

    #[inline]
    fn rhs_in_chart(&self, chart: usize, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.system.rhs_with_input_in_chart(chart, t, x, &self.u)
    }

    #[inline]
    fn chart_regularity_in(&self, chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.system.chart_regularity_in(chart, t, x)
    }

    #[inline]
    fn crossed_pole_in(
        &self,
        chart: usize,
        t0: T,
        x0: &SVector<T, D>,
        t1: T,
        x1: &SVector<T, D>,
    ) -> Option<&'static str> {
        self.system.crossed_pole_in(chart, t0, x0, t1, x1)
    }

    #[inline]
    fn constraint_residual_in(&self, chart: usize, t: T, x: &SVector<T, D>) -> Option<T> {
        self.system.constraint_residual_in(chart, t, x)
    }

    #[inline]
    fn project_in(
        &self,
        chart: usize,
        t: T,
        x: &mut SVector<T, D>,
    ) -> Result<bool, ProjectionFailure<T>> {
        self.system.project_in(chart, t, x)
    }

    #[inline]
    fn change_chart(&self, from: usize, to: usize, t: T, x: &SVector<T, D>) -> SVector<T, D>
    where
        T: Copy,
    {
        self.system.change_chart(from, to, t, x)
    }

    #[inline]
    fn change_chart_near(
        &self,
        from: usize,
        to: usize,
        t: T,
        x: &SVector<T, D>,
        near: &SVector<T, D>,
    ) -> SVector<T, D>
    where
        T: Copy,
    {
        self.system.change_chart_near(from, to, t, x, near)
    }

    #[inline]
    fn chart_switch_below(&self, chart: usize) -> f64 {
        self.system.chart_switch_below(chart)
    }

    #[inline]
    fn free_rotation(&self, chart: usize) -> Option<crate::FreeRotation> {
        self.system.free_rotation(chart)
    }
}

/// `∂f/∂x` at the held input, for the implicit methods.
impl<S, T, const D: usize, const M: usize> OdeJacobian<T, D> for Driven<'_, S, T, M>
where
    S: ControlledJacobian<T, D, M> + ?Sized,
{
    #[inline]
    fn jacobian(&self, t: T, x: &SVector<T, D>) -> SMatrix<T, D, D> {
        self.system.jacobian_with_input(t, x, &self.u)
    }

    /// `∂f/∂t` at the held input (the input is constant in time).
    #[inline]
    fn time_derivative(&self, t: T, x: &SVector<T, D>) -> Option<SVector<T, D>> {
        self.system.time_derivative_with_input(t, x, &self.u)
    }

    /// `∂f/∂x` of chart `chart` at the held input.
    #[inline]
    fn jacobian_in_chart(&self, chart: usize, t: T, x: &SVector<T, D>) -> Option<SMatrix<T, D, D>> {
        self.system
            .jacobian_with_input_in_chart(chart, t, x, &self.u)
    }
}

/// A method that advances an [`OdeSystem`] from `(t0, x0)` to `t1`.
///
/// Implementors provide [`Integrator::integrate_with_steps`], which reports
/// every accepted step with its dense output ([`Step`]); plain integration,
/// observers and output at requested times are built on it.
///
/// Conventions shared by every integrator of this crate:
///
/// * `t0`, `t1` and every component of `x0` must be finite, otherwise
///   [`SimError::InvalidInput`] is returned and nothing is evaluated.
/// * `t1 < t0` is allowed: the integration runs backwards in time with
///   negative steps (step sizes given to the builders are magnitudes).
/// * `t1 == t0` returns `Ok` with `x0` and zeroed [`Stats`](crate::Stats)
///   (the observer is still called once, at `t0`).
/// * On success, [`Outcome::t`] is exactly `t1`.
/// * Every integrator runs on the one step driver of this crate, which owns
///   acceptance, step-size control, step budgets, stiffness detection,
///   observers, output times and the typed failures.
/// * A span too short to be resolved (below the smallest step, about
///   `10·eps·|t|`) is covered by one explicit Euler step and ends `Ok` at
///   `t1`.
/// * No heap allocation per step: states live in `SVector` stack arrays;
///   only [`GaussLegendre4`](crate::GaussLegendre4) allocates its work
///   matrices, once per call (once per chart segment, below).
/// * A system whose atlas has several charts ([`OdeSystem::charts`]) is
///   integrated over them, moving to a better chart wherever the current
///   one degrades (unless `with_chart_switching(false)`); everything
///   handed back (the outcome, the errors' states, observers, output
///   times, steps, events) is in chart 0's layout, and the switches are
///   in [`Outcome::switches`](crate::Outcome::switches).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{Dopri5, Integrator, Rk4};
///
/// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
/// let x0 = Vector2::new(1.0, 0.0);
///
/// fn run<I: Integrator<f64>>(i: &mut I, sys: &impl nh_runtime::OdeSystem<f64, 2>, x0: Vector2<f64>) -> f64 {
///     i.integrate(sys, 0.0, x0, 1.0).unwrap().x[0]
/// }
///
/// let exact = 1.0f64.cos();
/// assert!((run(&mut Rk4::new(0.01), &oscillator, x0) - exact).abs() < 1e-9);
/// assert!((run(&mut Dopri5::new(1e-10, 1e-12), &oscillator, x0) - exact).abs() < 1e-9);
/// ```
pub trait Integrator<T: RealField + Copy> {
    /// Integrates `sys` from `(t0, x0)` to `t1` and calls `on_step` after
    /// every accepted step with the step's end points and its continuous
    /// extension ([`Step::interpolate`]).
    ///
    /// Nothing is reported for `t0` itself (the first step's
    /// [`Step::t_prev`]/[`Step::x_prev`] are `t0` and `x0`); an empty
    /// interval reports no step. Steps are reported in order, and the last
    /// one of a successful integration ends exactly at `t1`. On error, the
    /// steps accepted before the failure have been reported.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::Vector1;
    /// use nh_runtime::{Integrator, Rk4};
    ///
    /// let decay = |_t: f64, x: &Vector1<f64>| -x;
    /// let mut ends = Vec::new();
    /// Rk4::new(0.25)
    ///     .integrate_with_steps(&decay, 0.0, Vector1::new(1.0), 1.0, |step| {
    ///         assert_eq!(step.interpolate(step.t_prev()), *step.x_prev());
    ///         ends.push(step.t());
    ///     })
    ///     .unwrap();
    /// assert_eq!(ends, [0.25, 0.5, 0.75, 1.0]);
    /// ```
    fn integrate_with_steps<S, F, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        on_step: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        F: FnMut(&Step<'_, T, D>);

    /// Integrates `sys` from `(t0, x0)` to `t1`.
    ///
    /// Equivalent to [`Integrator::integrate_with_steps`] with a callback
    /// that does nothing.
    fn integrate<S: OdeSystem<T, D> + ?Sized, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
    ) -> Result<Outcome<T, D>, SimError<T, D>> {
        self.integrate_with_steps(sys, t0, x0, t1, |_| {})
    }

    /// Like [`Integrator::integrate`], but calls `observer(t, &x)` at `t0`
    /// and after every accepted step (including the final one, at `t1`).
    ///
    /// The call at `t0` is skipped only when the arguments or settings are
    /// invalid ([`SimError::InvalidInput`]).
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::Vector1;
    /// use nh_runtime::{Integrator, Rk4};
    ///
    /// let decay = |_t: f64, x: &Vector1<f64>| -x;
    /// let mut calls = 0;
    /// let mut last_t = f64::NAN;
    /// Rk4::new(0.1)
    ///     .integrate_with_observer(&decay, 0.0, Vector1::new(1.0), 1.0, |t, _x| {
    ///         calls += 1;
    ///         last_t = t;
    ///     })
    ///     .unwrap();
    /// assert_eq!(calls, 11); // t0 plus 10 steps
    /// assert_eq!(last_t, 1.0);
    /// ```
    fn integrate_with_observer<S, F, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        observer: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        F: FnMut(T, &SVector<T, D>),
    {
        crate::sink::observe(t0, x0, observer, |k| {
            self.integrate_with_steps(sys, t0, x0, t1, |s| k.step(s))
        })
    }

    /// Integrates from `(t0, x0)` to `t1` and calls `on_output(t_i, &x(t_i))`
    /// for every requested time `t_i` in `times`, in order, using the
    /// integrator's dense output ([`Step::interpolate`]).
    ///
    /// The output times do not influence the step sequence: the result and
    /// the work counters are identical to those of
    /// [`Integrator::integrate`].
    ///
    /// * `times` must be finite and sorted in the direction of integration
    ///   (non-decreasing if `t1 ≥ t0`, non-increasing if `t1 < t0`;
    ///   repetitions are reported repeatedly), otherwise
    ///   [`SimError::InvalidInput`] is returned and nothing is integrated.
    /// * Times outside `[t0, t1]` are ignored (never reported).
    /// * Times equal to `t0` are reported with `x0`, times equal to `t1` with
    ///   the final state, exactly.
    /// * On error, the times up to the last accepted step have been
    ///   reported.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::Vector2;
    /// use nh_runtime::{Dopri5, Integrator};
    ///
    /// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
    /// let times: Vec<f64> = (0..=1000).map(|i| 0.01 * i as f64).collect();
    /// let mut samples = Vec::new();
    /// let out = Dopri5::new(1e-8, 1e-10)
    ///     .integrate_with_outputs(&oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0, &times, |t, x| {
    ///         samples.push((t, x[0]));
    ///     })
    ///     .unwrap();
    /// assert_eq!(samples.len(), 1001);
    /// assert!(out.stats.steps < 200, "far fewer steps than outputs");
    /// for (t, q) in samples {
    ///     assert!((q - t.cos()).abs() < 1e-6);
    /// }
    /// ```
    fn integrate_with_outputs<S, F, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        times: &[T],
        on_output: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        F: FnMut(T, &SVector<T, D>),
    {
        crate::sink::outputs((t0, x0, t1), times, on_output, |k| {
            self.integrate_with_steps(sys, t0, x0, t1, |s| k.step(s))
        })
    }

    /// Integrates from `(t0, x0)` to `t1` and locates the [`Events`]: the
    /// sign changes of `g(t, x)`, on the dense output of the steps across
    /// which they happen (see [`Events`] for the rules). Every event found
    /// is handed to `on_event` in time order, a terminal one last; a
    /// terminal event ends the run there: [`Outcome::t`] and
    /// [`Outcome::x`] are then its time and state (the dense output's,
    /// exactly `hit.t` and `hit.x`) and [`Outcome::event`] is `Some(hit)`.
    /// Otherwise the run ends at `t1` as [`Integrator::integrate`] would:
    /// the events do not change the steps. The evaluations of `g` are
    /// counted in [`Stats::event_evals`](crate::Stats::event_evals).
    ///
    /// With projection onto holonomic constraints on, the events are
    /// located on the step's dense output as it is (before projection);
    /// its end is the projected state.
    ///
    /// A step whose end cannot be accepted (a singular chart there, a
    /// failed projection) still ends the run at a terminal event inside
    /// it, since the dense output before that end is finite: a system
    /// that falls into the singularity of its coordinates stops at its
    /// event rather than with [`SimError::Singular`]. For a step across a
    /// pole of the equations ([`OdeSystem::crossed_pole`]) only the events
    /// before the pole count (it is located on the dense output).
    ///
    /// The integrators of this crate stop at a terminal event. The default
    /// body, for other implementors, runs to `t1` with
    /// [`Integrator::integrate_with_steps`] and reports the state at the
    /// first terminal event (a failure after it does not count; the work
    /// counters are then zero).
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Vector2, Vector3};
    /// use nh_runtime::{Direction, Dop853, Events, Integrator};
    ///
    /// // A ball thrown up at 10 m/s from the ground: (height, velocity).
    /// let ball = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -9.81);
    /// // Passing 2 m (either way), the top (velocity falling through 0),
    /// // the landing (terminal).
    /// let events = Events::new(|_t: f64, x: &Vector2<f64>| Vector3::new(x[0] - 2.0, x[1], x[0]))
    ///     .direction([Direction::Either, Direction::Falling, Direction::Falling])
    ///     .terminal([false, false, true]);
    /// let mut seen = Vec::new();
    /// let out = Dop853::new(1e-10, 1e-12)
    ///     .integrate_with_events(&ball, 0.0, Vector2::new(0.0, 10.0), 10.0, &events, |hit| {
    ///         seen.push((hit.index, hit.t));
    ///     })
    ///     .unwrap();
    /// let order: Vec<usize> = seen.iter().map(|s| s.0).collect();
    /// assert_eq!(order, [0, 1, 0, 2]);
    /// assert!((seen[1].1 - 10.0 / 9.81).abs() < 1e-12); // the top
    /// assert_eq!(out.t, seen[3].1); // the landing ended the run
    /// assert!((out.t - 20.0 / 9.81).abs() < 1e-12);
    /// assert_eq!(out.event.unwrap().index, 2);
    /// ```
    fn integrate_with_events<S, G, F, const D: usize, const N: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        events: &Events<T, G, N>,
        on_event: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        G: Fn(T, &SVector<T, D>) -> SVector<T, N>,
        F: FnMut(&EventHit<T, D>),
    {
        let mut tracker = crate::events::Tracker::new(events, on_event);
        let mut hit = None;
        let result = self.integrate_with_steps(sys, t0, x0, t1, |s| {
            if hit.is_none() {
                hit = tracker.step(s);
            }
        });
        crate::events::after_the_fact(result, hit, tracker.evals)
    }
}
