//! The checks of a call's arguments that every entry point makes before it
//! integrates (the step driver, and the output-time sampler before it
//! starts the driver).

use nalgebra::{RealField, SVector};

use crate::SimError;
use crate::numeric::all_finite;

/// Validates the arguments common to every integrator and returns the
/// direction of integration (`+1` or `-1`, or `0` when `t1 == t0`).
pub(crate) fn check_arguments<T: RealField + Copy, const D: usize>(
    t0: T,
    x0: &SVector<T, D>,
    t1: T,
) -> Result<T, SimError<T, D>> {
    if !t0.is_finite() {
        return Err(SimError::InvalidInput {
            what: "t0 must be finite",
        });
    }
    if !t1.is_finite() {
        return Err(SimError::InvalidInput {
            what: "t1 must be finite",
        });
    }
    if !all_finite(x0) {
        return Err(SimError::InvalidInput {
            what: "x0 must be finite",
        });
    }
    Ok(if t1 > t0 {
        T::one()
    } else if t1 < t0 {
        -T::one()
    } else {
        T::zero()
    })
}

/// Returns `Ok(())` if `v` is finite and positive, else `InvalidInput`.
pub(crate) fn check_positive<T: RealField + Copy, const D: usize>(
    v: T,
    what: &'static str,
) -> Result<(), SimError<T, D>> {
    if v.is_finite() && v > T::zero() {
        Ok(())
    } else {
        Err(SimError::InvalidInput { what })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn arguments_give_the_direction_or_invalid_input() {
        let ok = Vector2::new(1.0, 2.0);
        assert_eq!(check_arguments(0.0, &ok, 1.0), Ok(1.0));
        assert_eq!(check_arguments(1.0, &ok, 0.0), Ok(-1.0));
        assert_eq!(check_arguments(1.0, &ok, 1.0), Ok(0.0));
        let invalid = |what| Err(SimError::InvalidInput { what });
        assert_eq!(
            check_arguments(f64::NAN, &ok, 1.0),
            invalid("t0 must be finite")
        );
        assert_eq!(
            check_arguments(0.0, &ok, f64::INFINITY),
            invalid("t1 must be finite")
        );
        assert_eq!(
            check_arguments(0.0, &Vector2::new(1.0, f64::NAN), 1.0),
            invalid("x0 must be finite")
        );
    }

    #[test]
    fn positive_means_finite_and_above_zero() {
        assert_eq!(check_positive::<f64, 2>(1e-300, "x"), Ok(()));
        assert_eq!(check_positive::<f64, 2>(f64::MAX, "x"), Ok(()));
        let invalid = Err(SimError::<f64, 2>::InvalidInput { what: "h" });
        assert_eq!(check_positive::<f64, 2>(0.0, "h"), invalid);
        assert_eq!(check_positive::<f64, 2>(-1.0, "h"), invalid);
        assert_eq!(check_positive::<f64, 2>(f64::NAN, "h"), invalid);
        assert_eq!(check_positive::<f64, 2>(f64::INFINITY, "h"), invalid);
    }
}
