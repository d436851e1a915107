//! A variable-order, variable-step BDF method for stiff problems ([`Bdf`]),
//! in the quasi-constant-step form of Shampine & Reichelt (MATLAB's
//! `ode15s`, SciPy's `BDF`): backward differences of the interpolating
//! polynomial, rescaled when the step changes, orders 1 to 5, the
//! numerical differentiation formulas (NDF) of Klopfenstein and Shampine.

use nalgebra::{RealField, SMatrix, SVector};

use crate::ScalarTolerance;
use crate::Stats;
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource};
use crate::linalg::Lu;
use crate::method::{Failure, Method, Pi, counted};
use crate::numeric::{all_finite, c, machine_epsilon};
use crate::settings::{Settings, adaptive_builders, integrator_impl, jacobian_entry_points};
use crate::step::Poly;
use crate::tolerance::Tolerance;

/// The highest order.
const MAX_ORDER: usize = 5;
/// Backward differences kept: orders 0..=MAX_ORDER+2.
const NDIFF: usize = MAX_ORDER + 3;
/// Newton iterations allowed per solve.
const NEWTON_MAXITER: usize = 10;
/// The Newton iteration has converged when its remaining error, estimated
/// from the contraction rate, is below this fraction of the error weights.
const NEWTON_TOL: f64 = 0.2;
/// The contraction estimate `η = ρ/(1 − ρ)` assumed with a new iteration
/// matrix (`20^1.25`) and after a change of step (`100^1.25`); the first
/// iteration of a solve uses `η^(3/4)` (Hairer's `RADAU` and diffsol:
/// `η^0.8`).
const ETA_NEW_MATRIX: f64 = 42.294_850_537_622_565;
const ETA_NEW_STEP: f64 = 316.227_766_016_837_96;
/// A solve that needs this many Newton iterations with a Jacobian from an
/// earlier step has the Jacobian evaluated again at the next prediction.
const SLOW_NEWTON: usize = 3;
/// The LU decomposition is kept while `c = h/α_q` stays within 30 % of the
/// one it was made for and for at most 20 accepted steps.
const LU_C_CHANGE: f64 = 0.3;
const LU_MAX_AGE: usize = 20;
/// The step factor after a rejected step is at least this.
const MIN_FACTOR: f64 = 0.2;
/// The step factor after an accepted step is at most this; the step only
/// changes (the differences are only rescaled) when the proposed factor
/// reaches it or falls to [`SHRINK`], or the order changes.
const MAX_FACTOR: f64 = 2.0;
const SHRINK: f64 = 0.9;
/// An accepted step shrinks by at most this factor.
const MIN_ACCEPTED_FACTOR: f64 = 0.5;
/// The NDF coefficients κ_q of Shampine & Reichelt (order 5: plain BDF).
const KAPPA: [f64; MAX_ORDER + 1] = [0.0, -0.1850, -1.0 / 9.0, -0.0823, -0.0415, 0.0];
/// γ_q = Σ_{j=1..q} 1/j.
const GAMMA: [f64; MAX_ORDER + 1] = [0.0, 1.0, 1.5, 11.0 / 6.0, 25.0 / 12.0, 137.0 / 60.0];

/// `1/α_q`, `α_q = (1 − κ_q) γ_q` the leading coefficient of the order-q
/// formula.
const INV_ALPHA: [f64; MAX_ORDER + 1] = {
    let mut a = [0.0; MAX_ORDER + 1];
    let mut q = 1;
    while q <= MAX_ORDER {
        a[q] = 1.0 / ((1.0 - KAPPA[q]) * GAMMA[q]);
        q += 1;
    }
    a
};

/// The error constants `κ_q γ_q + 1/(q+1)` of the order-q formulas.
const ERROR_CONSTANT: [f64; MAX_ORDER + 1] = {
    let mut e = [0.0; MAX_ORDER + 1];
    let mut q = 0;
    while q <= MAX_ORDER {
        e[q] = KAPPA[q] * GAMMA[q] + 1.0 / (q as f64 + 1.0);
        q += 1;
    }
    e
};

/// Monomial coefficients in `θ` of the Newton basis polynomial
/// `Π_{m<j} (θ − 1 + m)/(m + 1)` of backward difference `j` on a step
/// `[t − h, t]`, `θ = (τ − t + h)/h`.
const DENSE_BASIS: [[f64; MAX_ORDER + 1]; MAX_ORDER + 1] = [
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [-1.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, -1.0 / 2.0, 1.0 / 2.0, 0.0, 0.0, 0.0],
    [0.0, -1.0 / 6.0, 0.0, 1.0 / 6.0, 0.0, 0.0],
    [0.0, -1.0 / 12.0, -1.0 / 24.0, 1.0 / 12.0, 1.0 / 24.0, 0.0],
    [
        0.0,
        -1.0 / 20.0,
        -1.0 / 24.0,
        1.0 / 24.0,
        1.0 / 24.0,
        1.0 / 120.0,
    ],
];

