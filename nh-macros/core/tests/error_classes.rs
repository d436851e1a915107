//! Errors the engine decides, one per mistake, at the culprit: constraints
//! that are not linear in the velocities once simplified, rolling contacts
//! whose geometry cannot roll, names with the generated code's prefix, and
//! syntax errors of one misplaced token.

/// The errors of an expansion: (the culprit's source text, the message).
fn errors(src: &str) -> Vec<(String, String)> {
    let expansion = nh_core::expand(src.parse().expect("Rust tokens"));
    nh_core::reported_errors(&expansion)
        .into_iter()
        .map(|e| {
            let (a, b) = (e.start.byte_range().start, e.end.byte_range().end);
            let text = src.get(a..b).unwrap_or("<outside the input>").to_string();
            (text, e.message)
        })
        .collect()
}

/// A system of three free coordinates with `items` added.
fn slide(items: &str) -> String {
    format!(
        "struct S {{
            parameters {{ m }}
            coordinates {{ x, y, theta }}
            lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(theta)^2)/2;
            {items}
        }}"
    )
}

#[test]
fn constraints_are_linear_in_the_velocities_once_simplified() {
    // (constraint, the culprit the error points at)
    let nonlinear = [
        ("abs(dot(x)) = dot(y);", "abs(dot(x))"),
        ("dot(y) = abs(dot(x));", "abs(dot(x))"),
        ("sqrt(dot(x)^2) = dot(y);", "sqrt(dot(x)^2)"),
        ("dot(y) = sqrt(dot(x)^2)*cos(theta);", "sqrt(dot(x)^2)"),
        (
            "sqrt(dot(x)^2 + dot(y)^2) = dot(theta);",
            "sqrt(dot(x)^2 + dot(y)^2)",
        ),
        ("dot(y) = exp(dot(x)) - 1;", "exp(dot(x))"),
        ("dot(y) = (dot(x)^3)^(1/3);", "(dot(x)^3)^(1/3)"),
        // a term that simplifies away is not blamed: the other one is
        (
            "dot(y) = abs(dot(x))/abs(dot(x))*dot(x) + abs(dot(theta));",
            "abs(dot(theta))",
        ),
        ("x*dot(y) + abs(dot(theta))*cos(x) = 0;", "abs(dot(theta))"),
    ];
    for (c, culprit) in nonlinear {
        let found = errors(&slide(&format!("constraints {{ {c} }}")));
        assert_eq!(found.len(), 1, "{c}: {found:?}");
        assert_eq!(found[0].0, culprit, "{c}: {found:?}");
        assert!(
            found[0]
                .1
                .contains("a constraint must be linear in the velocities"),
            "{c}: {}",
            found[0].1
        );
    }
    // linear once the engine has simplified them
    for c in [
        "dot(y) = abs(dot(x))/abs(dot(x))*dot(x);",
        "dot(y) = sqrt(dot(x))^2;",
        "dot(y) = abs(x)*dot(x) + sqrt(x^2)*dot(theta);",
        "dot(y) = (dot(x) + dot(theta))*sin(dot(x) - dot(x)) + dot(x);",
    ] {
        let found = errors(&slide(&format!("constraints {{ {c} }}")));
        assert!(found.is_empty(), "{c}: {found:?}");
    }
}

#[test]
fn a_let_that_is_not_linear_is_blamed_at_its_use() {
    let found = errors(&slide(
        "let V = abs(dot(x)); constraints { dot(y) = V*cos(theta); }",
    ));
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "V");
    assert!(found[0].1.contains("`abs(dot(x))`"), "{}", found[0].1);
}

#[test]
fn kinematics_are_affine_in_the_speeds() {
    let found = errors(&slide(
        "speeds { v, w } kinematics { dot(x) = abs(v); dot(y) = v*sin(theta); dot(theta) = w; }",
    ));
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].1.contains("not linear in the speeds"), "{found:?}");
}

#[test]
fn names_with_the_generated_codes_prefix_are_one_error_each() {
    let found = errors(
        "struct S {
            parameters { m, __nh_cache }
            coordinates { x, __nh_q_x, theta }
            inputs { __nh_u }
            let __nh_l = m*x;
            body __nh_body { mass: m, centre: [x, __nh_q_x, 0], orientation: rot_z(theta), inertia: diag(1, 1, 1) }
            lagrangian = kinetic_energy(__nh_body) - sin(__nh_cache)*__nh_l;
            forces { x: __nh_u; }
        }",
    );
    let culprits: Vec<&str> = found.iter().map(|e| e.0.as_str()).collect();
    assert_eq!(
        culprits,
        ["__nh_cache", "__nh_q_x", "__nh_u", "__nh_body", "__nh_l"],
        "{found:?}"
    );
    assert!(found.iter().all(|e| e.1.contains("reserved")), "{found:?}");
    let found = errors(
        "struct S { parameters { m } coordinates { x } speeds { __nh_v } kinematics { dot(x) = __nh_v; } lagrangian = m*dot(x)^2/2; }",
    );
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "__nh_v");
}
