//! One system's check: generate it, expand it with the engine, interpret
//! the generated methods in `f64` (what a user's code computes) and compare
//! them with the plain derivation in double-double at random states.

mod declared;
mod momenta;

pub use momenta::Cyclic;

use crate::Scalar;
use crate::generate::{self, Rng};
use crate::interp::{Arg, Expansion};
use crate::model::System;
use crate::plain::{Motion, Plain, Point, Unsolvable};
use nh_core::sym::dd::Dd;

/// How a system's check ended.
#[derive(Clone, Debug)]
pub enum Finding {
    /// Every compared value agreed at every usable state.
    Agree {
        /// The largest relative difference seen in `f64` (times the chart's ratio).
        worst: f64,
        /// The same in double-double.
        worst_exact: f64,
        /// States compared.
        states: usize,
    },
    /// The engine rejected the system with these errors.
    Rejected(Vec<String>),
    /// A generated method disagrees with the plain derivation.
    Disagree(String),
    /// The generated code could not be interpreted.
    Uninterpretable(String),
    /// No state could be compared (each singular or ill-conditioned).
    NoState(String),
}

/// The check of one seed.
#[derive(Clone, Debug)]
pub struct Report {
    /// The seed.
    pub seed: u64,
    /// The system's text.
    pub text: String,
    /// The outcome.
    pub finding: Finding,
    /// The family and route facts the engine reported (its `Stats`).
    pub route: String,
    /// The momenta's check, for a system with coordinates the plain
    /// derivation finds cyclic (`check/momenta.rs`).
    pub cyclic: Option<Cyclic>,
    /// The declared momenta's check (`check/declared.rs`): the numbers of
    /// momenta and of rotations' turns among them compared, for a system in
    /// its scope.
    pub declared: Option<(usize, usize)>,
    /// Whether the system, which has bodies, was checked a second time
    /// with every kinetic energy folded into a symbol (and agreed).
    pub folded: bool,
    /// Whether that second pass took the composite inertias of a group of
    /// bodies on chains of frames (`nh_core::with_composite_inertias`).
    pub composite: bool,
    /// Whether it solved a reduced system by the articulated-body
    /// recursion on the composite inertias' tree.
    pub articulated: bool,
}

/// Relative tolerance between the generated code in `f64` and the plain
/// derivation in double-double, on states where the plain derivation in
/// `f64` agrees with itself in double-double to [`CONDITION_GATE`],
/// divided by the chart's Hadamard ratio.
pub const TOLERANCE: f64 = 1e-9;
/// The same for the generated code in double-double: the algebra.
pub const EXACT_TOLERANCE: f64 = 1e-12;
/// States where the plain derivation loses more than this in `f64` are
/// ill-conditioned (near a singularity of the chart or of the mass
/// matrix) and not compared.
pub const CONDITION_GATE: f64 = 1e-10;
/// States tried per system.
pub const STATES: usize = 3;

/// Checks the system of `seed`.
pub fn check(seed: u64) -> Report {
    check_system(&generate::system(seed), seed)
}

/// Checks only the equations of `sys` at the states of `seed`: not its
/// other charts, its momenta or a momenta block (`tests/chains.rs`: a
/// chain's long Lagrangian, which those expand, is beyond the engine's work
/// limit at 13 links), and not again with the kinetic energies folded.
pub fn check_equations(sys: &System, seed: u64) -> Report {
    check_one(sys, seed, false)
}

/// Checks `sys` at the states of `seed`, and each other chart of its
/// atlas as a system of its own; a system with bodies again with every
/// kinetic energy folded into a symbol of the Lagrangian and every group
/// of bodies on chains of frames summed as composite inertias.
pub fn check_system(sys: &System, seed: u64) -> Report {
    let first = check_one(sys, seed, true);
    if !matches!(first.finding, Finding::Agree { .. }) || !first.text.contains("kinetic_energy(") {
        return first;
    }
    // again with every kinetic energy folded into a symbol of the
    // Lagrangian (the path of a chain's far links): Kane's form, and the
    // Lagrangian expanded again where an output takes it
    let (folded, composite) = nh_core::with_fold_terms(0, || {
        nh_core::with_composite_inertias(|| check_one(sys, seed, true))
    });
    match folded.finding {
        Finding::Agree { .. } => Report {
            folded: true,
            composite: composite.groups > 0,
            articulated: composite.articulated > 0,
            ..first
        },
        Finding::Disagree(why) => Report {
            finding: Finding::Disagree(format!("with the kinetic energies folded: {why}")),
            ..first
        },
        _ => Report {
            finding: Finding::Disagree(format!(
                "with the kinetic energies folded the expansion differs: {:?}",
                folded.finding
            )),
            ..first
        },
    }
}

