//! The stability suite: named cases that push the generated dynamics and the
//! integrators to their limits, each with an explicit expected outcome.
//!
//! A controller that embeds generated dynamics must be able to rely on this:
//! every run ends either in a correct answer or in a clear, typed
//! [`SimError`] — never a NaN passed off as a result, never a hang. Each case
//! family below returns [`Row`]s (case, expected outcome, method, outcome,
//! error against a reference, steps, seconds, notes, and whether the
//! expectation held); `tests/stability.rs` asserts every row, and
//! `cargo run --release -p nh-lab --example stability_report` prints the table and
//! writes `target/reports/stability.csv` ([`write_csv`]).
//!
//! | family | what it does | expected |
//! |---|---|---|
//! | [`stiff`] | [`StiffDisc`]: Q_ψ = −k(ψ − ψ₀) − cψ̇, k = 1e2 … 1e8, critical damping | `Rodas4` within 10·rtol, steps growing logarithmically in k; explicit methods accurate or `StepSizeTooSmall`/`MaxSteps` within their budget; `Dopri5` flags stiffness (k ≥ 1e6) |
//! | [`fast_spin`] | [`ThesisDisc`] and [`RollingDisc`], θ̇ = 1e2 … 1e5 rad/s, fixed number of revolutions | adaptive methods within 10·rtol of the reference; energy drift reported |
//! | [`scale_extremes`] | R, m from 1e-6 to 1e6, nondimensional time | the nondimensional answers agree with the unit case to 10·rtol |
//! | [`long_horizon`] | [`ThesisDisc`] over 1e4 s (the test: 50 s) | `GaussLegendre4`'s energy error bounded (no growth); the others' drift reported |
//! | [`near_singular`] | [`RollingDisc`] towards flat (ψ → π/2) | see below |
//! | [`bad_input`] | NaN/Inf states and parameters, reversed, empty and short spans, bad tolerances | the table below |
//! | [`single_precision`] | `f32` runs of both discs | agree with `f64` to 1e-4 |
//!
//! **Errors** are mixed relative: `max_i |x_i − ref_i| / max(|ref_i|, 1)`
//! over the whole state `[θ, φ, ψ, x, y, θ̇, φ̇, ψ̇]` (angles, rates and
//! positions in the case's natural units).
//!
//! **Near-singular motion.** The reduced equations of the physical disc
//! contain `φ̈ = 2 ψ̇ θ̇ / cos ψ`, singular when the disc lies flat. The
//! conservative rolling disc does *not* reach ψ = π/2 when θ̇ ≠ 0: the body
//! rates `w_u = φ̇ cos ψ`, `w_n = φ̇ sin ψ − θ̇` obey
//! `dw_n/dψ = −(2/3) w_u`, `dw_u/dψ = w_u tan ψ − 2 w_n`, so reaching flat
//! would need unbounded kinetic energy; the disc bounces back a distance
//! `≈ 0.016·θ̇` (in these cases) short of flat, with a precession spike
//! `φ̇ ≈ 3·10⁴·(0.02/θ̇)`. The suite therefore checks (a) the bounces for
//! θ̇ = 0.2, 0.02, 0.002 (adaptive methods must resolve the spike, fixed-step
//! methods must either finish or fail typed — they have no error control),
//! and (b) the pure fall (θ̇ = φ̇ = 0), which does reach flat at a finite
//! time t*: the model itself has no floor and continues through it, so the
//! system is wrapped in a *domain guard* ([`Guarded`]: NaN derivatives for
//! cos ψ ≤ 0), and every method must stop with a typed error whose time is
//! t* (adaptive methods: within 1e-6 s; fixed steps: within one step).
//!
//! **Bad input** (every integrator unless noted):
//!
//! | input | result |
//! |---|---|
//! | NaN or ±Inf in the initial state, NaN `t0`, infinite `t1` | `InvalidInput`, nothing evaluated |
//! | NaN or ±Inf parameter, or `R = 0` | `NonFinite` at `t0` carrying `x0` (the derivative at the start is not finite); a mass of 0 or NaN cancels from the disc's reduced equations at compile time, so those runs are as with any mass |
//! | `t1 < t0` | defined: integrates backwards in time (forward then back returns to `x0`) |
//! | `t1 == t0` | `Ok(x0)` exactly, zero steps |
//! | step (or initial/maximal step) larger than the span | `Ok`: one step, shortened to land on `t1` |
//! | `rtol ≤ 0` or NaN, `atol < 0`, step `h ≤ 0` | `InvalidInput` |
//! | `atol = 0` with a component that stays exactly zero (a disc at rest) | `Ok` (fixed in this suite's runtime change: the error norm took `0/0` as NaN and reported `NonFinite`) |
//! | `rtol` below machine precision (1e-20) | `Ok` accurate, `MaxSteps` within the step budget, or `ToleranceTooTight` at the start (the Rosenbrock methods) |
//!
//! [`ThesisDisc`]: crate::systems::ThesisDisc
//! [`RollingDisc`]: crate::systems::RollingDisc
//! [`StiffDisc`]: crate::systems::StiffDisc

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use nalgebra::{RealField, SMatrix, SVector};
use nh_runtime::{
    Dop853, Dopri5, GaussLegendre4, Integrator, OdeJacobian, OdeSystem, Outcome, Rk4, Rodas4,
    SimError, Stats,
};

use crate::systems::{RollingDisc, StiffDisc, ThesisDisc};

/// The disc state `[θ, φ, ψ, x, y, θ̇, φ̇, ψ̇]`.
pub type State<T> = SVector<T, 8>;

/// How much work the cases do: [`Effort::Test`] keeps `cargo test` (debug)
/// fast with shorter spans, [`Effort::Report`] runs the full spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effort {
    /// Short spans for the debug test profile.
    Test,
    /// Full spans (1e4 s long horizon, 100 revolutions) for the report.
    Report,
}

/// An integrator and its settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// [`Rk4`] with step `h`.
    Rk4 {
        /// Step size.
        h: f64,
    },
    /// [`Dopri5`] 5(4).
    Dopri5 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// [`Dop853`].
    Dop853 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// [`Rodas4`] (RODAS4) with the generated Jacobian.
    Rodas4 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// [`GaussLegendre4`] with step `h` and the generated Jacobian.
    Gauss {
        /// Step size.
        h: f64,
    },
}

impl Method {
    /// The five integrators: adaptive ones at `rtol` (atol = `rtol·1e-3`),
    /// fixed-step ones at `h`.
    pub fn all(rtol: f64, h: f64) -> [Method; 5] {
        let atol = rtol * 1e-3;
        [
            Method::Dopri5 { rtol, atol },
            Method::Dop853 { rtol, atol },
            Method::Rodas4 { rtol, atol },
            Method::Rk4 { h },
            Method::Gauss { h },
        ]
    }

    /// Whether the method controls its error (adaptive step).
    pub fn adaptive(&self) -> bool {
        !matches!(self, Method::Rk4 { .. } | Method::Gauss { .. })
    }

