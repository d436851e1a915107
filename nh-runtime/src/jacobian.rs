//! Where the implicit methods get their Jacobians from: finite differences
//! for any [`OdeSystem`], or the analytic [`OdeJacobian::jacobian`]; and
//! the methods that keep the Jacobian of the accepted point for others to
//! read ([`Linearised`]).

use nalgebra::{RealField, SMatrix, SVector};

use crate::method::Method;
use crate::numeric::{c, machine_epsilon};
use crate::{OdeJacobian, OdeSystem, Stats};

/// A right-hand side together with a way to obtain `∂f/∂x`, so that the
/// stepping code of the implicit methods exists once for both sources.
pub(crate) trait JacobianSource<T: RealField + Copy, const D: usize> {
    /// `f(t, x)` (not counted: callers count).
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D>;

    /// Writes `∂f/∂x` at `(t, x)`, where `f0 = f(t, x)`, into `out`
    /// (column-major, `D·D` entries, so that it may live on the heap);
    /// counts its work in `stats`.
    fn jacobian(
        &self,
        t: T,
        x: &SVector<T, D>,
        f0: &SVector<T, D>,
        out: &mut [T],
        stats: &mut Stats,
    );

    /// [`OdeSystem::is_autonomous`] of the system.
    fn is_autonomous(&self) -> bool;

    /// The system's own `∂f/∂t` ([`OdeJacobian::time_derivative`]), if it
    /// has one; `None` (the default) for a finite-difference source.
    #[inline]
    fn analytic_time_derivative(&self, _t: T, _x: &SVector<T, D>) -> Option<SVector<T, D>> {
        None
    }
}

/// The forward-difference increment for a variable of value `v`:
/// `max(sqrt(eps·max(1e-5, |v|)), sqrt(eps)·|v|)`, rounded so that
/// `v + δ − v` is exact; returns `(v + δ, δ)`. For `|v| ≤ 1` this is
/// Hairer's `sqrt(eps·max(1e-5, |v|))`; above, the increment scales with
/// `|v|` (relative `sqrt(eps)`), so it resolves any finite value, where
/// Hairer's falls below the spacing of the floating-point numbers near
/// `|v| = 1e17` in `f64` (`1e10` in `f32`).
pub(crate) fn increment<T: RealField + Copy>(v: T) -> (T, T) {
    let eps = machine_epsilon::<T>();
    let delta = (eps * v.abs().max(c::<T>(1e-5)))
        .sqrt()
        .max(eps.sqrt() * v.abs());
    let vp = v + delta;
    (vp, vp - v)
}

/// Forward-difference Jacobian of any [`OdeSystem`]: column `j` is
/// `(f(t, x + δ_j e_j) − f0)/δ_j` with the increment of [`increment`].
/// Costs `D` evaluations of the right-hand side.
pub(crate) struct FiniteDifference<'a, S: ?Sized>(pub(crate) &'a S);

impl<T, S, const D: usize> JacobianSource<T, D> for FiniteDifference<'_, S>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.0.rhs(t, x)
    }

    #[inline]
    fn is_autonomous(&self) -> bool {
        self.0.is_autonomous()
    }

    fn jacobian(
        &self,
        t: T,
        x: &SVector<T, D>,
        f0: &SVector<T, D>,
        out: &mut [T],
        stats: &mut Stats,
    ) {
        let mut xp = *x;
        for (j, column) in out.chunks_exact_mut(D.max(1)).take(D).enumerate() {
            let xj = x[j];
            let (xpj, delta) = increment(xj);
            xp[j] = xpj;
            let fj = self.0.rhs(t, &xp);
            for (i, o) in column.iter_mut().enumerate() {
                *o = (fj[i] - f0[i]) / delta;
            }
            xp[j] = xj;
        }
        stats.rhs_evals += D;
        stats.jacobian_evals += 1;
    }
}

/// The analytic Jacobian of an [`OdeJacobian`] system.
pub(crate) struct Analytic<'a, S: ?Sized>(pub(crate) &'a S);

