//! The synthetic systems the size tests (`tests/scale.rs`, `tests/chains.rs`)
//! and the scaling tables (`examples/scaling.rs`, `examples/chains.rs`)
//! expand: one definition for all. Each includer uses some of them.
#![allow(dead_code)]

/// The dense family: n coordinates q1..qn, p = n/3 dense constraints
/// `dot(s_a) = Σ_α sin(q_α + s_a)/c dot(q_α)`, a dense mass matrix with
/// entries cos(q_i − q_j)/c, with the given `outputs` (may be empty).
pub fn dense(n: usize, outputs: &str) -> String {
    let (p, q) = (n / 3, (1..=n).map(|i| format!("q{i}")).collect::<Vec<_>>());
    let k = n - p;
    let mut terms = Vec::new();
    for i in 0..n {
        terms.push(format!("({}/10)*dot({})^2/2", 20 + i, q[i]));
        for j in (i + 1)..n {
            let c = (i + j + 2) * 2;
            terms.push(format!(
                "cos({} - {})*dot({})*dot({})/{c}",
                q[i], q[j], q[i], q[j]
            ));
        }
        terms.push(format!("g*cos({})/{}", q[i], i + 1));
    }
    let constraints: Vec<String> = (0..p)
        .map(|a| {
            let s = &q[k + a];
            let rhs: Vec<String> = (0..k)
                .map(|al| format!("sin({} + {s})/{}*dot({})", q[al], a + al + 2, q[al]))
                .collect();
            format!("dot({s}) = {};", rhs.join(" + "))
        })
        .collect();
    let outputs = if outputs.is_empty() {
        String::new()
    } else {
        format!("outputs {{ {outputs} }}")
    };
    format!(
        "pub struct Synth{n} {{ parameters {{ g }} coordinates {{ {} }} lagrangian = {}; constraints {{ {} }} {outputs} }}",
        q.join(", "),
        terms.join(" + "),
        constraints.join(" ")
    )
}

/// `let a{i+1} = a{i} + sin(a{i})/2;` n times; L uses only the last.
pub fn chain(n: usize) -> String {
    let lets: String = (0..n)
        .map(|i| format!("let a{} = a{i} + sin(a{i})/2; ", i + 1))
        .collect();
    format!(
        "pub struct Chain{n} {{ parameters {{ g }} coordinates {{ x, y }} let a0 = x; {lets}lagrangian = dot(a{n})^2/2 + dot(y)^2/2 - g*a{n}*y; }}"
    )
}

/// `outputs { .. }` listing `outputs`, or nothing when it is empty.
fn outputs_block(outputs: &str) -> String {
    if outputs.is_empty() {
        String::new()
    } else {
        format!("outputs {{ {outputs} }}")
    }
}

/// The `let`s and the body of link `i` (1-based) of a chain of uniform links
/// of length `l` along their x axis: its orientation `R{i}` is `turn`
/// applied after `R{i-1}` (or after `base` for the first link), its centre
/// `C{i}` halfway and its far end `E{i}` at the end of the link, starting from
/// `E{i-1}` (or from `origin`, `None` for the world origin). The body is
/// `{body}{i}`, with the fields `mass` and `inertia`.
fn link(
    i: usize,
    body: &str,
    base: &str,
    origin: Option<&str>,
    turn: &str,
    mass: &str,
    inertia: &str,
) -> String {
    let (parent, start) = if i == 1 {
        (base.to_string(), origin.map(|o| format!("{o} + ")))
    } else {
        (format!("R{}*", i - 1), Some(format!("E{} + ", i - 1)))
    };
    let start = start.unwrap_or_default();
    format!(
        "let R{i} = {parent}{turn}; let C{i} = {start}R{i}*[l/2, 0, 0]; let E{i} = {start}R{i}*[l, 0, 0]; \
         body {body}{i} {{ mass: {mass}, centre: C{i}, orientation: R{i}, inertia: {inertia} }} "
    )
}

/// Σ kinetic_energy(`{body}{i}`) − `weight`·(C1.`axis` + … + CN.`axis`)
/// for links 1..=n.
fn chain_lagrangian(n: usize, body: &str, weight: &str, axis: &str) -> String {
    let kinetic: Vec<String> = (1..=n)
        .map(|i| format!("kinetic_energy({body}{i})"))
        .collect();
    let heights: Vec<String> = (1..=n).map(|i| format!("C{i}.{axis}")).collect();
    format!(
        "lagrangian = {} - {weight}*({});",
        kinetic.join(" + "),
        heights.join(" + ")
    )
}