    /// The relative tolerance (adaptive) or the step (fixed-step).
    pub fn setting(&self) -> f64 {
        match *self {
            Method::Rk4 { h } | Method::Gauss { h } => h,
            Method::Dopri5 { rtol, .. }
            | Method::Dop853 { rtol, .. }
            | Method::Rodas4 { rtol, .. } => rtol,
        }
    }

    /// A short label, e.g. `Dopri5 1e-6` or `Rk4 h=1e-3`.
    pub fn label(&self) -> String {
        match *self {
            Method::Rk4 { h } => format!("Rk4 h={h:.0e}"),
            Method::Gauss { h } => format!("GaussLegendre4 h={h:.0e}"),
            Method::Dopri5 { rtol, .. } => format!("Dopri5 {rtol:.0e}"),
            Method::Dop853 { rtol, .. } => format!("Dop853 {rtol:.0e}"),
            Method::Rodas4 { rtol, .. } => format!("Rodas4 {rtol:.0e}"),
        }
    }
}

/// One integration: its result, its work counters (also after an error,
/// from `last_stats()`) and its wall time.
#[derive(Clone, Debug)]
pub struct Run<T, const D: usize> {
    /// What the integrator returned.
    pub result: Result<Outcome<T, D>, SimError<T, D>>,
    /// Work counters of the call, whether it succeeded or not.
    pub stats: Stats,
    /// Wall time of the call in seconds.
    pub seconds: f64,
}

/// Integrates `sys` from `(t0, x0)` to `t1` with `method` and a budget of
/// `max_steps` step attempts, calling `observer(t, x)` at `t0` and after
/// every accepted step. The implicit methods use the generated Jacobian.
pub fn integrate<T, S, const D: usize>(
    method: Method,
    sys: &S,
    t0: T,
    x0: SVector<T, D>,
    t1: T,
    max_steps: usize,
    mut observer: impl FnMut(T, &SVector<T, D>),
) -> Run<T, D>
where
    T: RealField + Copy,
    S: OdeJacobian<T, D>,
{
    let c = |v: f64| nalgebra::convert::<f64, T>(v);
    let start = Instant::now();
    let mut first = true;
    let mut on_step = |s: &nh_runtime::Step<'_, T, D>| {
        if first {
            first = false;
            observer(s.t_prev(), s.x_prev());
        }
        observer(s.t(), s.x());
    };
    let (result, stats) = match method {
        Method::Rk4 { h } => {
            let mut i = Rk4::new(c(h)).with_max_steps(max_steps);
            let r = i.integrate_with_steps(sys, t0, x0, t1, &mut on_step);
            (r, i.last_stats())
        }
        Method::Dopri5 { rtol, atol } => {
            let mut i = Dopri5::new(c(rtol), c(atol)).with_max_steps(max_steps);
            let r = i.integrate_with_steps(sys, t0, x0, t1, &mut on_step);
            (r, i.last_stats())
        }
        Method::Dop853 { rtol, atol } => {
            let mut i = Dop853::new(c(rtol), c(atol)).with_max_steps(max_steps);
            let r = i.integrate_with_steps(sys, t0, x0, t1, &mut on_step);
            (r, i.last_stats())
        }
        Method::Rodas4 { rtol, atol } => {
            let mut i = Rodas4::new(c(rtol), c(atol)).with_max_steps(max_steps);
            let r = i.integrate_with_jacobian_and_steps(sys, t0, x0, t1, &mut on_step);
            (r, i.last_stats())
        }
        Method::Gauss { h } => {
            let mut i = GaussLegendre4::new(c(h)).with_max_steps(max_steps);
            let r = i.integrate_with_jacobian_and_steps(sys, t0, x0, t1, &mut on_step);
            (r, i.last_stats())
        }
    };
    Run {
        result,
        stats,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// `Ok`.
    Ok,
    /// [`SimError::NonFinite`].
    NonFinite,
    /// [`SimError::StepSizeTooSmall`].
    StepSizeTooSmall,
    /// [`SimError::NoConvergence`] (the Newton iteration of an implicit
    /// method: its fixed step is too large).
    NoConvergence,
    /// [`SimError::MaxSteps`].
    MaxSteps,
    /// [`SimError::Singular`].
    Singular,
    /// [`SimError::ProjectionFailed`].
    ProjectionFailed,
    /// [`SimError::ToleranceTooTight`].
    ToleranceTooTight,
    /// [`SimError::InvalidInput`].
    InvalidInput,
}

impl Kind {
    /// The kind of a result.
    pub fn of<T, const D: usize>(r: &Result<Outcome<T, D>, SimError<T, D>>) -> Kind {
        match r {
            Ok(_) => Kind::Ok,
            Err(SimError::NonFinite { .. }) => Kind::NonFinite,
            Err(SimError::StepSizeTooSmall { .. }) => Kind::StepSizeTooSmall,
            Err(SimError::NoConvergence { .. }) => Kind::NoConvergence,
            Err(SimError::MaxSteps { .. }) => Kind::MaxSteps,
            Err(SimError::Singular { .. }) => Kind::Singular,
            Err(SimError::ProjectionFailed { .. }) => Kind::ProjectionFailed,
            Err(SimError::ToleranceTooTight { .. }) => Kind::ToleranceTooTight,
            Err(SimError::InvalidInput { .. }) => Kind::InvalidInput,
        }
    }

    /// The name, as in the table (`Ok`, `NonFinite`, ...).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Ok => "Ok",
            Kind::NonFinite => "NonFinite",
            Kind::StepSizeTooSmall => "StepSizeTooSmall",
            Kind::NoConvergence => "NoConvergence",
            Kind::MaxSteps => "MaxSteps",
            Kind::Singular => "Singular",
            Kind::ProjectionFailed => "ProjectionFailed",
            Kind::ToleranceTooTight => "ToleranceTooTight",
            Kind::InvalidInput => "InvalidInput",
        }
    }
}

/// Errors that end a run which could not be completed honestly.
const GAVE_UP: &[Kind] = &[Kind::StepSizeTooSmall, Kind::NoConvergence, Kind::MaxSteps];
/// Errors of a run stopped by non-finite values, a collapsing step or a
/// step too large for the Newton iteration.
const STOPPED: &[Kind] = &[Kind::NonFinite, Kind::StepSizeTooSmall, Kind::NoConvergence];
/// Any typed error.
const ANY_ERROR: &[Kind] = &[
    Kind::NonFinite,
    Kind::StepSizeTooSmall,
    Kind::NoConvergence,
    Kind::MaxSteps,
    Kind::Singular,
    Kind::ProjectionFailed,
];

