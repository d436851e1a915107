//! The classical fourth-order Runge–Kutta method with a fixed step.

use nalgebra::{RealField, SVector};

use nalgebra::SimdBool;

use crate::lanes::{LaneOutcome, LaneSystem, Lanes, finite_lanes, select};
use crate::method::{Failure, Method};
use crate::numeric::{all_finite_in, c, machine_epsilon};
use crate::settings::{Settings, fixed_builders, integrator_impl};
use crate::step::Poly;
use crate::tolerance::Tolerance;
use crate::{OdeSystem, SimError, Stats};

/// Classical fourth-order Runge–Kutta with a fixed step `h`.
///
/// Step `k` ends at `t0 + k·h` (computed from `k`, so round-off does not
/// accumulate in `t`); the last step is shortened so that the integration
/// lands exactly on `t1` (a remainder below a few ulps of `t` is merged into
/// the previous step instead of becoming a tiny extra step).
///
/// * `h` is a magnitude: its sign follows the direction from `t0` to `t1`.
///   A non-positive or non-finite `h` makes `integrate` return
///   [`SimError::InvalidInput`](crate::SimError::InvalidInput).
/// * After each step the new state is checked; if any component is NaN or
///   infinite, [`SimError::NonFinite`](crate::SimError::NonFinite) is returned at once with the last good
///   `(t, x)`.
/// * If `h` is too small to advance `t` in floating point,
///   [`SimError::StepSizeTooSmall`](crate::SimError::StepSizeTooSmall) is returned.
/// * At most 1 000 000 steps by default ([`Rk4::with_max_steps`] raises
///   or lowers the budget); more return [`SimError::MaxSteps`](crate::SimError::MaxSteps).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Integrator, Rk4};
///
/// let decay = |_t: f64, x: &Vector1<f64>| -x;
/// let out = Rk4::new(0.01).integrate(&decay, 0.0, Vector1::new(1.0), 1.0).unwrap();
/// assert!((out.x[0] - (-1.0f64).exp()).abs() < 1e-10);
/// assert_eq!(out.stats.steps, 100);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4<T> {
    f: Settings<T>,
}

fixed_builders!(Rk4);
integrator_impl!(Rk4, f, |sys| Rk4Stages::new(sys));

/// Rk4 is a one-step method.
impl<E: RealField + Copy> Rk4<E> {
    /// Integrates one state per lane from `t0` to `t1` (DESIGN §6.8): the
    /// lanes share the steps of [`Integrator::integrate`](crate::Integrator::integrate)
    /// (step `k` ends at `t0 + k·h`, the last lands on `t1`) and the same
    /// stage arithmetic, so each lane follows the scalar run of its state
    /// with projection and chart switching off (`with_projection(false)`),
    /// to the rounding of the lane type's elementary functions.
    ///
    /// A lane whose state becomes NaN or infinite stops at its last good
    /// state (the others go on); the call ends early when every lane has.
    /// [`LaneOutcome::lane`] reads each lane's result as a scalar run's.
    /// The budget of [`Rk4::with_max_steps`] counts steps of all lanes at
    /// once. Allocates nothing.
    ///
    /// # Errors
    ///
    /// [`SimError::InvalidInput`] for a non-positive or non-finite `h`, or a
    /// non-finite `t0` or `t1`: then nothing was integrated.
    ///
    /// # Example
    ///
    /// Four decay rates in one call:
    ///
    /// ```rust
    /// use nalgebra::Vector1;
    /// use nh_runtime::{Rk4, WideF64x4};
    ///
    /// let k = WideF64x4::from([0.5, 1.0, 2.0, 4.0]);
    /// let decay = move |_t: WideF64x4, x: &Vector1<WideF64x4>| x * -k;
    /// let x0 = Vector1::new(WideF64x4::from([1.0; 4]));
    /// let out = Rk4::new(0.01).integrate_lanes(&decay, 0.0, x0, 1.0).unwrap();
    /// for (i, k) in [0.5f64, 1.0, 2.0, 4.0].into_iter().enumerate() {
    ///     let (t, x) = out.lane(i).unwrap();
    ///     assert_eq!(t, 1.0);
    ///     assert!((x[0] - (-k).exp()).abs() < 1e-8);
    /// }
    /// assert_eq!(out.stats.steps, 100);
    /// ```
    pub fn integrate_lanes<T, S, const D: usize>(
        &self,
        sys: &S,
        t0: E,
        x0: SVector<T, D>,
        t1: E,
    ) -> Result<LaneOutcome<T, D>, SimError<E, D>>
    where
        T: Lanes<Element = E>,
        S: LaneSystem<T, D> + ?Sized,
    {
        let h_abs = self.step_size();
        if !(h_abs > E::zero() && h_abs.is_finite()) {
            return Err(SimError::InvalidInput {
                what: "step size h (must be positive and finite)",
            });
        }
        if !(t0.is_finite() && t1.is_finite()) {
            return Err(SimError::InvalidInput {
                what: "t0 and t1 (must be finite)",
            });
        }
        let dir = if t1 >= t0 { E::one() } else { -E::one() };
        let h = h_abs * dir;
        let tol = (c::<E>(64.0) * machine_epsilon::<E>() * (t0.abs() + t1.abs() + h_abs))
            .min(h_abs * c(0.5));
        let splat = T::splat;
        let mut out = LaneOutcome {
            t: splat(t0),
            x: x0,
            non_finite: !finite_lanes(&x0),
            out_of_steps: false,
            stats: Stats::default(),
        };
        let (mut t, mut k) = (t0, 0usize);
        while (t1 - t) * dir > E::zero() && !out.non_finite.all() {
            if out.stats.steps >= self.f.max_steps {
                out.out_of_steps = true;
                break;
            }
            k += 1;
            let mut t_new = t0 + h * c::<E>(k as f64);
            if (t1 - t_new) * dir <= tol {
                t_new = t1;
            }
            let hk = t_new - t;
            if hk * dir <= E::zero() {
                return Err(SimError::InvalidInput {
                    what: "step size h (too small to advance t)",
                });
            }
            let rhs = |t, x: &SVector<T, D>| sys.lane_rhs(t, x);
            let (_, x_new) = stages(rhs, splat, t, &out.x, hk);
            out.stats.rhs_evals += 4;
            out.stats.steps += 1;
            out.non_finite = out.non_finite | !finite_lanes(&x_new);
            let going = !out.non_finite;
            out.x = select(going, &x_new, &out.x);
            out.t = splat(t_new).select(going, out.t);
            t = t_new;
        }
        Ok(out)
    }
}

