//! Spelling suggestions for unknown names ("did you mean `cos`?"), the
//! functions of other notations with what to write instead (`arctan` is
//! `atan`), and the identity of names: `r#x` and `x` are one name, as they are to Rust.

use proc_macro2::Ident;

/// Rust's keywords, strict and reserved, in every edition: as names they
/// must be written as raw identifiers (`r#type`).
const KEYWORDS: [&str; 52] = [
    "abstract", "as", "async", "await", "become", "box", "break", "const", "continue", "crate",
    "do", "dyn", "else", "enum", "extern", "false", "final", "fn", "for", "gen", "if", "impl",
    "in", "let", "loop", "macro", "match", "mod", "move", "mut", "override", "priv", "pub", "ref",
    "return", "Self", "self", "static", "struct", "super", "trait", "true", "try", "type",
    "typeof", "unsafe", "unsized", "use", "virtual", "where", "while", "yield",
];

/// Keywords that are not identifiers even when written raw (`r#self` is
/// rejected by Rust), and `_`.
const NEVER_NAMES: [&str; 5] = ["self", "Self", "super", "crate", "_"];

/// The one spelling of a name: a raw identifier whose text is not a keyword
/// (`r#x`) becomes the plain identifier (`x`), with its span, because Rust
/// makes no difference between them; `r#type` stays raw. Every name of the
/// input goes through here, so duplicates, lookups and the generated code
/// all see one name.
pub fn canonical(id: Ident) -> Ident {
    let text = id.to_string();
    match text.strip_prefix("r#") {
        Some(bare) if !KEYWORDS.contains(&bare) => Ident::new(bare, id.span()),
        _ => id,
    }
}

/// Why `id` (canonical) cannot name a parameter, coordinate, input or `let`
/// (`kind`, e.g. "a parameter"), if it cannot: it is a keyword.
pub fn keyword_problem(id: &Ident, kind: &str) -> Option<String> {
    let text = id.to_string();
    if text == "_" {
        return Some(format!(
            "`_` cannot be used as {kind} name: in Rust `_` is a wildcard, not a name; choose another name"
        ));
    }
    if NEVER_NAMES.contains(&text.as_str()) {
        return Some(format!(
            "`{text}` cannot be used as {kind} name: it is a Rust keyword, which cannot name a field or a variable of the generated code, not even as a raw identifier; choose another name"
        ));
    }
    if KEYWORDS.contains(&text.as_str()) {
        return Some(format!(
            "`{text}` is a Rust keyword and cannot be used as {kind} name as written: write the raw identifier `r#{text}`, or choose another name"
        ));
    }
    None
}

/// Whether a canonical name can be emitted as a Rust identifier (a field,
/// an argument): not a keyword written plain.
pub fn is_rust_identifier(id: &Ident) -> bool {
    let text = id.to_string();
    !KEYWORDS.contains(&text.as_str()) && text != "_"
}

/// Edit distance (Levenshtein) between two short strings.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        // transposition of adjacent characters counts as one edit
        prev = cur;
    }
    prev[b.len()]
}

/// The closest candidate within a small distance, if any.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = (name.chars().count() / 3).max(1) + usize::from(name.len() > 2);
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (edit_distance(name, c).min(transposed(name, c)), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}

/// One if `a` and `b` differ by swapping two adjacent characters.
fn transposed(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    if a.len() != b.len() {
        return usize::MAX;
    }
    let diff: Vec<usize> = (0..a.len()).filter(|&i| a[i] != b[i]).collect();
    if diff.len() == 2
        && diff[1] == diff[0] + 1
        && a[diff[0]] == b[diff[1]]
        && a[diff[1]] == b[diff[0]]
    {
        1
    } else {
        usize::MAX
    }
}

/// `": did you mean `x`?"`-style suffix, or the empty string.
pub fn suggest(name: &str, candidates: &[&str]) -> String {
    match closest(name, candidates.iter().copied()) {
        Some(c) => format!(" (did you mean `{c}`?)"),
        None => String::new(),
    }
}