/// A variable-order (1–5), variable-step BDF integrator for stiff problems,
/// in the quasi-constant-step form of Shampine & Reichelt ("The MATLAB ODE
/// suite", SIAM J. Sci. Comput. 18, 1997; MATLAB's `ode15s`, SciPy's
/// `BDF`, which diffsol follows): the numerical differentiation formulas
/// (NDF, with Klopfenstein's and Shampine's `κ`) of orders 1 to 4 and the
/// BDF of order 5, on backward differences of the interpolating polynomial
/// that are rescaled whenever the step changes.
///
/// For stiff problems at moderate tolerances (`rtol` about 1e-4 to 1e-10),
/// where it needs fewer evaluations of the right-hand side than the
/// Rosenbrock methods: a step costs one Newton iteration (one evaluation)
/// most of the time, no Jacobian and mostly no LU decomposition.
///
/// * Newton iteration on `I − (h/α_q) J` with a stored LU decomposition,
///   kept while `c = h/α_q` stays within 30 % of the `c` it was made for
///   and for at most 20 steps (CVODE's and diffsol's rule); the iteration
///   has converged when `η·‖Δx‖ < 0.2` in the error norm, `η = ρ/(1 − ρ)`
///   from its contraction rate `ρ`, carried from solve to solve (at a first
///   iteration `η^(3/4)`), so that a solve usually converges after one
///   evaluation (Hairer's `RADAU`; diffsol). The Jacobian is evaluated at
///   the start and again (at the prediction) only when the iteration fails
///   to converge or needed 3 iterations or more; if it fails with a fresh
///   Jacobian and an exact matrix, the step is halved. The [`Integrator`](crate::Integrator) implementation
///   works for any [`OdeSystem`](crate::OdeSystem) with a forward-difference
///   Jacobian (`D` evaluations each, as [`Rodas4`](crate::Rodas4));
///   [`Bdf::integrate_with_jacobian`] uses the analytic
///   [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian).
///   [`Stats::newton_iterations`](crate::Stats::newton_iterations),
///   [`Stats::jacobian_evals`](crate::Stats::jacobian_evals) and
///   [`Stats::lu_decompositions`](crate::Stats::lu_decompositions) count
///   the work.
/// * Error: the estimate `(κ_q γ_q + 1/(q+1))·(x_new − x_pred)` in the
///   error norm of the other adaptive methods (see [Tolerances and the
///   error norm](crate#tolerances-and-the-error-norm), per component with
///   [`Bdf::with_tolerances`]; the Newton iteration weighs with `x` and the
///   prediction `x_pred` instead of `x_new`); a rejected step shrinks by
///   `max(0.2, s·err^(−1/(q+1)))`, `s = 0.9·21/(20 + Newton iterations)`.
///   After `q + 1` accepted steps of equal size the estimates at orders
///   `q − 1`, `q` and `q + 1` choose the next order; the step changes only
///   with the order or when it can grow 2× (at most) or must shrink to
///   0.9× (at least 0.5×), so that runs of equal steps keep the LU
///   decomposition and the order rises. The first step is of order 1, its
///   size from Hairer's `hinit` for a local error `O(h²)` unless
///   [`Bdf::with_initial_step`] is given. The error is controlled per
///   step: on modes that do not decay (an undamped oscillation, a slow
///   manifold approaching a jump) the global error grows with the number
///   of steps, `∝ rtol^(q/(q+1))`, and may exceed `rtol` tenfold or more
///   (Van der Pol, ε = 1e-6: 0.1 to 24·rtol for rtol 1e-4 … 1e-9; see
///   `tests/bdf.rs`);
///   on the decaying modes of stiff problems it stays below `rtol`.
/// * Tolerances: `rtol ≥ 400·eps` (8.9e-14 in `f64`); the error levels off
///   near `1e-13·max|x|` (the rounding of the difference arrays), so a
///   smaller positive `rtol` ends the run in
///   [`SimError::ToleranceTooTight`](crate::SimError::ToleranceTooTight).
/// * Dense output: the interpolating polynomial of the step (degree `q`).
/// * A state moved by the projection onto holonomic constraints by no
///   more than the tolerance (the correction at most 1 in the step's error
///   norm) keeps the history: the interpolating polynomial is shifted by
///   the correction, its differences are kept, and the order and step go
///   on (a projection after every step, as on a Cartesian pendulum, costs
///   nothing). A larger move restarts the method at order 1, with the step
///   just taken as the next trial; so does every call.
///
/// Measured on the lab's stiff disc (`lab/tests/bdf_stiff_disc.rs`;
/// `atol = rtol/100`, analytic Jacobian): errors 5.4e-7, 6.2e-9 and
/// 4.6e-11 for 436, 1,107 and 3,149 right-hand sides plus Jacobians (one
/// Jacobian each); in the lab's side-by-side benchmark at errors 1e-6, 1e-8,
/// 1e-10 [`Rodas4`](crate::Rodas4) needs 521, 1,565 and 5,508
/// right-hand sides. Its own work is about 1,800 instructions per step
/// (callgrind, outside the right-hand side and Jacobian), Rodas4's
/// 7,350.
///
/// Failure modes are those of [`Rodas4`](crate::Rodas4): a
/// singular iteration matrix or a failed Newton iteration rejects the step
/// and halves it (after 5 consecutive singular matrices
/// [`SimError::Singular`](crate::SimError::Singular)); non-finite values
/// give [`SimError::NonFinite`](crate::SimError::NonFinite) once the step
/// underflows; the budget of step attempts (default 100 000)
/// [`SimError::MaxSteps`](crate::SimError::MaxSteps).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Bdf, Integrator};
///
/// // x' = −1e6 (x − cos t) − sin t, exact solution x = cos t.
/// let stiff = |t: f64, x: &Vector1<f64>| Vector1::new(-1e6 * (x[0] - t.cos()) - t.sin());
/// let out = Bdf::new(1e-7, 1e-9)
///     .integrate(&stiff, 0.0, Vector1::new(1.0), 10.0)
///     .unwrap();
/// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-6);
/// assert!(out.stats.rhs_evals < 2000, "{:?}", out.stats);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bdf<T, Tol = ScalarTolerance<T>> {
    a: Settings<T, Tol>,
}

