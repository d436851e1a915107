//! The three problems: the thesis's disc, the physically correct rolling
//! disc and the stiff disc, each with a reference final state obtained at a
//! tolerance far below any measured run's and cross-checked twice.

use nh_lab::systems::{RollingDisc, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;

use crate::measure::{Counted, Sys};
use crate::methods::{Finish, Start, diffsol_peer, ode_solvers_peer};

/// A problem: a generated system, where it starts and ends, and the
/// reference final state every run's error is measured against.
pub struct Problem<S, const D: usize> {
    /// Short name (file names, tables).
    pub name: &'static str,
    /// The generated system.
    pub sys: S,
    /// Initial state, final time, step budget.
    pub start: Start<D>,
    /// The fixed-step methods' ladder of step sizes.
    pub step_sizes: Vec<f64>,
    /// The reference final state.
    pub reference: SVector<f64, D>,
    /// How the reference was obtained and checked.
    pub reference_note: String,
}

/// The adaptive methods' ladder of relative tolerances: 1e-3 to 1e-13 in
/// half decades.
pub fn tolerances() -> Vec<f64> {
    (0..=20)
        .map(|k| 10f64.powf(-3.0 - 0.5 * k as f64))
        .collect()
}

/// `h0`, `h0/2`, … (`n` sizes).
fn halvings(h0: f64, n: i32) -> Vec<f64> {
    (0..n).map(|k| h0 * 0.5f64.powi(k)).collect()
}

/// The second method a reference is checked against.
#[derive(Clone, Copy, Debug)]
enum SecondMethod {
    /// Our Gauss–Legendre 4 (implicit, symplectic) at a fixed step far
    /// below any measured run's: for the smooth problems.
    Gauss(f64),
    /// diffsol's BDF at a relative tolerance: for the stiff disc, where
    /// Gauss–Legendre's order drops (it is 8e-11 from the others even at
    /// h = 2.5e-6).
    Bdf(f64),
}

/// The reference final state: our Dop853 at rtol 1e-14 (atol 1e-16), a
/// tolerance far below any measured run's, cross-checked against the same
/// formula in code written by someone else (ode_solvers' Dop853 at rtol
/// 1e-14, without its step budget and stiffness test) and against a
/// second method. The note says by how much each differs.
fn reference<S: Sys<D>, const D: usize>(
    sys: &S,
    start: &Start<D>,
    second: SecondMethod,
) -> (SVector<f64, D>, String) {
    let reference = Dop853::new(1e-14, 1e-16)
        .with_max_steps(usize::MAX)
        .integrate(sys, 0.0, start.x0, start.t1)
        .map(|o| o.x)
        .unwrap_or_else(|e| panic!("reference run: {e}"));
    let counted = Counted::new(sys);
    let long = Start {
        max_steps: 10_000_000,
        ..*start
    };
    let differs = |r: Result<Finish<D>, String>| match r {
        Ok(f) => format!("{:.1e}", (f.x - reference).amax()),
        Err(e) => format!("— (failed: {e})"),
    };
    let same_formula = differs(ode_solvers_peer::dop853_unlimited(&counted, &long, 1e-14));
    let (name, other) = match second {
        SecondMethod::Gauss(h) => (
            format!("our Gauss–Legendre 4 at h = {h:e}"),
            GaussLegendre4::new(h)
                .with_max_steps(usize::MAX)
                .integrate_with_jacobian(sys, 0.0, start.x0, start.t1)
                .map(|o| Finish {
                    x: o.x,
                    steps: o.stats.steps,
                })
                .map_err(|e| e.to_string()),
        ),
        SecondMethod::Bdf(rtol) => (
            format!("diffsol's BDF at rtol {rtol:e}"),
            diffsol_peer::run(&counted, &long, rtol, diffsol_peer::Kind::Bdf),
        ),
    };
    let note = format!(
        "our Dop853 at rtol 1e-14; ode_solvers' Dop853 at rtol 1e-14 differs from it by {same_formula}, {name} by {} (max abs)",
        differs(other)
    );
    (reference, note)
}

fn state(q: [f64; 5], rdot: [f64; 3]) -> SVector<f64, 8> {
    SVector::<f64, 8>::from_fn(|i, _| if i < 5 { q[i] } else { rdot[i - 5] })
}

/// The thesis's disc, scene as in `lab/examples/work_precision.rs`.
pub fn thesis_disc() -> Problem<ThesisDisc<f64>, 8> {
    let sys = ThesisDisc::new(1.7, 0.35, 9.81);
    let start = Start {
        x0: state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]),
        t1: 5.0,
        max_steps: 1_000_000,
    };
    let (reference, reference_note) = reference(&sys, &start, SecondMethod::Gauss(5e-5));
    Problem {
        name: "thesis_disc",
        sys,
        start,
        step_sizes: halvings(0.02, 10),
        reference,
        reference_note,
    }
}

/// The physically correct thin disc, rolling and precessing for 5 s
/// (the motion of `lab/tests/rolling_disc.rs`' energy test).
pub fn rolling_disc() -> Problem<RollingDisc<f64>, 8> {
    let sys = RollingDisc::new(1.7, 0.35, 9.81);
    let start = Start {
        x0: state([0.0, 0.0, 0.2, 0.0, 0.0], [15.0, 1.0, 0.3]),
        t1: 5.0,
        max_steps: 1_000_000,
    };
    let (reference, reference_note) = reference(&sys, &start, SecondMethod::Gauss(5e-5));
    Problem {
        name: "rolling_disc",
        sys,
        start,
        step_sizes: halvings(0.02, 10),
        reference,
        reference_note,
    }
}

/// The stiff disc: k = 1e6 on the lean, critically damped, scene as in
/// `lab/examples/work_precision.rs`.
pub fn stiff_disc() -> Problem<StiffDisc<f64>, 8> {
    let (m, r) = (1.7f64, 0.35f64);
    let inertia = 1.25 * m * r * r; // the lean's inertia in the thesis model
    let k = 1e6;
    let sys = StiffDisc::new(m, r, 9.81, k, 2.0 * (k * inertia).sqrt(), 0.2);
    let start = Start {
        x0: state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]),
        t1: 1.0,
        max_steps: 200_000,
    };
    let (reference, reference_note) = reference(&sys, &start, SecondMethod::Bdf(1e-12));
    Problem {
        name: "stiff_disc",
        sys,
        start,
        step_sizes: halvings(0.01, 11),
        reference,
        reference_note,
    }
}