/// [`check_system`], the other charts only if `charts`.
fn check_one(sys: &System, seed: u64, charts: bool) -> Report {
    let text = sys.text();
    let tokens: proc_macro2::TokenStream = match text.parse() {
        Ok(t) => t,
        Err(e) => {
            return report(
                seed,
                text,
                Finding::Uninterpretable(format!("lexing: {e}")),
                String::new(),
            );
        }
    };
    let (out, stats) = nh_core::expand_with_stats(tokens);
    let route = format!("{:?}", stats.route);
    let errors = nh_core::reported_errors(&out);
    if !errors.is_empty() {
        let msgs = errors.into_iter().map(|e| e.message).collect();
        return report(seed, text, Finding::Rejected(msgs), route);
    }
    let exp = match Expansion::new(&out) {
        Ok(e) => e,
        Err(e) => return report(seed, text, Finding::Uninterpretable(e), route),
    };
    let mut finding = compare(sys, &exp, seed);
    if charts && matches!(finding, Finding::Agree { .. }) {
        // the atlas's other charts, each as the system it was derived as
        // (its `dependent` list, or its rotation in another sequence)
        for chart in other_charts(sys, &out.to_string()) {
            if let Finding::Disagree(why) = check_one(&chart.1, seed, false).finding {
                finding = Finding::Disagree(format!("in the chart {}: {why}", chart.0));
                break;
            }
        }
    }
    let (mut cyclic, mut declared) = (None, None);
    if charts && matches!(finding, Finding::Agree { .. }) {
        match momenta::check(sys, seed, &exp) {
            Ok(c) => cyclic = c,
            Err(f) => finding = f,
        }
    }
    if charts && matches!(finding, Finding::Agree { .. }) {
        match declared::check(sys, seed, &exp) {
            Ok(d) => declared = d,
            Err(f) => finding = f,
        }
    }
    Report {
        cyclic,
        declared,
        ..report(seed, text, finding, route)
    }
}

/// The charts of `sys`'s atlas other than its own, read off the struct's
/// documentation in the expansion `out` (DESIGN §9.3, §9.4), each as a
/// system of its own: "solved for `a`, `b`" with that `dependent` list,
/// "the angles of `rot_z(q1)*rot_x(q2)*rot_y(q3)`" with its free rotation
/// written in that sequence.
fn other_charts(sys: &System, out: &str) -> Vec<(String, System)> {
    let Some(section) = out.split("# Charts").nth(1) else {
        return Vec::new();
    };
    // "c. NAME: singular where ..." of the struct's documentation
    let name = |c: usize| -> Option<&str> {
        let line = section.split(&format!("\"{c}. ")).nth(1)?;
        line.split(": singular where").next()
    };
    const ANGLES: &str = "the angles of `";
    let own = name(0)
        .and_then(|n| n.strip_prefix(ANGLES))
        .map(|p| p.trim_end_matches('`'));
    let mut charts = Vec::new();
    for c in 1..=3 {
        let Some(name) = name(c) else { break };
        let mut chart = sys.clone();
        if let Some(names) = name.strip_prefix("solved for ") {
            let named = names.split(", ").map(|n| n.trim_matches('`'));
            chart.dependent = named
                .map(|n| sys.coords.iter().position(|c| c == n))
                .collect();
            if chart.dependent.is_none() {
                continue;
            }
        } else if let (Some(product), Some(own)) = (name.strip_prefix(ANGLES), own) {
            let axes: Vec<usize> = (product.trim_end_matches('`').split('*'))
                .filter_map(|f| {
                    ["rot_x", "rot_y", "rot_z"]
                        .iter()
                        .position(|r| f.starts_with(r))
                })
                .collect();
            let [a, b, c] = axes[..] else { continue };
            if !chart.rewrite_rotation(own, [a, b, c]) {
                continue;
            }
        } else {
            continue;
        }
        charts.push((name.to_string(), chart));
    }
    charts
}

fn report(seed: u64, text: String, finding: Finding, route: String) -> Report {
    Report {
        seed,
        text,
        finding,
        route,
        cyclic: None,
        declared: None,
        folded: false,
        composite: false,
        articulated: false,
    }
}