/// The expected outcome of a row.
#[derive(Clone, Debug, PartialEq)]
pub enum Expect {
    /// `Ok` with a finite state and error ≤ the bound.
    Accurate(f64),
    /// `Ok` with error ≤ the bound, or one of the errors.
    AccurateOr(f64, &'static [Kind]),
    /// `Ok` with a finite state (no accuracy promised: fixed-step methods
    /// have no error control; the error is reported), or one of the errors.
    FiniteOr(&'static [Kind]),
    /// One of the errors.
    Fails(&'static [Kind]),
    /// One of the errors, at a time within `tol` of `at`.
    FailsAt(&'static [Kind], f64, f64),
    /// A measured figure (the `error` column) at most the bound.
    AtMost(f64),
}

fn kinds(k: &[Kind]) -> String {
    k.iter().map(Kind::name).collect::<Vec<_>>().join("/")
}

impl Expect {
    /// A short description for the table.
    pub fn describe(&self) -> String {
        match self {
            Expect::Accurate(b) => format!("Ok, err ≤ {b:.0e}"),
            Expect::AccurateOr(b, k) => format!("Ok err ≤ {b:.0e} or {}", kinds(k)),
            Expect::FiniteOr([]) => "finite Ok".into(),
            Expect::FiniteOr(k) => format!("finite Ok or {}", kinds(k)),
            Expect::Fails(k) => kinds(k),
            Expect::FailsAt(k, at, tol) => format!("{} at t = {at:.6} ± {tol:.0e}", kinds(k)),
            Expect::AtMost(b) => format!("≤ {b:.3}"),
        }
    }
}

/// One row of the stability table.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Case name (family/variant).
    pub case: String,
    /// Expected outcome.
    pub expected: String,
    /// Integrator and setting (or "all" when every integrator ran).
    pub method: String,
    /// Outcome: `Ok`, or the error kind with its time.
    pub outcome: String,
    /// Error against the reference (or the measured figure), when defined.
    pub error: Option<f64>,
    /// Accepted steps.
    pub steps: usize,
    /// Wall time in seconds.
    pub seconds: f64,
    /// Further measured facts (energy drift, stiffness flag, ...).
    pub notes: String,
    /// Whether the expectation held.
    pub pass: bool,
}

/// The measured facts a row is judged on.
#[derive(Clone, Debug, Default)]
pub struct Observed {
    /// How the run ended.
    pub kind: Option<Kind>,
    /// Time of the error (`SimError::time`).
    pub time: Option<f64>,
    /// Whether an `Ok` state is finite.
    pub finite: bool,
    /// Error against the reference (for `Ok`) or the measured figure.
    pub error: Option<f64>,
    /// Accepted steps.
    pub steps: usize,
    /// Seconds.
    pub seconds: f64,
}

impl Observed {
    /// The facts of a run, with `error` computed by the caller for `Ok`.
    pub fn of<T: RealField + Copy + Into<f64>, const D: usize>(
        run: &Run<T, D>,
        error: Option<f64>,
    ) -> Observed {
        Observed {
            kind: Some(Kind::of(&run.result)),
            time: run
                .result
                .as_ref()
                .err()
                .and_then(|e| e.time())
                .map(Into::into),
            finite: run
                .result
                .as_ref()
                .is_ok_and(|o| o.x.iter().all(|v| v.is_finite())),
            error,
            steps: run.stats.steps,
            seconds: run.seconds,
        }
    }
}

impl Row {
    /// Judges `obs` against `expect`; `extra` is a further condition that
    /// must hold (e.g. the stiffness flag), explained in `notes`.
    pub fn judge(
        case: impl Into<String>,
        method: impl Into<String>,
        expect: Expect,
        obs: &Observed,
        extra: bool,
        notes: impl Into<String>,
    ) -> Row {
        let ok = obs.kind == Some(Kind::Ok);
        let err_le = |b: f64| obs.error.is_some_and(|e| e <= b);
        let failed_with = |k: &[Kind]| obs.kind.is_some_and(|kind| k.contains(&kind));
        let pass = extra
            && match &expect {
                Expect::Accurate(b) => ok && obs.finite && err_le(*b),
                Expect::AccurateOr(b, k) => (ok && obs.finite && err_le(*b)) || failed_with(k),
                Expect::FiniteOr(k) => (ok && obs.finite) || failed_with(k),
                Expect::Fails(k) => failed_with(k),
                Expect::FailsAt(k, at, tol) => {
                    failed_with(k) && obs.time.is_some_and(|t| (t - at).abs() <= *tol)
                }
                Expect::AtMost(b) => err_le(*b),
            };
        let outcome = match (obs.kind, obs.time) {
            (Some(Kind::Ok), _) => "Ok".to_string(),
            (Some(k), Some(t)) => format!("{} at t = {t:.6}", k.name()),
            (Some(k), None) => k.name().to_string(),
            (None, _) => "measured".to_string(),
        };
        Row {
            case: case.into(),
            expected: expect.describe(),
            method: method.into(),
            outcome,
            error: obs.error,
            steps: obs.steps,
            seconds: obs.seconds,
            notes: notes.into(),
            pass,
        }
    }
}

/// Mixed relative error `max_i |x_i − r_i| / max(|r_i|, 1)` (∞ if not finite).
pub fn mixed_error<const D: usize>(x: &SVector<f64, D>, reference: &SVector<f64, D>) -> f64 {
    let e = (0..D)
        .map(|i| (x[i] - reference[i]).abs() / reference[i].abs().max(1.0))
        .fold(0.0, f64::max);
    if e.is_finite() { e } else { f64::INFINITY }
}

fn to_f64<T: RealField + Copy + Into<f64>, const D: usize>(x: &SVector<T, D>) -> SVector<f64, D> {
    x.map(Into::into)
}

/// The error of a successful run against `reference` (`None` on error).
fn run_error<T: RealField + Copy + Into<f64>, const D: usize>(
    run: &Run<T, D>,
    reference: &SVector<f64, D>,
) -> Option<f64> {
    run.result
        .as_ref()
        .ok()
        .map(|o| mixed_error(&to_f64(&o.x), reference))
}

/// A reference solution: Dop853 at rtol 1e-13 (atol 1e-15).
fn reference<S: OdeSystem<f64, D>, const D: usize>(
    sys: &S,
    x0: SVector<f64, D>,
    t1: f64,
) -> SVector<f64, D> {
    Dop853::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(sys, 0.0, x0, t1)
        .expect("reference run")
        .x
}

/// `[q, ṙ]` from the generalized coordinates and independent velocities.
pub fn state(q: [f64; 5], rdot: [f64; 3]) -> State<f64> {
    State::from_fn(|i, _| if i < 5 { q[i] } else { rdot[i - 5] })
}

/// The energy of a disc state through a system's `energy(q, ṙ)`.
fn energy_of<T: RealField + Copy>(
    e: impl Fn(&SVector<T, 5>, &SVector<T, 3>) -> T,
) -> impl Fn(&State<T>) -> T {
    move |x| {
        e(
            &x.fixed_rows::<5>(0).into_owned(),
            &x.fixed_rows::<3>(5).into_owned(),
        )
    }
}

/// The discs' parameters in the cases (kg, m, m/s²).
const M: f64 = 1.7;
const R: f64 = 0.35;
const G: f64 = 9.81;

// ------------------------------------------------------------------ stiff

/// The stiff spring-damper on ψ: [`StiffDisc`] with k = 1e2 … 1e8 and
/// critical damping c = 2·sqrt(k·I), I = 5/4·mR² the lean inertia, ψ₀ = 0.2,
/// from ψ = 0.3 (an initial deflection), over 2 s; reference Dop853 at 1e-13.
///
/// Rodas4 (rtol 1e-6): error ≤ 10·rtol, and its steps grow at most
/// logarithmically: `steps(k) ≤ steps(1e2)·(1 + log10(k/1e2))` (the row
/// "stiff steps vs k" reports the largest ratio of the two sides over
/// k > 1e2; steps and seconds there are the sums over the four runs).
/// Dopri5 and Dop853 (budget 50 000 attempts): accurate or
/// `StepSizeTooSmall`/`MaxSteps`; Dopri5 must set
/// `stiffness_detected` for k ≥ 1e6 (read with `last_stats()`, valid after
/// an error too). Rk4 with h = 1e-3 (no error control): finite or
/// `NonFinite` (unstable for k = 1e8, where h·sqrt(k/I) ≈ 20).
///
/// [`StiffDisc`]: crate::systems::StiffDisc
pub fn stiff(_effort: Effort) -> Vec<Row> {
    let ks = [1e2, 1e4, 1e6, 1e8];
    let rtol = 1e-6;
    let (atol, t1, budget) = (1e-9, 2.0, 50_000);
    let inertia = 1.25 * M * R * R;
    let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let mut rows = Vec::new();
    let mut ros_steps = Vec::new();
    let mut ros_seconds = 0.0;
    for &k in &ks {
        let sys: StiffDisc = StiffDisc::new(M, R, G, k, 2.0 * (k * inertia).sqrt(), 0.2);
        let reference = reference(&sys, x0, t1);
        let case = format!("stiff k={k:.0e}");
        let omega = (k / inertia).sqrt();
        let methods = [
            Method::Rodas4 { rtol, atol },
            Method::Dopri5 { rtol, atol },
            Method::Dop853 { rtol, atol },
            Method::Rk4 { h: 1e-3 },
        ];
        for method in methods {
            let run = integrate(method, &sys, 0.0, x0, t1, budget, |_, _| {});
            let obs = Observed::of(&run, run_error(&run, &reference));
            let flagged = run.stats.stiffness_detected;
            let (expect, extra, notes) = match method {
                Method::Rodas4 { .. } => {
                    ros_steps.push(run.stats.steps);
                    ros_seconds += run.seconds;
                    (Expect::Accurate(10.0 * rtol), true, String::new())
                }
                Method::Dopri5 { .. } => (
                    Expect::AccurateOr(10.0 * rtol, GAVE_UP),
                    k < 1e6 || flagged,
                    format!(
                        "stiffness_detected = {flagged}{}",
                        if k >= 1e6 { " (required)" } else { "" }
                    ),
                ),
                Method::Dop853 { .. } => (
                    Expect::AccurateOr(10.0 * rtol, GAVE_UP),
                    true,
                    format!("stiffness_detected = {flagged}"),
                ),
                _ => (
                    if k >= 1e8 {
                        Expect::Fails(&[Kind::NonFinite])
                    } else {
                        Expect::FiniteOr(&[Kind::NonFinite])
                    },
                    true,
                    format!("h·ω = {:.2} (RK4 stable for ≲ 2.8)", 1e-3 * omega),
                ),
            };
            rows.push(Row::judge(
                &case,
                method.label(),
                expect,
                &obs,
                extra,
                notes,
            ));
        }
    }
    // Logarithmic growth of Rodas4's steps.
    let ratio = ks
        .iter()
        .zip(&ros_steps)
        .skip(1)
        .map(|(&k, &n)| n as f64 / (ros_steps[0] as f64 * (1.0 + (k / ks[0]).log10())))
        .fold(0.0, f64::max);
    let obs = Observed {
        error: Some(ratio),
        steps: ros_steps.iter().sum(),
        seconds: ros_seconds,
        ..Observed::default()
    };
    rows.push(Row::judge(
        "stiff steps vs k",
        "Rodas4 1e-6",
        Expect::AtMost(1.0),
        &obs,
        true,
        format!(
            "steps {ros_steps:?} for k = 1e2…1e8; error column = max over k > 1e2 of steps(k)/(steps(1e2)(1+log10(k/1e2)))"
        ),
    ));
    rows
}

// -------------------------------------------------------------- fast spin

/// Fast spin: both discs from ψ = 0.3 with rates (θ̇, φ̇, ψ̇) = Ω·(1, 0.5,
/// 0.05), Ω = 1e2 … 1e5 rad/s, over a fixed number of revolutions of θ
/// (10 in the test, 100 in the report); reference Dop853 at 1e-13.
///
/// The tolerances are local (per step), so the global error after many
/// revolutions is a multiple of rtol (≈ 1e4·rtol for Dopri5 over 100
/// revolutions). "No silent loss of accuracy" is checked as: for each disc
/// and adaptive method (rtol 1e-7), the error at Ω is at most 10× the error
/// at Ω = 1e2 (plus 10·rtol), and the error falls at least tenfold when
/// rtol is divided by 100 (the notes give both). The relative energy drift
/// |E(t1) − E0|/|E0| is reported. Rk4 with 200 steps per revolution is
/// reported (finite, no error control).
pub fn fast_spin(effort: Effort) -> Vec<Row> {
    let revolutions = match effort {
        Effort::Test => 10.0,
        Effort::Report => 100.0,
    };
    let rtol = 1e-7;
    let omegas = [1e2, 1e3, 1e4, 1e5];
    let mut rows = Vec::new();
    let thesis: ThesisDisc = ThesisDisc::new(M, R, G);
    let rolling: RollingDisc = RollingDisc::new(M, R, G);
    let e_thesis = energy_of(|q, r| thesis.energy(q, r));
    let e_rolling = energy_of(|q, r| rolling.energy(q, r));
    let adaptive = |rtol: f64| {
        let atol = rtol * 1e-3;
        [
            Method::Dopri5 { rtol, atol },
            Method::Dop853 { rtol, atol },
            Method::Rodas4 { rtol, atol },
        ]
    };
    for name in ["thesis", "rolling"] {
        let energy: &dyn Fn(&State<f64>) -> f64 = if name == "thesis" {
            &e_thesis
        } else {
            &e_rolling
        };
        // Error at Ω = 1e2 per adaptive method, the baseline.
        let mut baseline = [0.0f64; 3];
        for (oi, &omega) in omegas.iter().enumerate() {
            let x0 = state(
                [0.0, 0.0, 0.3, 0.0, 0.0],
                [omega, 0.5 * omega, 0.05 * omega],
            );
            let period = 2.0 * core::f64::consts::PI / omega;
            let t1 = revolutions * period;
            let go = |method: Method| {
                if name == "thesis" {
                    integrate(method, &thesis, 0.0, x0, t1, 10_000_000, |_, _| {})
                } else {
                    integrate(method, &rolling, 0.0, x0, t1, 10_000_000, |_, _| {})
                }
            };
            let reference = if name == "thesis" {
                reference(&thesis, x0, t1)
            } else {
                reference(&rolling, x0, t1)
            };
            let case = format!("fast spin {name} Ω={omega:.0e}");
            let drift = |run: &Run<f64, 8>| {
                run.result
                    .as_ref()
                    .map(|o| ((energy(&o.x) - energy(&x0)) / energy(&x0)).abs())
                    .unwrap_or(f64::NAN)
            };
            for (mi, (method, fine)) in adaptive(rtol)
                .into_iter()
                .zip(adaptive(rtol / 100.0))
                .enumerate()
            {
                let run = go(method);
                let fine_run = go(fine);
                let err = run_error(&run, &reference);
                let fine_err = run_error(&fine_run, &reference).unwrap_or(f64::INFINITY);
                if oi == 0 {
                    baseline[mi] = err.unwrap_or(f64::INFINITY);
                }
                let obs = Observed::of(&run, err);
                let converges = err.is_some_and(|e| fine_err <= e / 10.0);
                rows.push(Row::judge(
                    &case,
                    method.label(),
                    Expect::Accurate(10.0 * baseline[mi] + 10.0 * rtol),
                    &obs,
                    converges,
                    format!(
                        "{revolutions} revs; err at rtol/100 {fine_err:.1e} (≤ err/10 required); energy drift {:.1e}",
                        drift(&run)
                    ),
                ));
            }
            let method = Method::Rk4 { h: period / 200.0 };
            let run = go(method);
            let obs = Observed::of(&run, run_error(&run, &reference));
            rows.push(Row::judge(
                &case,
                "Rk4 h=T/200",
                Expect::FiniteOr(&[]),
                &obs,
                true,
                format!("{revolutions} revs; energy drift {:.1e}", drift(&run)),
            ));
        }
    }
    rows
}

// ---------------------------------------------------------- scale extremes

/// Scale extremes: [`ThesisDisc`] with R and m from 1e-6 to 1e6. With the
/// length scale R and the time scale T = sqrt(R/g), the angles as functions
/// of t/T, x/R, y/R and the rates times T do not depend on R and m; the
/// nondimensional state at τ = 10 must agree with the unit case (R = m = 1)
/// to 10·rtol (rtol 1e-8, pure relative control: atol = 0) for the adaptive
/// methods and fixed-step methods with the step scaled by T.
///
/// [`ThesisDisc`]: crate::systems::ThesisDisc
pub fn scale_extremes(_effort: Effort) -> Vec<Row> {
    let rtol = 1e-8;
    let tau1 = 10.0;
    let scales = [
        (1e-6, 1.0),
        (1e6, 1.0),
        (1.0, 1e-6),
        (1.0, 1e6),
        (1e-6, 1e6),
        (1e6, 1e-6),
    ];
    let methods = [
        Method::Dopri5 { rtol, atol: 0.0 },
        Method::Rodas4 { rtol, atol: 0.0 },
        Method::Gauss { h: 0.01 },
    ];
    // Nondimensional rates (θ̇, φ̇, ψ̇)·T.
    let rates = [2.0, 6.0, 0.2];
    let run_at = |method: Method, r: f64, m: f64| {
        let sys: ThesisDisc = ThesisDisc::new(m, r, G);
        let t = (r / G).sqrt();
        let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], rates.map(|w| w / t));
        let method = match method {
            Method::Gauss { h } => Method::Gauss { h: h * t },
            other => other,
        };
        let run = integrate(method, &sys, 0.0, x0, tau1 * t, 1_000_000, |_, _| {});
        let nondim = run.result.as_ref().ok().map(|o| {
            let mut x = o.x;
            x[3] /= r;
            x[4] /= r;
            for i in 5..8 {
                x[i] *= t;
            }
            x
        });
        (run, nondim)
    };
    let mut rows = Vec::new();
    for method in methods {
        let (_, unit) = run_at(method, 1.0, 1.0);
        let unit = unit.expect("the unit case integrates");
        for &(r, m) in &scales {
            let (run, nondim) = run_at(method, r, m);
            let obs = Observed::of(&run, nondim.map(|x| mixed_error(&x, &unit)));
            rows.push(Row::judge(
                format!("scale R={r:.0e} m={m:.0e}"),
                method.label().replace("h=1e-2", "h=T/100"),
                Expect::Accurate(10.0 * rtol),
                &obs,
                true,
                "error = nondimensional state vs unit case",
            ));
        }
    }
    rows
}

// ------------------------------------------------------------ long horizon

/// Long horizon: [`ThesisDisc`] from ψ = 0.3, (θ̇, φ̇, ψ̇) = (6, 20, 0.5)
/// over 1e4 s (50 s in the test). The error column is the largest relative
/// energy error max_t |E(t) − E0|/|E0|; the notes give its growth, the
/// ratio of the largest error in the last tenth of the run to that in the
/// first tenth (≈ 1 for bounded, ≈ 10 or more for linear drift).
/// GaussLegendre4 (h = 0.01; symmetric, and the reduced disc is
/// reversible) must keep the energy error bounded: ≤ 1e-6 and growth ≤ 3.
/// The others must finish with a finite state; their drift is reported.
///
/// [`ThesisDisc`]: crate::systems::ThesisDisc
pub fn long_horizon(effort: Effort) -> Vec<Row> {
    let t1 = match effort {
        Effort::Test => 50.0,
        Effort::Report => 1e4,
    };
    let sys: ThesisDisc = ThesisDisc::new(M, R, G);
    let energy = energy_of(|q, r| sys.energy(q, r));
    let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let e0 = energy(&x0);
    let mut rows = Vec::new();
    for method in Method::all(1e-8, 0.01) {
        let (mut first, mut last, mut worst) = (0.0f64, 0.0f64, 0.0f64);
        let run = integrate(method, &sys, 0.0, x0, t1, 100_000_000, |t, x| {
            let e = ((energy(x) - e0) / e0).abs();
            worst = worst.max(e);
            if t <= 0.1 * t1 {
                first = first.max(e);
            }
            if t >= 0.9 * t1 {
                last = last.max(e);
            }
        });
        let growth = last / first;
        let mut obs = Observed::of(&run, Some(worst));
        if obs.kind != Some(Kind::Ok) {
            obs.error = None;
        }
        let gauss = matches!(method, Method::Gauss { .. });
        let (expect, extra) = if gauss {
            (Expect::Accurate(1e-6), growth <= 3.0)
        } else {
            (Expect::FiniteOr(&[]), true)
        };
        rows.push(Row::judge(
            format!("long horizon {t1:.0e} s"),
            method.label(),
            expect,
            &obs,
            extra,
            format!(
                "error = max energy error; growth last/first tenth {growth:.2}{}",
                if gauss { " (≤ 3 required)" } else { "" }
            ),
        ));
    }
    rows
}

// ----------------------------------------------------------- near-singular

/// A system with a domain: outside it (`inside(x)` false) the derivative is
/// NaN, which the integrators answer with rejected steps and, at the
/// boundary, a typed [`SimError::NonFinite`] or
/// [`SimError::StepSizeTooSmall`] carrying the last state inside.
pub struct Guarded<'a, S, F> {
    /// The wrapped system.
    pub sys: &'a S,
    /// The domain test.
    pub inside: F,
}

