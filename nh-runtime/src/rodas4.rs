//! RODAS4 ([`Rodas4`]), after Hairer's `RODAS`: the L-stable Rosenbrock–Wanner
//! method of order 4 for stiff problems, on the stepping code of
//! `rosenbrock.rs` with the tableau `Rodas4Scheme` of `rodas_tableau.rs`.

use nalgebra::RealField;

use crate::ScalarTolerance;
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource};
use crate::rodas_tableau::Rodas4Scheme;
use crate::rosenbrock::Rodas;
use crate::settings::{Settings, adaptive_builders, integrator_impl, jacobian_entry_points};

/// RODAS4: a 6-stage, L-stable, stiffly accurate Rosenbrock–Wanner method of
/// order 4 with an embedded 3rd-order error estimate and a 3rd-order dense
/// output, a port of the algorithm of Hairer's `RODAS` (Hairer & Wanner,
/// *Solving ODEs II*, IV.7).
///
/// For stiff problems (fast decaying modes, chemical kinetics, stiff
/// springs, high-gain controllers), where explicit methods are limited by
/// stability rather than accuracy. It is linearly implicit: each step
/// solves six linear systems with the one matrix `I/(hγ) − J`, `γ = 1/4`,
/// factorised by a stack-allocated LU with partial pivoting; there is no
/// Newton iteration.
///
/// * Jacobian: the [`Integrator`](crate::Integrator) implementation works for any
///   [`OdeSystem`](crate::OdeSystem) with a forward-difference Jacobian (`D` extra right-hand
///   side evaluations, increment `sqrt(eps·max(1e-5, |x_j|))` as in
///   Hairer's codes, but at least `sqrt(eps)·|x_j|`, so that it resolves
///   any finite state);
///   [`Rodas4::integrate_with_jacobian`] uses the analytic
///   [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead. `∂f/∂t` is always obtained by one
///   forward difference (exactly zero for autonomous systems). The Jacobian
///   is evaluated once per accepted step and reused after rejections;
///   [`Stats::jacobian_evals`](crate::Stats::jacobian_evals) counts Jacobians (analytic or finite
///   difference), [`Stats::lu_decompositions`](crate::Stats::lu_decompositions) the LU factorisations.
/// * Error norm as [`Dopri5`](crate::Dopri5) (RMS of
///   `err_i/(atol_i + rtol_i·max(|x_i|, |x_new_i|))`, per component with
///   [`Rodas4::with_tolerances`]) applied to the embedded
///   estimate `U_6`; step control of `RODAS`:
///   `h_new = h·clamp(0.9·err^(−1/4), 1/5, 6)` with Gustafsson's predictive
///   correction; automatic initial step (`hinit`, order 4) unless
///   [`Rodas4::with_initial_step`] is given.
/// * [`Rodas4::with_fixed_step`] switches the error control off (for
///   convergence studies).
/// * Rounding: each step integrates over exactly the interval the clock
///   advances (`t_new − t` as represented, not the nominal `h`), and the
///   state is updated with compensated summation (the rounding error of
///   `x + Δx` is carried into the next step), so that neither the time nor
///   the state drifts by an ulp per step over tens of thousands of steps:
///   the error stays proportional to `rtol` down to about `1e-14`
///   (see [`Rodas5P`](crate::Rodas5P) for the measurements). A smaller positive `rtol`
///   (below `50·eps`, 1.1e-14 in `f64`) ends the run at once in
///   [`SimError::ToleranceTooTight`](crate::SimError::ToleranceTooTight).
///
/// Failure modes:
///
/// * A singular (or non-finite) iteration matrix rejects the step and
///   halves `h`; after 5 consecutive failures [`SimError::Singular`](crate::SimError::Singular) is
///   returned with the last accepted state. A non-finite Jacobian at an
///   accepted state returns [`SimError::NonFinite`](crate::SimError::NonFinite) at once.
/// * Non-finite stages are rejected and retried with half the step; as in
///   [`Dopri5`](crate::Dopri5), an underflowing step gives
///   [`SimError::NonFinite`](crate::SimError::NonFinite) or [`SimError::StepSizeTooSmall`](crate::SimError::StepSizeTooSmall), and the
///   budget of step attempts (default 100 000) [`SimError::MaxSteps`](crate::SimError::MaxSteps).
/// * Invalid tolerances or step settings give [`SimError::InvalidInput`](crate::SimError::InvalidInput).
///
/// Work per step attempt: 6 evaluations of the right-hand side and one LU
/// decomposition; per accepted step (and at `t0`) additionally `f(t, x)`,
/// the Jacobian and `∂f/∂t` (`D + 2` evaluations with finite differences,
/// 2 and one Jacobian call with the analytic Jacobian).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Dopri5, Integrator, Rodas4};
///
/// // x' = −1e6 (x − cos t) − sin t, exact solution x = cos t.
/// let stiff = |t: f64, x: &Vector1<f64>| Vector1::new(-1e6 * (x[0] - t.cos()) - t.sin());
/// let out = Rodas4::new(1e-6, 1e-9)
///     .integrate(&stiff, 0.0, Vector1::new(1.0), 10.0)
///     .unwrap();
/// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-6);
/// assert!(out.stats.steps < 100);
/// ```
///
/// The type parameter `Tol` is how errors are weighed: [`ScalarTolerance`]
/// (the default, from [`Rodas4::new`]) or
/// [`PerComponentTolerance`](crate::PerComponentTolerance) (from
/// [`Rodas4::with_tolerances`]); see [Tolerances and the error
/// norm](crate#tolerances-and-the-error-norm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rodas4<T, Tol = ScalarTolerance<T>> {
    a: Settings<T, Tol>,
}

adaptive_builders!(Rodas4);
integrator_impl!(Rodas4<T, Tol>, a, |sys| rodas4(FiniteDifference(sys)));

/// Rodas4 is a one-step method.
impl<T, Tol> crate::settings::OneStep for Rodas4<T, Tol> {
    const ONE_STEP: bool = true;
}

jacobian_entry_points! {
    Rodas4<T, Tol>, a, |sys| rodas4(Analytic(sys)),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{OdeJacobian, OdeSystem, Rodas4};
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
    /// let mut ros = Rodas4::new(1e-8, 1e-10);
    /// let out = ros.integrate_with_jacobian(&TwoScales, 0.0, Vector2::new(1.0, 0.0), 5.0).unwrap();
    /// assert!((out.x[0] - (-5.0f64).exp()).abs() < 1e-8);
    /// // One Jacobian at t0 and one after every accepted step but the last.
    /// assert_eq!(out.stats.jacobian_evals, out.stats.steps);
    /// ```
    integrate_with_jacobian;
    /// Like [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps), but with the analytic
    /// Jacobian [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    integrate_with_jacobian_and_steps;
}

/// RODAS4 for a system whose Jacobian comes from `src`.
pub(crate) fn rodas4<J, T, const D: usize>(src: J) -> Rodas<J, T, Rodas4Scheme, D, 6>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    Rodas::new(src)
}
