//! Rigid bodies (DESIGN §10) in the engine: the rolling disc written with a
//! body and a rolling contact costs no more operations than the same disc
//! expanded by hand, and the kinds of values are checked before derivation.

/// The rolling disc with its Lagrangian written out by hand.
const HAND: &str = include_str!("data/disc_by_hand.txt");

/// The same disc written with a body and a rolling contact.
const BODY: &str = include_str!("data/disc_body.txt");

fn stats(src: &str) -> (String, nh_core::Stats) {
    let (out, stats) = nh_core::expand_with_stats(src.parse().expect("lexes"));
    (out.to_string(), stats)
}

#[test]
fn the_disc_as_a_body_costs_no_more_than_by_hand() {
    let (_, hand) = stats(HAND);
    let (out, body) = stats(BODY);
    assert!(!out.contains("compile_error"), "{out}");
    assert_eq!(body.route, hand.route);
    assert!(
        body.ops_curvature <= hand.ops_curvature && body.ops_multiplier <= hand.ops_multiplier,
        "body: {} / {} ops, by hand: {} / {}",
        body.ops_curvature,
        body.ops_multiplier,
        hand.ops_curvature,
        hand.ops_multiplier
    );
    // the rolling contact is solved for the contact point's coordinates
    assert!(
        out.contains("solved for `x`") && out.contains("solved for `y`"),
        "{out}"
    );
}

#[test]
fn a_wheel_that_can_fall_flat_has_a_chart_check() {
    // |e_z × n| = cos ψ vanishes when the disc lies flat: the chart check
    // reads the lean ψ (the rows' own block, solved for x and y, does not)
    let (out, _) = stats(BODY);
    let at = out.find("fn chart_regularity").expect("a chart check");
    let body = &out[at..];
    let body = &body[..body[3..].find(" fn ").map_or(body.len(), |e| e + 3)];
    assert!(body.contains("__nh_q_psi"), "{body}");
}

#[test]
fn kinds_are_checked_with_one_error_each() {
    for (bad, needle) in [
        ("- m*g*C.z;", "- m*g*C;"),
        ("centre: C,", "centre: x,"),
        ("axle: [0, 1, 0]", "axle: [0, 0, 0]"),
        ("orientation: F*rot_y(theta)", "orientation: 2*F"),
        (
            "inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4)",
            "inertia: [[m, 1, 0], [0, m, 0], [0, 0, m]]",
        ),
    ] {
        let src = BODY.replace(bad, needle);
        assert_ne!(src, BODY, "{bad}");
        let out = nh_core::expand(src.parse().expect("lexes")).to_string();
        assert_eq!(out.matches("compile_error").count(), 1, "{needle}: {out}");
    }
}