adaptive_builders!(Bdf);
integrator_impl!(Bdf<T, Tol>, a, |sys| BdfMethod::new(FiniteDifference(sys)));

/// Bdf is a multistep method: a free rotation switches sequences (DESIGN §9.4).
impl<T, Tol> crate::settings::OneStep for Bdf<T, Tol> {
    const ONE_STEP: bool = false;
}

jacobian_entry_points! {
    Bdf<T, Tol>, a, |sys| BdfMethod::new(Analytic(sys)),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{Bdf, OdeJacobian, OdeSystem};
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
    /// let mut bdf = Bdf::new(1e-8, 1e-10);
    /// let out = bdf.integrate_with_jacobian(&TwoScales, 0.0, Vector2::new(1.0, 0.0), 5.0).unwrap();
    /// assert!((out.x[0] - (-5.0f64).exp()).abs() < 1e-7);
    /// // The Jacobian of a linear system never needs to be evaluated again.
    /// assert_eq!(out.stats.jacobian_evals, 1);
    /// ```
    integrate_with_jacobian;
    /// Like [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps), but with the analytic
    /// Jacobian [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    integrate_with_jacobian_and_steps;
}

/// How a Newton solve ended (its solution is in [`BdfMethod::x_new`] and
/// [`BdfMethod::d`]).
#[derive(Clone, Copy)]
struct Newton {
    converged: bool,
    /// `f` was not finite at an iterate.
    nonfinite: bool,
    iterations: usize,
}

/// The LU decomposition of the iteration matrix `I − c J`.
#[derive(Clone, Copy)]
struct Factored<T, const D: usize> {
    lu: Lu<T, D>,
    c: T,
    /// Accepted steps since it was made.
    age: usize,
}

