//! What an integration method supplies to the step driver: the [`Method`]
//! trait (the stages of one step, their error estimate and dense output),
//! the ways a trial step fails ([`Failure`]), the step-size controller's
//! parameters ([`Pi`]) and the evaluation helpers the methods share.

use nalgebra::{RealField, SVector};

use crate::numeric::all_finite;
use crate::step::Poly;
use crate::tolerance::Tolerance;
use crate::{SimError, Singularity, Stats};

/// Why a trial step could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Failure {
    /// A stage, the new state or a derivative is NaN or infinite.
    NonFinite,
    /// The iteration matrix of an implicit method is singular.
    Singular,
    /// The Newton iteration of an implicit method did not converge.
    #[cfg_attr(not(feature = "alloc"), allow(dead_code))]
    NoConvergence,
}

impl Failure {
    /// The error of a run that ends with this failure at `(t, x)`, step `h`.
    pub(crate) fn at<T, const D: usize>(self, t: T, x: SVector<T, D>, h: T) -> SimError<T, D> {
        match self {
            Failure::NonFinite => SimError::NonFinite { t, x },
            Failure::Singular => SimError::Singular {
                t,
                x,
                cause: Singularity::IterationMatrix,
            },
            Failure::NoConvergence => SimError::NoConvergence { t, x, h },
        }
    }
}

/// What an integration method supplies to the driver: the stages of one
/// step from an accepted point, their error estimate and dense output.
pub(crate) trait Method<T: RealField + Copy, const D: usize> {
    /// The order of the method, for the initial step heuristic.
    const ORDER: u32;
    /// Whether the method is symmetric (its step with −h inverts its step
    /// with h): the fixed-step loop then projects onto holonomic
    /// constraints symmetrically (`driver::Run::symmetric_end`).
    const SYMMETRIC: bool = false;
    /// `h·λ` above which Hairer's stiffness test counts a step as being at
    /// the stability boundary; `None` for methods without the test.
    const STIFF_LIMIT: Option<f64> = None;
    /// The smallest relative tolerance, in units of the machine epsilon,
    /// at which the method's error still follows the tolerance; a smaller
    /// one ends the run in [`SimError::ToleranceTooTight`] before the first
    /// step. `None`: smaller tolerances are raised to `10·eps`.
    const MIN_RTOL_EPS: Option<f64> = None;
    /// The step-size controller of the method's reference code (unused by
    /// the fixed-step methods, which keep this default).
    const PI: Pi = Pi {
        safe: 0.9,
        expo: 0.2,
        beta: 0.0,
        fac_lo: 0.1,
        fac_hi: 5.0,
        gustafsson: false,
    };

    /// The right-hand side `f(t, x)` (not counted: callers count).
    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D>;

    /// Prepares the first step from `(t0, x0)`: evaluates what it needs
    /// there (the derivative, a Jacobian) and counts it.
    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure>;

    /// The derivative at the current point, if the method keeps it (for
    /// the initial step heuristic).
    fn slope(&self) -> Option<&SVector<T, D>> {
        None
    }

    /// Computes the trial step `(t, x) → (t_new, x_new)` of signed size `h`
    /// (`t_new` is `t + h`, or exactly `t1` on the last step) and returns
    /// its scaled error norm (0 for methods without an estimate). Every
    /// stage must be finite, or the trial fails.
    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure>;

    /// Completes a trial that the controller accepts (for example the
    /// derivative at the new point, first same as last); a failure rejects
    /// it after all.
    fn complete(&mut self, _t_new: T, _stats: &mut Stats) -> Result<(), Failure> {
        Ok(())
    }

    /// The new state of the last trial.
    /// Replaces the end of the last attempted step by `x` (the symmetric
    /// projection's end, `driver::Run::symmetric_end`); only symmetric
    /// methods are asked, and the default ignores it.
    fn replace_end(&mut self, x: &SVector<T, D>) {
        let _ = x;
    }

    fn x_new(&self) -> &SVector<T, D>;

    /// Builds the dense output of the last completed trial, which started
    /// at `(t, x)` with step `h`; `false` if it is not finite (the driver
    /// then interpolates the step on its chord; the trial stands).
    fn build_dense(&mut self, t: T, x: &SVector<T, D>, h: T, stats: &mut Stats) -> bool;

    /// The dense output built by [`Method::build_dense`].
    fn dense(&self) -> &Poly<T, D>;

    /// `‖Δf‖ / ‖Δx‖` between the last two stages at the end of the step
    /// (Hairer's stiffness estimate without `|h|`), if defined.
    fn stiffness_ratio(&self) -> Option<T> {
        None
    }

    /// The step-size controller in use: [`Method::PI`], unless the method
    /// changes its nature within a run (stiffness switching).
    fn pi(&self) -> Pi {
        Self::PI
    }

    /// `Some(factor)` when the last [`Method::advance`] switched the method
    /// over (stiffness switching): the driver restarts its step-size
    /// controller with [`Method::pi`], and the next step is `factor` times
    /// the one just accepted.
    fn switched(&self) -> Option<f64> {
        None
    }

    /// The signed step proposed by a method that chooses its own steps (a
    /// multistep method, which also changes its order): read after a
    /// rejected trial and after [`Method::advance`]. `None` (the default):
    /// the driver's step-size controller chooses.
    fn proposed_step(&self) -> Option<T> {
        None
    }

    /// Moves to the accepted point `(t, x)` (the end of the completed
    /// trial); `last` when the integration ends there.
    fn advance(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure>;

    /// Moves to the accepted point `(t, x)` whose state the projection onto
    /// the holonomic constraints moved away from the trial's end
    /// [`Method::x_new`]; `last` when the integration ends there. The
    /// default restarts the method at the projected state
    /// ([`Method::start`]), which is all a one-step method needs (its next
    /// step starts from the derivative there); a multistep method may keep
    /// its history instead.
    fn advance_projected(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        if last {
            Ok(())
        } else {
            self.start(t, x, stats)
        }
    }
}

/// `f`, one evaluation of the right-hand side (counted), if it is finite.
pub(crate) fn counted<T: RealField + Copy, const D: usize>(
    f: SVector<T, D>,
    stats: &mut Stats,
) -> Result<SVector<T, D>, Failure> {
    stats.rhs_evals += 1;
    if all_finite(&f) {
        Ok(f)
    } else {
        Err(Failure::NonFinite)
    }
}

/// Hairer's stiffness estimate `‖f_new − f_prev‖ / ‖x_new − x_prev‖` from
/// the last two stages of a step (both evaluated at its end), if defined.
pub(crate) fn stiffness_estimate<T: RealField + Copy, const D: usize>(
    (f_new, f_prev): (&SVector<T, D>, &SVector<T, D>),
    (x_new, x_prev): (&SVector<T, D>, &SVector<T, D>),
) -> Option<T> {
    let stnum = (f_new - f_prev).norm_squared();
    let stden = (x_new - x_prev).norm_squared();
    (stden > T::zero()).then(|| (stnum / stden).sqrt())
}

/// Parameters of Hairer's step-size controller
/// `h_new = h / clamp(err^expo / errold^beta / safe, fac_lo, fac_hi)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pi {
    pub(crate) safe: f64,
    pub(crate) expo: f64,
    pub(crate) beta: f64,
    /// The smallest `h/h_new` (the largest growth is `1/fac_lo`).
    pub(crate) fac_lo: f64,
    /// The largest `h/h_new` (the largest reduction).
    pub(crate) fac_hi: f64,
    /// Gustafsson's predictive correction (`RODAS`).
    pub(crate) gustafsson: bool,
}
