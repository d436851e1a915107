//! Numeric helpers every part of the runtime uses: constants of `T`
//! (`c`, `machine_epsilon`), branch-free finiteness tests and the stage
//! sums of the explicit Runge–Kutta methods.

use nalgebra::{RealField, SVector};

/// Converts an `f64` constant to `T`.
#[inline(always)]
pub(crate) fn c<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert::<f64, T>(x)
}

/// Machine epsilon of `T`: the smallest power of two `e` with `1 + e > 1`.
///
/// Computed rather than looked up, because `RealField` does not expose it.
pub(crate) fn machine_epsilon<T: RealField + Copy>() -> T {
    let one = T::one();
    let half = c::<T>(0.5);
    let mut eps = one;
    // The iteration cap only matters for exotic number types.
    for _ in 0..2048 {
        let next = eps * half;
        if one + next <= one {
            break;
        }
        eps = next;
    }
    eps
}

/// Whether every component of `x` is finite, without a branch per
/// component (`0·v` is `0` for a finite `v` and NaN otherwise).
#[inline]
pub(crate) fn all_finite<T: RealField + Copy, const D: usize>(x: &SVector<T, D>) -> bool {
    x.iter().fold(T::zero(), |zero, &v| zero + v * T::zero()) == T::zero()
}

/// `x + (Σ_j a_j·k_{s_j})·h` for the stages and weights `terms = [(s_j,
/// a_j)]` of an explicit Runge–Kutta step, summed left to right as in the
/// formulas of Hairer's codes, component by component (no temporary vector
/// per term; the same rounding as the vector expression).
#[inline(always)]
pub(crate) fn stage_point<T: RealField + Copy, const D: usize, const M: usize, const N: usize>(
    x: &SVector<T, D>,
    k: &[SVector<T, D>; M],
    terms: [(usize, f64); N],
    h: T,
) -> SVector<T, D> {
    let mut point = *x;
    for (i, p) in point.iter_mut().enumerate() {
        let mut sum = k[terms[0].0][i] * c::<T>(terms[0].1);
        for &(s, a) in &terms[1..] {
            sum += k[s][i] * c::<T>(a);
        }
        *p += sum * h;
    }
    point
}

/// Whether every component of every vector in `vs` is finite, without a
/// branch per component: `0·v` is `0` for a finite `v` and NaN otherwise,
/// so the sum of `0·v_i` over the vectors is zero exactly when all of them
/// are finite (the stage checks of every step go through here).
#[inline]
pub(crate) fn all_finite_in<T: RealField + Copy, const D: usize>(vs: &[SVector<T, D>]) -> bool {
    let mut zero = SVector::<T, D>::zeros();
    for v in vs {
        zero += v * T::zero();
    }
    all_finite(&zero)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SVector, Vector2, Vector3};

    #[test]
    fn constants_convert_to_the_scalar() {
        assert_eq!(c::<f64>(0.1), 0.1);
        assert_eq!(c::<f32>(0.1), 0.1f32);
        assert_eq!(c::<f32>(1e300), f32::INFINITY);
    }

    #[test]
    fn machine_epsilon_matches_std() {
        assert_eq!(machine_epsilon::<f64>(), f64::EPSILON);
        assert_eq!(machine_epsilon::<f32>(), f32::EPSILON);
    }

    #[test]
    fn all_finite_rejects_nan_and_both_infinities() {
        assert!(all_finite(&Vector2::new(f64::MAX, -f64::MIN_POSITIVE)));
        assert!(all_finite(&SVector::<f64, 0>::zeros()));
        assert!(!all_finite(&Vector2::new(1.0, f64::NAN)));
        assert!(!all_finite(&Vector2::new(f64::INFINITY, 1.0)));
        assert!(!all_finite(&Vector2::new(1.0, f64::NEG_INFINITY)));
        // +∞ and −∞ do not cancel.
        assert!(!all_finite(&Vector2::new(f64::INFINITY, f64::NEG_INFINITY)));
    }

    #[test]
    fn all_finite_in_checks_every_vector() {
        let ok = Vector2::new(1.0, -2.0);
        assert!(all_finite_in::<f64, 2>(&[]));
        assert!(all_finite_in(&[ok, ok * 1e300]));
        assert!(!all_finite_in(&[ok, Vector2::new(0.0, f64::NAN)]));
        assert!(!all_finite_in(&[Vector2::new(f64::INFINITY, 0.0), ok]));
        // Two finite vectors whose sum would overflow are still finite.
        assert!(all_finite_in(&[
            Vector2::repeat(f64::MAX),
            Vector2::repeat(f64::MAX)
        ]));
    }

    #[test]
    fn stage_point_sums_the_weighted_stages() {
        let x = Vector3::new(1.0, -2.0, 0.5);
        let k = [
            Vector3::new(0.3, 0.7, -1.1),
            Vector3::new(2.0, -0.25, 0.125),
            Vector3::new(-5.0, 3.0, 1.0),
        ];
        let h = 0.1;
        let point = stage_point(&x, &k, [(0, 0.25), (2, -0.5)], h);
        // The same rounding as the vector expression.
        assert_eq!(point, x + (k[0] * 0.25 + k[2] * -0.5) * h);
        assert_eq!(stage_point(&x, &k, [(1, 1.0)], 2.0), x + k[1] * 2.0);
    }
}
