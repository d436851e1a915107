//! The check of `momenta { .. }` (declared momenta, DESIGN §4.1) on systems
//! nobody planned. For a system in coordinates whose rows are all
//! `dot(s) = Σ_j c_j(q) dot(r_j)` (or that has none), each of its first two
//! independent coordinates r_j gives a direction the constraints allow,
//! X_j = w_j(q)·(e_{r_j} + Σ_s c_j e_s) with w_j = 1 + r_j²/2 (so that X
//! turns with the state), written into the system's text from the rows'
//! own terms. The engine's `declared_momenta` and `declared_momentum_rates`
//! must agree with the plain J = ⟨∂L/∂q̇, X⟩ and its total derivative along
//! the plain motion (`plain/declared.rs`), and a verdict `Conserved` or
//! `Undecided` needs a rate that vanishes at every state. A system without
//! rows whose first rotation `let` is free of t also gets the turn of that
//! rotation about the axis [1, -1, 2] (`R: [1, -1, 2]`), which the engine
//! solves symbolically and the plain side numerically.

use super::{CONDITION_GATE, EXACT_TOLERANCE, Finding, generated, plain, relative_dd, states};
use super::{flat, relative, widen};
use crate::interp::Expansion;
use crate::model::{Constraint, Ex, LetValue, System};
use crate::plain::{Direction, Plain};
use nh_core::sym::dd::Dd;

/// Directions declared per system, at most, along the rows.
const DIRECTIONS: usize = 2;
/// The axis of a rotation's turn.
const TURN_AXIS: [i64; 3] = [1, -1, 2];

/// Whether `e` is free of velocities (a `let` through its value; a
/// vector's component, conservatively, never).
fn still(sys: &System, e: &Ex) -> bool {
    match e {
        Ex::Num(..) | Ex::Pi | Ex::Param(_) | Ex::Coord(_) | Ex::Input(_) | Ex::Time => true,
        Ex::Let(i) => matches!(&sys.lets[*i].1, LetValue::Scalar(x) if still(sys, x)),
        Ex::Add(v) | Ex::Mul(v) => v.iter().all(|x| still(sys, x)),
        Ex::Sub(a, b) | Ex::Div(a, b) | Ex::Atan2(a, b) => still(sys, a) && still(sys, b),
        Ex::Neg(a) | Ex::Pow(a, ..) | Ex::Call(_, a) => still(sys, a),
        _ => false,
    }
}

/// The coefficient of `dot(r_j)` in `e` if `e` is linear and homogeneous
/// in velocities that are all `dot(..)` of independent coordinates: `e`
/// with `dot(r_j)` = 1 and every other velocity 0.
fn coefficient(sys: &System, e: &Ex, j: usize, independent: &[usize]) -> Option<Ex> {
    Some(match e {
        Ex::Vel(i) if independent.contains(i) => Ex::Num(i64::from(*i == j), 1),
        Ex::Add(v) => Ex::Add(
            (v.iter())
                .map(|x| coefficient(sys, x, j, independent))
                .collect::<Option<_>>()?,
        ),
        Ex::Sub(a, b) => Ex::Sub(
            Box::new(coefficient(sys, a, j, independent)?),
            Box::new(coefficient(sys, b, j, independent)?),
        ),
        Ex::Neg(a) => Ex::Neg(Box::new(coefficient(sys, a, j, independent)?)),
        Ex::Mul(v) => {
            let moving: Vec<usize> = (0..v.len()).filter(|&k| !still(sys, &v[k])).collect();
            let [k] = moving[..] else { return None };
            let mut out = v.clone();
            out[k] = coefficient(sys, &v[k], j, independent)?;
            Ex::Mul(out)
        }
        _ => return None,
    })
}

/// The directions X_j (one expression per coordinate), or `None` when the
/// rows are not all explicit, homogeneous and solved for the coordinates
/// the engine made dependent.
fn directions(sys: &System, exp: &Expansion) -> Option<Vec<Direction>> {
    let independent = exp.independent();
    let mut rows = Vec::new();
    for c in &sys.constraints {
        let Constraint::Explicit { s, rhs } = c else {
            return None;
        };
        if !exp.dependent().contains(s) {
            return None;
        }
        rows.push((*s, rhs));
    }
    let mut out = Vec::new();
    for &j in independent.iter().take(DIRECTIONS) {
        let weight = Ex::Add(vec![
            Ex::Num(1, 1),
            Ex::Mul(vec![Ex::Num(1, 2), Ex::Coord(j), Ex::Coord(j)]),
        ]);
        let mut x = vec![Ex::Num(0, 1); sys.coords.len()];
        x[j] = weight.clone();
        for &(s, rhs) in &rows {
            x[s] = Ex::Mul(vec![weight.clone(), coefficient(sys, rhs, j, independent)?]);
        }
        out.push(Direction::Rates(x));
    }
    if rows.is_empty()
        && let Some(r) = (sys.lets.iter()).position(|(_, v)| matches!(v, LetValue::Rotation(_)))
        && let LetValue::Rotation(rx) = &sys.lets[r].1
        && !sys.rx_timed(rx)
    {
        out.push(Direction::Turn(r, TURN_AXIS));
    }
    (!out.is_empty()).then_some(out)
}

