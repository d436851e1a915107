//! The check of `outputs { momenta }` (§5.5) on systems nobody planned: a
//! system some of whose independent coordinates the plain derivation finds
//! cyclic (∂Lc/∂r_k and ∂Q/∂r_k zero at every state, `plain/momenta.rs`)
//! is expanded again with `momenta` asked for. The coordinates the engine
//! lists in `CYCLIC` must be among those; its `momenta` and
//! `momentum_rates` must agree with the plain p = Cᵀ ∂L/∂q̇ and
//! ṗ = Ċᵀ ∂L/∂q̇ + Cᵀ(∂L/∂q + Q); and a rate it calls `Conserved` or
//! `Undecided` must vanish at every state.

use super::{CONDITION_GATE, Finding, compare, flat, plain, relative, states, widen};
use crate::interp::Expansion;
use crate::model::{Constraint, System};
use crate::plain::Motion;
use nh_core::sym::dd::Dd;

/// A slope or rate below this (in double-double, relative to the larger of
/// 1 and the state's momenta) is zero.
const ZERO: f64 = 1e-20;

/// The outcome of the momenta's check of one system.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cyclic {
    /// Independent coordinates the plain derivation finds cyclic.
    pub found: usize,
    /// Coordinates the engine lists in `CYCLIC`.
    pub listed: usize,
    /// The engine's reason for refusing `momenta`, when it did (its
    /// constraints are not homogeneous rows solved in closed form, or it
    /// proves no coordinate cyclic).
    pub refused: Option<String>,
}

/// Why asking `momenta` of `sys` is out of the output's scope: speeds,
/// holonomic or time-dependent rows, or asked already.
pub(super) fn out_of_scope(sys: &System) -> bool {
    sys.speeds.is_some()
        || sys.timed_rows()
        || sys.outputs.contains(&"momenta")
        || (sys.constraints.iter()).any(|c| matches!(c, Constraint::Holonomic { .. }))
}

/// The plain motions at the states of `seed` that pass the condition gate.
fn motions(sys: &System, seed: u64, exp: &Expansion) -> Vec<Motion<Dd>> {
    let k = exp.independent().len();
    let mut out = Vec::new();
    for p in states(sys, seed, k) {
        let (Ok(exact), Ok(rough)) = (
            plain(sys, &widen(&p), exp.dependent()),
            plain(sys, &p, exp.dependent()),
        ) else {
            continue;
        };
        if relative(&flat(&rough.accelerations), &flat(&exact.accelerations)) <= CONDITION_GATE {
            out.push(exact);
        }
    }
    out
}

/// The positions (in `INDEPENDENT` order) of the coordinates cyclic at
/// every one of `motions`.
fn cyclic_at(motions: &[Motion<Dd>], k: usize) -> Vec<usize> {
    (0..k)
        .filter(|&j| {
            motions.iter().all(|m| {
                let scale = m
                    .momenta
                    .iter()
                    .fold(1.0f64, |s, p| s.max(p.to_f64().abs()));
                m.cyclic_slopes[j] <= ZERO * scale
            })
        })
        .collect()
}

/// The momenta's check of `sys` (whose expansion `exp` agreed): `None`
/// when out of scope or no coordinate is cyclic, a disagreement as `Err`.
pub(super) fn check(sys: &System, seed: u64, exp: &Expansion) -> Result<Option<Cyclic>, Finding> {
    if out_of_scope(sys) {
        return Ok(None);
    }
    let motions = motions(sys, seed, exp);
    let found = cyclic_at(&motions, exp.independent().len());
    if motions.is_empty() || found.is_empty() {
        return Ok(None);
    }
    let mut asked = sys.clone();
    asked.outputs.push("momenta");
    let tokens: proc_macro2::TokenStream = (asked.text().parse())
        .map_err(|e| Finding::Uninterpretable(format!("lexing with momenta: {e}")))?;
    let out = nh_core::expand(tokens);
    let errors = nh_core::reported_errors(&out);
    if let Some(e) = errors.first() {
        const REFUSED: &str = "output `momenta` is not available here: ";
        return match e.message.strip_prefix(REFUSED) {
            Some(why) if errors.len() == 1 => Ok(Some(Cyclic {
                found: found.len(),
                listed: 0,
                refused: Some(why.chars().take(60).collect()),
            })),
            _ => Err(Finding::Disagree(format!(
                "with `momenta` asked for, the engine rejects the system: {}",
                e.message
            ))),
        };
    }
    let with = Expansion::new(&out).map_err(Finding::Uninterpretable)?;
    listed_are_cyclic(&with, &found)?;
    if let Finding::Disagree(why) = compare(&asked, &with, seed) {
        return Err(Finding::Disagree(format!("with `momenta`: {why}")));
    }
    verdicts(&with, &motions)?;
    Ok(Some(Cyclic {
        found: found.len(),
        listed: with.cyclic().len(),
        refused: None,
    }))
}

/// Every coordinate of `CYCLIC` is independent and among those `found`
/// cyclic (positions in `INDEPENDENT` order).
fn listed_are_cyclic(exp: &Expansion, found: &[usize]) -> Result<(), Finding> {
    for &c in exp.cyclic() {
        let at = exp.independent().iter().position(|&r| r == c);
        if !at.is_some_and(|j| found.contains(&j)) {
            return Err(Finding::Disagree(format!(
                "CYCLIC lists `{}`, which is {} by the plain derivation",
                exp.coordinates()[c],
                if at.is_some() {
                    "not cyclic"
                } else {
                    "not independent"
                }
            )));
        }
    }
    if exp.conserved().len() != exp.cyclic().len() {
        return Err(Finding::Disagree(format!(
            "CONSERVED has {} verdicts for {} cyclic coordinates",
            exp.conserved().len(),
            exp.cyclic().len()
        )));
    }
    Ok(())
}

/// A rate called `Conserved` or `Undecided` vanishes at every state.
fn verdicts(exp: &Expansion, motions: &[Motion<Dd>]) -> Result<(), Finding> {
    for (&c, verdict) in exp.cyclic().iter().zip(exp.conserved()) {
        if verdict == "NotConserved" {
            continue;
        }
        let Some(j) = exp.independent().iter().position(|&r| r == c) else {
            continue;
        };
        for m in motions {
            let scale = m
                .momenta
                .iter()
                .fold(1.0f64, |s, p| s.max(p.to_f64().abs()));
            let rate = m.momentum_rates[j].to_f64();
            if rate.abs() > ZERO * scale {
                return Err(Finding::Disagree(format!(
                    "the momentum of `{}` is {verdict}, but its rate is {rate:e} by the plain derivation",
                    exp.coordinates()[c]
                )));
            }
        }
    }
    Ok(())
}