/// The state of the BDF method: the backward differences at the accepted
/// point, the Jacobian, the LU decomposition of the iteration matrix, and
/// the result of the last trial.
pub(crate) struct BdfMethod<J, T, const D: usize> {
    src: J,
    /// `f(t0, x0)`, for the initial step heuristic.
    f0: SVector<T, D>,
    /// Backward differences `∇^j x` of the interpolating polynomial at the
    /// accepted point for the step `h_diff` (only `0..=order` are kept
    /// scaled; `order + 1` is the last correction).
    diff: [SVector<T, D>; NDIFF],
    /// The (signed) step the differences are scaled to.
    h_diff: T,
    order: usize,
    /// Steps accepted since the step or the order last changed.
    equal_steps: usize,
    jac: SMatrix<T, D, D>,
    /// Whether the Jacobian was evaluated since the last accepted point.
    jac_fresh: bool,
    lu: Option<Factored<T, D>>,
    /// The last solve needed [`SLOW_NEWTON`] iterations or more with a
    /// Jacobian from an earlier step: the next one evaluates it again.
    stale: bool,
    /// The contraction estimate `ρ/(1 − ρ)` of the Newton iteration.
    eta: T,
    eps: EpsConstants<T>,
    // The last trial:
    x_new: SVector<T, D>,
    /// `x_new − x_pred`, the correction.
    d: SVector<T, D>,
    /// `f(t_new, x_pred)`, the first evaluation of the last solve.
    f_pred: SVector<T, D>,
    /// The reciprocal error weights `1/sk_i` of the trial's step.
    weights: SVector<T, D>,
    err: T,
    /// The safety factor of the step controller (after the Newton count).
    safety: T,
    /// The step proposed after the last trial (rejected) or accepted step.
    proposal: Option<T>,
    dense: Poly<T, D>,
}

