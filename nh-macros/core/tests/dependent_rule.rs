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
fn a_row_left_without_a_candidate_sends_the_rule_back() {
    // greedily the 1st row takes x, which the 2nd row alone involves: the
    // rule goes back and gives the 1st row y
    let out = expand(
        "x, y, z",
        "constraints { dot(x) + dot(y) = 0; 2*dot(x) = 0; }",
    );
    assert_eq!(dependent(&out), "[0usize,1usize]");
    assert!(
        out.contains("dot(x) + dot(y) = 0` (implicit): solved for `y`"),
        "{out}"
    );
    assert!(
        out.contains("2*dot(x) = 0` (implicit): solved for `x`"),
        "{out}"
    );
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

/// The messages of an expansion's errors.
fn errors(src: &str) -> Vec<String> {
    let expansion = nh_core::expand(src.parse().expect("Rust tokens"));
    nh_core::reported_errors(&expansion)
        .into_iter()
        .map(|e| e.message)
        .collect()
}

/// A system of coordinates `x, y, z, w` with `items` added.
fn four(items: &str) -> String {
    format!(
        "pub struct S {{ parameters {{ m }} coordinates {{ x, y, z, w }} \
         lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(z)^2 + dot(w)^2)/2; {items} }}"
    )
}

#[test]
fn a_list_in_the_wrong_order_gets_the_order_that_works() {
    let src = four(
        "constraints { dot(x) + z*dot(z) = 0; dot(y) + dot(x) = w*dot(w); } dependent { y, x }",
    );
    assert_eq!(
        errors(&src),
        [
            "`dot(y)` does not appear in the 1st implicit or holonomic constraint, `dot(x) + z*dot(z) = 0`, which `dependent { .. }` pairs with `y` (it lists one coordinate per such constraint, in the constraints' order); write `dependent { x, y }`: the same coordinates in an order that works"
        ]
    );
    // the order suggested is accepted
    let fixed = src.replace("dependent { y, x }", "dependent { x, y }");
    assert!(errors(&fixed).is_empty());
}

#[test]
fn a_velocity_that_an_explicit_row_cancels_is_said_to() {
    // written, the 1st implicit row has dot(x); dot(w) = -dot(x) cancels it
    let src = four(
        "constraints { dot(w) = -dot(x); dot(x) + dot(w) + z*dot(y) = 0; y*dot(x) + dot(z) = 0; } dependent { x, y }",
    );
    let found = errors(&src);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("`dot(x)` does not appear in the 1st implicit or holonomic constraint, `dot(x) + dot(w) + z*dot(y) = 0`, once the explicit constraints are substituted into it, which"),
        "{}",
        found[0]
    );
    assert!(
        found[0]
            .ends_with("write `dependent { y, x }`: the same coordinates in an order that works"),
        "{}",
        found[0]
    );
}

#[test]
fn a_holonomic_row_names_the_coordinate() {
    let src =
        four("constraints { y^2 + z^2 = 1; y*dot(x) = dot(z) + x*dot(w); } dependent { x, z }");
    let found = errors(&src);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("`x` does not appear in the 1st implicit or holonomic constraint, `y^2 + z^2 = 1`, which"),
        "{}",
        found[0]
    );
}

#[test]
fn rows_that_no_choice_solves_get_the_rules_error_once() {
    // the 2nd row repeats the 1st: no list of dependent coordinates works
    let src =
        four("constraints { dot(x) + dot(y) = 0; 2*dot(x) + 2*dot(y) = 0; } dependent { x, y }");
    let found = errors(&src);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0]
            .starts_with("this constraint cannot be solved for any velocity not already dependent"),
        "{}",
        found[0]
    );
}

#[test]
fn the_search_over_orders_of_eight_rows_is_bounded() {
    // eight rows, Vandermonde in x1..x8 but the last repeats the first:
    // every leading block is regular until the last, so the search sees
    // every set of columns before it gives up
    let names: Vec<String> = (1..=9).map(|i| format!("x{i}")).collect();
    let row = |a: i64| -> String {
        let terms: Vec<String> = (0..8)
            .map(|j| format!("{}*dot(x{})", (a + 1).pow(j as u32), j + 1))
            .collect();
        format!("{} = dot(x9);", terms.join(" + "))
    };
    let rows: Vec<String> = (0..7).map(row).chain([row(0)]).collect();
    let src = format!(
        "pub struct S {{ parameters {{ m }} coordinates {{ {} }} lagrangian = m*dot(x9)^2/2; \
         constraints {{ {} }} dependent {{ x8, x7, x6, x5, x4, x3, x2, x1 }} }}",
        names.join(", "),
        rows.join(" ")
    );
    let start = std::time::Instant::now();
    let found = errors(&src);
    assert!(
        start.elapsed().as_secs_f64() < 20.0,
        "{:?}",
        start.elapsed()
    );
    assert_eq!(found.len(), 1, "{found:?}");
}