impl<S, F, const D: usize> OdeSystem<f64, D> for Guarded<'_, S, F>
where
    S: OdeSystem<f64, D>,
    F: Fn(&SVector<f64, D>) -> bool,
{
    fn rhs(&self, t: f64, x: &SVector<f64, D>) -> SVector<f64, D> {
        if (self.inside)(x) {
            self.sys.rhs(t, x)
        } else {
            SVector::from_element(f64::NAN)
        }
    }
}

impl<S, F, const D: usize> OdeJacobian<f64, D> for Guarded<'_, S, F>
where
    S: OdeJacobian<f64, D>,
    F: Fn(&SVector<f64, D>) -> bool,
{
    fn jacobian(&self, t: f64, x: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        if (self.inside)(x) {
            self.sys.jacobian(t, x)
        } else {
            SMatrix::from_element(f64::NAN)
        }
    }
}

/// The time at which ψ reaches π/2 in a Dop853 run at rtol 1e-13, located
/// on its 7th-order dense output by bisection.
fn flat_time(sys: &RollingDisc, x0: State<f64>, t1: f64) -> f64 {
    let half_pi = core::f64::consts::FRAC_PI_2;
    let mut found = None;
    let _ = Dop853::new(1e-13, 1e-15).integrate_with_steps(sys, 0.0, x0, t1, |s| {
        if found.is_none() && s.x_prev()[2] < half_pi && s.x()[2] >= half_pi {
            let (mut a, mut b) = (s.t_prev(), s.t());
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if s.interpolate(mid)[2] < half_pi {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            found = Some(0.5 * (a + b));
        }
    });
    found.expect("the falling disc reaches flat")
}

/// Near-singular motion of the physical [`RollingDisc`] (see the module
/// docs): (a) bounces near flat from ψ = 1.2 with θ̇ = 0.2, 0.02, 0.002
/// (φ̇ = θ̇/2) over 0.4 s — adaptive methods (rtol 1e-8) within 100·rtol of
/// the reference (the precession spike reaches 3e5 rad/s), fixed-step
/// methods finite or a typed error; (b) the pure fall from ψ = 1.2 at rest
/// with the domain guard cos ψ > 0: every method stops with `NonFinite` or
/// `StepSizeTooSmall` at the time ψ reaches π/2 (adaptive: ± 1e-6 s;
/// fixed: within one step before it); (c) the same fall without the guard
/// is a defined result: the model has no floor, the disc goes through it.
///
/// [`RollingDisc`]: crate::systems::RollingDisc
pub fn near_singular(_effort: Effort) -> Vec<Row> {
    let sys: RollingDisc = RollingDisc::new(M, R, G);
    let half_pi = core::f64::consts::FRAC_PI_2;
    let mut rows = Vec::new();
    let rtol = 1e-8;
    for &td in &[0.2, 0.02, 0.002] {
        let x0 = state([0.0, 0.0, 1.2, 0.0, 0.0], [td, 0.5 * td, 0.0]);
        let t1 = 0.4;
        let reference = reference(&sys, x0, t1);
        for method in Method::all(rtol, 1e-3) {
            let (mut psi_max, mut spike) = (0.0f64, 0.0f64);
            let run = integrate(method, &sys, 0.0, x0, t1, 1_000_000, |_, x| {
                psi_max = psi_max.max(x[2]);
                spike = spike.max(x[6].abs());
            });
            let obs = Observed::of(&run, run_error(&run, &reference));
            let expect = if method.adaptive() {
                Expect::Accurate(100.0 * rtol)
            } else {
                Expect::FiniteOr(ANY_ERROR)
            };
            rows.push(Row::judge(
                format!("near-flat bounce θ̇={td}"),
                method.label(),
                expect,
                &obs,
                true,
                format!(
                    "π/2 − max ψ = {:.1e}, max |φ̇| = {spike:.1e}",
                    half_pi - psi_max
                ),
            ));
        }
    }
    // (b) the pure fall, guarded.
    let x0 = state([0.0, 0.0, 1.2, 0.0, 0.0], [0.0, 0.0, 0.0]);
    let t1 = 1.0;
    let t_flat = flat_time(&sys, x0, t1);
    let guarded = Guarded {
        sys: &sys,
        inside: |x: &State<f64>| x[2].cos() > 0.0,
    };
    for method in Method::all(rtol, 1e-3) {
        let run = integrate(method, &guarded, 0.0, x0, t1, 1_000_000, |_, _| {});
        let obs = Observed::of(&run, None);
        let expect = if method.adaptive() {
            Expect::FailsAt(STOPPED, t_flat, 1e-6)
        } else {
            let h = method.setting();
            Expect::FailsAt(STOPPED, t_flat - 0.5 * h, 0.5 * h)
        };
        let psi = run
            .result
            .as_ref()
            .err()
            .and_then(|e| e.state())
            .map(|x| x[2]);
        rows.push(Row::judge(
            "fall to flat, guarded",
            method.label(),
            expect,
            &obs,
            true,
            format!(
                "t* = {t_flat:.9} (reference); last good π/2 − ψ = {:.1e}",
                psi.map_or(f64::NAN, |p| half_pi - p)
            ),
        ));
    }
    // (c) the fall without a guard.
    let method = Method::Dopri5 {
        rtol,
        atol: rtol * 1e-3,
    };
    let run = integrate(method, &sys, 0.0, x0, t1, 1_000_000, |_, _| {});
    let psi1 = run.result.as_ref().map_or(f64::NAN, |o| o.x[2]);
    let obs = Observed::of(&run, None);
    rows.push(Row::judge(
        "fall to flat, no guard",
        method.label(),
        Expect::FiniteOr(&[]),
        &obs,
        true,
        format!("defined: ψ(1 s) = {psi1:.3} > π/2 (no floor in the model)"),
    ));
    rows
}

// --------------------------------------------------------------- bad input

/// An integration's span: start time, start state and end time.
type Span = (f64, State<f64>, f64);

/// Runs every method on one input and summarises: the row passes when every
/// method's outcome satisfies `ok`.
fn all_methods<S: OdeJacobian<f64, 8>>(
    budget: usize,
    case: &str,
    expected: &str,
    sys: &S,
    (t0, x0, t1): Span,
    methods: &[Method],
    ok: impl Fn(&Method, &Run<f64, 8>) -> bool,
) -> Row {
    let mut pass = true;
    let mut outcomes = Vec::new();
    let (mut steps, mut seconds) = (0, 0.0);
    for &method in methods {
        let run = integrate(method, sys, t0, x0, t1, budget, |_, _| {});
        pass &= ok(&method, &run);
        let k = Kind::of(&run.result).name();
        if !outcomes.contains(&k) {
            outcomes.push(k);
        }
        steps += run.stats.steps;
        seconds += run.seconds;
    }
    Row {
        case: case.into(),
        expected: expected.into(),
        method: if methods.len() == 5 {
            "all 5".into()
        } else {
            methods
                .iter()
                .map(|m| m.label())
                .collect::<Vec<_>>()
                .join(", ")
        },
        outcome: outcomes.join("/"),
        error: None,
        steps,
        seconds,
        notes: String::new(),
        pass,
    }
}

/// Bad input (see the table in the module docs). Every row runs all five
/// methods (or the ones the input applies to) and passes only if each of
/// them gives the documented result. The step budget is 1e4 attempts in
/// the test, 1e5 in the report.
pub fn bad_input(effort: Effort) -> Vec<Row> {
    let c = BadInput {
        budget: match effort {
            Effort::Test => 10_000,
            Effort::Report => 100_000,
        },
        disc: ThesisDisc::new(M, R, G),
        x0: state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]),
        all: Method::all(1e-8, 1e-3),
    };
    let mut rows = bad_states_and_times(&c);
    rows.extend(bad_parameters(&c));
    rows.extend(odd_spans_and_steps(&c));
    rows.extend(bad_tolerances(&c));
    rows
}

