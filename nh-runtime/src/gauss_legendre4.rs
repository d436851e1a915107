//! The 2-stage Gauss–Legendre collocation method (order 4, symplectic).

use alloc::vec;
use alloc::vec::Vec;

use nalgebra::{RealField, SVector};

use crate::Stats;
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource};
use crate::linalg::{factor, matvec, solve};
use crate::method::{Failure, Method, counted};
use crate::numeric::{all_finite, c, machine_epsilon};
use crate::settings::{Settings, fixed_builders, integrator_impl, jacobian_entry_points};
use crate::step::{Poly, hermite_terms};
use crate::tolerance::Tolerance;

/// `√3`, to full precision.
const SQRT3: f64 = 1.732_050_807_568_877_2;
/// Newton iterations allowed per step.
const MAX_NEWTON: usize = 50;
/// Iterations above which the (reused) Jacobian is refreshed next step.
const SLOW_NEWTON: usize = 10;

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
/// block elimination with a single `D×D` LU (partial pivoting)
/// of `Δ = I − (h/2) J + (h²/12) J²` (`det A = 1/12`, `tr A = 1/2`):
/// `M⁻¹ = Δ⁻¹ [[I − h a22 J, h a12 J], [h a21 J, I − h a11 J]]`.
/// `Δ` is singular exactly when `M` is (`hλ = 3 ± i√3` for an eigenvalue
/// `λ` of `J`). The iteration starts from the previous step's interpolant
/// extrapolated to the stage times (`Z_i = c_i h f(t, x)` on the first step)
/// and runs
/// until the scaled increment reaches round-off (so that the method stays
/// symplectic to machine precision), at most 50 iterations. An iteration
/// that stops contracting has converged when its increment is within the
/// round-off the stages' arguments carry, `ε h |J| |x|` (which grows with
/// an angle that has turned many times), else it has failed. The new state
/// is `x + √3 (Z_2 − Z_1)` (i.e. `x + Σ d_i Z_i` with `dᵀ = bᵀA⁻¹`, no
/// extra evaluations).
///
/// The Jacobian (finite differences for any [`OdeSystem`](crate::OdeSystem), or the
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
/// * a singular `Δ` (even with a fresh Jacobian) → [`SimError::Singular`](crate::SimError::Singular);
/// * non-finite stages, Jacobian or new state → [`SimError::NonFinite`](crate::SimError::NonFinite);
/// * a Newton iteration that does not converge in 50 iterations, or
///   diverges, with a fresh Jacobian → [`SimError::NoConvergence`](crate::SimError::NoConvergence)
///   carrying `h`: the step is too large for the stage equations to be
///   solvable by the simplified Newton iteration; reduce `h`;
/// * `h` too small to advance `t` → [`SimError::StepSizeTooSmall`](crate::SimError::StepSizeTooSmall); the
///   step budget ([`GaussLegendre4::with_max_steps`], 1 000 000 steps by
///   default) → [`SimError::MaxSteps`](crate::SimError::MaxSteps); `h` not finite and positive →
///   [`SimError::InvalidInput`](crate::SimError::InvalidInput).
///
/// **Memory.** The `D×D` Jacobian and the LU of `Δ` live in a heap
/// workspace allocated once per call (three allocations, whatever the
/// number of steps; once per chart segment for a system whose atlas it
/// runs over, [`OdeSystem::charts`](crate::OdeSystem::charts)), so large
/// systems do not need a large stack; this is
/// why `GaussLegendre4` needs the `alloc` feature (part of the default
/// `std`). The analytic Jacobian of [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) is returned
/// by value, so it passes through the stack once per evaluation.
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
    f: Settings<T>,
}

fixed_builders!(GaussLegendre4);
integrator_impl!(GaussLegendre4, f, |sys| Gauss::new(FiniteDifference(sys)));

/// GaussLegendre4 is a one-step method.
impl<T> crate::settings::OneStep for GaussLegendre4<T> {
    const ONE_STEP: bool = true;
}