/// One classical Runge–Kutta step of size `h` from (t, x): the four
/// stages and the new state. `lanes` puts a time or a weight into every
/// lane of `T` (the identity for a scalar `T`), so that
/// [`Rk4::integrate_lanes`] and the scalar method share one arithmetic.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn stages<E, T, const D: usize>(
    rhs: impl Fn(T, &SVector<T, D>) -> SVector<T, D>,
    lanes: impl Fn(E) -> T,
    t: E,
    x: &SVector<T, D>,
    h: E,
) -> ([SVector<T, D>; 4], SVector<T, D>)
where
    E: RealField + Copy,
    T: Lanes,
{
    let half = h * c::<E>(0.5);
    let k1 = rhs(lanes(t), x);
    let k2 = rhs(lanes(t + half), &(x + k1 * lanes(half)));
    let k3 = rhs(lanes(t + half), &(x + k2 * lanes(half)));
    let k4 = rhs(lanes(t + h), &(x + k3 * lanes(h)));
    let x_new = x + (k1 + (k2 + k3) * lanes(c::<E>(2.0)) + k4) * lanes(h / c::<E>(6.0));
    ([k1, k2, k3, k4], x_new)
}

impl<T> crate::settings::OneStep for Rk4<T> {
    const ONE_STEP: bool = true;
}

/// The four stages of one classical RK4 step.
struct Rk4Stages<'a, S: ?Sized, T, const D: usize> {
    sys: &'a S,
    k: [SVector<T, D>; 4],
    x_new: SVector<T, D>,
    dense: Poly<T, D>,
}

impl<'a, S: ?Sized, T: RealField + Copy, const D: usize> Rk4Stages<'a, S, T, D> {
    fn new(sys: &'a S) -> Self {
        Rk4Stages {
            sys,
            k: [SVector::zeros(); 4],
            x_new: SVector::zeros(),
            dense: Poly::from_monomial(&[]),
        }
    }
}

impl<T, S, const D: usize> Method<T, D> for Rk4Stages<'_, S, T, D>
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    const ORDER: u32 = 4;

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.sys.rhs(t, x)
    }

    fn start(&mut self, _t: T, _x: &SVector<T, D>, _stats: &mut Stats) -> Result<(), Failure> {
        Ok(())
    }

    #[inline(always)]
    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        _t_new: T,
        _tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        let sys = self.sys;
        (self.k, self.x_new) = stages(|t, x| sys.rhs(t, x), |v| v, t, x, h);
        stats.rhs_evals += 4;
        // Every stage enters `x_new` with a positive weight, so (in IEEE
        // arithmetic) `x_new` is finite only if all of them are.
        if all_finite_in(&[self.x_new]) {
            Ok(T::zero())
        } else {
            Err(Failure::NonFinite)
        }
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    /// The continuous extension `x + h Σ b_i(θ) k_i` with
    /// `b1 = θ − 3θ²/2 + 2θ³/3`, `b2 = b3 = θ² − 2θ³/3`, `b4 = −θ²/2 + 2θ³/3`.
    fn build_dense(&mut self, _t: T, x: &SVector<T, D>, h: T, _stats: &mut Stats) -> bool {
        let [k1, k2, k3, k4] = self.k;
        self.dense = Poly::from_monomial(&[
            *x,
            k1 * h,
            (k2 + k3 - k1 * c::<T>(1.5) - k4 * c::<T>(0.5)) * h,
            (k1 - k2 - k3 + k4) * (h * c::<T>(2.0 / 3.0)),
        ]);
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn advance(
        &mut self,
        _t: T,
        _x: &SVector<T, D>,
        _last: bool,
        _: &mut Stats,
    ) -> Result<(), Failure> {
        Ok(())
    }
}
