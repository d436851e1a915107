//! The errors of an expansion read back from its tokens
//! (`nh_core::reported_errors`, which the `expand` tool prints): each
//! message once, pointing at the line and columns of its culprit.

use proc_macro2::TokenStream;

const SOURCE: &str = "pub struct Slide {
    parameters { m k }
    coordinates { x }
    lagrangian = m*dot(x)^2/2 - k*cso(x);
}";

fn expansion_of(src: &str) -> TokenStream {
    nh_core::expand(src.parse().expect("Rust tokens"))
}

#[test]
fn every_error_is_read_with_its_message_and_place() {
    let errors = nh_core::reported_errors(&expansion_of(SOURCE));
    let found: Vec<(usize, usize, usize, &str)> = errors
        .iter()
        .map(|e| {
            let (start, end) = (e.start.start(), e.end.end());
            assert_eq!(start.line, end.line, "{}", e.message);
            (start.line, start.column, end.column, e.message.as_str())
        })
        .collect();
    assert_eq!(found.len(), 2, "{found:?}");
    // `parameters { m k }`: the missing comma, at `k` (columns 0-based)
    assert_eq!(found[0], (2, 19, 20, "expected `,` between names"));
    // `cso`, underlined as its three letters
    assert_eq!((found[1].0, found[1].1, found[1].2), (4, 34, 37));
    assert!(
        found[1]
            .3
            .starts_with("unknown function `cso` (did you mean `cos`?)"),
        "{}",
        found[1].3
    );
}

#[test]
fn a_system_without_errors_reports_none() {
    let src = "pub struct Slide { parameters { m } coordinates { x } lagrangian = m*dot(x)^2/2; }";
    let expansion = expansion_of(src);
    assert!(!expansion.is_empty());
    assert!(nh_core::reported_errors(&expansion).is_empty());
}
