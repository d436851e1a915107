//! The sample of systems whose plain derivation SymPy checks
//! (`data/sympy_reference.py`): each system's structure as Python
//! expressions, its dependent coordinates and its states, as JSON.

use crate::model::{Constraint, LetValue, System};
use crate::plain::Point;
use std::fmt::Write;

fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn numbers(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(", "))
}

fn strings(v: impl IntoIterator<Item = String>) -> String {
    let items: Vec<String> = v.into_iter().map(|s| quoted(&s)).collect();
    format!("[{}]", items.join(", "))
}

/// One system of the sample as a JSON object.
pub fn entry(seed: u64, sys: &System, dependent: &[usize], states: &[Point<f64>]) -> String {
    let mut s = String::from("{");
    let _ = write!(s, "\"seed\": {seed}, \"text\": {}, ", quoted(&sys.text()));
    let dep: Vec<String> = dependent.iter().map(|d| d.to_string()).collect();
    let _ = write!(s, "\"dependent\": [{}], ", dep.join(", "));
    let _ = write!(
        s,
        "\"sizes\": [{}, {}, {}], ",
        sys.params.len(),
        sys.coords.len(),
        sys.inputs.len()
    );
    let lets = sys.lets.iter().map(|(name, v)| {
        let (kind, value) = match v {
            LetValue::Scalar(e) => ("scalar", sys.py(e)),
            LetValue::Vector(v) => ("vector", sys.py_v(v)),
            LetValue::Rotation(r) => ("rotation", sys.py_r(r)),
        };
        format!("[{}, {}, {}]", quoted(name), quoted(kind), quoted(&value))
    });
    let _ = write!(s, "\"lets\": [{}], ", lets.collect::<Vec<_>>().join(", "));
    let bodies = sys.bodies.iter().map(|(name, b)| {
        let rotation = match &b.rotation {
            Some((r, i)) => {
                let rows = i.iter().map(|row| strings(row.iter().map(|x| sys.py(x))));
                format!(
                    "[{}, [{}]]",
                    quoted(&sys.py_r(r)),
                    rows.collect::<Vec<_>>().join(", ")
                )
            }
            None => "null".into(),
        };
        format!(
            "[{}, {}, {}, {rotation}]",
            quoted(name),
            quoted(&sys.py(&b.mass)),
            quoted(&sys.py_v(&b.centre))
        )
    });
    let _ = write!(
        s,
        "\"bodies\": [{}], ",
        bodies.collect::<Vec<_>>().join(", ")
    );
    let _ = write!(s, "\"lagrangian\": {}, ", quoted(&sys.py(&sys.lagrangian)));
    let forces = sys
        .forces
        .iter()
        .map(|(i, f)| format!("[{i}, {}]", quoted(&sys.py(f))));
    let _ = write!(
        s,
        "\"forces\": [{}], ",
        forces.collect::<Vec<_>>().join(", ")
    );
    let rows = sys.constraints.iter().map(|c| constraint(sys, c));
    let _ = write!(
        s,
        "\"constraints\": [{}], ",
        rows.collect::<Vec<_>>().join(", ")
    );
    match &sys.speeds {
        Some(sp) => {
            let _ = write!(
                s,
                "\"kinematics\": {}, ",
                strings(sp.kinematics.iter().map(|w| sys.py(w)))
            );
        }
        None => s.push_str("\"kinematics\": null, "),
    }
    let states = states.iter().map(|p| {
        format!(
            "{{\"params\": {}, \"inputs\": {}, \"t\": {:?}, \"q\": {}, \"v\": {}}}",
            numbers(&p.params),
            numbers(&p.inputs),
            p.t,
            numbers(&p.q),
            numbers(&p.v)
        )
    });
    let _ = write!(
        s,
        "\"states\": [{}]}}",
        states.collect::<Vec<_>>().join(", ")
    );
    s
}

fn constraint(sys: &System, c: &Constraint) -> String {
    match c {
        Constraint::Explicit { s, rhs } => format!("[\"explicit\", {s}, {}]", quoted(&sys.py(rhs))),
        Constraint::Implicit { lhs, rhs } => {
            format!(
                "[\"implicit\", {}, {}]",
                quoted(&sys.py(lhs)),
                quoted(&sys.py(rhs))
            )
        }
        Constraint::Holonomic { lhs, rhs } => {
            format!(
                "[\"holonomic\", {}, {}]",
                quoted(&sys.py(lhs)),
                quoted(&sys.py(rhs))
            )
        }
        Constraint::Rolls {
            body,
            radius,
            axle,
            tube,
            centre,
        } => format!(
            "[\"rolls\", {body}, {}, {}, {}, {}]",
            quoted(&sys.py(radius)),
            axle.map_or("null".into(), |a| format!("[{}, {}, {}]", a[0], a[1], a[2])),
            tube.as_ref().map_or("null".into(), |t| quoted(&sys.py(t))),
            centre
                .as_ref()
                .map_or("null".into(), |g| quoted(&sys.py_v(g)))
        ),
    }
}
