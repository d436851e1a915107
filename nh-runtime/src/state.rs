//! Building a state from the velocities a user knows: the check that they
//! satisfy the constraints ([`ConstraintViolation`]) and the speeds that
//! give them ([`speeds_from_velocities`]).

use core::fmt;

use nalgebra::{RealField, SMatrix, SVector};

use crate::common::{c, machine_epsilon};
use crate::linalg::Lu;

/// Velocities given for a state that do not satisfy the system's velocity
/// constraints: the coordinate whose velocity is furthest from the value
/// the constraints give, with both values.
///
/// Returned by the generated `state_from_velocities` of a system (the
/// velocities of all coordinates in, the state out), which compares every
/// velocity with the one the constraints imply at the given coordinates.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::ConstraintViolation;
///
/// // ẏ = 2 ẋ is implied; ẏ = 3 is given with ẋ = 1
/// let given = Vector2::new(1.0, 3.0);
/// let implied = Vector2::new(1.0, 2.0);
/// let e = ConstraintViolation::check(&["x", "y"], &given, &implied).unwrap_err();
/// assert_eq!((e.coordinate, e.given, e.implied), ("y", 3.0, 2.0));
/// assert_eq!(
///     e.to_string(),
///     "the velocity of `y` is 3 but the constraints give 2 at these coordinates \
///      (off by 1; the tolerance is 1e-9 of the largest velocity)"
/// );
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstraintViolation<T> {
    /// The coordinate whose given velocity breaks the constraints.
    pub coordinate: &'static str,
    /// The velocity given for it.
    pub given: T,
    /// The velocity the constraints give it at the given coordinates and
    /// the other velocities.
    pub implied: T,
    /// The largest difference accepted: [`ConstraintViolation::RELATIVE_TOLERANCE`]
    /// times the largest velocity, given or implied.
    pub tolerance: T,
}

impl<T: RealField + Copy> ConstraintViolation<T> {
    /// The tolerance relative to the largest velocity: differences up to
    /// `1e-9` of it are rounding, not a violation.
    pub const RELATIVE_TOLERANCE: f64 = 1e-9;

    /// Compares the `given` velocities of the coordinates `names` with
    /// those the constraints imply (`implied`, in the same order): `Ok` if
    /// every difference is within the tolerance, else the coordinate with
    /// the largest difference.
    pub fn check<const N: usize>(
        names: &[&'static str; N],
        given: &SVector<T, N>,
        implied: &SVector<T, N>,
    ) -> Result<(), Self> {
        let scale = given
            .iter()
            .chain(implied.iter())
            .fold(T::zero(), |s, v| s.max(v.abs()));
        let tolerance = c::<T>(Self::RELATIVE_TOLERANCE) * scale;
        let mut worst: Option<(usize, T)> = None;
        for (i, (&g, &v)) in given.iter().zip(implied.iter()).enumerate() {
            let off = (g - v).abs();
            // a NaN difference is a violation too (and stays the worst)
            let violates = off > tolerance || !off.is_finite();
            if violates && worst.is_none_or(|(_, w)| off > w) {
                worst = Some((i, off));
            }
        }
        match worst {
            None => Ok(()),
            Some((i, _)) => Err(Self {
                coordinate: names[i],
                given: given[i],
                implied: implied[i],
                tolerance,
            }),
        }
    }
}

impl<T: fmt::Display + Copy + core::ops::Sub<Output = T>> fmt::Display for ConstraintViolation<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the velocity of `{}` is {} but the constraints give {} at these coordinates \
             (off by {}; the tolerance is 1e-9 of the largest velocity)",
            self.coordinate,
            self.given,
            self.implied,
            self.given - self.implied,
        )
    }
}

#[cfg(feature = "std")]
impl<T> std::error::Error for ConstraintViolation<T> where
    T: fmt::Debug + fmt::Display + Copy + core::ops::Sub<Output = T>
{
}

