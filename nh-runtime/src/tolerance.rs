//! Error tolerances of the adaptive integrators (one `(rtol, atol)` for
//! every component, or a pair per component) and the error norm they
//! define; the norm is documented in the crate documentation,
//! [Tolerances and the error norm](crate#tolerances-and-the-error-norm).

use nalgebra::{RealField, SVector};

use crate::SimError;

/// How an adaptive integrator weighs the error of each state component:
/// [`ScalarTolerance`] (the same `rtol`, `atol` for every component, what
/// `new(rtol, atol)` gives) or [`PerComponentTolerance`] (what
/// `with_tolerances(rtol, atol)` gives). The norm they define is described
/// in the crate documentation, [Tolerances and the error
/// norm](crate#tolerances-and-the-error-norm).
///
/// The trait is sealed: these two types are its only implementations.
pub trait ErrorTolerance<T: RealField + Copy>:
    Copy + core::fmt::Debug + PartialEq + sealed::Sealed<T>
{
}

/// The same relative tolerance `rtol` and absolute tolerance `atol` for
/// every component: the tolerance of `Dopri5::new(rtol, atol)` and
/// of the other adaptive integrators' `new`.
///
/// # Example
///
/// ```rust
/// use nh_runtime::{Dopri5, ScalarTolerance};
///
/// // The type parameter defaults to `ScalarTolerance`.
/// let dp: Dopri5<f64, ScalarTolerance<f64>> = Dopri5::new(1e-8, 1e-10);
/// let same: Dopri5<f64> = dp;
/// assert_eq!(same, dp);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarTolerance<T> {
    rtol: T,
    atol: T,
}

impl<T: RealField + Copy> ScalarTolerance<T> {
    /// Relative tolerance `rtol` (finite, > 0) and absolute tolerance
    /// `atol` (finite, ≥ 0), checked when an integration starts.
    pub(crate) fn new(rtol: T, atol: T) -> Self {
        ScalarTolerance { rtol, atol }
    }
}

/// A relative tolerance `rtol[i]` and an absolute tolerance `atol[i]` for
/// each component `i` of a state of dimension `N`: for states whose
/// components have very different scales (a position in metres next to an
/// angle, a concentration of 1e-6 next to one of 1), or components that
/// matter less than others.
///
/// Made by the adaptive integrators' `with_tolerances(rtol, atol)`. Every
/// `rtol[i]` must be finite and > 0 and every `atol[i]` finite and ≥ 0;
/// integrating a state whose dimension is not `N` returns
/// [`SimError::InvalidInput`](crate::SimError::InvalidInput) before
/// anything is evaluated. Equal entries give exactly the steps of
/// [`ScalarTolerance`] with those values.
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{Dopri5, Integrator, SimError};
///
/// // x1 ≈ 1e6 and x2 ≈ 1e-6, decaying at rates 1 and 3.
/// let decay = |_t: f64, x: &Vector2<f64>| Vector2::new(-x[0], -3.0 * x[1]);
/// let x0 = Vector2::new(1e6, 1e-6);
/// let exact = Vector2::new(1e6 * (-1.0f64).exp(), 1e-6 * (-3.0f64).exp());
/// let relative = |x: Vector2<f64>| (x - exact).component_div(&exact).abs().max();
/// // atol = rtol times each component's scale: both accurate to ~rtol.
/// let mut dp = Dopri5::new(1e-8, 0.0)
///     .with_tolerances(Vector2::new(1e-8, 1e-8), Vector2::new(1e-2, 1e-14));
/// let out = dp.integrate(&decay, 0.0, x0, 1.0).unwrap();
/// assert!(relative(out.x) < 1e-7);
/// // One atol for both, suited to x1: x2 is hardly controlled.
/// let out = Dopri5::new(1e-8, 1e-2).integrate(&decay, 0.0, x0, 1.0).unwrap();
/// assert!(relative(out.x) > 1e-6);
///
/// // The tolerances have two components, the state three.
/// let decay3 = |_t: f64, x: &nalgebra::Vector3<f64>| -x;
/// let r = dp.integrate(&decay3, 0.0, nalgebra::Vector3::zeros(), 1.0);
/// assert!(matches!(r, Err(SimError::InvalidInput { .. })));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PerComponentTolerance<T, const N: usize> {
    rtol: SVector<T, N>,
    atol: SVector<T, N>,
}