/// The planar chain of `n` uniform rigid links (a compound n-pendulum),
/// hinged at the origin, in the plane z = 0 with gravity along −y:
/// coordinates th1..thN, each link's angle relative to the one before;
/// link i has mass m, length l, inertia J about every axis through its
/// centre. `let R1 = rot_z(th1); let C1 = R1*[l/2, 0, 0]; let E1 = R1*[l, 0, 0];`,
/// then `let Ri = R{i-1}*rot_z(thi); let Ci = E{i-1} + Ri*[l/2, 0, 0]; ..`.
pub fn planar(n: usize, outputs: &str) -> String {
    let q: Vec<String> = (1..=n).map(|i| format!("th{i}")).collect();
    let links: String = (1..=n)
        .map(|i| {
            link(
                i,
                "b",
                "",
                None,
                &format!("rot_z(th{i})"),
                "m",
                "diag(J, J, J)",
            )
        })
        .collect();
    format!(
        "pub struct Planar{n} {{ parameters {{ m, l, J, g }} coordinates {{ {} }} {links}{} {} }}",
        q.join(", "),
        chain_lagrangian(n, "b", "m*g", "y"),
        outputs_block(outputs)
    )
}

/// The spatial chain of `n` uniform rigid links joined by universal joints,
/// hinged at the origin, gravity along −z: two coordinates per link, a_i
/// about the previous link's z axis, then b_i about the new y axis
/// (`let Ri = R{i-1}*rot_z(ai)*rot_y(bi);`), offsets along x as in
/// [`planar`]; body `link{i}` has mass m, length l, inertia diag(J1, J2, J2)
/// (J1 about its own axis).
pub fn spatial(n: usize, outputs: &str) -> String {
    let q: Vec<String> = (1..=n)
        .flat_map(|i| [format!("a{i}"), format!("b{i}")])
        .collect();
    let links: String = (1..=n)
        .map(|i| {
            let turn = format!("rot_z(a{i})*rot_y(b{i})");
            link(i, "link", "", None, &turn, "m", "diag(J1, J2, J2)")
        })
        .collect();
    format!(
        "pub struct Spatial{n} {{ parameters {{ m, l, J1, J2, g }} coordinates {{ {} }} {links}{} {} }}",
        q.join(", "),
        chain_lagrangian(n, "link", "m*g", "z"),
        outputs_block(outputs)
    )
}

/// A mobile manipulator: an arm of `n` uniform links on the
/// differential-drive robot of `examples/diff_drive.rs` (the root crate's;
/// axle midpoint (x, y), heading theta, wheels phi_l and phi_r of radius r at
/// ±b, chassis of mass m and yaw inertia Ic with its centre a distance d
/// ahead of the axle, the three rolling constraints written out, wheel rates
/// independent). The arm stands on the chassis at height h above the axle's
/// centre, a distance d ahead of it; joint 1 turns about the vertical
/// (`rot_z(q1)`), joints 2..N about the previous link's y axis
/// (`rot_y(qi)`); each link (body `link{i}`) has mass ma, length l, inertia
/// diag(Ja1, Ja2, Ja2); gravity along −z. No forces or inputs.
pub fn manipulator(n: usize, outputs: &str) -> String {
    let arm: Vec<String> = (1..=n).map(|i| format!("q{i}")).collect();
    let links: String = (1..=n)
        .map(|i| {
            let turn = if i == 1 {
                "rot_z(q1)".to_string()
            } else {
                format!("rot_y(q{i})")
            };
            link(
                i,
                "link",
                "F*",
                Some("A"),
                &turn,
                "ma",
                "diag(Ja1, Ja2, Ja2)",
            )
        })
        .collect();
    let base = "let F = rot_z(theta); let heading = [cos(theta), sin(theta), 0]; \
        let axle = [-sin(theta), cos(theta), 0]; let O = [x, y, r]; let A = O + d*heading + [0, 0, h]; \
        body chassis { mass: m, centre: O + d*heading, orientation: F, inertia: diag(0, 0, Ic) } \
        body wheel_l { mass: mw, centre: O + b*axle, orientation: F*rot_y(phi_l), inertia: diag(Id, Iw, Id) } \
        body wheel_r { mass: mw, centre: O - b*axle, orientation: F*rot_y(phi_r), inertia: diag(Id, Iw, Id) } ";
    let constraints = "constraints { dot(x) = r/2*(dot(phi_l) + dot(phi_r))*cos(theta); \
        dot(y) = r/2*(dot(phi_l) + dot(phi_r))*sin(theta); dot(theta) = r/(2*b)*(dot(phi_r) - dot(phi_l)); }";
    let arm_lagrangian = chain_lagrangian(n, "link", "ma*g", "z");
    let lagrangian = arm_lagrangian.replacen(
        "lagrangian = ",
        "lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r) + ",
        1,
    );
    format!(
        "pub struct Manipulator{n} {{ parameters {{ m, Ic, d, mw, Iw, Id, r, b, h, ma, l, Ja1, Ja2, g }} \
         coordinates {{ x, y, theta, phi_l, phi_r, {} }} {base}{links}{lagrangian} {constraints} {} }}",
        arm.join(", "),
        outputs_block(outputs)
    )
}