/// A Segway: a body pitching (`alpha`) on a differential drive.
const SEGWAY: &str = "
    pub struct Segway {
        parameters { m, I1, I2, I3, l, mw, Iw, Id, r, b, g }
        coordinates { x, y, theta, alpha, phi_l, phi_r }
        let axle = [-sin(theta), cos(theta), 0];
        let O = [x, y, r];
        let B = rot_z(theta)*rot_y(alpha);
        body chassis { mass: m, centre: O + l*(B*[0, 0, 1]), orientation: B, inertia: diag(I1, I2, I3) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r) - m*g*l*cos(alpha);
        constraints {
            rolls(wheel_l, radius: r, axle: [0, 1, 0]);
            rolls(wheel_r, radius: r, axle: [0, 1, 0]);
        }
    }";

/// A differential-drive robot towing a two-wheeled trailer hitched at its
/// axle's centre (`beta`, the hitch angle).
const TOWING: &str = "
    pub struct Towing {
        parameters { m, Ic, mw, Iw, Id, r, b, L, mt, It }
        coordinates { x, y, theta, phi_l, phi_r, beta, psi_l, psi_r }
        let axle = [-sin(theta), cos(theta), 0];
        let O = [x, y, r];
        let T = rot_z(theta + beta);
        let H = O - L*(T*[1, 0, 0]);
        body chassis { mass: m, centre: O, orientation: rot_z(theta), inertia: diag(0, 0, Ic) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        body trailer { mass: mt, centre: H, orientation: T, inertia: diag(0, 0, It) }
        body trailer_l { mass: mw, centre: H + b*(T*[0, 1, 0]), orientation: T*rot_y(psi_l), inertia: diag(Id, Iw, Id) }
        body trailer_r { mass: mw, centre: H - b*(T*[0, 1, 0]), orientation: T*rot_y(psi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r)
                   + kinetic_energy(trailer) + kinetic_energy(trailer_l) + kinetic_energy(trailer_r);
        constraints {
            rolls(wheel_l, radius: r, axle: [0, 1, 0]);
            rolls(wheel_r, radius: r, axle: [0, 1, 0]);
            rolls(trailer_l, radius: r, axle: [0, 1, 0]);
            rolls(trailer_r, radius: r, axle: [0, 1, 0]);
        }
    }";

/// The coordinates each constraint is solved for, as the documentation of
/// `DEPENDENT` lists them (constraint: coordinate).
fn pairs(out: &str) -> Vec<String> {
    out.split("\\n - `")
        .skip(1)
        .filter_map(|s| {
            let (row, rest) = s.split_once('`')?;
            let (_, name) = rest.split_once("solved for `")?;
            Some(format!("{row}: {}", name.split('`').next()?))
        })
        .collect()
}

#[test]
fn a_wheeled_vehicle_keeps_its_wheels_rates_independent() {
    // the heading, on which the wheels' headings depend, is preferred to
    // the wheels' spins: the third row is solved for theta, not phi_r
    let out = nh_core::expand(SEGWAY.parse().expect("lexes")).to_string();
    assert_eq!(dependent(&out), "[0usize,1usize,2usize]");
    assert_eq!(
        pairs(&out),
        [
            "rolls(wheel_l, ..): no slip along x: x",
            "rolls(wheel_l, ..): no slip along y: y",
            "rolls(wheel_r, ..): no slip along x: theta",
        ]
    );
    // with the trailer, its hitch angle and its wheels' spins are dependent
    let out = nh_core::expand(TOWING.parse().expect("lexes")).to_string();
    assert_eq!(
        dependent(&out),
        "[0usize,1usize,2usize,5usize,6usize,7usize]"
    );
    assert!(
        out.contains(
            "pub const INDEPENDENT : [:: core :: primitive :: usize ; 2usize] = [3usize , 4usize]"
        ),
        "{}",
        &out[out.find("INDEPENDENT").unwrap_or(0)..][..120]
    );
}