impl<T: RealField + Copy, const N: usize> PerComponentTolerance<T, N> {
    /// Relative tolerances `rtol` (each finite, > 0) and absolute
    /// tolerances `atol` (each finite, ≥ 0), checked when an integration
    /// starts.
    pub(crate) fn new(rtol: SVector<T, N>, atol: SVector<T, N>) -> Self {
        PerComponentTolerance { rtol, atol }
    }
}

impl<T: RealField + Copy> ErrorTolerance<T> for ScalarTolerance<T> {}
impl<T: RealField + Copy, const N: usize> ErrorTolerance<T> for PerComponentTolerance<T, N> {}

pub(crate) mod sealed {
    use super::{PerComponentTolerance, ScalarTolerance, Tolerance};
    use nalgebra::{RealField, SVector};

    /// The per-run weights of a tolerance (not implementable outside the
    /// crate).
    pub trait Sealed<T> {
        /// The tolerances of a state of dimension `D`, or `None` if this
        /// tolerance is for another dimension.
        fn for_dimension<const D: usize>(&self) -> Option<Tolerance<T, D>>;
    }

    impl<T: RealField + Copy> Sealed<T> for ScalarTolerance<T> {
        fn for_dimension<const D: usize>(&self) -> Option<Tolerance<T, D>> {
            Some(Tolerance {
                rtol: SVector::repeat(self.rtol),
                atol: SVector::repeat(self.atol),
            })
        }
    }

    impl<T: RealField + Copy, const N: usize> Sealed<T> for PerComponentTolerance<T, N> {
        fn for_dimension<const D: usize>(&self) -> Option<Tolerance<T, D>> {
            (N == D).then(|| Tolerance {
                rtol: SVector::from_fn(|i, _| self.rtol[i]),
                atol: SVector::from_fn(|i, _| self.atol[i]),
            })
        }
    }
}

/// The tolerances of one run, per component (a scalar tolerance repeated):
/// what [`error_norm`] and every method's error estimate weigh errors with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance<T, const D: usize> {
    pub(crate) rtol: SVector<T, D>,
    pub(crate) atol: SVector<T, D>,
}

impl<T: RealField + Copy, const D: usize> Tolerance<T, D> {
    /// The same `rtol` and `atol` for every component.
    #[cfg(test)]
    pub(crate) fn uniform(rtol: T, atol: T) -> Self {
        Tolerance {
            rtol: SVector::repeat(rtol),
            atol: SVector::repeat(atol),
        }
    }

    /// The weight `atol_i + rtol_i·max(|x_i|, |x_new_i|)` of component `i`
    /// over a step from `x_i` to `x_new_i`.
    #[inline(always)]
    pub(crate) fn weight(&self, i: usize, x_i: T, x_new_i: T) -> T {
        self.atol[i] + self.rtol[i] * x_i.abs().max(x_new_i.abs())
    }

    /// The weights `atol_i + rtol_i·max(|x_i|, |x_new_i|)` of a step from
    /// `x` to `x_new`.
    #[inline(always)]
    pub(crate) fn weights(&self, x: &SVector<T, D>, x_new: &SVector<T, D>) -> SVector<T, D> {
        let mut sk = self.atol;
        for i in 0..D {
            sk[i] = self.weight(i, x[i], x_new[i]);
        }
        sk
    }

    /// The weights `atol_i + rtol_i·|x_i|` at one point `x` (for the
    /// initial-step heuristic).
    pub(crate) fn weights_at(&self, x: &SVector<T, D>) -> SVector<T, D> {
        x.zip_zip_map(&self.rtol, &self.atol, |xi, r, a| a + r * xi.abs())
    }