impl<J, T, const D: usize> BdfMethod<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    pub(crate) fn new(src: J) -> Self {
        BdfMethod {
            src,
            f0: SVector::zeros(),
            diff: [SVector::zeros(); NDIFF],
            h_diff: T::one(),
            order: 1,
            equal_steps: 0,
            jac: SMatrix::zeros(),
            jac_fresh: false,
            lu: None,
            stale: false,
            eta: c(ETA_NEW_MATRIX),
            eps: EpsConstants::new(),
            x_new: SVector::zeros(),
            d: SVector::zeros(),
            f_pred: SVector::zeros(),
            weights: SVector::zeros(),
            err: T::zero(),
            safety: T::one(),
            proposal: None,
            dense: Poly::from_monomial(&[]),
        }
    }

    /// Evaluates the Jacobian at `(t, x)` (where `f = f(t, x)`), which
    /// invalidates the LU decomposition.
    fn linearise(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        f: &SVector<T, D>,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        self.src.jacobian(t, x, f, self.jac.as_mut_slice(), stats);
        self.jac_fresh = true;
        self.lu = None;
        if self.jac.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(Failure::NonFinite)
        }
    }

    /// Rescales the differences `0..=order` from the step `h_diff` to
    /// `h_diff·factor` (the same polynomial on the new grid): `D ← (R U)ᵀ D`.
    fn rescale(&mut self, factor: T) {
        let q = self.order;
        let r = step_matrix::<T>(q, factor);
        let old = self.diff;
        for k in 0..=q {
            let mut sum = SVector::<T, D>::zeros();
            for (i, di) in old.iter().enumerate().take(q + 1) {
                let mut ru = T::zero();
                for (l, ul) in UNIT_STEP_MATRIX.iter().enumerate().take(q + 1) {
                    ru += r[i][l] * c::<T>(ul[k]);
                }
                sum += di * ru;
            }
            self.diff[k] = sum;
        }
        self.h_diff *= factor;
        self.equal_steps = 0;
        self.eta = self.eta.max(c(ETA_NEW_STEP));
    }

    /// Makes sure [`BdfMethod::lu`] decomposes `I − c J` for a `c` within
    /// 30 % of `cc` (`exact`: for `cc` itself), and is young enough.
    fn factor(&mut self, cc: T, exact: bool, stats: &mut Stats) -> Result<(), Failure> {
        if let Some(f) = &self.lu {
            let close = ((cc - f.c) / f.c).abs() <= c(LU_C_CHANGE) && f.age < LU_MAX_AGE;
            if f.c == cc || (close && !exact) {
                return Ok(());
            }
        }
        stats.lu_decompositions += 1;
        let m = SMatrix::<T, D, D>::identity() - self.jac * cc;
        self.lu = None;
        let lu = Lu::new(m).ok_or(Failure::Singular)?;
        self.lu = Some(Factored { lu, c: cc, age: 0 });
        self.eta = c(ETA_NEW_MATRIX);
        Ok(())
    }

    /// Newton's method for `x = x_pred + d`, `d = c f(t_new, x) − ψ`, with
    /// the stored LU decomposition (after evaluating the Jacobian at the
    /// prediction, from the first evaluation, when it is stale); converged when `η·‖Δx‖ < NEWTON_TOL`,
    /// `η = ρ/(1 − ρ)` from the mean contraction rate `ρ` of this solve, or
    /// at its first iteration from the previous solves (`η^(3/4)`); diverged
    /// when `ρ > 0.9` or the rate cannot reach the tolerance in the
    /// iterations left.
    fn newton(
        &mut self,
        t_new: T,
        (pred, psi, cc): (&SVector<T, D>, &SVector<T, D>, T),
        weights: &SVector<T, D>,
        stats: &mut Stats,
    ) -> Result<Newton, Failure> {
        let tol = c::<T>(NEWTON_TOL);
        let mut eta = self.eta;
        let mut sol = Newton {
            converged: false,
            nonfinite: false,
            iterations: 0,
        };
        self.x_new = *pred;
        self.d = SVector::zeros();
        let mut norm_first = T::zero();
        for k in 0..NEWTON_MAXITER {
            sol.iterations = k + 1;
            let f = self.src.rhs(t_new, &self.x_new);
            stats.rhs_evals += 1;
            stats.newton_iterations += 1;
            if !all_finite(&f) {
                sol.nonfinite = true;
                break;
            }
            if k == 0 {
                self.f_pred = f;
                if self.stale && !self.jac_fresh {
                    self.stale = false;
                    self.linearise(t_new, pred, &f, stats)?;
                    self.factor(cc, true, stats)?;
                    eta = self.eta;
                }
            }
            let Some(Factored { lu, .. }) = &self.lu else {
                return Err(Failure::Singular);
            };
            let mut residual = f;
            for i in 0..D {
                residual[i] = f[i] * cc - psi[i] - self.d[i];
            }
            let dx = lu.solve(&residual);
            let norm = rms(&dx, weights);
            if k == 0 {
                // η^(3/4) (RADAU and diffsol take η^0.8), without a `powf`.
                let root = eta.max(self.eps.eta_floor).sqrt();
                eta = root * root.sqrt();
                norm_first = norm;
            } else {
                let ratio = norm / norm_first;
                let rate = match k {
                    1 => ratio,
                    2 => ratio.sqrt(),
                    _ => ratio.powf(T::one() / c::<T>(k as f64)),
                };
                let left = power(rate, NEWTON_MAXITER - k - 1);
                let contracting = rate.is_finite() && rate <= c(0.9);
                if !contracting || left / (T::one() - rate) * norm > tol {
                    break;
                }
                eta = rate / (T::one() - rate);
            }
            self.x_new += dx;
            self.d += dx;
            if eta * norm < tol || norm == T::zero() {
                sol.converged = true;
                break;
            }
        }
        self.eta = eta;
        Ok(sol)
    }

    /// The Newton solution of the step to `t_new` of size `h` at the
    /// current order. After a failure the Jacobian is evaluated again at
    /// the prediction (once per accepted step) or the matrix made for the
    /// exact `c`, and the solve repeated.
    fn solve(
        &mut self,
        t_new: T,
        h: T,
        (pred, psi): (&SVector<T, D>, &SVector<T, D>),
        stats: &mut Stats,
    ) -> Result<Newton, Failure> {
        let cc = h * c::<T>(INV_ALPHA[self.order]);
        let weights = self.weights;
        let mut exact = false;
        loop {
            self.factor(cc, exact, stats)?;
            let sol = self.newton(t_new, (pred, psi, cc), &weights, stats)?;
            if sol.converged {
                if sol.iterations >= SLOW_NEWTON && !self.jac_fresh {
                    self.stale = true;
                }
                return Ok(sol);
            }
            let was_exact = self.lu.as_ref().is_some_and(|f| f.c == cc);
            if sol.iterations == 1 && sol.nonfinite {
                return Err(Failure::NonFinite);
            }
            if !self.jac_fresh {
                let f_pred = self.f_pred;
                self.linearise(t_new, pred, &f_pred, stats)?;
            } else if was_exact {
                return Err(if sol.nonfinite {
                    Failure::NonFinite
                } else {
                    Failure::NoConvergence
                });
            }
            exact = true;
        }
    }

    /// The differences of the interpolating polynomial after the trial is
    /// accepted (orders `0..=order`): `∇'_q = ∇_q + d`, `∇'_j = ∇_j + ∇'_{j+1}`.
    fn updated(&self) -> [SVector<T, D>; MAX_ORDER + 1] {
        let q = self.order;
        let mut out = [SVector::<T, D>::zeros(); MAX_ORDER + 1];
        let mut acc = self.d;
        for j in (0..=q).rev() {
            acc += self.diff[j];
            out[j] = acc;
        }
        out
    }

    /// The order and step after an accepted step: from the error estimates
    /// at orders `q − 1`, `q`, `q + 1` once `q + 1` steps had the same size,
    /// the one whose step factor `e^(−1/(p+1))` is largest (at order p);
    /// the step changes only when the order does or the factor reaches
    /// [`MAX_FACTOR`] or falls to [`SHRINK`]. The factors are compared
    /// through integer powers of the estimates (`e_a^(1/a) < e_b^(1/b)` iff
    /// `e_a^b < e_b^a`), so that a step that keeps its size and order costs
    /// no `powf`.
    fn choose_next(&mut self) -> T {
        let q = self.order;
        let h = self.h_diff;
        if self.equal_steps < q + 1 {
            return h;
        }
        let estimate = |j: usize, p: usize| {
            rms(&self.diff[j], &self.weights) * c::<T>(ERROR_CONSTANT[p].abs())
        };
        // (estimate, its exponent p + 1, order p)
        let mut best = (self.err, q + 1, q);
        let better =
            |(ea, pa): (T, usize), (eb, pb): (T, usize)| ea.powi(pb as i32) < eb.powi(pa as i32);
        if q > 1 {
            let e_m = estimate(q, q - 1);
            if better((e_m, q), (best.0, best.1)) {
                best = (e_m, q, q - 1);
            }
        }
        if q < MAX_ORDER {
            let e_p = estimate(q + 2, q + 1);
            if better((e_p, q + 2), (best.0, best.1)) {
                best = (e_p, q + 2, q + 1);
            }
        }
        let (e, exponent, order) = best;
        if order == q {
            let grow = e <= power(self.safety / c(MAX_FACTOR), exponent);
            let shrink = e >= power(self.safety / c(SHRINK), exponent);
            if !(grow || shrink) {
                return h;
            }
        }
        let f = e.powf(-T::one() / c::<T>(exponent as f64));
        let f = if f.is_finite() { f } else { c(MAX_FACTOR) };
        let factor = (self.safety * f)
            .min(c(MAX_FACTOR))
            .max(c(MIN_ACCEPTED_FACTOR));
        self.order = order;
        self.equal_steps = 0;
        h * factor
    }
}

