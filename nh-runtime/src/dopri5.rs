//! Dormand–Prince 5(4) with PI step-size control, after Hairer's `DOPRI5`.

use nalgebra::{RealField, SVector};

use crate::ScalarTolerance;
use crate::method::{Failure, Method, Pi, counted, stiffness_estimate};
use crate::numeric::{c, stage_point};
use crate::settings::{Settings, adaptive_builders, integrator_impl};
use crate::step::{Poly, hermite_terms};
use crate::tolerance::{Tolerance, scaled};
use crate::{OdeSystem, Stats};

// Butcher tableau of RK5(4)7M (Dormand & Prince 1980), FSAL.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error coefficients: 5th-order minus embedded 4th-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output of Shampine (1986), Hairer's `CONTD5`.
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Hairer's DOPRI5 step-size control: `β = 0.04`, `α = 0.2 − 0.75β`,
/// safety 0.9, step ratio `0.2 ..= 10`.
const PI: Pi = Pi {
    safe: 0.9,
    expo: 0.2 - 0.04 * 0.75,
    beta: 0.04,
    fac_lo: 1.0 / 10.0,
    fac_hi: 1.0 / 0.2,
    gustafsson: false,
};

/// Dormand–Prince 5(4) (RK5(4)7M, first same as last) with adaptive steps.
///
/// A port of the algorithm of Hairer's `DOPRI5` (Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, section II.4 and its Fortran code):
///
/// * the solution is advanced with the 5th-order weights (local
///   extrapolation), the 4th-order embedded solution gives the error estimate;
/// * error norm: RMS over components of
///   `err_i / (atol_i + rtol_i·max(|x_i|, |x_new_i|))`, a step is accepted
///   when it is ≤ 1 (see [Tolerances and the error
///   norm](crate#tolerances-and-the-error-norm); the tolerances are the same
///   for every component with [`Dopri5::new`], per component with
///   [`Dopri5::with_tolerances`]);
/// * PI step-size control with `β = 0.04`, `α = 0.2 − 0.75β`, safety factor
///   0.9 and step ratio limits `0.2 ..= 10`; after a rejection the step may
///   not grow in the next accepted step;
/// * automatic initial step (Hairer's `hinit`) unless
///   [`Dopri5::with_initial_step`] is given;
/// * stiffness detection (Hairer's test): every 1000 accepted steps, and at
///   every step once it fired, `h·λ ≈ |h|·‖k7 − k6‖ / ‖y7 − y6‖` is estimated;
///   after 15 estimates above 3.25 (without 6 consecutive ones below)
///   [`Stats::stiffness_detected`](crate::Stats::stiffness_detected) is
///   set. Integration continues regardless. (Not with
///   [`Dopri5::with_fixed_step`]: the test is about a controlled
///   step being held at the stability boundary.)
///
/// Failure modes (those of every adaptive integrator of this crate, which
/// share one step driver):
///
/// * A trial step with a non-finite stage or new state is rejected and
///   retried with half the step (a dense output that is not finite, which
///   only an overflow can make, rejects nothing: the step is then
///   interpolated on its chord, see [`Step`](crate::Step)); a finite
///   trial whose error norm overflows is an ordinary rejection. When the
///   step falls below `10·eps·|t|` (at least `10·eps²·|t1|` and
///   `1/(eps·T::MAX)`), [`SimError::NonFinite`](crate::SimError::NonFinite)
///   is returned if the last rejection was due to non-finite values,
///   otherwise [`SimError::StepSizeTooSmall`](crate::SimError::StepSizeTooSmall);
///   both carry the last accepted `(t, x)`. A non-finite derivative at
///   `(t0, x0)` itself returns `NonFinite` at once.
/// * A span shorter than that smallest step is covered by one explicit
///   Euler step and ends `Ok` at `t1`; a step that reaches `t1` by rounding
///   ends the run there.
/// * More than `max_steps` step attempts (accepted plus rejected, default
///   100 000) returns [`SimError::MaxSteps`](crate::SimError::MaxSteps).
/// * `rtol` (every component) must be finite and > 0, `atol` finite and
///   ≥ 0, per-component tolerances of the state's dimension, the initial
///   and maximal step (when given) finite and > 0; otherwise
///   [`SimError::InvalidInput`](crate::SimError::InvalidInput) is returned
///   before anything is evaluated. An `rtol` below `10·eps` (what the
///   scalar can resolve in one step) is raised to `10·eps`.
///
/// Work per attempt: 6 evaluations of the right-hand side (FSAL), plus 1 for
/// the derivative at `t0` and 1 for the initial-step heuristic, i.e.
/// `rhs_evals = 6·(steps + rejected) + 2` (or `+ 1` with an explicit initial
/// step).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{Dopri5, Integrator};
///
/// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
/// let mut dp = Dopri5::new(1e-8, 1e-10);
/// let out = dp.integrate(&oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0).unwrap();
/// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-6);
/// assert_eq!(out.stats.rhs_evals, 6 * (out.stats.steps + out.stats.rejected) + 2);
/// assert!(!out.stats.stiffness_detected);
/// ```
///
/// The type parameter `Tol` is how errors are weighed: [`ScalarTolerance`]
/// (the default, from [`Dopri5::new`]) or
/// [`PerComponentTolerance`](crate::PerComponentTolerance) (from
/// [`Dopri5::with_tolerances`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dopri5<T, Tol = ScalarTolerance<T>> {
    a: Settings<T, Tol>,
}

adaptive_builders!(Dopri5);
integrator_impl!(Dopri5<T, Tol>, a, |sys| Dopri5Stages::new(sys));