    /// These tolerances with every positive `rtol_i` raised to at least
    /// `floor` (the smallest relative error the scalar resolves in a step).
    pub(crate) fn floored(mut self, floor: T) -> Self {
        for r in self.rtol.iter_mut() {
            if *r > T::zero() {
                *r = r.max(floor);
            }
        }
        self
    }

    /// `InvalidInput` unless every `rtol_i` is finite and > 0 and every
    /// `atol_i` finite and ≥ 0.
    pub(crate) fn check(&self) -> Result<(), SimError<T, D>> {
        if !self.rtol.iter().all(|r| r.is_finite() && *r > T::zero()) {
            return Err(SimError::InvalidInput {
                what: "rtol must be positive and finite",
            });
        }
        if !self.atol.iter().all(|a| a.is_finite() && *a >= T::zero()) {
            return Err(SimError::InvalidInput {
                what: "atol must be non-negative and finite",
            });
        }
        Ok(())
    }
}

/// `e / sk` with `0 / 0 = 0`: a component whose error is exactly zero meets
/// any tolerance, also a zero one (`atol = 0` on a component that is exactly
/// zero, such as a coordinate of a system at rest), instead of turning the
/// error norm into NaN and the step into a spurious non-finite rejection.
#[inline]
pub(crate) fn scaled<T: RealField + Copy>(e: T, sk: T) -> T {
    if e == T::zero() { T::zero() } else { e / sk }
}

/// Hairer's error norm: the RMS over components of
/// `err_i / (atol_i + rtol_i·max(|x_i|, |x_new_i|))` (with `0 / 0 = 0`, see
/// [`scaled`]).
#[inline(always)]
pub(crate) fn error_norm<T: RealField + Copy, const D: usize>(
    err: &SVector<T, D>,
    x: &SVector<T, D>,
    x_new: &SVector<T, D>,
    tol: &Tolerance<T, D>,
) -> T {
    if D == 0 {
        return T::zero();
    }
    // The weights first, as one vector: the loop below then compiles to the
    // same vectorised code as with scalar tolerances (within 1 % of the
    // instructions per DOPRI5 step at D = 6 and 12; a fused loop cost 7–12 %).
    let sk = tol.weights(x, x_new);
    let mut sum = T::zero();
    for i in 0..D {
        let r = scaled(err[i], sk[i]);
        sum += r * r;
    }
    (sum / nalgebra::convert::<f64, T>(D as f64)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn error_norm_is_hairer_rms() {
        let err = Vector2::new(1e-6, 2e-6);
        let x = Vector2::new(1.0, -3.0);
        let x_new = Vector2::new(2.0, 0.5);
        // sk = atol + rtol * max(|x|, |x_new|) = 1e-6 * (1 + [2, 3]).
        let n = error_norm(&err, &x, &x_new, &Tolerance::uniform(1e-6, 1e-6));
        let expected = (((1.0f64 / 3.0).powi(2) + (2.0f64 / 4.0).powi(2)) / 2.0).sqrt();
        assert!((n - expected).abs() < 1e-12, "{n} vs {expected}");
    }

    #[test]
    fn zero_error_meets_a_zero_tolerance() {
        // atol = 0 on a component that is exactly zero before and after.
        let err = Vector2::new(0.0, 1e-9);
        let x = Vector2::new(0.0, 1.0);
        let n = error_norm(&err, &x, &x, &Tolerance::uniform(1e-6, 0.0));
        assert!((n - (0.5e-6f64).sqrt()).abs() < 1e-12, "{n}");
        assert_eq!(
            error_norm(
                &Vector2::zeros(),
                &Vector2::zeros(),
                &Vector2::zeros(),
                &Tolerance::uniform(1e-6, 0.0)
            ),
            0.0
        );
    }
}