jacobian_entry_points! {
    GaussLegendre4, f, |sys| Gauss::new(Analytic(sys)),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) in the Newton iteration.
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
    integrate_with_jacobian;
    /// Like [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps), but with the analytic
    /// Jacobian [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) in the Newton iteration.
    integrate_with_jacobian_and_steps;
}

impl<T: RealField + Copy> GaussLegendre4<T> {}

/// The state of the Gauss method: the Newton workspace (Jacobian and LU of
/// `Δ`, on the heap), the derivative at the accepted point and the last
/// trial with its interpolant.
struct Gauss<J, T, const D: usize> {
    src: J,
    eps: T,
    /// `∂f/∂x`, column-major.
    jac: Vec<T>,
    /// The LU factors of `Δ = I − (h/2) J + (h²/12) J²`, column-major.
    lu: Vec<T>,
    perm: Vec<usize>,
    jac_valid: bool,
    /// The step the LU was built for.
    lu_h: Option<T>,
    /// Whether the next step needs a fresh Jacobian.
    refresh: bool,
    f0: SVector<T, D>,
    x_new: SVector<T, D>,
    f_new: SVector<T, D>,
    /// The step of the last trial.
    h: T,
    dense: Poly<T, D>,
    /// The previous step and its interpolant (the next starting guess).
    prev: Option<(T, Poly<T, D>)>,
}

impl<J, T, const D: usize> Gauss<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    /// The method with its workspace (allocated here, once per call).
    fn new(src: J) -> Self {
        Gauss {
            src,
            eps: machine_epsilon(),
            jac: vec![T::zero(); D * D],
            lu: vec![T::zero(); D * D],
            perm: vec![0; D],
            jac_valid: false,
            lu_h: None,
            refresh: true,
            f0: SVector::zeros(),
            x_new: SVector::zeros(),
            f_new: SVector::zeros(),
            h: T::zero(),
            dense: Poly::from_monomial(&[]),
            prev: None,
        }
    }

    /// A fresh Jacobian at `(t, x)`.
    fn new_jacobian(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.src.jacobian(t, x, &self.f0, &mut self.jac, stats);
        self.jac_valid = self.jac.iter().all(|v| v.is_finite());
        if self.jac_valid {
            Ok(())
        } else {
            Err(Failure::NonFinite)
        }
    }

    /// Builds and factorises `Δ = I − (h/2) J + (h²/12) J²` for step `h`.
    fn factor(&mut self, h: T, stats: &mut Stats) -> Result<(), Failure> {
        let (half, twelfth) = (h * c::<T>(0.5), h * h / c::<T>(12.0));
        let j = &self.jac;
        for col in 0..D {
            for row in 0..D {
                let mut jj = T::zero();
                for k in 0..D {
                    jj += j[row + k * D] * j[k + col * D];
                }
                let id = if row == col { T::one() } else { T::zero() };
                self.lu[row + col * D] = id - j[row + col * D] * half + jj * twelfth;
            }
        }
        stats.lu_decompositions += 1;
        self.lu_h = None;
        if !factor::<T, D>(&mut self.lu, &mut self.perm) {
            return Err(Failure::Singular);
        }
        self.lu_h = Some(h);
        Ok(())
    }

    /// The scaled increment below which round-off in the stages' arguments
    /// keeps the Newton iteration from contracting: `x + Z` is rounded to
    /// about `ε|x|` in each component, which moves `h f` by about
    /// `ε h |J| |x|`. It matters where a coordinate has grown large (an
    /// angle that has turned ten thousand times), not at round-off of
    /// order-one states.
    fn round_off(&self, x: &SVector<T, D>, h: T, scale: &SVector<T, D>) -> T {
        let mut worst = T::zero();
        for (row, s) in scale.iter().enumerate() {
            let sum = (0..D).fold(T::zero(), |acc, col| {
                acc + self.jac[row + col * D].abs() * x[col].abs()
            });
            worst = worst.max(sum * *s);
        }
        self.eps * h.abs() * worst
    }

    /// Solves the stage equations of the step `(t, x) → t + h`; returns the
    /// new state and the number of Newton iterations.
    fn solve_stages(
        &self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        guess: Option<&Poly<T, D>>,
        stats: &mut Stats,
    ) -> Result<(SVector<T, D>, usize), Failure> {
        let (src, f0, eps) = (&self.src, &self.f0, self.eps);
        let jv = |r: &SVector<T, D>| matvec(&self.jac, r) * h;
        let solve = |b: &SVector<T, D>| solve(&self.lu, &self.perm, b);
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
        let mut prev = T::zero();
        for k in 1..=MAX_NEWTON {
            let f1 = src.rhs(t + c1 * h, &(x + z1));
            let f2 = src.rhs(t + c2 * h, &(x + z2));
            stats.rhs_evals += 2;
            stats.newton_iterations += 1;
            // Residual r = −G(Z) = h A F − Z.
            let r1 = (f1 * a11 + f2 * a12) * h - z1;
            let r2 = (f1 * a21 + f2 * a22) * h - z2;
            let (j1, j2) = (jv(&r1), jv(&r2));
            let d1 = solve(&(r1 - j1 * a22 + j2 * a12));
            let d2 = solve(&(j1 * a21 + r2 - j2 * a11));
            z1 += d1;
            z2 += d2;
            if !(all_finite(&z1) && all_finite(&z2)) {
                return Err(Failure::NonFinite);
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
                if norm <= c::<T>(1e3) * eps + c::<T>(1e2) * self.round_off(x, h, &scale) {
                    return Ok((x + (z2 - z1) * c::<T>(SQRT3), k));
                }
                if norm >= prev {
                    return Err(Failure::NoConvergence);
                }
            }
            prev = norm;
        }
        Err(Failure::NoConvergence)
    }
}