/// What every [`bad_input`] case shares: the step budget, the disc, its
/// start and the five methods.
struct BadInput {
    budget: usize,
    disc: ThesisDisc,
    x0: State<f64>,
    all: [Method; 5],
}

/// The check that a run ended in an error of kind `k`.
fn is(k: Kind) -> impl Fn(&Method, &Run<f64, 8>) -> bool {
    move |_, r| Kind::of(&r.result) == k
}

/// The same Dopri5, Dop853 and Rodas4 settings at `rtol`, `atol`.
fn with_tol(rtol: f64, atol: f64) -> [Method; 3] {
    [
        Method::Dopri5 { rtol, atol },
        Method::Dop853 { rtol, atol },
        Method::Rodas4 { rtol, atol },
    ]
}

/// NaN or infinite initial states, a NaN start time, an infinite end time.
fn bad_states_and_times(c: &BadInput) -> Vec<Row> {
    let x0 = c.x0;
    let mut spans: Vec<(String, Span)> = Vec::new();
    for (name, v) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        let mut x = x0;
        x[6] = v;
        spans.push((format!("bad input: {name} in x0"), (0.0, x, 1.0)));
    }
    spans.push(("bad input: t0 = NaN".into(), (f64::NAN, x0, 1.0)));
    spans.push(("bad input: t1 = +Inf".into(), (0.0, x0, f64::INFINITY)));
    spans
        .into_iter()
        .map(|(case, span)| {
            let invalid = is(Kind::InvalidInput);
            all_methods(
                c.budget,
                &case,
                "InvalidInput",
                &c.disc,
                span,
                &c.all,
                invalid,
            )
        })
        .collect()
}

