//! The whole expansion with a lowered limit of work (DESIGN §5): a system
//! that exceeds it is one error, at the part of the input the engine was
//! deriving then, naming the task, the measure and its figure — in a
//! fraction of the time the default limit takes to reach
//! (`tests/reported_errors.rs` holds the same for the default).

use crate::errors::{ReportedError, reported_errors};
use crate::sym::Engine;

/// A chain of `n` lets a_i = sin(a_(i-1)) cos(a_(i-1)) + a_(i-1) f from
/// a0 = x + y (line 4), a_i on line 4 + i, with the Lagrangian or the
/// constraints `rest` after it (from line `n + 5`).
fn let_chain(n: usize, f: &str, rest: &str) -> String {
    let mut src = String::from(
        "pub struct Swell {\n    parameters { m, g }\n    coordinates { x, y }\n    let a0 = x + y;\n",
    );
    for i in 1..=n {
        let p = i - 1;
        src += &format!("    let a{i} = sin(a{p})*cos(a{p}) + a{p}*{f};\n");
    }
    src + rest + "\n}"
}

/// The errors of `src` expanded in an engine that may do `max_work` units.
fn errors_within(src: &str, max_work: usize) -> Vec<ReportedError> {
    let tokens = src.parse().expect("Rust tokens");
    reported_errors(&crate::expand_in(tokens, || Engine::with_work_limit(max_work)).0)
}

/// The one error, as (line, first column, last column, message).
fn one_error(errors: &[ReportedError]) -> (usize, usize, usize, &str) {
    assert_eq!(errors.len(), 1, "{errors:?}");
    let e = &errors[0];
    let (start, end) = (e.start.start(), e.end.end());
    assert_eq!(start.line, end.line, "{}", e.message);
    (start.line, start.column, end.column, e.message.as_str())
}

/// The system: the lets lower within the limit, the Lagrangian's
/// derivatives exceed it, and the error underlines the Lagrangian.
#[test]
fn a_lagrangian_whose_derivatives_swell_is_the_culprit() {
    let lagrangian = "    lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - g*a200;";
    let src = let_chain(200, "dot(x)", lagrangian);
    let errors = errors_within(&src, 200_000);
    let (line, first, last, message) = one_error(&errors);
    assert_eq!((line, first, last), (205, 17, 51), "{message}");
    assert!(
        message.starts_with(
            "differentiating the Lagrangian (its mass matrix and Euler–Lagrange terms) exceeded the engine's limit of 200,000 units of work"
        ),
        "{message}"
    );
    assert!(message.contains("or split the system"), "{message}");
}

/// With less work allowed the lets themselves exceed it: the error is at
/// the one being expanded then, and what follows from the abandoned
/// values (a division by the `let`, which may come out zero) is not
/// reported.
#[test]
fn a_let_whose_expansion_swells_is_the_culprit() {
    let lagrangian = "    lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - g*a200 + 1/a200;";
    let src = let_chain(200, "dot(x)", lagrangian);
    let errors = errors_within(&src, 20_000);
    let (line, first, _, message) = one_error(&errors);
    let culprit = line - 4;
    assert!((1..=200).contains(&culprit), "line {line}: {message}");
    assert_eq!(first, 8, "{message}");
    assert!(
        message.starts_with(&format!(
            "expanding `a{culprit}` exceeded the engine's limit of 20,000 units of work"
        )),
        "{message}"
    );
}

/// A constraint through the chain: the dependent accelerations
/// differentiate it, and the error is at the `constraints` keyword.
#[test]
fn constraints_whose_derivatives_swell_are_the_culprit() {
    let rest =
        "    lagrangian = m*(dot(x)^2 + dot(y)^2)/2;\n    constraints { dot(y) = a200*dot(x); }";
    let src = let_chain(200, "x", rest);
    let errors = errors_within(&src, 200_000);
    let (line, first, last, message) = one_error(&errors);
    assert_eq!((line, first, last), (206, 4, 15), "{message}");
    assert!(
        message.starts_with("differentiating the constraints along the motion exceeded the engine's limit of 200,000 units of work"),
        "{message}"
    );
}

/// Within the limit, nothing is reported: the chain of 20 expands.
#[test]
fn a_short_chain_expands() {
    let lagrangian = "    lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - g*a20;";
    let errors = errors_within(&let_chain(20, "dot(x)", lagrangian), crate::sym::MAX_WORK);
    assert!(errors.is_empty(), "{errors:?}");
}
