//! Forward sensitivities: the variational equations of `x' = f(t, x; p)`
//! integrated together with the system, by any integrator.
//!
//! For the `D × P` matrix `S_p = ∂x/∂p` and the `D × D` matrix
//! `S_x0 = ∂x/∂x0`,
//!
//! ```text
//! S_p'  = (∂f/∂x) S_p + ∂f/∂p,   S_p(t0)  = 0,
//! S_x0' = (∂f/∂x) S_x0,          S_x0(t0) = I.
//! ```
//!
//! [`Sensitivities`] is the augmented system with state
//! `[x, vec(S_p), vec(S_x0)]` (columns stacked), an [`OdeSystem`] of
//! dimension `A = D·(1 + P + D)`: integrated by an adaptive method, the
//! error control covers the sensitivities as well as the state (the *full
//! error control* choice; the sensitivities are then as accurate as the
//! tolerances say, at the price of steps that the state alone might not
//! need).

use nalgebra::{RealField, SMatrix, SVector};

use crate::{OdeJacobian, OdeSystem, ProjectionFailure};

/// A system that gives `∂f/∂p`, the derivative of its right-hand side with
/// respect to `P` of its parameters, and with it the right-hand side of the
/// variational equations.
///
/// A generated system with `outputs { sensitivities }` implements it (the
/// parameters: all of them in declared order, or those listed,
/// `sensitivities(m, k)`), with one common-subexpression-eliminated body for
/// [`ParameterJacobian::variational_rhs`].
///
/// # Example
///
/// ```rust
/// use nalgebra::{Matrix1, Matrix2, Matrix2x1, Vector2};
/// use nh_runtime::{Dopri5, Integrator, OdeJacobian, OdeSystem, ParameterJacobian, Sensitivities};
///
/// /// A damped oscillator x'' = −k x − x' with the stiffness k as parameter.
/// struct Oscillator { k: f64 }
/// impl OdeSystem<f64, 2> for Oscillator {
///     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
///         Vector2::new(x[1], -self.k * x[0] - x[1])
///     }
/// }
/// impl OdeJacobian<f64, 2> for Oscillator {
///     fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
///         Matrix2::new(0.0, 1.0, -self.k, -1.0)
///     }
/// }
/// impl ParameterJacobian<f64, 2, 1> for Oscillator {
///     fn parameter_jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2x1<f64> {
///         Matrix2x1::new(0.0, -x[0])
///     }
/// }
///
/// let sens = Sensitivities::<_, 2, 1, 8>::new(&Oscillator { k: 4.0 });
/// let x0 = Vector2::new(1.0, 0.0);
/// let out = Dopri5::new(1e-10, 1e-12).integrate(&sens, 0.0, sens.initial_state(&x0), 2.0).unwrap();
/// let (x, dx_dk, dx_dx0) = sens.split(&out.x);
/// // against a central difference of two whole runs in k
/// let run = |k: f64| Dopri5::new(1e-12, 1e-14).integrate(&Oscillator { k }, 0.0, x0, 2.0).unwrap().x;
/// let fd = (run(4.0 + 1e-5) - run(4.0 - 1e-5)) / 2e-5;
/// assert!((dx_dk.column(0) - fd).amax() < 1e-7);
/// assert!((x - run(4.0)).amax() < 1e-9);
/// // ∂x/∂x0 of a linear system is its flow: x = (∂x/∂x0) x0
/// assert!((dx_dx0 * x0 - x).amax() < 1e-9);
/// ```
pub trait ParameterJacobian<T: RealField + Copy, const D: usize, const P: usize>:
    OdeJacobian<T, D>
{
    /// `∂f/∂p` at `(t, x)`: column `j` is the derivative with respect to
    /// the `j`-th parameter.
    fn parameter_jacobian(&self, t: T, x: &SVector<T, D>) -> SMatrix<T, D, P>;

    /// The right-hand side of the variational equations at `(t, x)` with
    /// sensitivities `s_p = ∂x/∂p` and `s_x0 = ∂x/∂x0`:
    /// `(f, (∂f/∂x) s_p + ∂f/∂p, (∂f/∂x) s_x0)`.
    ///
    /// The default evaluates [`OdeSystem::rhs`], [`OdeJacobian::jacobian`]
    /// and [`ParameterJacobian::parameter_jacobian`] and multiplies densely;
    /// a generated system computes all of it in one body, with the
    /// structural zeros of `∂f/∂x` pruned from the products.
    #[allow(clippy::type_complexity)]
    fn variational_rhs(
        &self,
        t: T,
        x: &SVector<T, D>,
        s_p: &SMatrix<T, D, P>,
        s_x0: &SMatrix<T, D, D>,
    ) -> (SVector<T, D>, SMatrix<T, D, P>, SMatrix<T, D, D>) {
        let j = self.jacobian(t, x);
        (
            self.rhs(t, x),
            j * s_p + self.parameter_jacobian(t, x),
            j * s_x0,
        )
    }
}

