//! The classical fourth-order Runge–Kutta method with a fixed step.

use nalgebra::{RealField, SVector};

use crate::common::{all_finite, c, check_arguments, check_positive, machine_epsilon};
use crate::step::Poly;
use crate::{Integrator, OdeSystem, Outcome, SimError, Stats, Step};

/// Classical fourth-order Runge–Kutta with a fixed step `h`.
///
/// Step `k` ends at `t0 + k·h` (computed from `k`, so round-off does not
/// accumulate in `t`); the last step is shortened so that the integration
/// lands exactly on `t1` (a remainder below a few ulps of `t` is merged into
/// the previous step instead of becoming a tiny extra step).
///
/// * `h` is a magnitude: its sign follows the direction from `t0` to `t1`.
///   A non-positive or non-finite `h` makes `integrate` return
///   [`SimError::InvalidInput`].
/// * After each step the new state is checked; if any component is NaN or
///   infinite, [`SimError::NonFinite`] is returned at once with the last good
///   `(t, x)`.
/// * If `h` is too small to advance `t` in floating point,
///   [`SimError::StepSizeTooSmall`] is returned.
/// * The step budget ([`Rk4::with_max_steps`]) is unlimited by default.
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
    h: T,
    max_steps: usize,
    stats: Stats,
}

impl<T: RealField + Copy> Rk4<T> {
    /// A fixed-step integrator with step size `h` (> 0).
    pub fn new(h: T) -> Self {
        Self {
            h,
            max_steps: usize::MAX,
            stats: Stats::default(),
        }
    }

    /// Sets the maximum number of steps (default: unlimited); exceeding it
    /// returns [`SimError::MaxSteps`].
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }

    /// The step size.
    pub fn step_size(&self) -> T {
        self.h
    }

    /// Work counters of the most recent call to `integrate*`, whether it
    /// succeeded or failed.
    pub fn last_stats(&self) -> Stats {
        self.stats
    }

    fn run<S, F, const D: usize>(
        &self,
        stats: &mut Stats,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        mut on_step: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeSystem<T, D> + ?Sized,
        F: FnMut(&Step<'_, T, D>),
    {
        let dir = check_arguments(t0, &x0, t1)?;
        check_positive(self.h, "Rk4 step size h must be positive and finite")?;
        if dir == T::zero() {
            return Ok(Outcome {
                t: t0,
                x: x0,
                stats: *stats,
            });
        }

        let h = self.h * dir;
        // Remainders this small are round-off in `t0 + k h`, not real steps.
        let tol = (c::<T>(64.0) * machine_epsilon::<T>() * (t0.abs() + t1.abs() + self.h))
            .min(self.h * c::<T>(0.5));
        let (mut t, mut x) = (t0, x0);
        let mut k: usize = 0;
        loop {
            if stats.steps >= self.max_steps {
                return Err(SimError::MaxSteps {
                    t,
                    x,
                    steps: stats.steps,
                });
            }
            k += 1;
            let mut t_next = t0 + h * c::<T>(k as f64);
            let last = (t1 - t_next) * dir <= tol;
            if last {
                t_next = t1;
            }
            let hk = t_next - t;
            if hk * dir <= T::zero() {
                return Err(SimError::StepSizeTooSmall { t, x, h });
            }
            let (x_new, dense) = rk4_step(sys, t, &x, hk);
            stats.steps += 1;
            stats.rhs_evals += 4;
            if !all_finite(&x_new) {
                return Err(SimError::NonFinite { t, x });
            }
            on_step(&Step::new(t, &x, t_next, &x_new, &dense));
            t = t_next;
            x = x_new;
            if last {
                return Ok(Outcome {
                    t,
                    x,
                    stats: *stats,
                });
            }
        }
    }
}

/// One classical RK4 step of size `h` from `(t, x)`, with its continuous
/// extension: `x + h Σ b_i(θ) k_i` with `b1 = θ − 3θ²/2 + 2θ³/3`,
/// `b2 = b3 = θ² − 2θ³/3`, `b4 = −θ²/2 + 2θ³/3`.
#[inline]
fn rk4_step<T, S, const D: usize>(
    sys: &S,
    t: T,
    x: &SVector<T, D>,
    h: T,
) -> (SVector<T, D>, Poly<T, D>)
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    let half = h * c::<T>(0.5);
    let k1 = sys.rhs(t, x);
    let k2 = sys.rhs(t + half, &(x + k1 * half));
    let k3 = sys.rhs(t + half, &(x + k2 * half));
    let k4 = sys.rhs(t + h, &(x + k3 * h));
    let x_new = x + (k1 + (k2 + k3) * c::<T>(2.0) + k4) * (h / c::<T>(6.0));
    let dense = Poly::from_monomial(&[
        *x,
        k1 * h,
        (k2 + k3 - k1 * c::<T>(1.5) - k4 * c::<T>(0.5)) * h,
        (k1 - k2 - k3 + k4) * (h * c::<T>(2.0 / 3.0)),
    ]);
    (x_new, dense)
}

impl<T: RealField + Copy> Integrator<T> for Rk4<T> {
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
        F: FnMut(&Step<'_, T, D>),
    {
        let mut stats = Stats::default();
        let result = self.run(&mut stats, sys, t0, x0, t1, on_step);
        self.stats = stats;
        result
    }
}
