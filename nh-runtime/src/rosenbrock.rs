//! The L-stable Rosenbrock method RODAS4 for stiff problems, after Hairer's
//! `RODAS`.

use nalgebra::{RealField, SMatrix, SVector};

use crate::ScalarTolerance;
use crate::Stats;
use crate::common::{
    Adaptive, adaptive_builders, all_finite, all_finite_in, c, error_norm, integrator_impl,
    jacobian_entry_points,
};
use crate::driver::{Failure, Method, Pi, Tolerance, counted};
use crate::jacobian::{Analytic, FiniteDifference, JacobianSource, time_derivative};
use crate::linalg::Lu;
use crate::step::Poly;

// RODAS4 (Hairer & Wanner, Solving ODEs II, section IV.7, table 7.2, and
// Hairer's rodas.f, METH = 1) in the transformed formulation
// (I/(hγ) − J) U_i = f(t + c_i h, x + Σ a_ij U_j) + Σ (c_ij/h) U_j + h d_i f_t.
const GAMMA: f64 = 0.25;
const C2: f64 = 0.386;
const C3: f64 = 0.21;
const C4: f64 = 0.63;
const D1: f64 = 0.25;
const D2: f64 = -0.1043;
const D3: f64 = 0.1035;
const D4: f64 = -0.036_200_000_000_000_23;
const A21: f64 = 1.544;
const A31: f64 = 0.946_678_528_081_582_6;
const A32: f64 = 0.255_701_169_898_328_4;
const A41: f64 = 3.314_825_187_068_521;
const A42: f64 = 2.896_124_015_972_201;
const A43: f64 = 0.998_641_913_997_781_7;
const A51: f64 = 1.221_224_509_226_641;
const A52: f64 = 6.019_134_481_288_629;
const A53: f64 = 12.537_083_329_320_87;
const A54: f64 = -0.687_886_036_105_895;
const C21: f64 = -5.6688;
const C31: f64 = -2.430_093_356_833_875;
const C32: f64 = -0.206_359_915_709_191_5;
const C41: f64 = -0.107_352_905_815_137_5;
const C42: f64 = -9.594_562_251_023_355;
const C43: f64 = -20.470_286_148_096_16;
const C51: f64 = 7.496_443_313_967_647;
const C52: f64 = -10.246_804_314_643_52;
const C53: f64 = -33.999_903_528_199_05;
const C54: f64 = 11.708_908_932_061_6;
const C61: f64 = 8.083_246_795_921_522;
const C62: f64 = -7.981_132_988_064_893;
const C63: f64 = -31.521_594_328_743_71;
const C64: f64 = 16.319_305_431_231_36;
const C65: f64 = -6.058_818_238_834_054;
// Dense output (rodas.f `D21`…`D35`).
const H21: f64 = 10.126_235_083_445_86;
const H22: f64 = -7.487_995_877_610_167;
const H23: f64 = -34.800_918_615_557_47;
const H24: f64 = -7.992_771_707_568_823;
const H25: f64 = 1.025_137_723_295_662;
const H31: f64 = -0.676_280_339_280_125_3;
const H32: f64 = 6.087_714_651_680_015;
const H33: f64 = 16.430_843_208_924_78;
const H34: f64 = 24.767_225_114_183_86;
const H35: f64 = -6.594_389_125_716_872;

