//! The choice of dependent coordinates for implicit and holonomic constraints
//! (DESIGN §9): the rule, its fallback past a singular block, `dependent { .. }`,
//! the documentation of the choice, and which systems get the manifold hooks.

/// The expansion of a system with coordinates `coords` and the given items.
fn expand(coords: &str, items: &str) -> String {
    let src = format!(
        "pub struct S {{ parameters {{ m }} coordinates {{ {coords} }} \
         lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(z)^2)/2; {items} }}"
    );
    nh_core::expand(src.parse().expect("the test system lexes")).to_string()
}

/// The value of the `DEPENDENT` constant in an expansion.
fn dependent(out: &str) -> String {
    let at = out
        .find("pub const DEPENDENT")
        .expect("DEPENDENT is emitted");
    let rest = &out[at..];
    let value = &rest[rest.find('=').unwrap() + 1..];
    value[..value.find(';').unwrap()].replace(' ', "")
}

#[test]
fn without_a_constant_coefficient_the_last_declared_coordinate() {
    let out = expand("x, y, z", "constraints { z*dot(x) - x*dot(y) = 0; }");
    assert_eq!(dependent(&out), "[1usize]");
    assert!(out.contains("solved for `y`"), "{out}");
}

#[test]
fn a_constant_coefficient_first() {
    let out = expand("x, y, z", "constraints { dot(x)*z + 3*dot(z) = y*dot(y); }");
    assert_eq!(dependent(&out), "[2usize]");
}

#[test]
fn a_singular_block_moves_on_to_the_next_candidate() {
    // the second row's y would repeat the first row: z is taken instead
    let out = expand(
        "x, y, z",
        "constraints { dot(x) + dot(y) = 0; dot(x) + dot(y) + z*dot(z) = 0; }",
    );
    assert_eq!(dependent(&out), "[0usize,2usize]");
}

#[test]
fn named_dependent_coordinates_win() {
    let out = expand(
        "x, y, z",
        "constraints { z*dot(x) - x*dot(y) = 0; } dependent { x }",
    );
    assert_eq!(dependent(&out), "[0usize]");
    assert!(out.contains("solved for `x`"));
}

#[test]
fn only_implicit_and_holonomic_systems_get_the_manifold_hooks() {
    let explicit = expand("x, y, z", "constraints { dot(y) = z*dot(x); }");
    assert!(!explicit.contains("chart_regularity"));
    assert!(!explicit.contains("fn project ("));
    let implicit = expand("x, y, z", "constraints { z*dot(x) - x*dot(y) = 0; }");
    assert!(implicit.contains("fn chart_regularity"));
    assert!(!implicit.contains("fn project ("));
    let holonomic = expand("x, y, z", "constraints { x^2 + y^2 = 1; }");
    assert_eq!(dependent(&holonomic), "[1usize]");
    assert!(holonomic.contains("fn chart_regularity"));
    assert!(holonomic.contains("fn constraint_residual"));
    assert!(holonomic.contains("fn project"));
}

#[test]
fn an_affine_explicit_constraint_takes_the_multiplier_route() {
    let out = expand("x, y, z", "constraints { dot(y) = z*dot(x) + t; }");
    assert_eq!(dependent(&out), "[1usize]");
    assert!(out.contains("the curvature route needs homogeneous"));
    // its dependent velocity depends on time: `dependent_velocities` takes `t`
    assert!(out.contains("pub fn dependent_velocities (& self , t : T"));
}
