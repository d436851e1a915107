//! The 2-stage Gauss–Legendre collocation method (order 4, symplectic).

use nalgebra::{RealField, SMatrix, SVector};

use crate::common::{all_finite, c, check_arguments, check_positive, machine_epsilon};
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource};
use crate::linalg::Lu;
use crate::step::Poly;
use crate::{Integrator, OdeJacobian, OdeSystem, Outcome, SimError, Stats, Step};

/// `√3`, to full precision.
const SQRT3: f64 = 1.732_050_807_568_877_2;
/// Newton iterations allowed per step.
const MAX_NEWTON: usize = 50;
/// Iterations above which the (reused) Jacobian is refreshed next step.
const SLOW_NEWTON: usize = 10;

/// Why the stage equations of one step could not be solved.
enum StageFailure {
    Singular,
    NonFinite,
    NoConvergence,
}

/// The 2-stage Gauss–Legendre method: implicit Runge–Kutta collocation at
/// the Gauss points `1/2 ∓ √3/6`, order 4, A-stable, symmetric and
/// **symplectic** — on canonical Hamiltonian systems (and for quadratic
/// invariants such as angular momentum of free rigid bodies) the energy
/// error stays bounded over exponentially long times instead of drifting.
/// Fixed step `h`; use it for long conservative simulations.
///
/// Steps are laid out as for [`Rk4`](crate::Rk4): step `k` ends at
/// `t0 + k·h`, the last one is shortened to land on `t1`.
///
/// **Stage equations.** The increments `Z_i = h Σ_j a_ij f(t + c_j h, x + Z_j)`
/// are solved by simplified Newton iteration with the Jacobian `J` at the
/// start of a step. The `2D×2D` Newton matrix `I − h A⊗J` cannot be named
/// as a static matrix on stable Rust (`2*D` in a const generic), but its
/// blocks are polynomials in `J` and commute, so it is inverted exactly by
/// block elimination with a single `D×D` LU (partial pivoting, stack only)
/// of `Δ = I − (h/2) J + (h²/12) J²` (`det A = 1/12`, `tr A = 1/2`):
/// `M⁻¹ = Δ⁻¹ [[I − h a22 J, h a12 J], [h a21 J, I − h a11 J]]`.
/// `Δ` is singular exactly when `M` is (`hλ = 3 ± i√3` for an eigenvalue
/// `λ` of `J`). The iteration starts from the previous step's interpolant
/// extrapolated to the stage times (`Z_i = c_i h f(t, x)` on the first step)
/// and runs
/// until the scaled increment reaches round-off (so that the method stays
/// symplectic to machine precision), at most 50 iterations. The new state
/// is `x + √3 (Z_2 − Z_1)` (i.e. `x + Σ d_i Z_i` with `dᵀ = bᵀA⁻¹`, no
/// extra evaluations).
///
/// The Jacobian (finite differences for any [`OdeSystem`], or the
/// analytic one via [`GaussLegendre4::integrate_with_jacobian`]) and the LU
/// of `Δ` are reused from step to step as long as the Newton iteration
/// converges quickly (≤ 10 iterations); a step whose iteration fails with a
/// reused Jacobian is retried once with a fresh one.
///
/// **Dense output**: the cubic Hermite interpolant of
/// `(x_prev, f(x_prev), x, f(x))` (3rd order, C¹; more accurate than the
/// method's own quadratic collocation polynomial). `f(x)` at the end of each
/// step is evaluated anyway as the next step's starting guess.
///
/// Failure modes (the step is fixed, so nothing is retried with a smaller
/// step; use a smaller `h`):
///
/// * a singular `Δ` (even with a fresh Jacobian) → [`SimError::Singular`];
/// * non-finite stages, Jacobian or new state → [`SimError::NonFinite`];
/// * a Newton iteration that does not converge in 50 iterations, or
///   diverges, with a fresh Jacobian → [`SimError::StepSizeTooSmall`]
///   carrying `h` (read: the step is too *large* for the stage equations to
///   be solvable by the simplified Newton iteration);
/// * `h` too small to advance `t` → [`SimError::StepSizeTooSmall`]; the
///   step budget ([`GaussLegendre4::with_max_steps`], unlimited by default)
///   → [`SimError::MaxSteps`]; `h` not finite and positive →
///   [`SimError::InvalidInput`].
///
/// All carry the last accepted `(t, x)`.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{GaussLegendre4, Integrator};
///
/// // A pendulum over ~1600 periods: the energy error stays bounded.
/// let pendulum = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0].sin());
/// let energy = |x: &Vector2<f64>| 0.5 * x[1] * x[1] - x[0].cos();
/// let x0 = Vector2::new(1.0, 0.0);
/// let mut worst: f64 = 0.0;
/// GaussLegendre4::new(0.1)
///     .integrate_with_observer(&pendulum, 0.0, x0, 1e4, |_t, x| {
///         worst = worst.max((energy(x) - energy(&x0)).abs());
///     })
///     .unwrap();
/// assert!(worst < 1e-5, "{worst:e}");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussLegendre4<T> {
    h: T,
    max_steps: usize,
    stats: Stats,
}