/// The system `S` with its forward sensitivities: an [`OdeSystem`] of the
/// augmented state `[x, vec(∂x/∂p), vec(∂x/∂x0)]` of dimension
/// `A = D·(1 + P + D)` (checked when the type is built: a wrong `A` does
/// not compile).
///
/// A generated system with `outputs { sensitivities }` builds it with the
/// right `A` (`sys.sensitivities()`); [`Sensitivities::initial_state`]
/// makes the augmented initial state and [`Sensitivities::split`] reads
/// `x`, `∂x/∂p` and `∂x/∂x0` from a result. The chart's regularity, the
/// holonomic residual and the projection are those of the state `x`; the
/// projection moves `x` alone (the sensitivities are not projected).
/// The augmented system keeps the system's chart 0: it has one chart
/// ([`OdeSystem::charts`] is not forwarded), since the sensitivities
/// would have to be carried from chart to chart with the state; a run
/// ends at chart 0's singularity as the system's own would without
/// switching.
///
/// See [`ParameterJacobian`] for an example.
pub struct Sensitivities<'a, S: ?Sized, const D: usize, const P: usize, const A: usize> {
    system: &'a S,
}

impl<S: ?Sized, const D: usize, const P: usize, const A: usize> Clone
    for Sensitivities<'_, S, D, P, A>
{
    fn clone(&self) -> Self {
        *self
    }
}

impl<S: ?Sized, const D: usize, const P: usize, const A: usize> Copy
    for Sensitivities<'_, S, D, P, A>
{
}

impl<S: ?Sized + core::fmt::Debug, const D: usize, const P: usize, const A: usize> core::fmt::Debug
    for Sensitivities<'_, S, D, P, A>
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Sensitivities")
            .field("system", &self.system)
            .field("parameters", &P)
            .finish()
    }
}

impl<'a, S: ?Sized, const D: usize, const P: usize, const A: usize> Sensitivities<'a, S, D, P, A> {
    /// `A = D·(1 + P + D)`, checked at compile time.
    const LAYOUT: () = assert!(
        A == D * (1 + P + D),
        "the augmented dimension A of `Sensitivities` must be D·(1 + P + D)"
    );

    /// The sensitivities of `system` with respect to its `P` parameters and
    /// its `D` initial values.
    pub fn new(system: &'a S) -> Self {
        let () = Self::LAYOUT;
        Sensitivities { system }
    }

    /// The system.
    pub fn system(&self) -> &'a S {
        self.system
    }

    /// The augmented initial state for `x(t0) = x0`: `∂x/∂p = 0` and
    /// `∂x/∂x0 = I`.
    pub fn initial_state<T: RealField + Copy>(&self, x0: &SVector<T, D>) -> SVector<T, A> {
        self.initial_state_with(x0, &SMatrix::zeros())
    }

    /// The augmented initial state for an initial state that depends on the
    /// parameters, `x(t0) = x0(p)` with `∂x0/∂p = dx0_dp`.
    pub fn initial_state_with<T: RealField + Copy>(
        &self,
        x0: &SVector<T, D>,
        dx0_dp: &SMatrix<T, D, P>,
    ) -> SVector<T, A> {
        pack(x0, dx0_dp, &SMatrix::identity())
    }

    /// `x`, `∂x/∂p` (`D × P`) and `∂x/∂x0` (`D × D`) of an augmented state.
    #[allow(clippy::type_complexity)]
    pub fn split<T: RealField + Copy>(
        &self,
        augmented: &SVector<T, A>,
    ) -> (SVector<T, D>, SMatrix<T, D, P>, SMatrix<T, D, D>) {
        unpack(augmented)
    }
}

/// `[x, vec(s_p), vec(s_x0)]` (`A = D·(1 + P + D)`, see [`Sensitivities`]).
fn pack<T: RealField + Copy, const D: usize, const P: usize, const A: usize>(
    x: &SVector<T, D>,
    s_p: &SMatrix<T, D, P>,
    s_x0: &SMatrix<T, D, D>,
) -> SVector<T, A> {
    let mut out = SVector::<T, A>::zeros();
    let (head, rest) = out.as_mut_slice().split_at_mut(D);
    let (middle, tail) = rest.split_at_mut(D * P);
    head.copy_from_slice(x.as_slice());
    middle.copy_from_slice(s_p.as_slice());
    tail.copy_from_slice(s_x0.as_slice());
    out
}