/// The states a system of `seed` with `k` independent velocities (or
/// speeds) is checked at.
pub fn states(sys: &System, seed: u64, k: usize) -> Vec<Point<f64>> {
    let mut rng = Rng::new(seed ^ 0x5EED_0F57_A7E5);
    (0..STATES).map(|_| point(&mut rng, sys, k)).collect()
}

/// A random state: parameters in [0.6, 1.4], coordinates in [−1.2, 1.2],
/// velocities and inputs in [−1, 1], t in [0, 1.5].
fn point(rng: &mut Rng, sys: &System, k: usize) -> Point<f64> {
    Point {
        params: sys.params.iter().map(|_| rng.uniform(0.6, 1.4)).collect(),
        inputs: sys.inputs.iter().map(|_| rng.uniform(-1.0, 1.0)).collect(),
        t: rng.uniform(0.0, 1.5),
        q: sys.coords.iter().map(|_| rng.uniform(-1.2, 1.2)).collect(),
        v: (0..k).map(|_| rng.uniform(-1.0, 1.0)).collect(),
    }
}

fn widen(p: &Point<f64>) -> Point<Dd> {
    let w = |v: &[f64]| v.iter().map(|&x| Dd::from_f64(x)).collect();
    Point {
        params: w(&p.params),
        inputs: w(&p.inputs),
        t: Dd::from_f64(p.t),
        q: w(&p.q),
        v: w(&p.v),
    }
}

fn plain<S: Scalar>(
    sys: &System,
    p: &Point<S>,
    dependent: &[usize],
) -> Result<Motion<S>, Unsolvable> {
    let plain = Plain::new(sys, p);
    match sys.speeds {
        Some(_) => plain.speeds_motion(p),
        None => plain.motion(p, dependent),
    }
}

/// The largest difference of two lists relative to the larger of 1 and
/// the reference's largest entry.
fn relative(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    if worst.is_nan() {
        f64::INFINITY
    } else {
        worst / scale
    }
}

fn flat<S: Scalar>(v: &[S]) -> Vec<f64> {
    v.iter().map(|x| x.to_f64()).collect()
}

/// Column-major entries of a row-major matrix (nalgebra's storage order).
fn column_major<S: Scalar>(m: &[Vec<S>]) -> Vec<S> {
    let cols = m.first().map_or(0, |r| r.len());
    (0..cols)
        .flat_map(|j| m.iter().map(move |r| r[j]))
        .collect()
}

fn compare(sys: &System, exp: &Expansion, seed: u64) -> Finding {
    let speeds = sys.speeds.is_some();
    let k = match &sys.speeds {
        Some(s) => s.names.len(),
        None => exp.independent().len(),
    };
    let (mut worst, mut worst_exact, mut used, mut why) = (0.0f64, 0.0f64, 0, String::new());
    for p in states(sys, seed, k) {
        let (exact, rough) = match (
            plain(sys, &widen(&p), exp.dependent()),
            plain(sys, &p, exp.dependent()),
        ) {
            (Ok(e), Ok(r)) => (e, r),
            (Err(e), _) | (_, Err(e)) => {
                if let Unsolvable::RowCount { .. } | Unsolvable::Contradiction(_) = e {
                    return Finding::Disagree(format!(
                        "the constraints' rows: {e:?} (DEPENDENT {:?})",
                        exp.dependent()
                    ));
                }
                why = format!("{e:?}");
                continue;
            }
        };
        let gate = relative(&flat(&rough.accelerations), &flat(&exact.accelerations));
        if gate > CONDITION_GATE {
            why = format!("ill-conditioned ({gate:.1e})");
            continue;
        }
        used += 1;
        match compare_state(exp, &p, &exact, speeds) {
            Ok((w, x)) => {
                worst = worst.max(w);
                worst_exact = worst_exact.max(x);
            }
            Err(e) => return e,
        }
    }
    if used == 0 {
        return Finding::NoState(why);
    }
    Finding::Agree {
        worst,
        worst_exact,
        states: used,
    }
}