/// Functions of other languages and notations, each with what to write
/// instead (by meaning: `arctan` is `atan`, `log` is `ln`, not by spelling).
const FUNCTION_MEANINGS: [(&[&str], &str); 16] = [
    (
        &["arctan", "arctg", "atn"],
        "the inverse tangent is `atan`; the angle of the point (x, y) is `atan2(y, x)`",
    ),
    (&["arcsin", "arcsine"], "the inverse sine is `asin`"),
    (&["arccos", "arccosine"], "the inverse cosine is `acos`"),
    (
        &["arctan2", "atan2f", "arg", "angle"],
        "the angle of the point (x, y) is `atan2(y, x)`",
    ),
    (
        &["atan2d", "atand", "asind", "acosd", "sind", "cosd", "tand"],
        "the functions work in radians: write `atan2(y, x)`, `sin(x)`, ... and convert degrees with `pi/180`",
    ),
    (&["log", "loge", "log_e"], "the natural logarithm is `ln`"),
    (
        &["log10", "lg", "log2"],
        "there is only the natural logarithm `ln`: write `ln(x)/ln(10)` (or `ln(x)/ln(2)`)",
    ),
    (
        &["sign", "sgn", "signum"],
        "there is no sign function: `abs(x)` exists, and `x/abs(x)` is the sign where x ≠ 0",
    ),
    (&["tg"], "the tangent is `tan`"),
    (&["ctg", "cotan", "cotg", "ctn"], "the cotangent is `cot`"),
    (&["cosec"], "the cosecant is `csc`"),
    (
        &["sech", "csch", "coth"],
        "write it with `sinh` and `cosh`: sech(x) = 1/cosh(x), csch(x) = 1/sinh(x), coth(x) = cosh(x)/sinh(x)",
    ),
    (
        &[
            "asinh", "acosh", "atanh", "arsinh", "arcosh", "artanh", "arcsinh", "arccosh",
            "arctanh",
        ],
        "there are no inverse hyperbolic functions: asinh(x) = ln(x + sqrt(x^2 + 1)), acosh(x) = ln(x + sqrt(x^2 - 1)), atanh(x) = ln((1 + x)/(1 - x))/2",
    ),
    (
        &["fabs", "absolute", "mag", "magnitude"],
        "the absolute value is `abs`; the length of a vector is `norm`",
    ),
    (
        &["pow", "powf", "powi", "sqr", "square", "cbrt"],
        "powers are written with `^`: `x^2`, `x^(1/3)`, `x^y`",
    ),
    (&["hypot"], "write `sqrt(x^2 + y^2)`"),
];

/// What to write instead of a function of another notation (`arctan`,
/// `log`, `sgn`, ...), if `name` is one.
pub fn function_meaning(name: &str) -> Option<&'static str> {
    FUNCTION_MEANINGS
        .iter()
        .find(|(names, _)| names.contains(&name))
        .map(|(_, meaning)| *meaning)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names() {
        assert_eq!(closest("cso", ["sin", "cos", "tan"]), Some("cos"));
        assert_eq!(closest("lagrangain", ["lagrangian"]), Some("lagrangian"));
        assert_eq!(closest("zzz", ["sin", "cos"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn functions_of_other_notations_are_answered_by_meaning() {
        assert!(function_meaning("arctan").is_some_and(|m| m.contains("`atan`")));
        assert!(function_meaning("log").is_some_and(|m| m.contains("`ln`")));
        assert!(function_meaning("sgn").is_some_and(|m| m.contains("`abs(x)`")));
        assert!(function_meaning("ctg").is_some_and(|m| m.contains("`cot`")));
        // the language's own functions have no other meaning
        let functions = crate::words::Function::ALL.map(crate::words::Function::name);
        for f in functions {
            assert_eq!(function_meaning(f), None, "{f}");
        }
        // spelling still finds the nearest function for a typo
        assert_eq!(closest("cso", functions), Some("cos"));
        assert_eq!(closest("atna", functions), Some("atan"));
    }

    #[test]
    fn raw_and_plain_identifiers_are_one_name() {
        let span = proc_macro2::Span::call_site();
        assert_eq!(canonical(Ident::new_raw("x", span)), "x");
        assert_eq!(canonical(Ident::new("x", span)), "x");
        assert_eq!(canonical(Ident::new_raw("type", span)), "r#type");
        assert!(keyword_problem(&Ident::new("self", span), "a parameter").is_some());
        assert!(keyword_problem(&Ident::new("type", span), "a parameter").is_some());
        assert!(keyword_problem(&Ident::new_raw("type", span), "a parameter").is_none());
        assert!(keyword_problem(&Ident::new("x", span), "a parameter").is_none());
        assert!(!is_rust_identifier(&Ident::new("Self", span)));
        assert!(is_rust_identifier(&Ident::new_raw("type", span)));
    }
}