/// `U = R(q, 1)` of [`step_matrix`] for `q = MAX_ORDER` (its entries do
/// not depend on `q`; smaller orders use the leading block).
const UNIT_STEP_MATRIX: [[f64; MAX_ORDER + 1]; MAX_ORDER + 1] = {
    let mut u = [[1.0; MAX_ORDER + 1]; MAX_ORDER + 1];
    let mut i = 1;
    while i <= MAX_ORDER {
        let mut j = 0;
        while j <= MAX_ORDER {
            let l = i as f64;
            u[i][j] = u[i - 1][j] * (l - 1.0 - j as f64) / l;
            j += 1;
        }
        i += 1;
    }
    u
};

/// The matrix `R(q, factor)` of Shampine & Reichelt, `R[i][j] =
/// Π_{l=1..i} (l − 1 − factor·j)/l` (`R[0][j] = 1`), for `i, j ≤ q`.
fn step_matrix<T: RealField + Copy>(q: usize, factor: T) -> [[T; MAX_ORDER + 1]; MAX_ORDER + 1] {
    let mut r = [[T::zero(); MAX_ORDER + 1]; MAX_ORDER + 1];
    r[0] = [T::one(); MAX_ORDER + 1];
    for i in 1..=q {
        let li = c::<T>(i as f64);
        let (above, rest) = r.split_at_mut(i);
        let row = above[i - 1].iter().zip(rest[0].iter_mut());
        for (j, (&up, rij)) in row.enumerate().take(q + 1) {
            *rij = up * (li - T::one() - factor * c::<T>(j as f64)) / li;
        }
    }
    r
}

/// `x^n` by multiplication (`n` ≤ 9 here; `powi` is a library call).
#[inline]
fn power<T: RealField + Copy>(x: T, n: usize) -> T {
    let mut p = T::one();
    for _ in 0..n {
        p *= x;
    }
    p
}

/// The RMS of `v_i·w_i`: the error norm from the reciprocal weights
/// `w_i = 1/max(sk_i, eps⁴)` of [`reciprocal_weights`].
#[inline]
fn rms<T: RealField + Copy, const D: usize>(v: &SVector<T, D>, w: &SVector<T, D>) -> T {
    if D == 0 {
        return T::zero();
    }
    let mut sum = T::zero();
    for i in 0..D {
        let r = v[i] * w[i];
        sum += r * r;
    }
    (sum * c::<T>(1.0 / D as f64)).sqrt()
}