/// The generalized speeds `u` whose kinematics `q̇ = S u + σ` comes closest
/// to the velocities `qdot` (least squares; exact when `qdot` satisfies
/// the constraints). `kinematics(u)` is `S u + σ` at fixed coordinates and
/// time, for instance a generated system's `velocities(t, &q, u)`.
///
/// S is read off `kinematics` column by column (`K + 1` calls) and the
/// normal equations `SᵀS u = Sᵀ(q̇ − σ)` are solved by LU; where S loses
/// rank they are regularised by `√eps · tr(SᵀS)/K`. Whether the result
/// reproduces `qdot` is for the caller to check
/// ([`ConstraintViolation::check`]).
///
/// # Example
///
/// ```rust
/// use nalgebra::{Vector2, Vector3};
/// use nh_runtime::speeds_from_velocities;
///
/// // a blade at heading θ = 0.3: ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω
/// let th: f64 = 0.3;
/// let kinematics = |u: &Vector2<f64>| Vector3::new(u[0] * th.cos(), u[0] * th.sin(), u[1]);
/// let u = speeds_from_velocities(kinematics, &Vector3::new(2.0 * th.cos(), 2.0 * th.sin(), 0.5));
/// assert!((u - Vector2::new(2.0, 0.5)).amax() < 1e-15);
/// ```
pub fn speeds_from_velocities<T, const N: usize, const K: usize>(
    kinematics: impl Fn(&SVector<T, K>) -> SVector<T, N>,
    qdot: &SVector<T, N>,
) -> SVector<T, K>
where
    T: RealField + Copy,
{
    let sigma = kinematics(&SVector::zeros());
    let s = SMatrix::<T, N, K>::from_fn(|i, j| {
        let unit = SVector::<T, K>::from_fn(|l, _| if l == j { T::one() } else { T::zero() });
        kinematics(&unit)[i] - sigma[i]
    });
    let (sts, rhs) = (s.transpose() * s, s.transpose() * (qdot - sigma));
    if let Some(lu) = Lu::new(sts) {
        return lu.solve(&rhs);
    }
    let trace = (0..K).fold(T::zero(), |t, i| t + sts[(i, i)]);
    let delta = machine_epsilon::<T>().sqrt() * trace / c::<T>(K.max(1) as f64);
    let regularised = sts + SMatrix::<T, K, K>::identity() * delta;
    Lu::new(regularised).map_or_else(SVector::zeros, |lu| lu.solve(&rhs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};

    #[test]
    fn within_tolerance_is_accepted() {
        let given = Vector3::new(1.0, 2.0, 1e3);
        let implied = Vector3::new(1.0, 2.0 + 0.9e-6, 1e3);
        assert_eq!(
            ConstraintViolation::check(&["a", "b", "c"], &given, &implied),
            Ok(())
        );
    }

    #[test]
    fn the_largest_difference_is_reported() {
        let given = Vector3::new(1.0, 2.5, 4.0);
        let implied = Vector3::new(1.0, 2.0, 3.0);
        let e = ConstraintViolation::check(&["a", "b", "c"], &given, &implied).unwrap_err();
        assert_eq!(e.coordinate, "c");
        assert_eq!((e.given, e.implied), (4.0, 3.0));
        assert_eq!(e.tolerance, 4.0 * 1e-9);
    }

    #[test]
    fn nan_is_a_violation_and_zero_is_exact() {
        let e = ConstraintViolation::check(&["a"], &Vector1::new(f64::NAN), &Vector1::new(0.0));
        assert_eq!(e.unwrap_err().coordinate, "a");
        assert!(ConstraintViolation::check(&["a"], &Vector1::new(0.0), &Vector1::new(0.0)).is_ok());
        let e = ConstraintViolation::check(&["a"], &Vector1::new(0.0), &Vector1::new(1e-300));
        assert_eq!(e.unwrap_err().implied, 1e-300);
    }

    use nalgebra::Vector1;

    #[test]
    fn speeds_of_a_rank_deficient_kinematics() {
        // S = [[1, 1], [0, 0], [1, 1]]: any u with u0 + u1 = 2 gives (2, 0, 2)
        let k = |u: &Vector2<f64>| Vector3::new(u[0] + u[1], 0.0, u[0] + u[1]);
        let u = speeds_from_velocities(k, &Vector3::new(2.0, 0.0, 2.0));
        assert!((k(&u) - Vector3::new(2.0, 0.0, 2.0)).amax() < 1e-6, "{u}");
    }

    #[test]
    fn speeds_with_an_affine_term() {
        // q̇ = (u + 1, 2u): q̇ = (3, 4) has u = 2
        let k = |u: &Vector1<f64>| Vector2::new(u[0] + 1.0, 2.0 * u[0]);
        assert_eq!(speeds_from_velocities(k, &Vector2::new(3.0, 4.0))[0], 2.0);
    }
}