/// Dopri5 is a one-step method.
impl<T, Tol> crate::settings::OneStep for Dopri5<T, Tol> {
    const ONE_STEP: bool = true;
}

/// The stages of one Dormand–Prince step (`k[6]` is the next step's `k[0]`).
pub(crate) struct Dopri5Stages<'a, S: ?Sized, T, const D: usize> {
    sys: &'a S,
    k: [SVector<T, D>; 7],
    x6: SVector<T, D>,
    x_new: SVector<T, D>,
    dense: Poly<T, D>,
}

impl<'a, S: ?Sized, T: RealField + Copy, const D: usize> Dopri5Stages<'a, S, T, D> {
    pub(crate) fn new(sys: &'a S) -> Self {
        Dopri5Stages {
            sys,
            k: [SVector::zeros(); 7],
            x6: SVector::zeros(),
            x_new: SVector::zeros(),
            dense: Poly::from_monomial(&[]),
        }
    }
}

impl<T, S, const D: usize> Dopri5Stages<'_, S, T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    /// The error estimate `h·Σ e_j k_j` in the norm of
    /// [`error_norm`](crate::tolerance::error_norm), component by component
    /// with the same rounding; `None` if `x6`, `x_new` or `k7` is not
    /// finite (`x6` combines k1 … k5 and `x_new` k1, k3 … k6, all with
    /// non-zero weights, so these three are finite only if every stage is).
    #[inline(always)]
    fn error(&self, x: &SVector<T, D>, h: T, tol: &Tolerance<T, D>) -> Option<T> {
        let cc = |v: f64| c::<T>(v);
        let (k, x_new) = (&self.k, &self.x_new);
        let (mut r, mut finite) = ([T::zero(); D], [T::zero(); D]);
        for i in 0..D {
            let e = (k[0][i] * cc(E1)
                + k[2][i] * cc(E3)
                + k[3][i] * cc(E4)
                + k[4][i] * cc(E5)
                + k[5][i] * cc(E6)
                + k[6][i] * cc(E7))
                * h;
            let sk = tol.weight(i, x[i], x_new[i]);
            r[i] = scaled(e, sk);
            // 0·v is 0 for a finite v and NaN otherwise.
            let zero = T::zero();
            finite[i] = self.x6[i] * zero + x_new[i] * zero + k[6][i] * zero;
        }
        if finite.iter().fold(T::zero(), |sum, &z| sum + z) != T::zero() {
            return None;
        }
        if D == 0 {
            return Some(T::zero());
        }
        let mut sum = T::zero();
        for ri in r {
            sum += ri * ri;
        }
        Some((sum / c::<T>(D as f64)).sqrt())
    }
}

impl<T, S, const D: usize> Method<T, D> for Dopri5Stages<'_, S, T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    const ORDER: u32 = 5;
    const STIFF_LIMIT: Option<f64> = Some(3.25);
    const PI: Pi = PI;

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.sys.rhs(t, x)
    }

    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.k[0] = counted(self.sys.rhs(t, x), stats)?;
        Ok(())
    }

    fn slope(&self) -> Option<&SVector<T, D>> {
        Some(&self.k[0])
    }

    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        let sys = self.sys;
        let cc = |v: f64| c::<T>(v);
        let k = &mut self.k;
        k[1] = sys.rhs(t + h * cc(C2), &(x + k[0] * (h * cc(A21))));
        let point = stage_point(x, k, [(0, A31), (1, A32)], h);
        k[2] = sys.rhs(t + h * cc(C3), &point);
        let point = stage_point(x, k, [(0, A41), (1, A42), (2, A43)], h);
        k[3] = sys.rhs(t + h * cc(C4), &point);
        let point = stage_point(x, k, [(0, A51), (1, A52), (2, A53), (3, A54)], h);
        k[4] = sys.rhs(t + h * cc(C5), &point);
        let terms = [(0, A61), (1, A62), (2, A63), (3, A64), (4, A65)];
        self.x6 = stage_point(x, k, terms, h);
        k[5] = sys.rhs(t_new, &self.x6);
        let terms = [(0, A71), (2, A73), (3, A74), (4, A75), (5, A76)];
        self.x_new = stage_point(x, k, terms, h);
        k[6] = sys.rhs(t_new, &self.x_new);
        stats.rhs_evals += 6;
        self.error(x, h, tol).ok_or(Failure::NonFinite)
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    fn build_dense(&mut self, _t: T, x: &SVector<T, D>, h: T, _stats: &mut Stats) -> bool {
        // Hairer's CONTD5 in the nested form
        // x + θ(Δ + (1−θ)(r3 + θ(r4 + (1−θ) r5))).
        let [k1, _, k3, k4, k5, k6, k7] = self.k;
        let [r0, r1, r2, r3] = hermite_terms(x, &k1, &self.x_new, &k7, h);
        self.dense = Poly::from_nested(&[
            r0,
            r1,
            r2,
            r3,
            (k1 * c::<T>(D1)
                + k3 * c::<T>(D3)
                + k4 * c::<T>(D4)
                + k5 * c::<T>(D5)
                + k6 * c::<T>(D6)
                + k7 * c::<T>(D7))
                * h,
        ]);
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn stiffness_ratio(&self) -> Option<T> {
        stiffness_estimate((&self.k[6], &self.k[5]), (&self.x_new, &self.x6))
    }

    fn advance(
        &mut self,
        _t: T,
        _x: &SVector<T, D>,
        _last: bool,
        _: &mut Stats,
    ) -> Result<(), Failure> {
        self.k[0] = self.k[6];
        Ok(())
    }
}