/// The values a generated method is compared with: its name and the plain
/// derivation's values (in double-double).
fn expected(exp: &Expansion, exact: &Motion<Dd>, speeds: bool) -> Vec<(&'static str, Vec<Dd>)> {
    let mut checks = vec![("accelerations", exact.accelerations.clone())];
    if speeds {
        checks.push(("velocities", exact.qdot.clone()));
    } else if !exact.sdot.is_empty() {
        checks.push(("dependent_velocities", exact.sdot.clone()));
    }
    let optional = [
        ("multipliers", exact.multipliers.clone()),
        ("energy", vec![exact.energy]),
        ("mass_matrix", column_major(&exact.mass)),
        ("constraint_matrix", column_major(&exact.constraint_matrix)),
    ];
    for (name, want) in optional {
        if exp.has_method(name) {
            checks.push((name, want));
        }
    }
    if exp.has_method("momenta") {
        // `CYCLIC` names coordinates; the plain values are by independent ones
        let pick = |v: &[Dd]| -> Vec<Dd> {
            (exp.cyclic().iter())
                .filter_map(|c| exp.independent().iter().position(|r| r == c))
                .map(|j| v[j])
                .collect()
        };
        checks.push(("momenta", pick(&exact.momenta)));
        checks.push(("momentum_rates", pick(&exact.momentum_rates)));
    }
    checks
}

/// The generated method `name` at `p` in the number type `S`.
fn generated<S: Scalar>(
    exp: &Expansion,
    bound: &mut crate::interp::Bound<'_, S>,
    name: &str,
    p: &Point<S>,
) -> Result<Vec<S>, Finding> {
    let args = [
        ("t", Arg::Scalar(p.t)),
        ("q", Arg::Vector(p.q.clone())),
        ("rdot", Arg::Vector(p.v.clone())),
        ("speeds", Arg::Vector(p.v.clone())),
        ("u", Arg::Vector(p.inputs.clone())),
    ];
    let fail = |e: String| Finding::Uninterpretable(format!("{name}: {e}"));
    let takes = exp.arguments(name).map_err(fail)?;
    let given: Vec<(&str, Arg<S>)> = (args.iter())
        .filter(|(a, _)| takes.iter().any(|(b, _)| a == b))
        .cloned()
        .collect();
    bound.call(name, &given).map_err(fail)
}

/// Every generated method the system has against the plain motion, twice:
/// interpreted in double-double against [`EXACT_TOLERANCE`] (the algebra:
/// a wrong term shows at any precision) and in `f64` against
/// [`TOLERANCE`] (the rounding a user's code meets), both divided by the
/// chart's Hadamard ratio (near a singularity of the chosen dependent
/// coordinates any route divides by a small number). The largest `f64`
/// difference, relative to the tolerance's unit.
fn compare_state(
    exp: &Expansion,
    p: &Point<f64>,
    exact: &Motion<Dd>,
    speeds: bool,
) -> Result<(f64, f64), Finding> {
    let chart = exact.chart.max(1e-12);
    // the rounding any route's solve of Cᵀ M C meets: ε times its condition
    let cond = exact.reduced_condition.min(1e16);
    let (exact_tol, tol) = (EXACT_TOLERANCE + 1e-14 * cond, TOLERANCE + 1e-12 * cond);
    let wide = widen(p);
    let parameters = |e: String| Finding::Uninterpretable(format!("parameters: {e}"));
    let mut in_f64 = exp.bind(&p.params).map_err(parameters)?;
    let mut in_dd = exp.bind(&wide.params).map_err(parameters)?;
    let (mut worst, mut worst_exact) = (0.0f64, 0.0f64);
    for (name, want) in expected(exp, exact, speeds) {
        let got = generated(exp, &mut in_dd, name, &wide)?;
        let err = relative_dd(&got, &want);
        if err.is_nan() || err > exact_tol / chart {
            return Err(disagree(
                name,
                "double-double",
                p,
                &flat(&got),
                &flat(&want),
                err,
            ));
        }
        worst_exact = worst_exact.max(err * chart);
        let got = generated(exp, &mut in_f64, name, p)?;
        let err = relative(&got, &flat(&want));
        if err.is_nan() || err > tol / chart {
            return Err(disagree(name, "f64", p, &got, &flat(&want), err));
        }
        worst = worst.max(err * chart);
    }
    Ok((worst, worst_exact))
}

fn disagree(
    name: &str,
    number: &str,
    p: &Point<f64>,
    got: &[f64],
    want: &[f64],
    err: f64,
) -> Finding {
    Finding::Disagree(format!(
        "{name} in {number} at {p:?}: generated {got:?}, plain {want:?} (relative {err:.2e})"
    ))
}

/// [`relative`] in double-double.
fn relative_dd(a: &[Dd], b: &[Dd]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.to_f64().abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((*x - *y).to_f64().abs()));
    if worst.is_nan() {
        f64::INFINITY
    } else {
        worst / scale
    }
}
