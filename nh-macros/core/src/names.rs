//! Spelling suggestions for unknown names ("did you mean `cos`?"), and the
//! identity of names: `r#x` and `x` are one name, as they are to Rust.

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
