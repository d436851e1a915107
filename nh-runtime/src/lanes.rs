//! Lanes: several states per call. A lane type is a SIMD scalar such as
//! [`WideF64x4`] (four `f64`s, one per state), for which the generated
//! methods and [`LaneSystem::lane_rhs`] evaluate one state per lane, and
//! [`Rk4::integrate_lanes`](crate::Rk4::integrate_lanes) advances them
//! together (DESIGN §6.8).

use nalgebra::{RealField, SVector, Scalar, SimdBool, SimdRealField};

use crate::{SimError, Stats};

pub use simba::simd::WideF64x4;

/// A scalar that holds one value per lane: every real field of `nalgebra`
/// (`f64`: one lane) and its SIMD types (simba's [`WideF64x4`]: four).
///
/// Its methods are the elementary functions the generated code calls,
/// under the names `RealField` gives them, so that one generated body
/// serves `f64` and lanes alike; each is the lane-wise `simd_*` function of
/// [`SimdRealField`]. For `f64` they are `f64`'s own; simba's wide types
/// evaluate `sin`, `cos` and `sin_cos` by polynomials accurate to about one
/// unit in the last place (Agner Fog's vector class library), so results
/// agree with the scalar ones to rounding, lane by lane.
///
/// ```rust
/// use nh_runtime::{Lanes, WideF64x4};
///
/// fn hypot<T: Lanes>(a: T, b: T) -> T {
///     (a * a + b * b).sqrt()
/// }
/// let x = WideF64x4::from([3.0, 5.0, 8.0, 0.0]);
/// let y = WideF64x4::from([4.0, 12.0, 15.0, 0.0]);
/// let h = hypot(x, y);
/// assert_eq!(<[f64; 4]>::from(h), [5.0, 13.0, 17.0, 0.0]);
/// assert_eq!(hypot(3.0f64, 4.0), 5.0);
/// ```
pub trait Lanes: SimdRealField<Element: RealField + Copy> + Copy + Scalar {
    /// π in every lane.
    fn pi() -> Self;
    /// Sine, lane by lane.
    fn sin(self) -> Self;
    /// Cosine, lane by lane.
    fn cos(self) -> Self;
    /// Sine and cosine, lane by lane.
    fn sin_cos(self) -> (Self, Self);
    /// Tangent, lane by lane.
    fn tan(self) -> Self;
    /// Arcsine, lane by lane.
    fn asin(self) -> Self;
    /// Arccosine, lane by lane.
    fn acos(self) -> Self;
    /// Arctangent, lane by lane.
    fn atan(self) -> Self;
    /// The angle of the point (`x`, `self`), lane by lane.
    fn atan2(self, x: Self) -> Self;
    /// Hyperbolic sine, lane by lane.
    fn sinh(self) -> Self;
    /// Hyperbolic cosine, lane by lane.
    fn cosh(self) -> Self;
    /// Hyperbolic tangent, lane by lane.
    fn tanh(self) -> Self;
    /// Exponential, lane by lane.
    fn exp(self) -> Self;
    /// Natural logarithm, lane by lane.
    fn ln(self) -> Self;
    /// Square root, lane by lane.
    fn sqrt(self) -> Self;
    /// Absolute value, lane by lane.
    fn abs(self) -> Self;
    /// Integer power, lane by lane.
    fn powi(self, n: i32) -> Self;
    /// Real power, lane by lane.
    fn powf(self, e: Self) -> Self;
}

/// The functions of [`Lanes`] by their `simd_*` namesakes.
macro_rules! lane_functions {
    ($($name:ident => $simd:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self) -> Self {
                self.$simd()
            }
        )*
    };
}

impl<T> Lanes for T
where
    T: SimdRealField<Element: RealField + Copy> + Copy + Scalar,
{
    #[inline(always)]
    fn pi() -> Self {
        T::simd_pi()
    }
    lane_functions!(
        sin => simd_sin, cos => simd_cos, tan => simd_tan, asin => simd_asin,
        acos => simd_acos, atan => simd_atan, sinh => simd_sinh, cosh => simd_cosh,
        tanh => simd_tanh, exp => simd_exp, ln => simd_ln, sqrt => simd_sqrt,
        abs => simd_abs
    );
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        self.simd_sin_cos()
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        self.simd_atan2(x)
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        self.simd_powi(n)
    }
    #[inline(always)]
    fn powf(self, e: Self) -> Self {
        self.simd_powf(e)
    }
}

/// A first-order system x' = f(t, x) evaluated at one state per lane: the
/// generated systems implement it for every [`Lanes`] type when their
/// right-hand side is straight-line code (no inputs, no piecewise
/// functions), and so does every closure `Fn(T, &SVector<T, D>) ->
/// SVector<T, D>`.
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{LaneSystem, WideF64x4};
///
/// let oscillator = |_t: WideF64x4, x: &Vector2<WideF64x4>| Vector2::new(x[1], -x[0]);
/// let x = Vector2::new(WideF64x4::from([1.0, 2.0, 3.0, 4.0]), WideF64x4::from([0.5; 4]));
/// let f = oscillator.lane_rhs(WideF64x4::from([0.0; 4]), &x);
/// assert_eq!(<[f64; 4]>::from(f[1]), [-1.0, -2.0, -3.0, -4.0]);
/// ```
pub trait LaneSystem<T: Lanes, const D: usize> {
    /// f(t, x), one state per lane.
    fn lane_rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D>;
}

impl<T: Lanes, const D: usize, F> LaneSystem<T, D> for F
where
    F: Fn(T, &SVector<T, D>) -> SVector<T, D>,
{
    #[inline(always)]
    fn lane_rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self(t, x)
    }
}