/// Reusable Newton data: the Jacobian and the LU of `Δ` for the step size
/// they were built with.
struct NewtonMatrix<T, const D: usize> {
    jac: SMatrix<T, D, D>,
    lu: Lu<T, D>,
    h: T,
}

impl<T: RealField + Copy> GaussLegendre4<T> {
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

    /// Like [`Integrator::integrate`], but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`] in the Newton iteration.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{GaussLegendre4, OdeJacobian, OdeSystem};
    ///
    /// struct Oscillator;
    /// impl OdeSystem<f64, 2> for Oscillator {
    ///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
    ///         Vector2::new(x[1], -x[0])
    ///     }
    /// }
    /// impl OdeJacobian<f64, 2> for Oscillator {
    ///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
    ///         Matrix2::new(0.0, 1.0, -1.0, 0.0)
    ///     }
    /// }
    ///
    /// let out = GaussLegendre4::new(0.01)
    ///     .integrate_with_jacobian(&Oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0)
    ///     .unwrap();
    /// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-8);
    /// // A linear problem: one Jacobian and one LU for the whole run.
    /// assert_eq!(out.stats.jacobian_evals, 1);
    /// ```
    pub fn integrate_with_jacobian<S, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeJacobian<T, D> + ?Sized,
    {
        self.integrate_with_jacobian_and_steps(sys, t0, x0, t1, |_| {})
    }

