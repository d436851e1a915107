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

/// A top on a general body (its Lagrangian has more terms than the
/// expanded form is compared at, so the reduced mass matrix is sampled from
/// the Lagrangian) with a fourth coordinate `s`, silent unless `extra` gives
/// it kinetic energy.
fn top(extra: &str) -> String {
    format!(
        "pub struct Top {{
    parameters {{ m, a, b, l, A, B, C, g }}
    coordinates {{ yaw, nutation, spin, s }}
    let R = rot_z(yaw) * rot_x(nutation) * rot_z(spin);
    body top {{ mass: m, centre: R*[a, b, l], orientation: R, inertia: diag(A, B, C) }}
    lagrangian = kinetic_energy(top) - m*g*(R*[a, b, l]).z{extra};
}}"
    )
}

#[test]
fn a_velocity_no_body_moves_is_reported_at_its_coordinate() {
    let errors = nh_core::reported_errors(&expansion_of(&top("")));
    assert_eq!(errors.len(), 1, "{errors:?}");
    let e = &errors[0];
    assert!(
        e.message
            .starts_with("the velocity of `s` appears nowhere in the Lagrangian"),
        "{}",
        e.message
    );
    // `s` in `coordinates { yaw, nutation, spin, s }`, line 3
    assert_eq!((e.start.start().line, e.start.start().column), (3, 39));
    let fixed = expansion_of(&top(" + m*dot(s)^2/2"));
    assert!(nh_core::reported_errors(&fixed).is_empty());
}

/// Issue 34: a Lagrangian through 200 nested lets, each the sine times the
/// cosine of the one before plus it times a velocity. The lets expand; the
/// Lagrangian's derivatives swell past the engine's limit of work (in
/// 6-7 s with the optimised engine). One error, at the Lagrangian, naming
/// what was being done and the measure with its figure.
#[test]
fn a_system_beyond_the_limit_of_work_is_one_error_at_its_culprit() {
    let mut src = String::from(
        "pub struct Swell {\n    parameters { m, g }\n    coordinates { x, y }\n    let a0 = x + y;\n",
    );
    for i in 1..=200 {
        let p = i - 1;
        src += &format!("    let a{i} = sin(a{p})*cos(a{p}) + a{p}*dot(x);\n");
    }
    src += "    lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - g*a200;\n}";
    let errors = nh_core::reported_errors(&expansion_of(&src));
    assert_eq!(errors.len(), 1, "{errors:?}");
    let e = &errors[0];
    let (start, end) = (e.start.start(), e.end.end());
    // `m*(dot(x)^2 + dot(y)^2)/2 - g*a200` on line 205 (columns 0-based)
    assert_eq!((start.line, start.column), (205, 17), "{}", e.message);
    assert_eq!((end.line, end.column), (205, 51), "{}", e.message);
    assert!(
        e.message.starts_with(
            "differentiating the Lagrangian (its mass matrix and Euler–Lagrange terms) exceeded the engine's limit of 50,000,000 units of work"
        ),
        "{}",
        e.message
    );
    assert!(e.message.contains("or split the system"), "{}", e.message);
}