/// Step-size control of rodas.f: `0.2 ≤ h_new/h ≤ 6`, safety 0.9, with
/// Gustafsson's predictive controller.
const PI: Pi = Pi {
    safe: 0.9,
    expo: 0.25,
    beta: 0.0,
    fac_lo: 1.0 / 6.0,
    fac_hi: 5.0,
    gustafsson: true,
};

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
///   [`Rosenbrock::integrate_with_jacobian`] uses the analytic
///   [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead. `∂f/∂t` is always obtained by one
///   forward difference (exactly zero for autonomous systems). The Jacobian
///   is evaluated once per accepted step and reused after rejections;
///   [`Stats::jacobian_evals`](crate::Stats::jacobian_evals) counts Jacobians (analytic or finite
///   difference), [`Stats::lu_decompositions`](crate::Stats::lu_decompositions) the LU factorisations.
/// * Error norm as [`DormandPrince`](crate::DormandPrince) (RMS of
///   `err_i/(atol_i + rtol_i·max(|x_i|, |x_new_i|))`, per component with
///   [`Rosenbrock::with_tolerances`]) applied to the embedded
///   estimate `U_6`; step control of `RODAS`:
///   `h_new = h·clamp(0.9·err^(−1/4), 1/5, 6)` with Gustafsson's predictive
///   correction; automatic initial step (`hinit`, order 4) unless
///   [`Rosenbrock::with_initial_step`] is given.
/// * [`Rosenbrock::with_fixed_step`] switches the error control off (for
///   convergence studies).
///
/// Failure modes:
///
/// * A singular (or non-finite) iteration matrix rejects the step and
///   halves `h`; after 5 consecutive failures [`SimError::Singular`](crate::SimError::Singular) is
///   returned with the last accepted state. A non-finite Jacobian at an
///   accepted state returns [`SimError::NonFinite`](crate::SimError::NonFinite) at once.
/// * Non-finite stages are rejected and retried with half the step; as in
///   [`DormandPrince`](crate::DormandPrince), an underflowing step gives
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
/// use nh_runtime::{DormandPrince, Integrator, Rosenbrock};
///
/// // x' = −1e6 (x − cos t) − sin t, exact solution x = cos t.
/// let stiff = |t: f64, x: &Vector1<f64>| Vector1::new(-1e6 * (x[0] - t.cos()) - t.sin());
/// let out = Rosenbrock::new(1e-6, 1e-9)
///     .integrate(&stiff, 0.0, Vector1::new(1.0), 10.0)
///     .unwrap();
/// assert!((out.x[0] - 10.0f64.cos()).abs() < 1e-6);
/// assert!(out.stats.steps < 100);
/// ```
///
/// The type parameter `Tol` is how errors are weighed: [`ScalarTolerance`]
/// (the default, from [`Rosenbrock::new`]) or
/// [`PerComponentTolerance`](crate::PerComponentTolerance) (from
/// [`Rosenbrock::with_tolerances`]); see [Tolerances and the error
/// norm](crate#tolerances-and-the-error-norm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rosenbrock<T, Tol = ScalarTolerance<T>> {
    a: Adaptive<T, Tol>,
}

adaptive_builders!(Rosenbrock);
integrator_impl!(Rosenbrock<T, Tol>, a, |sys| Rodas::new(FiniteDifference(sys)));

jacobian_entry_points! {
    Rosenbrock<T, Tol>, a, |sys| Rodas::new(Analytic(sys)),
    /// Like [`Integrator::integrate`](crate::Integrator::integrate), but with the analytic Jacobian
    /// [`OdeJacobian::jacobian`](crate::OdeJacobian::jacobian) instead of finite differences.
    ///
    /// # Example
    ///
    /// ```rust
    /// use nalgebra::{Matrix2, Vector2};
    /// use nh_runtime::{OdeJacobian, OdeSystem, Rosenbrock};
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
    /// let mut ros = Rosenbrock::new(1e-8, 1e-10);
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

/// The state of RODAS4 at an accepted point (derivative, Jacobian, `∂f/∂t`)
/// and the stages `U_1 … U_5` of the last trial.
pub(crate) struct Rodas<J, T, const D: usize> {
    src: J,
    f0: SVector<T, D>,
    jac: SMatrix<T, D, D>,
    ft: SVector<T, D>,
    u: [SVector<T, D>; 5],
    x_new: SVector<T, D>,
    f_new: SVector<T, D>,
    dense: Poly<T, D>,
}

impl<J, T, const D: usize> Rodas<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    pub(crate) fn new(src: J) -> Self {
        Rodas {
            src,
            f0: SVector::zeros(),
            jac: SMatrix::zeros(),
            ft: SVector::zeros(),
            u: [SVector::zeros(); 5],
            x_new: SVector::zeros(),
            f_new: SVector::zeros(),
            dense: Poly::from_monomial(&[]),
        }
    }

    /// The Jacobian and `∂f/∂t` at the accepted point `(t, x)`.
    fn linearise(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.src
            .jacobian(t, x, &self.f0, self.jac.as_mut_slice(), stats);
        self.ft = time_derivative(&self.src, t, x, &self.f0, stats);
        if self.jac.iter().all(|v| v.is_finite()) && all_finite(&self.ft) {
            Ok(())
        } else {
            Err(Failure::NonFinite)
        }
    }
}

