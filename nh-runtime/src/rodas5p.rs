//! Rodas5P ([`Rodas5P`], Steinebach 2023): the L-stable Rosenbrock–Wanner
//! method of order 5 for stiff problems at tight tolerances, on the
//! stepping code of `rosenbrock.rs` with the tableau `Rodas5PScheme` of
//! `rodas_tableau.rs`.

use nalgebra::RealField;

use crate::ScalarTolerance;
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource};
use crate::rodas_tableau::Rodas5PScheme;
use crate::rosenbrock::Rodas;
use crate::settings::{Settings, adaptive_builders, integrator_impl, jacobian_entry_points};

/// Rodas5P for a system whose Jacobian comes from `src`.
fn rodas5p<J, T, const D: usize>(src: J) -> Rodas<J, T, Rodas5PScheme, D, 8>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    Rodas::new(src)
}

/// Rodas5P: an 8-stage, L-stable, stiffly accurate Rosenbrock–Wanner method
/// of order 5 with an embedded 4th-order error estimate and a 4th-order
/// dense output (G. Steinebach, *Construction of Rosenbrock–Wanner method
/// Rodas5P and numerical benchmarks within the Julia Differential Equations
/// package*, BIT Numerical Mathematics 63, 27, 2023), for stiff problems at
/// tight tolerances.
///
/// It runs on the same stepping code as [`Rodas4`](crate::Rodas4) (RODAS4) with the
/// same builders, Jacobian sources, failure modes and rounding control; it
/// differs in its coefficients: 8 stages instead of 6 (7 evaluations of the
/// right-hand side and 8 linear solves with one LU decomposition per step
/// attempt, plus `f`, the Jacobian and `∂f/∂t` per accepted step), order 5
/// instead of 4, and the step-size controller
/// `h_new = h·clamp(0.9·err^(−1/5), 1/5, 6)` with Gustafsson's correction.
/// Its error estimate is closer to its error than RODAS4's (which
/// overstates it a thousandfold on stiff mechanical problems), so the same
/// `rtol` buys a larger error with far fewer steps; at equal error it needs
/// about 1.5× fewer evaluations than [`Rodas4`](crate::Rodas4) between errors of 1e-10
/// and 1e-12, and more at 1e-9 and above. Its larger coefficients cost more
/// rounding: its error levels off near `1e-14·max|x|`, RODAS4's ten times
/// lower.
///
/// Measured on the stiff disc of the lab (`k = 1e6` on the lean, a double
/// eigenvalue near −2000, `t ∈ [0, 1]`, `atol = rtol/100`, analytic
/// Jacobian) against a 16-digit reference computed independently (the
/// lab's `tight_tolerances` test holds the table): the final error stays
/// below `0.1·rtol·max|x|` from `rtol = 1e-6` down to `1e-13`, for both
/// methods.
///
/// # Example
///
/// ```rust
/// use nalgebra::{Matrix2, Vector2};
/// use nh_runtime::{OdeJacobian, OdeSystem, Rodas5P};
///
/// /// x' = −x, y' = −1e5 (y − x): eigenvalues −1 and −1e5.
/// struct TwoScales;
/// impl OdeSystem<f64, 2> for TwoScales {
///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
///         Vector2::new(-x[0], -1e5 * (x[1] - x[0]))
///     }
///     fn is_autonomous(&self) -> bool {
///         true
///     }
/// }
/// impl OdeJacobian<f64, 2> for TwoScales {
///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
///         Matrix2::new(-1.0, 0.0, 1e5, -1e5)
///     }
/// }
///
/// // y(t) = e^(−t) (1 − 1e−5)^(−1) + C e^(−1e5 t) → e^(−t)/(1 − 1e−5) after the transient.
/// let out = Rodas5P::new(1e-12, 1e-14)
///     .integrate_with_jacobian(&TwoScales, 0.0, Vector2::new(1.0, 0.0), 2.0)
///     .unwrap();
/// let exact = (-2.0f64).exp();
/// assert!((out.x[0] - exact).abs() < 1e-12 * 10.0);
/// assert!((out.x[1] - exact / (1.0 - 1e-5)).abs() < 1e-12 * 10.0);
/// assert!(out.stats.steps < 1000, "{:?}", out.stats);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rodas5P<T, Tol = ScalarTolerance<T>> {
    a: Settings<T, Tol>,
}

adaptive_builders!(Rodas5P);
integrator_impl!(Rodas5P<T, Tol>, a, |sys| rodas5p(FiniteDifference(sys)));

/// Rodas5P is a one-step method.
impl<T, Tol> crate::settings::OneStep for Rodas5P<T, Tol> {
    const ONE_STEP: bool = true;
}

jacobian_entry_points! {
    Rodas5P<T, Tol>, a, |sys| rodas5p(Analytic(sys)),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix1, Vector1};
    /// use nh_runtime::{OdeJacobian, OdeSystem, Rodas5P};
    ///
    /// /// Prothero–Robinson: x' = −1e6 (x − cos t) − sin t, solution x = cos t.
    /// struct Pr;
    /// impl OdeSystem<f64, 1> for Pr {
    ///     fn rhs(&self, t: f64, x: &Vector1<f64>) -> Vector1<f64> {
    ///         Vector1::new(-1e6 * (x[0] - t.cos()) - t.sin())
    ///     }
    /// }
    /// impl OdeJacobian<f64, 1> for Pr {
    ///     fn jacobian(&self, _t: f64, _x: &Vector1<f64>) -> Matrix1<f64> {
    ///         Matrix1::new(-1e6)
    ///     }
    /// }
    ///
    /// let out = Rodas5P::new(1e-10, 1e-12)
    ///     .integrate_with_jacobian(&Pr, 0.0, Vector1::new(1.0), 10.0)
    ///     .unwrap();
    /// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-9);
    /// assert_eq!(out.stats.jacobian_evals, out.stats.steps);
    /// ```
    integrate_with_jacobian;
    /// Like [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps), but with the analytic
    /// Jacobian [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    integrate_with_jacobian_and_steps;
}
