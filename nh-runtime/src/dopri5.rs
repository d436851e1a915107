//! Dormand–Prince 5(4) with PI step-size control, after Hairer's `DOPRI5`.

use nalgebra::{RealField, SVector};

use crate::common::{
    Adaptive, adaptive_builders, all_finite, c, check_arguments, error_norm, initial_step,
    machine_epsilon, min_step,
};
use crate::step::Poly;
use crate::{Integrator, OdeSystem, Outcome, SimError, Stats, Step};

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

// Hairer's DOPRI5 defaults.
const SAFE: f64 = 0.9;
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 10.0;
const BETA: f64 = 0.04;
const EXPO1: f64 = 0.2 - BETA * 0.75;
/// Accepted steps between routine stiffness tests (Hairer's `NSTIFF`).
const NSTIFF: usize = 1000;
/// `h·λ` above this counts as "at the stability boundary".
const STIFF_HLAMB: f64 = 3.25;
/// Consecutive-ish stiff tests needed to flag stiffness.
const STIFF_COUNT: usize = 15;
/// Non-stiff tests that reset the stiff counter.
const NONSTIFF_RESET: usize = 6;

/// Dormand–Prince 5(4) (RK5(4)7M, first same as last) with adaptive steps.
///
/// A port of the algorithm of Hairer's `DOPRI5` (Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, section II.4 and its Fortran code):
///
/// * the solution is advanced with the 5th-order weights (local
///   extrapolation), the 4th-order embedded solution gives the error estimate;
/// * error norm: RMS over components of
///   `err_i / (atol + rtol·max(|x_i|, |x_new_i|))`, a step is accepted when it
///   is ≤ 1;
/// * PI step-size control with `β = 0.04`, `α = 0.2 − 0.75β`, safety factor
///   0.9 and step ratio limits `0.2 ..= 10`; after a rejection the step may
///   not grow in the next accepted step;
/// * automatic initial step (Hairer's `hinit`) unless
///   [`DormandPrince::with_initial_step`] is given;
/// * stiffness detection (Hairer's test): every 1000 accepted steps, and at
///   every step once it fired, `h·λ ≈ |h|·‖k7 − k6‖ / ‖y7 − y6‖` is estimated;
///   after 15 estimates above 3.25 (without 6 consecutive ones below)
///   [`Stats::stiffness_detected`] is set. Integration continues regardless.
///
/// Failure modes:
///
/// * A trial step whose new state, final derivative or error estimate is
///   not finite is rejected and retried with half the step. When the step
///   falls below `10·eps·|t|` (at least `10·eps²·|t1|`), [`SimError::NonFinite`] is returned
///   if the last rejection was due to non-finite values, otherwise
///   [`SimError::StepSizeTooSmall`]; both carry the last accepted `(t, x)`.
///   A non-finite derivative at `(t0, x0)` itself returns `NonFinite` at once.
/// * More than `max_steps` step attempts (accepted plus rejected, default
///   100 000) returns [`SimError::MaxSteps`].
/// * `rtol` must be finite and > 0, `atol` finite and ≥ 0, the initial and
///   maximal step (when given) finite and > 0; otherwise
///   [`SimError::InvalidInput`] is returned before anything is evaluated.
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
/// use nh_runtime::{DormandPrince, Integrator};
///
/// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
/// let mut dp = DormandPrince::new(1e-8, 1e-10);
/// let out = dp.integrate(&oscillator, 0.0, Vector2::new(1.0, 0.0), 10.0).unwrap();
/// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-6);
/// assert_eq!(out.stats.rhs_evals, 6 * (out.stats.steps + out.stats.rejected) + 2);
/// assert!(!out.stats.stiffness_detected);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DormandPrince<T> {
    a: Adaptive<T>,
}

impl<T: RealField + Copy> DormandPrince<T> {
    /// An adaptive integrator with relative tolerance `rtol` (> 0) and
    /// absolute tolerance `atol` (≥ 0), applied to every component.
    pub fn new(rtol: T, atol: T) -> Self {
        Self {
            a: Adaptive::new(rtol, atol),
        }
    }