/// The inverse of [`pack`].
#[allow(clippy::type_complexity)]
fn unpack<T: RealField + Copy, const D: usize, const P: usize, const A: usize>(
    augmented: &SVector<T, A>,
) -> (SVector<T, D>, SMatrix<T, D, P>, SMatrix<T, D, D>) {
    let a = augmented.as_slice();
    (
        SVector::from_fn(|i, _| a[i]),
        SMatrix::from_fn(|i, j| a[D + j * D + i]),
        SMatrix::from_fn(|i, j| a[D + D * P + j * D + i]),
    )
}

impl<T, S, const D: usize, const P: usize, const A: usize> OdeSystem<T, A>
    for Sensitivities<'_, S, D, P, A>
where
    T: RealField + Copy,
    S: ParameterJacobian<T, D, P> + ?Sized,
{
    #[inline]
    fn rhs(&self, t: T, x: &SVector<T, A>) -> SVector<T, A> {
        let (x, s_p, s_x0) = unpack(x);
        let (f, ds_p, ds_x0) = self.system.variational_rhs(t, &x, &s_p, &s_x0);
        pack(&f, &ds_p, &ds_x0)
    }

    #[inline]
    fn chart_regularity(&self, t: T, x: &SVector<T, A>) -> Option<T> {
        self.system.chart_regularity(t, &state(x))
    }

    /// The system's poles between the state parts of the two augmented
    /// states (the sensitivities do not enter them).
    #[inline]
    fn crossed_pole(
        &self,
        t0: T,
        x0: &SVector<T, A>,
        t1: T,
        x1: &SVector<T, A>,
    ) -> Option<&'static str> {
        self.system.crossed_pole(t0, &state(x0), t1, &state(x1))
    }

    #[inline]
    fn constraint_residual(&self, t: T, x: &SVector<T, A>) -> Option<T> {
        self.system.constraint_residual(t, &state(x))
    }

    /// Projects the state `x`; the sensitivities are left as they are.
    fn project(&self, t: T, x: &mut SVector<T, A>) -> Result<bool, ProjectionFailure<T>> {
        let mut s = state(x);
        let moved = self.system.project(t, &mut s)?;
        if moved {
            x.as_mut_slice()[..D].copy_from_slice(s.as_slice());
        }
        Ok(moved)
    }

    #[inline]
    fn is_autonomous(&self) -> bool {
        self.system.is_autonomous()
    }
}

/// The state part `x` of an augmented state.
fn state<T: RealField + Copy, const D: usize, const A: usize>(
    augmented: &SVector<T, A>,
) -> SVector<T, D> {
    SVector::from_fn(|i, _| augmented[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Matrix2x1, Vector2};

    /// x' = −a x on both components, a the parameter.
    struct Decay {
        a: f64,
    }

    impl OdeSystem<f64, 2> for Decay {
        fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
            -self.a * x
        }
    }

    impl OdeJacobian<f64, 2> for Decay {
        fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
            Matrix2::identity() * -self.a
        }
    }

    impl ParameterJacobian<f64, 2, 1> for Decay {
        fn parameter_jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2x1<f64> {
            -x
        }
    }

    #[test]
    fn the_layout_round_trips() {
        let sens = Sensitivities::<_, 2, 1, 8>::new(&Decay { a: 1.0 });
        let x = Vector2::new(1.0, 2.0);
        let s_p = Matrix2x1::new(3.0, 4.0);
        let s_x0 = Matrix2::new(5.0, 6.0, 7.0, 8.0);
        let packed: SVector<f64, 8> = pack(&x, &s_p, &s_x0);
        assert_eq!(packed.as_slice(), [1.0, 2.0, 3.0, 4.0, 5.0, 7.0, 6.0, 8.0]);
        assert_eq!(sens.split(&packed), (x, s_p, s_x0));
        let (x0, p0, i0) = sens.split(&sens.initial_state(&x));
        assert_eq!((x0, p0, i0), (x, Matrix2x1::zeros(), Matrix2::identity()));
    }

    #[test]
    fn the_augmented_rhs_is_the_variational_equations() {
        let sens = Sensitivities::<_, 2, 1, 8>::new(&Decay { a: 0.5 });
        let x = Vector2::new(1.0, 2.0);
        let s_p = Matrix2x1::new(3.0, 4.0);
        let s_x0 = Matrix2::new(5.0, 6.0, 7.0, 8.0);
        let (f, ds_p, ds_x0) = sens.split(&sens.rhs(0.0, &pack(&x, &s_p, &s_x0)));
        assert_eq!(f, -0.5 * x);
        assert_eq!(ds_p, -0.5 * s_p - x);
        assert_eq!(ds_x0, -0.5 * s_x0);
    }
}