/// `1/max(sk_i, eps⁴)`: a zero weight (`atol_i = 0` on a component that is
/// zero) gets a huge but finite reciprocal, so that an exactly zero error
/// still counts as zero (`0/0 = 0`, as in the shared error norm) and any
/// other error fails the test, without a branch per component.
fn reciprocal_weights<T: RealField + Copy, const D: usize>(
    sk: SVector<T, D>,
    floor: T,
) -> SVector<T, D> {
    sk.map(|s| T::one() / s.max(floor))
}

/// Constants from the machine epsilon, computed once per run
/// ([`machine_epsilon`] is a loop).
#[derive(Clone, Copy)]
struct EpsConstants<T> {
    /// `eps⁴`, the smallest error weight.
    weight_floor: T,
    /// `1e4·eps`, the smallest contraction estimate `η`.
    eta_floor: T,
}

impl<T: RealField + Copy> EpsConstants<T> {
    fn new() -> Self {
        let eps = machine_epsilon::<T>();
        EpsConstants {
            weight_floor: eps * eps * eps * eps,
            eta_floor: c::<T>(1e4) * eps,
        }
    }
}

impl<J, T, const D: usize> Method<T, D> for BdfMethod<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    /// For the initial step heuristic (`hinit`, whose `h ~ (0.01/‖x''‖)^(1/ORDER)`
    /// is meant for a local error `O(h^ORDER)`): the first step is of
    /// order 1, its local error `O(h²)`.
    const ORDER: u32 = 2;
    /// `400·eps` (8.9e-14 in `f64`): below, the rounding of the difference
    /// arrays sets the error (it levels off near `1e-13·max|x|` on the
    /// stiff disc), not the tolerance.
    const MIN_RTOL_EPS: Option<f64> = Some(400.0);
    /// Unused: the method proposes its steps ([`Method::proposed_step`]);
    /// `expo = 0` spares the driver's controller its `powf`.
    const PI: Pi = Pi {
        safe: 0.9,
        expo: 0.0,
        beta: 0.0,
        fac_lo: 0.2,
        fac_hi: 5.0,
        gustafsson: false,
    };

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.src.rhs(t, x)
    }

    /// Restarts at order 1 from `(t, x)`: `∇⁰ = x`, `∇¹ = f` (for a step
    /// of 1, rescaled by the first trial), and the Jacobian there.
    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.f0 = counted(self.src.rhs(t, x), stats)?;
        self.diff = [SVector::zeros(); NDIFF];
        self.diff[0] = *x;
        self.diff[1] = self.f0;
        self.h_diff = T::one();
        self.order = 1;
        self.equal_steps = 0;
        self.proposal = None;
        self.lu = None;
        self.stale = false;
        let f0 = self.f0;
        self.linearise(t, x, &f0, stats)
    }

    fn slope(&self) -> Option<&SVector<T, D>> {
        Some(&self.f0)
    }

    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        _h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        let h = t_new - t;
        if h != self.h_diff {
            self.rescale(h / self.h_diff);
            self.h_diff = h;
        }
        let q = self.order;
        // The prediction Σ ∇^j and ψ = Σ γ_j ∇^j / α_q, in one pass.
        let mut pred = self.diff[0];
        let mut psi = SVector::<T, D>::zeros();
        for (dj, &g) in self.diff[1..=q].iter().zip(&GAMMA[1..=q]) {
            let gamma = c::<T>(g);
            for i in 0..D {
                pred[i] += dj[i];
                psi[i] += dj[i] * gamma;
            }
        }
        psi *= c::<T>(INV_ALPHA[q]);
        // One set of weights for the step, from x and its prediction.
        // The Newton iteration's weights from x and the prediction; the
        // error's from x and the solution (a prediction far off, as at the
        // jumps of a relaxation oscillation, must not loosen the test).
        self.weights = reciprocal_weights(tol.weights(x, &pred), self.eps.weight_floor);
        let sol = self.solve(t_new, h, (&pred, &psi), stats)?;
        if !all_finite(&self.x_new) {
            return Err(Failure::NonFinite);
        }
        self.weights = reciprocal_weights(tol.weights(x, &self.x_new), self.eps.weight_floor);
        let n_max = c::<T>(2.0 * NEWTON_MAXITER as f64);
        self.safety = c::<T>(0.9) * (n_max + T::one()) / (n_max + c(sol.iterations as f64));
        self.err = rms(&self.d, &self.weights) * c::<T>(ERROR_CONSTANT[q].abs());
        if self.err > T::one() {
            let exponent = -T::one() / c::<T>((q + 1) as f64);
            let factor = (self.safety * self.err.powf(exponent)).max(c(MIN_FACTOR));
            self.proposal = Some(h * factor);
        }
        Ok(self.err)
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    /// The interpolating polynomial of the accepted differences, in
    /// `θ = (τ − t)/h`.
    fn build_dense(&mut self, _t: T, _x: &SVector<T, D>, _h: T, _stats: &mut Stats) -> bool {
        let q = self.order;
        let diff = self.updated();
        let mut coeffs = [SVector::<T, D>::zeros(); MAX_ORDER + 1];
        for (j, dj) in diff.iter().enumerate().take(q + 1) {
            for (k, ck) in coeffs.iter_mut().enumerate().take(j + 1) {
                let w = DENSE_BASIS[j][k];
                if w != 0.0 {
                    *ck += dj * c::<T>(w);
                }
            }
        }
        self.dense = Poly::from_monomial(&coeffs[..=q]);
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn proposed_step(&self) -> Option<T> {
        self.proposal
    }

    /// Takes the accepted trial into the differences
    /// (`∇_{q+2} = d − ∇_{q+1}`, `∇_{q+1} = d`, `∇_j += ∇_{j+1}` downwards)
    /// and chooses the next order and step.
    fn advance(
        &mut self,
        _t: T,
        x: &SVector<T, D>,
        _last: bool,
        _stats: &mut Stats,
    ) -> Result<(), Failure> {
        let q = self.order;
        self.diff[q + 2] = self.d - self.diff[q + 1];
        self.diff[q + 1] = self.d;
        for j in (1..=q).rev() {
            let next = self.diff[j + 1];
            self.diff[j] += next;
        }
        // ∇⁰ = ∇⁰ + ∇¹ is the new state.
        self.diff[0] = *x;
        self.equal_steps += 1;
        self.jac_fresh = false;
        if let Some(f) = self.lu.as_mut() {
            f.age += 1;
        }
        self.proposal = Some(self.choose_next());
        Ok(())
    }

    /// A projection that moved the accepted state by no more than the
    /// tolerance (its correction `x − x_new` at most 1 in the step's error
    /// norm, the size of the local error the step was allowed) keeps the
    /// history: [`BdfMethod::advance`] with the projected state as `∇⁰`,
    /// which shifts the interpolating polynomial by the correction and
    /// leaves its differences (the derivatives) alone. A larger move
    /// restarts at order 1 from the projected state, with the step just
    /// taken as the next trial step.
    fn advance_projected(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        if rms(&(x - self.x_new), &self.weights) <= T::one() {
            return self.advance(t, x, last, stats);
        }
        if last {
            return Ok(());
        }
        let h = self.h_diff;
        self.start(t, x, stats)?;
        self.proposal = Some(h);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dense_basis_is_the_newton_basis() {
        for (j, row) in DENSE_BASIS.iter().enumerate() {
            for &theta in &[0.0, 0.3, 1.0, 1.7] {
                let mono: f64 = row.iter().rev().fold(0.0, |acc, &w| acc * theta + w);
                let product: f64 = (0..j)
                    .map(|m| (theta - 1.0 + m as f64) / (m as f64 + 1.0))
                    .product();
                assert!((mono - product).abs() < 1e-15, "j {j}, θ {theta}");
            }
        }
    }

    #[test]
    fn the_unit_step_matrix_is_r_of_one() {
        let r = step_matrix::<f64>(MAX_ORDER, 1.0);
        assert_eq!(r, UNIT_STEP_MATRIX);
    }

    #[test]
    fn rescaling_keeps_the_polynomial() {
        // p(τ) = 1 + 2τ − τ² + 0.5τ³ sampled backwards from τ = 0 with step 0.1.
        let p = |tau: f64| 1.0 + 2.0 * tau - tau * tau + 0.5 * tau.powi(3);
        let fd = |_t: f64, x: &SVector<f64, 1>| *x;
        let mut m = BdfMethod::<_, f64, 1>::new(FiniteDifference(&fd));
        m.order = 3;
        m.h_diff = 0.1;
        let values: [f64; 4] = core::array::from_fn(|k| p(-0.1 * k as f64));
        // Backward differences ∇^j p(0) on the grid 0, −h, −2h, −3h.
        let mut table = values;
        for j in 0..4 {
            m.diff[j] = SVector::<f64, 1>::new(table[0]);
            for k in 0..3 - j {
                table[k] -= table[k + 1];
            }
        }
        m.rescale(0.37);
        let h = m.h_diff;
        let mut table: [f64; 4] = core::array::from_fn(|k| p(-h * k as f64));
        for j in 0..4 {
            assert!((m.diff[j][0] - table[0]).abs() < 1e-13, "∇^{j}");
            for k in 0..3 - j {
                table[k] -= table[k + 1];
            }
        }
    }
}