    fn run<S, F, const D: usize>(
        &mut self,
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
        self.a.check()?;
        if dir == T::zero() {
            return Ok(Outcome {
                t: t0,
                x: x0,
                stats: *stats,
            });
        }

        let (rtol, atol) = (self.a.rtol, self.a.atol);
        let eps = machine_epsilon::<T>();
        let hmax = self.a.max_step.unwrap_or((t1 - t0).abs());

        let (mut t, mut x) = (t0, x0);
        let mut k1 = sys.rhs(t, &x);
        stats.rhs_evals += 1;
        if !all_finite(&k1) {
            return Err(SimError::NonFinite { t, x });
        }
        let mut h = match (self.a.fixed_step, self.a.initial_step) {
            (Some(hf), _) => hf,
            (None, Some(h0)) => h0.min(hmax),
            (None, None) => initial_step(sys, stats, t, &x, &k1, dir, hmax, rtol, atol, 5),
        } * dir;

        let mut facold = c::<T>(1e-4);
        let mut reject = false;
        let mut last = false;
        let mut nonfinite = false;
        let mut hlamb = T::zero();
        let (mut iasti, mut nonsti) = (0usize, 0usize);

        loop {
            let attempts = stats.steps + stats.rejected;
            if attempts >= self.a.max_steps {
                return Err(SimError::MaxSteps {
                    t,
                    x,
                    steps: attempts,
                });
            }
            if !h.is_finite() || h.abs() < min_step(eps, t, t1) {
                return Err(if nonfinite {
                    SimError::NonFinite { t, x }
                } else {
                    SimError::StepSizeTooSmall { t, x, h }
                });
            }
            if (t + h * c::<T>(1.01) - t1) * dir > T::zero() {
                h = t1 - t;
                last = true;
            }
            let t_new = if last { t1 } else { t + h };

            // The seven stages (k7 is the next step's k1).
            let k2 = sys.rhs(t + h * c::<T>(C2), &(x + k1 * (h * c::<T>(A21))));
            let k3 = sys.rhs(
                t + h * c::<T>(C3),
                &(x + (k1 * c::<T>(A31) + k2 * c::<T>(A32)) * h),
            );
            let k4 = sys.rhs(
                t + h * c::<T>(C4),
                &(x + (k1 * c::<T>(A41) + k2 * c::<T>(A42) + k3 * c::<T>(A43)) * h),
            );
            let k5 = sys.rhs(
                t + h * c::<T>(C5),
                &(x + (k1 * c::<T>(A51) + k2 * c::<T>(A52) + k3 * c::<T>(A53) + k4 * c::<T>(A54))
                    * h),
            );
            let x6 = x
                + (k1 * c::<T>(A61)
                    + k2 * c::<T>(A62)
                    + k3 * c::<T>(A63)
                    + k4 * c::<T>(A64)
                    + k5 * c::<T>(A65))
                    * h;
            let k6 = sys.rhs(t_new, &x6);
            let x_new = x
                + (k1 * c::<T>(A71)
                    + k3 * c::<T>(A73)
                    + k4 * c::<T>(A74)
                    + k5 * c::<T>(A75)
                    + k6 * c::<T>(A76))
                    * h;
            let k7 = sys.rhs(t_new, &x_new);
            stats.rhs_evals += 6;

            let err_vec = (k1 * c::<T>(E1)
                + k3 * c::<T>(E3)
                + k4 * c::<T>(E4)
                + k5 * c::<T>(E5)
                + k6 * c::<T>(E6)
                + k7 * c::<T>(E7))
                * h;
            let err = error_norm(&err_vec, &x, &x_new, rtol, atol);

            if !(err.is_finite() && all_finite(&x_new) && all_finite(&k7)) {
                if self.a.fixed_step.is_some() {
                    return Err(SimError::NonFinite { t, x });
                }
                // Overflow or NaN in the trial step: retry with half the step.
                stats.rejected += 1;
                nonfinite = true;
                reject = true;
                last = false;
                h *= c::<T>(0.5);
                continue;
            }
            nonfinite = false;

            // PI controller: fac = err^α / errold^β, bounded and with safety.
            let fac11 = err.powf(c::<T>(EXPO1));
            let fac = (fac11 / facold.powf(c::<T>(BETA)) / c::<T>(SAFE))
                .min(c::<T>(1.0 / FAC_MIN))
                .max(c::<T>(1.0 / FAC_MAX));
            let mut h_new = h / fac;

            if err <= T::one() || self.a.fixed_step.is_some() {
                facold = err.max(c::<T>(1e-4));
                stats.steps += 1;

                if stats.steps.is_multiple_of(NSTIFF) || iasti > 0 {
                    let stnum = (k7 - k6).norm_squared();
                    let stden = (x_new - x6).norm_squared();
                    if stden > T::zero() {
                        hlamb = h.abs() * (stnum / stden).sqrt();
                    }
                    if hlamb > c::<T>(STIFF_HLAMB) {
                        nonsti = 0;
                        iasti += 1;
                        if iasti >= STIFF_COUNT {
                            stats.stiffness_detected = true;
                        }
                    } else {
                        nonsti += 1;
                        if nonsti == NONSTIFF_RESET {
                            iasti = 0;
                        }
                    }
                }

                // Hairer's CONTD5 in the nested form
                // x + θ(Δ + (1−θ)(r3 + θ(r4 + (1−θ) r5))).
                let ydiff = x_new - x;
                let bspl = k1 * h - ydiff;
                let dense = Poly::from_nested(&[
                    x,
                    ydiff,
                    bspl,
                    ydiff - k7 * h - bspl,
                    (k1 * c::<T>(D1)
                        + k3 * c::<T>(D3)
                        + k4 * c::<T>(D4)
                        + k5 * c::<T>(D5)
                        + k6 * c::<T>(D6)
                        + k7 * c::<T>(D7))
                        * h,
                ]);
                on_step(&Step::new(t, &x, t_new, &x_new, &dense));

                k1 = k7;
                x = x_new;
                t = t_new;

                if let Some(hf) = self.a.fixed_step {
                    h_new = hf * dir;
                } else {
                    if h_new.abs() > hmax {
                        h_new = hmax * dir;
                    }
                    if reject {
                        h_new = h_new.abs().min(h.abs()) * dir;
                    }
                }
                self.a.last_step = Some(h_new.abs());
                if last {
                    return Ok(Outcome {
                        t,
                        x,
                        stats: *stats,
                    });
                }
                reject = false;
            } else {
                h_new = h / (fac11 / c::<T>(SAFE)).min(c::<T>(1.0 / FAC_MIN));
                reject = true;
                last = false;
                stats.rejected += 1;
            }
            h = h_new;
        }
    }
}

adaptive_builders!(DormandPrince);

impl<T: RealField + Copy> Integrator<T> for DormandPrince<T> {
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
        self.a.last_step = None;
        let result = self.run(&mut stats, sys, t0, x0, t1, on_step);
        self.a.stats = stats;
        result
    }
}