/// `sys`'s text with a `momenta` block declaring `directions`.
fn with_block(sys: &System, directions: &[Direction]) -> String {
    let text = sys.text();
    let lines: Vec<String> = (directions.iter().enumerate())
        .map(|(k, d)| {
            let entries: Vec<String> = match d {
                Direction::Rates(x) => (x.iter().enumerate())
                    .filter(|(_, e)| !matches!(e, Ex::Num(0, _)))
                    .map(|(i, e)| format!("{}: {}", sys.coords[i], sys.ex(e)))
                    .collect(),
                Direction::Turn(r, [a, b, c]) => {
                    vec![format!("{}: [{a}, {b}, {c}]", sys.lets[*r].0)]
                }
            };
            format!("        J{k}({});", entries.join(", "))
        })
        .collect();
    let block = format!("    momenta {{\n{}\n    }}\n}}", lines.join("\n"));
    match text.strip_suffix('}') {
        Some(head) => format!("{head}{block}"),
        None => text,
    }
}

/// The declared momenta's check of `sys` (whose expansion `exp` agreed):
/// the numbers of momenta and of turns compared, `None` when out of scope
/// or refused, a disagreement as `Err`. A turn the engine refuses (its
/// rotation not turned by three angles) is dropped and the rest checked.
pub(super) fn check(
    sys: &System,
    seed: u64,
    exp: &Expansion,
) -> Result<Option<(usize, usize)>, Finding> {
    if super::momenta::out_of_scope(sys) {
        return Ok(None);
    }
    let Some(mut directions) = directions(sys, exp) else {
        return Ok(None);
    };
    loop {
        match expanded(sys, &directions)? {
            Some(with) => return compared(sys, seed, exp, &with, &directions),
            None if matches!(directions.last(), Some(Direction::Turn(..))) => {
                directions.pop();
                if directions.is_empty() {
                    return Ok(None);
                }
            }
            None => return Ok(None),
        }
    }
}

/// `sys` expanded with a block of `directions`: `None` when the engine
/// refuses the block (out of its scope, or a rotation not turned by three
/// angles), any other error a disagreement.
fn expanded(sys: &System, directions: &[Direction]) -> Result<Option<Expansion>, Finding> {
    let text = with_block(sys, directions);
    let tokens: proc_macro2::TokenStream = (text.parse())
        .map_err(|e| Finding::Uninterpretable(format!("lexing with momenta: {e}")))?;
    let out = nh_core::expand(tokens);
    let errors = nh_core::reported_errors(&out);
    if let Some(e) = errors.first() {
        let refused = e.message.starts_with("`momenta` is not available here: ")
            || e.message.contains(" turns with the rates of ")
            || e.message.contains(" cannot turn about ");
        return match refused {
            true if errors.len() == 1 => Ok(None),
            _ => Err(Finding::Disagree(format!(
                "with a `momenta` block, the engine rejects the system: {}",
                e.message
            ))),
        };
    }
    Expansion::new(&out)
        .map(Some)
        .map_err(Finding::Uninterpretable)
}

/// The generated declared momenta and rates of `with` against the plain
/// ones at the states of `seed`, and the verdicts.
fn compared(
    sys: &System,
    seed: u64,
    exp: &Expansion,
    with: &Expansion,
    directions: &[Direction],
) -> Result<Option<(usize, usize)>, Finding> {
    let k = exp.independent().len();
    let mut rates: Vec<Vec<Dd>> = Vec::new();
    for p in states(sys, seed, k) {
        let wide = widen(&p);
        let (Ok(exact), Ok(rough)) = (
            plain(sys, &wide, exp.dependent()),
            plain(sys, &p, exp.dependent()),
        ) else {
            continue;
        };
        if relative(&flat(&rough.accelerations), &flat(&exact.accelerations)) > CONDITION_GATE {
            continue;
        }
        let chart = exact.chart.max(1e-12);
        let plain_at = Plain::new(sys, &wide);
        let Some(want): Option<Vec<(Dd, Dd)>> = (directions.iter())
            .map(|d| plain_at.declared_momentum(&wide, &exact, d))
            .collect()
        else {
            continue;
        };
        let (want_j, want_rate): (Vec<Dd>, Vec<Dd>) = want.into_iter().unzip();
        let mut bound = with
            .bind(&wide.params)
            .map_err(|e| Finding::Uninterpretable(format!("parameters: {e}")))?;
        for (name, want) in [
            ("declared_momenta", &want_j),
            ("declared_momentum_rates", &want_rate),
        ] {
            let got = generated(with, &mut bound, name, &wide)?;
            let err = relative_dd(&got, want);
            let tol = EXACT_TOLERANCE + 1e-14 * exact.reduced_condition.min(1e16);
            if err.is_nan() || err > tol / chart {
                return Err(Finding::Disagree(format!(
                    "{name} in double-double at {p:?}: generated {:?}, plain {:?} (relative {err:.2e})",
                    flat(&got),
                    flat(want)
                )));
            }
        }
        rates.push(want_rate);
    }
    verdicts(with, &rates)?;
    let turns = (directions.iter())
        .filter(|d| matches!(d, Direction::Turn(..)))
        .count();
    Ok((!rates.is_empty()).then_some((directions.len(), turns)))
}

/// A declared momentum called `Conserved` or `Undecided` has a plain rate
/// that vanishes at every state compared.
fn verdicts(exp: &Expansion, rates: &[Vec<Dd>]) -> Result<(), Finding> {
    for (k, verdict) in exp.declared_conserved().iter().enumerate() {
        if verdict == "NotConserved" {
            continue;
        }
        for r in rates {
            let rate = r[k].to_f64();
            if rate.abs() > 1e-20 * r.iter().fold(1.0f64, |s, x| s.max(x.to_f64().abs())) {
                return Err(Finding::Disagree(format!(
                    "the declared momentum J{k} is {verdict}, but its rate is {rate:e} by the plain derivation"
                )));
            }
        }
    }
    Ok(())
}