impl<J, T, const D: usize> Method<T, D> for Rodas<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    const ORDER: u32 = 4;
    const PI: Pi = PI;

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.src.rhs(t, x)
    }

    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.f0 = counted(self.src.rhs(t, x), stats)?;
        self.linearise(t, x, stats)
    }

    fn slope(&self) -> Option<&SVector<T, D>> {
        Some(&self.f0)
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
        let cc = |v: f64| c::<T>(v);
        let (src, f0, ft) = (&self.src, self.f0, self.ft);
        // The iteration matrix I/(hγ) − J and its LU decomposition.
        let fac = T::one() / (h * cc(GAMMA));
        stats.lu_decompositions += 1;
        let lu =
            Lu::new(SMatrix::<T, D, D>::identity() * fac - self.jac).ok_or(Failure::Singular)?;
        let solve = |b: SVector<T, D>| lu.solve(&b);
        let inv_h = T::one() / h;
        let u1 = solve(f0 + ft * (h * cc(D1)));
        let f2 = src.rhs(t + h * cc(C2), &(x + u1 * cc(A21)));
        let u2 = solve(f2 + u1 * (cc(C21) * inv_h) + ft * (h * cc(D2)));
        let f3 = src.rhs(t + h * cc(C3), &(x + u1 * cc(A31) + u2 * cc(A32)));
        let u3 = solve(f3 + (u1 * cc(C31) + u2 * cc(C32)) * inv_h + ft * (h * cc(D3)));
        let f4 = src.rhs(
            t + h * cc(C4),
            &(x + u1 * cc(A41) + u2 * cc(A42) + u3 * cc(A43)),
        );
        let u4 =
            solve(f4 + (u1 * cc(C41) + u2 * cc(C42) + u3 * cc(C43)) * inv_h + ft * (h * cc(D4)));
        let x5 = x + u1 * cc(A51) + u2 * cc(A52) + u3 * cc(A53) + u4 * cc(A54);
        let f5 = src.rhs(t_new, &x5);
        let u5 = solve(f5 + (u1 * cc(C51) + u2 * cc(C52) + u3 * cc(C53) + u4 * cc(C54)) * inv_h);
        // Embedded 3rd-order solution, then the last stage.
        let x6 = x5 + u5;
        let f6 = src.rhs(t_new, &x6);
        let u6 = solve(
            f6 + (u1 * cc(C61) + u2 * cc(C62) + u3 * cc(C63) + u4 * cc(C64) + u5 * cc(C65)) * inv_h,
        );
        stats.rhs_evals += 5;
        self.u = [u1, u2, u3, u4, u5];
        self.x_new = x6 + u6;
        if !(all_finite_in(&self.u) && all_finite_in(&[u6, self.x_new])) {
            return Err(Failure::NonFinite);
        }
        Ok(error_norm(&u6, x, &self.x_new, tol))
    }

    /// The derivative at the new point (for the next step); a non-finite
    /// one means the step went where the system is undefined.
    fn complete(&mut self, t_new: T, stats: &mut Stats) -> Result<(), Failure> {
        self.f_new = counted(self.src.rhs(t_new, &self.x_new), stats)?;
        Ok(())
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    /// RODAS's 3rd-order dense output
    /// `x(θ) = (1−θ) x + θ (x_new + (1−θ)(r3 + θ r4))`.
    fn build_dense(&mut self, _t: T, x: &SVector<T, D>, _h: T, _stats: &mut Stats) -> bool {
        let cc = |v: f64| c::<T>(v);
        let [u1, u2, u3, u4, u5] = self.u;
        let r3 = u1 * cc(H21) + u2 * cc(H22) + u3 * cc(H23) + u4 * cc(H24) + u5 * cc(H25);
        let r4 = u1 * cc(H31) + u2 * cc(H32) + u3 * cc(H33) + u4 * cc(H34) + u5 * cc(H35);
        self.dense = Poly::from_nested(&[*x, self.x_new - x, r3, r4]);
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn advance(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        self.f0 = self.f_new;
        if last {
            Ok(())
        } else {
            self.linearise(t, x, stats)
        }
    }
}

impl<J, T, const D: usize> crate::auto::Linearised<T, D> for Rodas<J, T, D>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
{
    fn jacobian(&self) -> &SMatrix<T, D, D> {
        &self.jac
    }
}