impl<T, S, const D: usize> JacobianSource<T, D> for Analytic<'_, S>
where
    T: RealField + Copy,
    S: OdeJacobian<T, D> + ?Sized,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.0.rhs(t, x)
    }

    #[inline]
    fn is_autonomous(&self) -> bool {
        self.0.is_autonomous()
    }

    #[inline]
    fn analytic_time_derivative(&self, t: T, x: &SVector<T, D>) -> Option<SVector<T, D>> {
        self.0.time_derivative(t, x)
    }

    fn jacobian(
        &self,
        t: T,
        x: &SVector<T, D>,
        _f0: &SVector<T, D>,
        out: &mut [T],
        stats: &mut Stats,
    ) {
        stats.jacobian_evals += 1;
        out.copy_from_slice(self.0.jacobian(t, x).as_slice());
    }
}

/// `∂f/∂t` at `(t, x)` with `f0 = f(t, x)`: zero, with no evaluation, for
/// a system that says it is autonomous; the system's own (analytic) one
/// where it has it ([`OdeJacobian::time_derivative`], no evaluation of
/// `f`); otherwise a forward difference (one evaluation, counted) with the
/// increment of [`increment`].
pub(crate) fn time_derivative<T, J, const D: usize>(
    src: &J,
    t: T,
    x: &SVector<T, D>,
    f0: &SVector<T, D>,
    stats: &mut Stats,
) -> SVector<T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D> + ?Sized,
{
    if src.is_autonomous() {
        return SVector::zeros();
    }
    if let Some(ft) = src.analytic_time_derivative(t, x) {
        return ft;
    }
    let (tp, delta) = increment(t);
    stats.rhs_evals += 1;
    (src.rhs(tp, x) - f0) / delta
}

/// A [`Method`] that evaluates the Jacobian at every accepted point and
/// lets others read it: the implicit member of `AutoSwitch`, whose switch
/// back to the explicit member estimates the Jacobian's spectral radius.
pub(crate) trait Linearised<T: RealField + Copy, const D: usize>: Method<T, D> {
    /// The Jacobian at the current accepted point (after
    /// [`Method::start`] or [`Method::advance`] with `last == false`).
    fn jacobian(&self) -> &SMatrix<T, D, D>;
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn finite_differences_match_analytic() {
        let f = |t: f64, x: &Vector2<f64>| Vector2::new(x[0] * x[1] + t, x[0].sin() - 3.0 * t * t);
        let x = Vector2::new(0.7, -1.3);
        let mut stats = Stats::default();
        let f0 = f(2.0, &x);
        let mut jac = Matrix2::zeros();
        FiniteDifference(&f).jacobian(2.0, &x, &f0, jac.as_mut_slice(), &mut stats);
        let exact = Matrix2::new(x[1], x[0], x[0].cos(), 0.0);
        assert!((jac - exact).amax() < 1e-7, "{jac} vs {exact}");
        let ft = time_derivative(&FiniteDifference(&f), 2.0, &x, &f0, &mut stats);
        assert!((ft - Vector2::new(1.0, -12.0)).amax() < 1e-6, "{ft}");
        assert_eq!(stats.rhs_evals, 3);
        assert_eq!(stats.jacobian_evals, 1);
    }

    /// `f(t, x) = (x₁, −x₀ + sin 3t)` with its own `∂f/∂t = (0, 3 cos 3t)`.
    struct Forced;

    impl OdeSystem<f64, 2> for Forced {
        fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> {
            Vector2::new(x[1], -x[0] + (3.0 * t).sin())
        }
    }

    impl OdeJacobian<f64, 2> for Forced {
        fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
            Matrix2::new(0.0, 1.0, -1.0, 0.0)
        }

        fn time_derivative(&self, t: f64, _x: &Vector2<f64>) -> Option<Vector2<f64>> {
            Some(Vector2::new(0.0, 3.0 * (3.0 * t).cos()))
        }
    }

    #[test]
    fn the_analytic_time_derivative_replaces_the_difference() {
        let x = Vector2::new(0.7, -1.3);
        let f0 = Forced.rhs(0.4, &x);
        let mut stats = Stats::default();
        let analytic = time_derivative(&Analytic(&Forced), 0.4, &x, &f0, &mut stats);
        assert_eq!(analytic, Vector2::new(0.0, 3.0 * (3.0 * 0.4f64).cos()));
        assert_eq!(stats.rhs_evals, 0, "no evaluation of f");
        let differenced = time_derivative(&FiniteDifference(&Forced), 0.4, &x, &f0, &mut stats);
        assert_eq!(stats.rhs_evals, 1);
        assert!(
            (differenced - analytic).amax() < 1e-6,
            "{differenced} vs {analytic}"
        );
    }
}