impl<J, T, const D: usize> Method<T, D> for Gauss<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    const ORDER: u32 = 4;
    const SYMMETRIC: bool = true;

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.src.rhs(t, x)
    }

    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.f0 = counted(self.src.rhs(t, x), stats)?;
        Ok(())
    }

    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        t_new: T,
        _tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        // (A Newton matrix or a guess for a step within 0.1 % of `h` is as good.)
        let near = |other: T| (other - h).abs() <= c::<T>(1e-3) * h.abs();
        let reusable = !self.refresh && self.lu_h.is_some_and(near);
        let mut fresh = false;
        if !reusable {
            if self.refresh || !self.jac_valid {
                fresh = true;
                self.new_jacobian(t, x, stats)?;
            }
            self.factor(h, stats)?;
        }
        // Starting guess: the previous step's interpolant, extrapolated to
        // the new stage times (when the steps are equal).
        let guess = self
            .prev
            .as_ref()
            .filter(|(hp, _)| near(*hp))
            .map(|(_, p)| p);
        let mut result = self.solve_stages(t, x, h, guess, stats);
        if result.is_err() && !fresh {
            // Retry once with a fresh Jacobian.
            self.new_jacobian(t, x, stats)?;
            self.factor(h, stats)?;
            result = self.solve_stages(t, x, h, None, stats);
        }
        let (x_new, iterations) = result?;
        self.refresh = iterations > SLOW_NEWTON;
        self.f_new = self.src.rhs(t_new, &x_new);
        stats.rhs_evals += 1;
        (self.x_new, self.h) = (x_new, h);
        if !(all_finite(&x_new) && all_finite(&self.f_new)) {
            return Err(Failure::NonFinite);
        }
        // Cubic Hermite in Hairer's nested form.
        self.dense = Poly::from_nested(&hermite_terms(x, &self.f0, &x_new, &self.f_new, h));
        Ok(T::zero())
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    fn replace_end(&mut self, x: &SVector<T, D>) {
        self.x_new = *x;
    }

    fn build_dense(&mut self, _t: T, _x: &SVector<T, D>, _h: T, _stats: &mut Stats) -> bool {
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
        self.prev = Some((self.h, self.dense));
        self.f0 = self.f_new;
        Ok(())
    }
}
