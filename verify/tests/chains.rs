//! Long chains of bodies against the plain derivation (issue 34, DESIGN
//! §12.6): the paths the random systems seldom reach, checked the same way.
//!
//! * a chain on universal joints of 13 links (26 coordinates), whose
//!   rotations' entries pass 256 terms from the 7th link on, so that the
//!   engine keeps them as atoms times the next factor's sines and cosines
//!   (`sym::SCALED_MIN`), its far links' kinetic energies folded;
//! * planar chains of 12 links with the weight along −y and along +x, which
//!   the engine takes through the partial velocities in the heading's frame.
//!
//! Each is built as the benchmark writes it (`R_i = R_(i-1)*turn`,
//! `C_i = E_(i-1) + R_i*[l/2, 0, 0]`, `E_i = E_(i-1) + R_i*[l, 0, 0]`) and
//! must agree at every usable state with the plain Euler–Lagrange equations
//! of its Lagrangian in double-double (the equations only: a momenta block
//! on the 13 links, which expands their kinetic energies again, exceeds the
//! engine's work limit).
use nh_verify::check::{Finding, check_equations};
use nh_verify::model::{Body, Ex, LetValue, Rx, System, Vx};

fn num(p: i64, q: i64) -> Ex {
    Ex::Num(p, q)
}

fn param(i: usize) -> Ex {
    Ex::Param(i)
}

/// The chain of `n` links turned by `turn(i)` (the coordinates it uses
/// among `coords`), weight γ (parameter 3) along `axis` with `sign`, each
/// link's principal moments J times `moments`.
fn chain(
    name: &str,
    coords: Vec<String>,
    n: usize,
    turn: impl Fn(usize) -> Rx,
    (axis, sign): (usize, i64),
    moments: [(i64, i64); 3],
) -> System {
    let mut lets: Vec<(String, LetValue)> = Vec::new();
    let mut bodies = Vec::new();
    let (l, m, j, g) = (param(0), param(1), param(2), param(3));
    for i in 0..n {
        let r = match i {
            0 => turn(0),
            _ => Rx::Mul(Box::new(Rx::Let(lets.len() - 3)), Box::new(turn(i))),
        };
        let r_at = lets.len();
        lets.push((format!("R{}", i + 1), LetValue::Rotation(r)));
        let along = |scale: Ex| {
            let offset = Vx::Lit(Box::new([scale, num(0, 1), num(0, 1)]));
            Vx::Rot(Box::new(Rx::Let(r_at)), Box::new(offset))
        };
        let from = |v: Vx| match i {
            0 => v,
            _ => Vx::Add(Box::new(Vx::Let(r_at - 1)), Box::new(v)),
        };
        let half = Ex::Mul(vec![num(1, 2), l.clone()]);
        lets.push((format!("C{}", i + 1), LetValue::Vector(from(along(half)))));
        lets.push((
            format!("E{}", i + 1),
            LetValue::Vector(from(along(l.clone()))),
        ));
        let diag = |x: Ex| {
            let d = |a: usize| {
                let (p, q) = moments[a];
                Ex::Mul(vec![num(p, q), x.clone()])
            };
            [
                [d(0), num(0, 1), num(0, 1)],
                [num(0, 1), d(1), num(0, 1)],
                [num(0, 1), num(0, 1), d(2)],
            ]
        };
        bodies.push((
            format!("link{}", i + 1),
            Body {
                mass: m.clone(),
                centre: Vx::Let(r_at + 1),
                rotation: Some((Rx::Let(r_at), diag(j.clone()))),
                diagonal: true,
            },
        ));
    }
    let kinetic: Vec<Ex> = (0..n).map(Ex::Kinetic).collect();
    let heights: Vec<Ex> = (0..n)
        .map(|i| Ex::Comp(Box::new(Vx::Let(3 * i + 1)), axis))
        .collect();
    let weight = Ex::Mul(vec![num(sign, 1), m.clone(), g, Ex::Add(heights)]);
    System {
        name: name.to_string(),
        params: ["l", "m", "J", "g"].map(String::from).to_vec(),
        coords,
        inputs: Vec::new(),
        lets,
        bodies,
        lagrangian: Ex::Sub(Box::new(Ex::Add(kinetic)), Box::new(weight)),
        forces: Vec::new(),
        constraints: Vec::new(),
        dependent: None,
        speeds: None,
        outputs: Vec::new(),
    }
}

/// Requires agreement at one or more states, and prints the figures;
/// returns what the composite inertias took.
fn agrees(sys: &System) -> nh_core::Taken {
    let (report, taken) = nh_core::with_composite_inertias(|| check_equations(sys, 34));
    match report.finding {
        Finding::Agree {
            worst,
            worst_exact,
            states,
        } => {
            eprintln!(
                "{}: {states} states, worst {worst:.1e} in f64, {worst_exact:.1e} in double-double",
                sys.name
            );
            assert!(states >= 1, "{}: no state compared", sys.name);
        }
        other => panic!("{}: {other:?}\n{}", sys.name, sys.text()),
    }
    taken
}

#[test]
fn a_long_chain_on_universal_joints_agrees_with_the_plain_derivation() {
    let n = 13;
    let coords: Vec<String> = (1..=n)
        .flat_map(|i| [format!("a{i}"), format!("b{i}")])
        .collect();
    let turn = |i: usize| {
        let z = Rx::Elem(2, Box::new(Ex::Coord(2 * i)));
        let y = Rx::Elem(1, Box::new(Ex::Coord(2 * i + 1)));
        Rx::Mul(Box::new(z), Box::new(y))
    };
    // equal moments: each link symmetric about its last joint's axis (a
    // spin, which its own sums turn out), carried in its full frame;
    // unequal moments: carried in its frame. Either way every link is a
    // composite inertia and the reduced system is solved by the
    // articulated-body recursion.
    for (name, moments) in [
        ("Spatial13", [(1, 1); 3]),
        ("Spatial13b", [(1, 1), (1, 2), (3, 4)]),
    ] {
        let taken = agrees(&chain(name, coords.clone(), n, turn, (2, 1), moments));
        assert!(taken.groups >= 1 && taken.articulated >= 1, "{taken:?}");
    }
}

#[test]
fn planar_chains_with_their_weight_along_y_and_x_agree_with_the_plain_derivation() {
    let n = 12;
    for (name, weight) in [("PlanarY", (1, 1)), ("PlanarX", (0, -1))] {
        let coords = (1..=n).map(|i| format!("th{i}")).collect();
        let turn = |i: usize| Rx::Elem(2, Box::new(Ex::Coord(i)));
        let taken = agrees(&chain(name, coords, n, turn, weight, [(1, 1); 3]));
        assert!(taken.groups >= 1 && taken.articulated >= 1, "{taken:?}");
    }
}
