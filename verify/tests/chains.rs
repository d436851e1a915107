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
/// among `coords`), weight γ (parameter 3) along `axis` with `sign`.
fn chain(
    name: &str,
    coords: Vec<String>,
    n: usize,
    turn: impl Fn(usize) -> Rx,
    (axis, sign): (usize, i64),
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
            [
                [x.clone(), num(0, 1), num(0, 1)],
                [num(0, 1), x.clone(), num(0, 1)],
                [num(0, 1), num(0, 1), x],
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

/// Requires agreement at one or more states, and prints the figures.
fn agrees(sys: &System) {
    let report = check_equations(sys, 34);
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
}

#[test]
fn a_long_chain_on_universal_joints_agrees_with_the_plain_derivation() {
    let n = 13;
    let coords = (1..=n)
        .flat_map(|i| [format!("a{i}"), format!("b{i}")])
        .collect();
    let turn = |i: usize| {
        let z = Rx::Elem(2, Box::new(Ex::Coord(2 * i)));
        let y = Rx::Elem(1, Box::new(Ex::Coord(2 * i + 1)));
        Rx::Mul(Box::new(z), Box::new(y))
    };
    agrees(&chain("Spatial13", coords, n, turn, (2, 1)));
}

#[test]
fn planar_chains_with_their_weight_along_y_and_x_agree_with_the_plain_derivation() {
    let n = 12;
    for (name, weight) in [("PlanarY", (1, 1)), ("PlanarX", (0, -1))] {
        let coords = (1..=n).map(|i| format!("th{i}")).collect();
        let turn = |i: usize| Rx::Elem(2, Box::new(Ex::Coord(i)));
        agrees(&chain(name, coords, n, turn, weight));
    }
}