/// Non-finite or zero parameters: `NonFinite` at the start, except for the
/// mass, which cancels from the reduced equations.
fn bad_parameters(c: &BadInput) -> Vec<Row> {
    let (disc, x0) = (c.disc, c.x0);
    let nonfinite_at_start = |x0: State<f64>| move |_: &Method, r: &Run<f64, 8>| matches!(r.result, Err(SimError::NonFinite { t, x }) if t == 0.0 && x == x0);
    let mut rows = Vec::new();
    for (name, (m, r, g)) in [
        ("g = +Inf", (M, R, f64::INFINITY)),
        ("R = -Inf", (M, f64::NEG_INFINITY, G)),
        ("R = NaN", (M, f64::NAN, G)),
        ("R = 0", (M, 0.0, G)),
    ] {
        let bad: ThesisDisc = ThesisDisc::new(m, r, g);
        rows.push(all_methods(
            c.budget,
            &format!("bad parameter: {name}"),
            "NonFinite at t0 with x0",
            &bad,
            (0.0, c.x0, 1.0),
            &c.all,
            nonfinite_at_start(x0),
        ));
    }
    // The mass cancels from the disc's reduced equations at compile time,
    // and so from the generated Jacobian (derived from the closed-form r̈):
    // every method runs as with the real mass.
    for (name, m) in [("m = NaN", f64::NAN), ("m = 0", 0.0)] {
        let bad: ThesisDisc = ThesisDisc::new(m, R, G);
        let mut row = all_methods(
            c.budget,
            &format!("bad parameter: {name}"),
            "Ok as with m = 1.7 (m cancels from r̈ and its Jacobian at compile time)",
            &bad,
            (0.0, c.x0, 1.0),
            &c.all,
            |method, r| {
                let good = integrate(*method, &disc, 0.0, x0, 1.0, 100_000, |_, _| {});
                matches!((&r.result, &good.result), (Ok(a), Ok(b)) if a.x == b.x)
            },
        );
        row.notes = "the mass is a common factor of the reduced equations".into();
        rows.push(row);
    }
    rows
}

