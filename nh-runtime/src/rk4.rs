//! The classical fourth-order Runge–Kutta method with a fixed step.

use nalgebra::{RealField, SVector};

use crate::method::{Failure, Method};
use crate::numeric::{all_finite_in, c};
use crate::settings::{Settings, fixed_builders, integrator_impl};
use crate::step::Poly;
use crate::tolerance::Tolerance;
use crate::{OdeSystem, Stats};

/// Classical fourth-order Runge–Kutta with a fixed step `h`.
///
/// Step `k` ends at `t0 + k·h` (computed from `k`, so round-off does not
/// accumulate in `t`); the last step is shortened so that the integration
/// lands exactly on `t1` (a remainder below a few ulps of `t` is merged into
/// the previous step instead of becoming a tiny extra step).
///
/// * `h` is a magnitude: its sign follows the direction from `t0` to `t1`.
///   A non-positive or non-finite `h` makes `integrate` return
///   [`SimError::InvalidInput`](crate::SimError::InvalidInput).
/// * After each step the new state is checked; if any component is NaN or
///   infinite, [`SimError::NonFinite`](crate::SimError::NonFinite) is returned at once with the last good
///   `(t, x)`.
/// * If `h` is too small to advance `t` in floating point,
///   [`SimError::StepSizeTooSmall`](crate::SimError::StepSizeTooSmall) is returned.
/// * At most 1 000 000 steps by default ([`Rk4::with_max_steps`] raises
///   or lowers the budget); more return [`SimError::MaxSteps`](crate::SimError::MaxSteps).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Integrator, Rk4};
///
/// let decay = |_t: f64, x: &Vector1<f64>| -x;
/// let out = Rk4::new(0.01).integrate(&decay, 0.0, Vector1::new(1.0), 1.0).unwrap();
/// assert!((out.x[0] - (-1.0f64).exp()).abs() < 1e-10);
/// assert_eq!(out.stats.steps, 100);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4<T> {
    f: Settings<T>,
}

fixed_builders!(Rk4);
integrator_impl!(Rk4, f, |sys| Rk4Stages::new(sys));

/// Rk4 is a one-step method.
impl<T> crate::settings::OneStep for Rk4<T> {
    const ONE_STEP: bool = true;
}

/// The four stages of one classical RK4 step.
struct Rk4Stages<'a, S: ?Sized, T, const D: usize> {
    sys: &'a S,
    k: [SVector<T, D>; 4],
    x_new: SVector<T, D>,
    dense: Poly<T, D>,
}

impl<'a, S: ?Sized, T: RealField + Copy, const D: usize> Rk4Stages<'a, S, T, D> {
    fn new(sys: &'a S) -> Self {
        Rk4Stages {
            sys,
            k: [SVector::zeros(); 4],
            x_new: SVector::zeros(),
            dense: Poly::from_monomial(&[]),
        }
    }
}

impl<T, S, const D: usize> Method<T, D> for Rk4Stages<'_, S, T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    const ORDER: u32 = 4;

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.sys.rhs(t, x)
    }

    fn start(&mut self, _t: T, _x: &SVector<T, D>, _stats: &mut Stats) -> Result<(), Failure> {
        Ok(())
    }

    #[inline(always)]
    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        _t_new: T,
        _tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        let sys = self.sys;
        let half = h * c::<T>(0.5);
        let k1 = sys.rhs(t, x);
        let k2 = sys.rhs(t + half, &(x + k1 * half));
        let k3 = sys.rhs(t + half, &(x + k2 * half));
        let k4 = sys.rhs(t + h, &(x + k3 * h));
        stats.rhs_evals += 4;
        self.x_new = x + (k1 + (k2 + k3) * c::<T>(2.0) + k4) * (h / c::<T>(6.0));
        self.k = [k1, k2, k3, k4];
        // Every stage enters `x_new` with a positive weight, so (in IEEE
        // arithmetic) `x_new` is finite only if all of them are.
        if all_finite_in(&[self.x_new]) {
            Ok(T::zero())
        } else {
            Err(Failure::NonFinite)
        }
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    /// The continuous extension `x + h Σ b_i(θ) k_i` with
    /// `b1 = θ − 3θ²/2 + 2θ³/3`, `b2 = b3 = θ² − 2θ³/3`, `b4 = −θ²/2 + 2θ³/3`.
    fn build_dense(&mut self, _t: T, x: &SVector<T, D>, h: T, _stats: &mut Stats) -> bool {
        let [k1, k2, k3, k4] = self.k;
        self.dense = Poly::from_monomial(&[
            *x,
            k1 * h,
            (k2 + k3 - k1 * c::<T>(1.5) - k4 * c::<T>(0.5)) * h,
            (k1 - k2 - k3 + k4) * (h * c::<T>(2.0 / 3.0)),
        ]);
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn advance(
        &mut self,
        _t: T,
        _x: &SVector<T, D>,
        _last: bool,
        _: &mut Stats,
    ) -> Result<(), Failure> {
        Ok(())
    }
}