    /// Like [`Integrator::integrate_with_steps`], but with the analytic
    /// Jacobian [`OdeJacobian::jacobian`] in the Newton iteration.
    pub fn integrate_with_jacobian_and_steps<S, F, const D: usize>(
        &mut self,
        sys: &S,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        on_step: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        S: OdeJacobian<T, D> + ?Sized,
        F: FnMut(&Step<'_, T, D>),
    {
        let mut stats = Stats::default();
        let result = self.run(&mut stats, &Analytic(sys), t0, x0, t1, on_step);
        self.stats = stats;
        result
    }

    /// Builds the Newton matrix data for step `h` at `(t, x)`.
    fn newton_matrix<J, const D: usize>(
        src: &J,
        stats: &mut Stats,
        t: T,
        x: &SVector<T, D>,
        f0: &SVector<T, D>,
        h: T,
    ) -> Result<NewtonMatrix<T, D>, StageFailure>
    where
        J: JacobianSource<T, D>,
    {
        let jac = src.jacobian(t, x, f0, stats);
        if !jac.iter().all(|v| v.is_finite()) {
            return Err(StageFailure::NonFinite);
        }
        Self::factor(stats, jac, h)
    }

    fn factor<const D: usize>(
        stats: &mut Stats,
        jac: SMatrix<T, D, D>,
        h: T,
    ) -> Result<NewtonMatrix<T, D>, StageFailure> {
        let hj = jac * h;
        let delta = SMatrix::<T, D, D>::identity() - hj * c::<T>(0.5) + hj * hj / c::<T>(12.0);
        stats.lu_decompositions += 1;
        let lu = Lu::new(delta).ok_or(StageFailure::Singular)?;
        Ok(NewtonMatrix { jac, lu, h })
    }

    /// Solves the stage equations of the step `(t, x) → t + h`; returns the
    /// new state and the number of Newton iterations, or why it failed.
    #[allow(clippy::too_many_arguments)]
    fn solve_stages<J, const D: usize>(
        src: &J,
        stats: &mut Stats,
        nm: &NewtonMatrix<T, D>,
        t: T,
        x: &SVector<T, D>,
        f0: &SVector<T, D>,
        h: T,
        eps: T,
        guess: Option<&Poly<T, D>>,
    ) -> Result<(SVector<T, D>, usize), StageFailure>
    where
        J: JacobianSource<T, D>,
    {
        let s36 = c::<T>(SQRT3 / 6.0);
        let quarter = c::<T>(0.25);
        let half = c::<T>(0.5);
        let (c1, c2) = (half - s36, half + s36);
        let (a11, a12, a21, a22) = (quarter, quarter - s36, quarter + s36, quarter);
        let (mut z1, mut z2) = match guess {
            Some(g) => (g.eval(T::one() + c1) - x, g.eval(T::one() + c2) - x),
            None => (f0 * (c1 * h), f0 * (c2 * h)),
        };
        let scale = x.map(|v| T::one() / (T::one() + v.abs()));
        let hj = nm.jac * h;
        let mut prev = T::zero();
        for k in 1..=MAX_NEWTON {
            let f1 = src.rhs(t + c1 * h, &(x + z1));
            let f2 = src.rhs(t + c2 * h, &(x + z2));
            stats.rhs_evals += 2;
            stats.newton_iterations += 1;
            // Residual r = −G(Z) = h A F − Z.
            let r1 = (f1 * a11 + f2 * a12) * h - z1;
            let r2 = (f1 * a21 + f2 * a22) * h - z2;
            let (j1, j2) = (hj * r1, hj * r2);
            let d1 = nm.lu.solve(&(r1 - j1 * a22 + j2 * a12));
            let d2 = nm.lu.solve(&(j1 * a21 + r2 - j2 * a11));
            z1 += d1;
            z2 += d2;
            if !(all_finite(&z1) && all_finite(&z2)) {
                return Err(StageFailure::NonFinite);
            }
            let norm = d1
                .component_mul(&scale)
                .amax()
                .max(d2.component_mul(&scale).amax());
            // Converged when the increment, or the remaining error
            // `θ/(1 − θ)·‖ΔZ‖` predicted from the contraction rate θ
            // (Hairer's criterion), is at round-off level.
            let theta = if k >= 2 { norm / prev } else { T::one() };
            if norm <= c::<T>(4.0) * eps
                || (theta < c::<T>(0.5) && norm * theta / (T::one() - theta) <= eps)
            {
                return Ok((x + (z2 - z1) * c::<T>(SQRT3), k));
            }
            if k >= 2 && norm >= prev * c::<T>(0.9) {
                // No longer contracting: round-off floor, or divergence.
                if norm <= c::<T>(1e3) * eps {
                    return Ok((x + (z2 - z1) * c::<T>(SQRT3), k));
                }
                if norm >= prev {
                    return Err(StageFailure::NoConvergence);
                }
            }
            prev = norm;
        }
        Err(StageFailure::NoConvergence)
    }

    fn run<J, F, const D: usize>(
        &self,
        stats: &mut Stats,
        src: &J,
        t0: T,
        x0: SVector<T, D>,
        t1: T,
        mut on_step: F,
    ) -> Result<Outcome<T, D>, SimError<T, D>>
    where
        J: JacobianSource<T, D>,
        F: FnMut(&Step<'_, T, D>),
    {
        let dir = check_arguments(t0, &x0, t1)?;
        check_positive(
            self.h,
            "GaussLegendre4 step size h must be positive and finite",
        )?;
        if dir == T::zero() {
            return Ok(Outcome {
                t: t0,
                x: x0,
                stats: *stats,
            });
        }

        let eps = machine_epsilon::<T>();
        let h = self.h * dir;
        let tol = (c::<T>(64.0) * eps * (t0.abs() + t1.abs() + self.h)).min(self.h * c::<T>(0.5));
        let (mut t, mut x) = (t0, x0);
        let mut f0 = src.rhs(t, &x);
        stats.rhs_evals += 1;
        if !all_finite(&f0) {
            return Err(SimError::NonFinite { t, x });
        }
        let fail = |why: StageFailure, t: T, x: SVector<T, D>, h: T| match why {
            StageFailure::Singular => SimError::Singular { t, x },
            StageFailure::NonFinite => SimError::NonFinite { t, x },
            StageFailure::NoConvergence => SimError::StepSizeTooSmall { t, x, h },
        };
        let mut nm: Option<NewtonMatrix<T, D>> = None;
        let mut refresh = true;
        let mut prev: Option<(T, Poly<T, D>)> = None;
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

            // Newton matrix: reuse unless stale, or built for another step.
            let mut fresh = false;
            // (A Newton matrix for a step within 0.1 % of `hk` is as good.)
            let reusable =
                !refresh && matches!(&nm, Some(m) if (m.h - hk).abs() <= c::<T>(1e-3) * hk.abs());
            // Starting guess: the previous step's interpolant, extrapolated
            // to the new stage times (when the steps are equal).
            let guess = match &prev {
                Some((hp, p)) if (*hp - hk).abs() <= c::<T>(1e-3) * hk.abs() => Some(p),
                _ => None,
            };
            if !reusable {
                let jac = match (&nm, refresh) {
                    (Some(m), false) => m.jac,
                    _ => {
                        fresh = true;
                        let jac = src.jacobian(t, &x, &f0, stats);
                        if !jac.iter().all(|v| v.is_finite()) {
                            return Err(SimError::NonFinite { t, x });
                        }
                        jac
                    }
                };
                nm = Some(Self::factor(stats, jac, hk).map_err(|e| fail(e, t, x, hk))?);
            }
            let mut result = match &nm {
                Some(m) => Self::solve_stages(src, stats, m, t, &x, &f0, hk, eps, guess),
                None => Err(StageFailure::Singular),
            };
            if result.is_err() && !fresh {
                // Retry once with a fresh Jacobian.
                let m = Self::newton_matrix(src, stats, t, &x, &f0, hk)
                    .map_err(|e| fail(e, t, x, hk))?;
                result = Self::solve_stages(src, stats, &m, t, &x, &f0, hk, eps, None);
                nm = Some(m);
            }
            let (x_new, iterations) = result.map_err(|e| fail(e, t, x, hk))?;
            refresh = iterations > SLOW_NEWTON;

            let f_new = src.rhs(t_next, &x_new);
            stats.rhs_evals += 1;
            if !(all_finite(&x_new) && all_finite(&f_new)) {
                return Err(SimError::NonFinite { t, x });
            }
            stats.steps += 1;
            // Cubic Hermite in Hairer's nested form.
            let ydiff = x_new - x;
            let bspl = f0 * hk - ydiff;
            let dense = Poly::from_nested(&[x, ydiff, bspl, ydiff - f_new * hk - bspl]);
            on_step(&Step::new(t, &x, t_next, &x_new, &dense));
            prev = Some((hk, dense));
            t = t_next;
            x = x_new;
            f0 = f_new;
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

impl<T: RealField + Copy> Integrator<T> for GaussLegendre4<T> {
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
        let result = self.run(&mut stats, &FiniteDifference(sys), t0, x0, t1, on_step);
        self.stats = stats;
        result
    }
}