/// Backwards and empty spans, and steps larger than the span.
fn odd_spans_and_steps(c: &BadInput) -> Vec<Row> {
    let (disc, x0) = (c.disc, c.x0);
    let mut rows = Vec::new();
    // Backwards: forward to 1, back to 0 returns x0.
    let fwd = |m: Method| {
        integrate(m, &disc, 0.0, x0, 1.0, 100_000, |_, _| {})
            .result
            .map(|o| o.x)
    };
    rows.push(all_methods(
        c.budget,
        "t1 < t0: backwards",
        "Ok, back to x0 (err ≤ 1e-5)",
        &disc,
        (0.0, c.x0, 1.0),
        &c.all,
        |&m, _| {
            let Ok(x1) = fwd(m) else { return false };
            let back = integrate(m, &disc, 1.0, x1, 0.0, 100_000, |_, _| {});
            back.result
                .is_ok_and(|o| o.t == 0.0 && mixed_error(&o.x, &x0) <= 1e-5)
        },
    ));
    rows.push(all_methods(
        c.budget,
        "t1 == t0: empty span",
        "Ok(x0) exactly, 0 steps",
        &disc,
        (0.5, c.x0, 0.5),
        &c.all,
        |_, r| {
            r.result
                .as_ref()
                .is_ok_and(|o| o.x == x0 && o.t == 0.5 && o.stats == Stats::default())
        },
    ));
    // A step larger than the span.
    let big = [
        Method::Rk4 { h: 10.0 },
        Method::Gauss { h: 10.0 },
        Method::Dopri5 {
            rtol: 1e-8,
            atol: 1e-11,
        },
    ];
    let short = reference(&disc, x0, 1e-3);
    rows.push(all_methods(
        c.budget,
        "step > span (h = 10, span 1e-3)",
        "Ok at t1, err ≤ 1e-8 (fixed steps: 1 step)",
        &disc,
        (0.0, c.x0, 1e-3),
        &big,
        |m, r| {
            r.result.as_ref().is_ok_and(|o| {
                o.t == 1e-3
                    && (m.adaptive() || o.stats.steps == 1)
                    && mixed_error(&o.x, &short) <= 1e-8
            })
        },
    ));
    {
        // Dopri5 with an initial and a maximal step beyond the span.
        let start = Instant::now();
        let r = Dopri5::new(1e-8, 1e-11)
            .with_initial_step(10.0)
            .with_max_step(100.0)
            .integrate(&disc, 0.0, x0, 1e-3);
        let obs = Observed {
            kind: Some(Kind::of(&r)),
            finite: true,
            error: r.as_ref().ok().map(|o| mixed_error(&o.x, &short)),
            steps: r.as_ref().map_or(0, |o| o.stats.steps),
            seconds: start.elapsed().as_secs_f64(),
            time: None,
        };
        rows.push(Row::judge(
            "initial/max step > span",
            "Dopri5 1e-8",
            Expect::Accurate(1e-8),
            &obs,
            true,
            "with_initial_step(10), with_max_step(100)",
        ));
    }
    rows
}