/// A first-order system with inputs, x' = f(t, x, u), evaluated at one
/// state and input per lane: the generated systems with inputs implement it
/// for every [`Lanes`] type when their right-hand side is straight-line.
/// Rollouts under sampled inputs (MPPI) integrate a closure over it:
///
/// ```rust
/// use nalgebra::{Vector1, Vector2};
/// use nh_runtime::{LaneControlledSystem, Rk4, WideF64x4};
///
/// /// A double integrator x'' = u.
/// struct Cart;
/// impl LaneControlledSystem<WideF64x4, 2, 1> for Cart {
///     fn lane_rhs_with_input(
///         &self,
///         _t: WideF64x4,
///         x: &Vector2<WideF64x4>,
///         u: &Vector1<WideF64x4>,
///     ) -> Vector2<WideF64x4> {
///         Vector2::new(x[1], u[0])
///     }
/// }
/// // four rollouts, each under its own constant input
/// let u = Vector1::new(WideF64x4::from([-1.0, 0.0, 1.0, 2.0]));
/// let rollout = |t: WideF64x4, x: &Vector2<WideF64x4>| Cart.lane_rhs_with_input(t, x, &u);
/// let x0 = Vector2::new(WideF64x4::from([0.0; 4]), WideF64x4::from([0.0; 4]));
/// let out = Rk4::new(0.1).integrate_lanes(&rollout, 0.0, x0, 1.0).unwrap();
/// let (_, x) = out.lane(3).unwrap();
/// assert!((x[0] - 1.0).abs() < 1e-12); // ½ u t² with u = 2
/// ```
pub trait LaneControlledSystem<T: Lanes, const D: usize, const M: usize> {
    /// f(t, x, u), one state and input per lane.
    fn lane_rhs_with_input(&self, t: T, x: &SVector<T, D>, u: &SVector<T, M>) -> SVector<T, D>;
}

/// The end of a run in lanes ([`Rk4::integrate_lanes`](crate::Rk4::integrate_lanes)):
/// per lane, the state at `t1` or the last good state of a lane that
/// failed, with the time of either. [`LaneOutcome::lane`] reads one lane
/// as the scalar run's result.
#[derive(Debug, Clone, Copy)]
pub struct LaneOutcome<T: Lanes, const D: usize> {
    /// Per lane: `t1`, or the time of the last good state of a lane that
    /// failed.
    pub t: T,
    /// Per lane: the state at `t1`, or the last good state of a lane that
    /// failed.
    pub x: SVector<T, D>,
    /// The lanes whose right-hand side or state became NaN or infinite.
    pub non_finite: T::SimdBool,
    /// Whether the step budget ran out before `t1`: then every lane that
    /// had not failed ends at the last step's time.
    pub out_of_steps: bool,
    /// Work counters of the call: steps, and right-hand side evaluations
    /// (one per evaluation of all lanes).
    pub stats: Stats,
}

impl<T: Lanes, const D: usize> LaneOutcome<T, D> {
    /// Lane `i` as a scalar run ends: `Ok((t1, x(t1)))`, or the typed
    /// failure with the lane's time and last good state
    /// ([`SimError::NonFinite`], [`SimError::MaxSteps`]).
    ///
    /// # Panics
    ///
    /// If `i` is not below the lane count `T::LANES`.
    #[allow(clippy::type_complexity)]
    pub fn lane(
        &self,
        i: usize,
    ) -> Result<(T::Element, SVector<T::Element, D>), SimError<T::Element, D>> {
        assert!(i < T::LANES, "lane {i} of {}", T::LANES);
        let (t, x) = (self.t.extract(i), self.x.map(|v| v.extract(i)));
        if self.non_finite.bitmask() >> i & 1 == 1 {
            Err(SimError::NonFinite { t, x })
        } else if self.out_of_steps {
            Err(SimError::MaxSteps {
                t,
                x,
                steps: self.stats.steps,
            })
        } else {
            Ok((t, x))
        }
    }
}

/// The lanes in which every entry of `x` is finite (`0·v` is ±0 for
/// finite `v`, NaN for infinities and NaN).
#[inline]
pub(crate) fn finite_lanes<T: Lanes, const D: usize>(x: &SVector<T, D>) -> T::SimdBool {
    let zero = T::zero();
    x.iter()
        .fold(zero.simd_eq(zero), |ok, &v| ok & (v * zero).simd_eq(zero))
}

/// `new` in the lanes `keep` selects, `old` in the others.
#[inline]
pub(crate) fn select<T: Lanes, const D: usize>(
    keep: T::SimdBool,
    new: &SVector<T, D>,
    old: &SVector<T, D>,
) -> SVector<T, D> {
    new.zip_map(old, |a, b| a.select(keep, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SimdValue, Vector2};

    #[test]
    fn finite_lanes_marks_nan_and_infinities() {
        let x = Vector2::new(
            WideF64x4::from([1.0, f64::NAN, 3.0, 4.0]),
            WideF64x4::from([1.0, 2.0, f64::INFINITY, -0.0]),
        );
        assert_eq!(finite_lanes(&x).bitmask(), 0b1001);
    }

    #[test]
    fn elementary_functions_agree_with_f64_lane_by_lane() {
        let a = [0.3, -1.7, 2.5, 12.0];
        let v = WideF64x4::from(a);
        let (s, c) = Lanes::sin_cos(v);
        for (i, a) in a.into_iter().enumerate() {
            assert!((s.extract(i) - a.sin()).abs() <= 2.0 * f64::EPSILON);
            assert!((c.extract(i) - a.cos()).abs() <= 2.0 * f64::EPSILON);
            assert_eq!(Lanes::sqrt(Lanes::abs(v)).extract(i), a.abs().sqrt());
            assert_eq!(Lanes::powi(v, 3).extract(i), a.powi(3));
        }
    }
}
