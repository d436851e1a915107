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

/// The disc of the thesis as a body, with `args` for its `rolls(..)` line.
fn disc(args: &str) -> String {
    format!(
        "struct Disc {{
            parameters {{ m, R, g }}
            coordinates {{ theta, phi, psi, x, y }}
            let F = rot_z(phi) * rot_x(-psi);
            let C = [x, y, 0] + R*(F*[0, 0, 1]);
            body disc {{ mass: m, centre: C, orientation: F*rot_y(theta), inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4) }}
            lagrangian = kinetic_energy(disc) - m*g*C.z;
            constraints {{ rolls(disc, {args}); }}
        }}"
    )
}

#[test]
fn a_radius_is_a_positive_constant_of_the_parameters() {
    // (arguments, the culprit, what the message says)
    let cases = [
        ("radius: 0, axle: [0, 1, 0]", "0", "is zero"),
        ("radius: R - R, axle: [0, 1, 0]", "R - R", "is zero"),
        ("radius: -1/2, axle: [0, 1, 0]", "-1/2", "is negative"),
        ("radius: 1 - pi, axle: [0, 1, 0]", "1 - pi", "is negative"),
        ("radius: R*x, axle: [0, 1, 0]", "R*x", "the coordinate `x`"),
        ("radius: R + t, axle: [0, 1, 0]", "R + t", "the time `t`"),
        (
            "radius: R*dot(x), axle: [0, 1, 0]",
            "R*dot(x)",
            "the velocity `dot(x)`",
        ),
        (
            "radius: R, axle: [0, 1, 0], tube: 0",
            "0",
            "leave `tube` out",
        ),
        (
            "radius: R, axle: [0, 1, 0], tube: -R/R",
            "-R/R",
            "is negative",
        ),
    ];
    for (args, culprit, says) in cases {
        let found = errors(&disc(args));
        assert_eq!(found.len(), 1, "{args}: {found:?}");
        assert_eq!(found[0].0, culprit, "{args}: {found:?}");
        assert!(found[0].1.contains(says), "{args}: {}", found[0].1);
    }
    // a parameter expression is taken as given
    assert!(errors(&disc("radius: R, axle: [0, 1, 0]")).is_empty());
}

#[test]
fn an_axle_vertical_in_every_configuration_is_an_error_at_the_axle() {
    let found = errors(
        "struct Puck {
            parameters { m, R, g }
            coordinates { phi, x, y, z }
            body puck { mass: m, centre: [x, y, z], orientation: rot_z(phi), inertia: diag(1, 1, 2) }
            lagrangian = kinetic_energy(puck) - m*g*z;
            constraints { rolls(puck, radius: R, axle: [0, 0, 1]); }
        }",
    );
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "[0, 0, 1]");
    assert!(found[0].1.contains("vertical in every configuration"));
}

#[test]
fn a_centre_at_the_wrong_height_is_an_error_at_the_centre_with_both_heights() {
    let ball = |centre: &str| {
        errors(&format!(
            "struct Ball {{
                parameters {{ m, r }}
                coordinates {{ x, y, a, b, c }}
                body ball {{ mass: m, centre: [x, y, r], orientation: rot_z(a)*rot_y(b)*rot_x(c), inertia: diag(1, 1, 1) }}
                lagrangian = kinetic_energy(ball);
                constraints {{ rolls(ball, radius: r{centre}); }}
            }}"
        ))
    };
    assert!(ball("").is_empty());
    let found = ball(", centre: [x, y, 2*r]");
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "[x, y, 2*r]");
    assert!(
        found[0].1.contains("at height `2*r`") && found[0].1.contains("at height `r`"),
        "{}",
        found[0].1
    );
    // a wheel whose radius does not match its centre's height: the height
    // row would vanish only with the wheel flat; the error is at the body's centre
    let found = errors(&disc("radius: 2*R, axle: [0, 1, 0]"));
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].0, "C");
    assert!(found[0].1.contains("`2*cos(psi)*R`"), "{}", found[0].1);
    // a torus whose centre leaves out the tube
    let found = errors(&disc("radius: R, axle: [0, 1, 0], tube: R/10"));
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].1.contains("plus the tube"), "{}", found[0].1);
}

/// The stand-in's number of independent velocities, `K`, read from an
/// expansion with errors.
fn stand_in_k(src: &str) -> usize {
    let out = nh_core::expand(src.parse().expect("Rust tokens")).to_string();
    let key = "pub const K : :: core :: primitive :: usize = ";
    let at = out.find(key).expect("the stand-in has K") + key.len();
    out[at..]
        .split("usize")
        .next()
        .and_then(|k| k.trim().parse().ok())
        .expect("K is a number")
}

#[test]
fn the_stand_in_has_the_rows_lowering_counted() {
    // two wheels on one axle: 3 rows, not 4; the mistake is in a force
    let robot = "struct Robot {
        parameters { m, Ic, d, mw, Iw, Id, r, b, c }
        coordinates { x, y, theta, phi_l, phi_r }
        let heading = [cos(theta), sin(theta), 0];
        let axle = [-sin(theta), cos(theta), 0];
        let O = [x, y, r];
        body chassis { mass: m, centre: O + d*heading, orientation: rot_z(theta), inertia: diag(0, 0, Ic) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r);
        constraints { rolls(wheel_l, radius: r, axle: [0, 1, 0]); rolls(wheel_r, radius: r, axle: [0, 1, 0]); }
        forces { phi_l: -c*dot(phi_ll); }
    }";
    assert_eq!(errors(robot).len(), 1);
    assert_eq!(stand_in_k(robot), 2);
    // a disc whose height is a coordinate: its contact adds a height row
    let free = "struct Disc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y, z }
        let F = rot_z(phi) * rot_x(-psi);
        body disc { mass: m, centre: [x, y, z], orientation: F*rot_y(theta), inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4) }
        lagrangian = kinetic_energy(disc) - m*g*zz;
        constraints { rolls(disc, radius: R, axle: [0, 1, 0]); }
    }";
    assert_eq!(errors(free).len(), 1);
    assert_eq!(stand_in_k(free), 3);
    // an error found after the constraints were solved (an output)
    let late = free.replace("m*g*zz;", "m*g*z; outputs { energie }");
    assert_eq!(errors(&late).len(), 1);
    assert_eq!(stand_in_k(&late), 3);
}