/// Invalid tolerances and steps, `atol = 0` on a state that stays zero, and
/// a relative tolerance below machine precision.
fn bad_tolerances(c: &BadInput) -> Vec<Row> {
    let (disc, x0, budget) = (c.disc, c.x0, c.budget);
    let reference1 = reference(&disc, x0, 1.0);
    let mut rows = Vec::new();
    for (name, rtol, atol) in [
        ("rtol = 0", 0.0, 1e-9),
        ("rtol < 0", -1e-6, 1e-9),
        ("rtol = NaN", f64::NAN, 1e-9),
        ("atol < 0", 1e-6, -1e-9),
    ] {
        rows.push(all_methods(
            budget,
            &format!("bad tolerance: {name}"),
            "InvalidInput",
            &disc,
            (0.0, c.x0, 1.0),
            &with_tol(rtol, atol),
            is(Kind::InvalidInput),
        ));
    }
    for (name, h) in [("h = 0", 0.0), ("h < 0", -0.01), ("h = NaN", f64::NAN)] {
        rows.push(all_methods(
            budget,
            &format!("bad step: {name}"),
            "InvalidInput",
            &disc,
            (0.0, c.x0, 1.0),
            &[Method::Rk4 { h }, Method::Gauss { h }],
            is(Kind::InvalidInput),
        ));
    }
    // atol = 0 on a disc at rest (every component stays exactly zero).
    let rest = State::<f64>::zeros();
    rows.push(all_methods(
        budget,
        "atol = 0, disc upright at rest",
        "Ok(x0)",
        &disc,
        (0.0, rest, 1.0),
        &with_tol(1e-6, 0.0),
        |_, r| r.result.as_ref().is_ok_and(|o| o.x == rest),
    ));
    // rtol below machine precision.
    rows.push(all_methods(
        budget,
        "rtol = 1e-20 (< eps)",
        "Ok err ≤ 1e-12, MaxSteps within the budget, or ToleranceTooTight at t0",
        &disc,
        (0.0, c.x0, 1.0),
        &with_tol(1e-20, 1e-22),
        |_, r| match &r.result {
            Ok(o) => mixed_error(&o.x, &reference1) <= 1e-12,
            Err(SimError::MaxSteps { steps, .. }) => *steps <= budget,
            Err(SimError::ToleranceTooTight { t, x, .. }) => *t == 0.0 && *x == c.x0,
            Err(_) => false,
        },
    ));
    rows
}

// -------------------------------------------------------- single precision

/// Single precision: both discs in `f32` (`ThesisDisc::<f32>`) over 2 s from
/// ψ = 0.3, (θ̇, φ̇, ψ̇) = (6, 20, 0.5) (thesis) and (15, 1, 0.3) (rolling),
/// adaptive methods at rtol 1e-5 (atol 1e-7), fixed steps h = 1e-3; the
/// mixed relative error against the `f64` reference must be ≤ 1e-4 (1e-3
/// for Dopri5, whose global error at rtol 1e-5 over 2 s is a few
/// times the tolerance).
pub fn single_precision(_effort: Effort) -> Vec<Row> {
    let t1 = 2.0;
    let mut rows = Vec::new();
    let methods = Method::all(1e-5, 1e-3).map(|m| match m {
        Method::Dopri5 { rtol, .. } => Method::Dopri5 { rtol, atol: 1e-7 },
        Method::Dop853 { rtol, .. } => Method::Dop853 { rtol, atol: 1e-7 },
        Method::Rodas4 { rtol, .. } => Method::Rodas4 { rtol, atol: 1e-7 },
        other => other,
    });
    let cases: [(&str, [f64; 3]); 2] =
        [("thesis", [6.0, 20.0, 0.5]), ("rolling", [15.0, 1.0, 0.3])];
    for (name, rates) in cases {
        let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], rates);
        let x0_32: State<f32> = x0.map(|v| v as f32);
        let (reference, runs) = if name == "thesis" {
            let d64: ThesisDisc = ThesisDisc::new(M, R, G);
            let d32 = ThesisDisc::<f32>::new(M as f32, R as f32, G as f32);
            (
                reference(&d64, x0, t1),
                methods.map(|m| integrate(m, &d32, 0.0f32, x0_32, t1 as f32, 1_000_000, |_, _| {})),
            )
        } else {
            let d64: RollingDisc = RollingDisc::new(M, R, G);
            let d32 = RollingDisc::<f32>::new(M as f32, R as f32, G as f32);
            (
                reference(&d64, x0, t1),
                methods.map(|m| integrate(m, &d32, 0.0f32, x0_32, t1 as f32, 1_000_000, |_, _| {})),
            )
        };
        for (method, run) in methods.iter().zip(&runs) {
            let obs = Observed::of(run, run_error(run, &reference));
            rows.push(Row::judge(
                format!("f32 {name}"),
                format!("{} (f32)", method.label()),
                Expect::Accurate(1e-4),
                &obs,
                true,
                "error vs f64 reference",
            ));
        }
    }
    rows
}

/// Every family, in the order of the module docs.
pub fn all(effort: Effort) -> Vec<Row> {
    let mut rows = stiff(effort);
    rows.extend(fast_spin(effort));
    rows.extend(scale_extremes(effort));
    rows.extend(long_horizon(effort));
    rows.extend(near_singular(effort));
    rows.extend(bad_input(effort));
    rows.extend(single_precision(effort));
    rows
}

fn fmt_error(e: Option<f64>) -> String {
    e.map_or_else(|| "—".into(), |e| format!("{e:.2e}"))
}

/// The rows as a Markdown table with the columns case, expected, method,
/// outcome, error, steps, seconds, pass, notes.
pub fn markdown_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| case | expected | method | outcome | error | steps | seconds | pass | notes |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {:.2e} | {} | {} |",
            r.case,
            r.expected,
            r.method,
            r.outcome,
            fmt_error(r.error),
            r.steps,
            r.seconds,
            if r.pass { "yes" } else { "**NO**" },
            r.notes
        );
    }
    s
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Writes the rows as CSV with the columns
/// `case,expected,method,outcome,error,steps,seconds,pass,notes` (an empty
/// error where none is defined), creating the directory if needed.
pub fn write_csv(path: &Path, rows: &[Row]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut s = String::from("case,expected,method,outcome,error,steps,seconds,pass,notes\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:e},{},{}",
            csv_field(&r.case),
            csv_field(&r.expected),
            csv_field(&r.method),
            csv_field(&r.outcome),
            r.error.map(|e| format!("{e:e}")).unwrap_or_default(),
            r.steps,
            r.seconds,
            r.pass,
            csv_field(&r.notes)
        );
    }
    std::fs::write(path, s)
}
