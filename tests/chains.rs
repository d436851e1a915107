//! The planar chain of the scaling benchmark (issue 34;
//! `nh-macros/core/tests/synthetic/mod.rs`, `planar`) with 2, 3, 10 and 12
//! links:
//!
//! * the bodies expanded here are the benchmark's, token for token;
//! * their `accelerations` agree to 1e-12 (relative to the largest
//!   acceleration of the state) with an independent SymPy derivation at 8
//!   states each (`tests/data/chains_sympy.py`: the Euler–Lagrange equations
//!   in the links' absolute angles, without rotations or bodies, solved at 50
//!   digits; for 2 links it also checks them against the closed form of the
//!   compound double pendulum); for 10 links the energy too.
use nonholonomic::prelude::*;

#[path = "common/differences.rs"]
mod central;
#[path = "../nh-macros/core/tests/synthetic/mod.rs"]
mod synthetic;

/// Expands the body as a system and keeps its text as `$text`, to compare
/// with the benchmark's generator.
macro_rules! system_with_text {
    ($text:ident: $($body:tt)*) => {
        nonholonomic_system! { $($body)* }
        /// The body as written.
        const $text: &str = stringify!($($body)*);
    };
}

system_with_text! { PLANAR2:
    pub struct Planar2 {
        parameters { m, l, J, g }
        coordinates { th1, th2 }
        let R1 = rot_z(th1);
        let C1 = R1*[l/2, 0, 0];
        let E1 = R1*[l, 0, 0];
        body b1 { mass: m, centre: C1, orientation: R1, inertia: diag(J, J, J) }
        let R2 = R1*rot_z(th2);
        let C2 = E1 + R2*[l/2, 0, 0];
        let E2 = E1 + R2*[l, 0, 0];
        body b2 { mass: m, centre: C2, orientation: R2, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(b1) + kinetic_energy(b2) - m*g*(C1.y + C2.y);
    }
}

system_with_text! { PLANAR3:
    pub struct Planar3 {
        parameters { m, l, J, g }
        coordinates { th1, th2, th3 }
        let R1 = rot_z(th1);
        let C1 = R1*[l/2, 0, 0];
        let E1 = R1*[l, 0, 0];
        body b1 { mass: m, centre: C1, orientation: R1, inertia: diag(J, J, J) }
        let R2 = R1*rot_z(th2);
        let C2 = E1 + R2*[l/2, 0, 0];
        let E2 = E1 + R2*[l, 0, 0];
        body b2 { mass: m, centre: C2, orientation: R2, inertia: diag(J, J, J) }
        let R3 = R2*rot_z(th3);
        let C3 = E2 + R3*[l/2, 0, 0];
        let E3 = E2 + R3*[l, 0, 0];
        body b3 { mass: m, centre: C3, orientation: R3, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(b1) + kinetic_energy(b2) + kinetic_energy(b3)
                   - m*g*(C1.y + C2.y + C3.y);
        outputs { jacobian }
    }
}

system_with_text! { PLANAR10:
    pub struct Planar10 {
        parameters { m, l, J, g }
        coordinates { th1, th2, th3, th4, th5, th6, th7, th8, th9, th10 }
        let R1 = rot_z(th1);
        let C1 = R1*[l/2, 0, 0];
        let E1 = R1*[l, 0, 0];
        body b1 { mass: m, centre: C1, orientation: R1, inertia: diag(J, J, J) }
        let R2 = R1*rot_z(th2);
        let C2 = E1 + R2*[l/2, 0, 0];
        let E2 = E1 + R2*[l, 0, 0];
        body b2 { mass: m, centre: C2, orientation: R2, inertia: diag(J, J, J) }
        let R3 = R2*rot_z(th3);
        let C3 = E2 + R3*[l/2, 0, 0];
        let E3 = E2 + R3*[l, 0, 0];
        body b3 { mass: m, centre: C3, orientation: R3, inertia: diag(J, J, J) }
        let R4 = R3*rot_z(th4);
        let C4 = E3 + R4*[l/2, 0, 0];
        let E4 = E3 + R4*[l, 0, 0];
        body b4 { mass: m, centre: C4, orientation: R4, inertia: diag(J, J, J) }
        let R5 = R4*rot_z(th5);
        let C5 = E4 + R5*[l/2, 0, 0];
        let E5 = E4 + R5*[l, 0, 0];
        body b5 { mass: m, centre: C5, orientation: R5, inertia: diag(J, J, J) }
        let R6 = R5*rot_z(th6);
        let C6 = E5 + R6*[l/2, 0, 0];
        let E6 = E5 + R6*[l, 0, 0];
        body b6 { mass: m, centre: C6, orientation: R6, inertia: diag(J, J, J) }
        let R7 = R6*rot_z(th7);
        let C7 = E6 + R7*[l/2, 0, 0];
        let E7 = E6 + R7*[l, 0, 0];
        body b7 { mass: m, centre: C7, orientation: R7, inertia: diag(J, J, J) }
        let R8 = R7*rot_z(th8);
        let C8 = E7 + R8*[l/2, 0, 0];
        let E8 = E7 + R8*[l, 0, 0];
        body b8 { mass: m, centre: C8, orientation: R8, inertia: diag(J, J, J) }
        let R9 = R8*rot_z(th9);
        let C9 = E8 + R9*[l/2, 0, 0];
        let E9 = E8 + R9*[l, 0, 0];
        body b9 { mass: m, centre: C9, orientation: R9, inertia: diag(J, J, J) }
        let R10 = R9*rot_z(th10);
        let C10 = E9 + R10*[l/2, 0, 0];
        let E10 = E9 + R10*[l, 0, 0];
        body b10 { mass: m, centre: C10, orientation: R10, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(b1) + kinetic_energy(b2) + kinetic_energy(b3) + kinetic_energy(b4) + kinetic_energy(b5) + kinetic_energy(b6) + kinetic_energy(b7) + kinetic_energy(b8) + kinetic_energy(b9) + kinetic_energy(b10)
                   - m*g*(C1.y + C2.y + C3.y + C4.y + C5.y + C6.y + C7.y + C8.y + C9.y + C10.y);
        outputs { energy }
    }
}

system_with_text! { PLANAR12:
    pub struct Planar12 {
        parameters { m, l, J, g }
        coordinates { th1, th2, th3, th4, th5, th6, th7, th8, th9, th10, th11, th12 }
        let R1 = rot_z(th1);
        let C1 = R1*[l/2, 0, 0];
        let E1 = R1*[l, 0, 0];
        body b1 { mass: m, centre: C1, orientation: R1, inertia: diag(J, J, J) }
        let R2 = R1*rot_z(th2);
        let C2 = E1 + R2*[l/2, 0, 0];
        let E2 = E1 + R2*[l, 0, 0];
        body b2 { mass: m, centre: C2, orientation: R2, inertia: diag(J, J, J) }
        let R3 = R2*rot_z(th3);
        let C3 = E2 + R3*[l/2, 0, 0];
        let E3 = E2 + R3*[l, 0, 0];
        body b3 { mass: m, centre: C3, orientation: R3, inertia: diag(J, J, J) }
        let R4 = R3*rot_z(th4);
        let C4 = E3 + R4*[l/2, 0, 0];
        let E4 = E3 + R4*[l, 0, 0];
        body b4 { mass: m, centre: C4, orientation: R4, inertia: diag(J, J, J) }
        let R5 = R4*rot_z(th5);
        let C5 = E4 + R5*[l/2, 0, 0];
        let E5 = E4 + R5*[l, 0, 0];
        body b5 { mass: m, centre: C5, orientation: R5, inertia: diag(J, J, J) }
        let R6 = R5*rot_z(th6);
        let C6 = E5 + R6*[l/2, 0, 0];
        let E6 = E5 + R6*[l, 0, 0];
        body b6 { mass: m, centre: C6, orientation: R6, inertia: diag(J, J, J) }
        let R7 = R6*rot_z(th7);
        let C7 = E6 + R7*[l/2, 0, 0];
        let E7 = E6 + R7*[l, 0, 0];
        body b7 { mass: m, centre: C7, orientation: R7, inertia: diag(J, J, J) }
        let R8 = R7*rot_z(th8);
        let C8 = E7 + R8*[l/2, 0, 0];
        let E8 = E7 + R8*[l, 0, 0];
        body b8 { mass: m, centre: C8, orientation: R8, inertia: diag(J, J, J) }
        let R9 = R8*rot_z(th9);
        let C9 = E8 + R9*[l/2, 0, 0];
        let E9 = E8 + R9*[l, 0, 0];
        body b9 { mass: m, centre: C9, orientation: R9, inertia: diag(J, J, J) }
        let R10 = R9*rot_z(th10);
        let C10 = E9 + R10*[l/2, 0, 0];
        let E10 = E9 + R10*[l, 0, 0];
        body b10 { mass: m, centre: C10, orientation: R10, inertia: diag(J, J, J) }
        let R11 = R10*rot_z(th11);
        let C11 = E10 + R11*[l/2, 0, 0];
        let E11 = E10 + R11*[l, 0, 0];
        body b11 { mass: m, centre: C11, orientation: R11, inertia: diag(J, J, J) }
        let R12 = R11*rot_z(th12);
        let C12 = E11 + R12*[l/2, 0, 0];
        let E12 = E11 + R12*[l, 0, 0];
        body b12 { mass: m, centre: C12, orientation: R12, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(b1) + kinetic_energy(b2) + kinetic_energy(b3) + kinetic_energy(b4) + kinetic_energy(b5) + kinetic_energy(b6) + kinetic_energy(b7) + kinetic_energy(b8) + kinetic_energy(b9) + kinetic_energy(b10) + kinetic_energy(b11) + kinetic_energy(b12)
                   - m*g*(C1.y + C2.y + C3.y + C4.y + C5.y + C6.y + C7.y + C8.y + C9.y + C10.y + C11.y + C12.y);
        outputs { jacobian }
    }
}

/// `s` without whitespace.
fn squeezed(s: &str) -> String {
    s.split_whitespace().collect()
}

#[test]
fn the_systems_are_the_benchmarks() {
    assert_eq!(squeezed(PLANAR2), squeezed(&synthetic::planar(2, "")));
    assert_eq!(
        squeezed(PLANAR3),
        squeezed(&synthetic::planar(3, "jacobian"))
    );
    assert_eq!(
        squeezed(PLANAR10),
        squeezed(&synthetic::planar(10, "energy"))
    );
    assert_eq!(
        squeezed(PLANAR12),
        squeezed(&synthetic::planar(12, "jacobian"))
    );
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// SymPy's data, its parameters (m, l, J, g) and the cases of `key`:
/// (q, rdot, accelerations) each.
fn reference(key: &str) -> ([f64; 4], Vec<[Vec<f64>; 3]>) {
    let data: serde_json::Value =
        serde_json::from_str(include_str!("data/chains.json")).expect("the reference lexes");
    let p = &data["parameters"];
    let get = |name: &str| p[name].as_f64().expect(name);
    let cases = data[key]
        .as_array()
        .expect("the cases")
        .iter()
        .map(|c| {
            [
                numbers(&c["q"]),
                numbers(&c["rdot"]),
                numbers(&c["accelerations"]),
            ]
        })
        .collect();
    ([get("m"), get("l"), get("J"), get("g")], cases)
}

/// The largest difference of `a` from `reference`, relative to the largest
/// reference acceleration.
fn relative_error(a: &[f64], reference: &[f64]) -> f64 {
    let scale = reference.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
    a.iter()
        .zip(reference)
        .map(|(x, r)| (x - r).abs() / scale)
        .fold(0.0, f64::max)
}

/// The largest relative error of `accelerations` over the cases of `key`,
/// each required within 1e-12.
fn agreement_with_sympy(key: &str, accelerations: impl Fn([f64; 4], &[f64], &[f64]) -> Vec<f64>) {
    let (parameters, cases) = reference(key);
    assert_eq!(cases.len(), 8);
    let mut worst = 0.0_f64;
    for [q, rdot, expected] in &cases {
        let a = accelerations(parameters, q, rdot);
        let err = relative_error(&a, expected);
        assert!(
            err <= 1e-12,
            "q = {q:?}, rdot = {rdot:?}: {a:?} against {expected:?} ({err:.1e})"
        );
        worst = worst.max(err);
    }
    eprintln!("{key}: largest relative error {worst:.1e}");
}

/// `accelerations` of the system `$sys` (parameters `$params`) against the
/// cases of `$key`.
macro_rules! against_sympy {
    ($key:literal, $sys:ident, $params:ident) => {
        agreement_with_sympy($key, |[m, l, j, g], q, rdot| {
            let sys = $sys::from_parameters($params { m, l, J: j, g });
            let (q, rdot) = (
                SVector::from_column_slice(q),
                SVector::from_column_slice(rdot),
            );
            sys.accelerations(0.0, &q, &rdot).as_slice().to_vec()
        })
    };
}

#[test]
fn double_pendulum_agrees_with_sympy() {
    against_sympy!("planar2", Planar2, Planar2Parameters);
}

#[test]
fn triple_pendulum_agrees_with_sympy() {
    against_sympy!("planar3", Planar3, Planar3Parameters);
}

/// Ten links: the far links' kinetic energies are folded into symbols in
/// the Lagrangian (their expansions are large, DESIGN §12.6) and Kane's
/// form takes the bodies, with the weight along −y through the partial
/// velocities; `energy` expands them again.
#[test]
fn ten_links_agree_with_sympy() {
    against_sympy!("planar10", Planar10, Planar10Parameters);
}

/// The energy of the ten links, from the Lagrangian with the folded
/// kinetic energies expanded, against SymPy's T + V at the same 8 states
/// (1e-12 relative).
#[test]
fn ten_links_energy_agrees_with_sympy() {
    let data: serde_json::Value =
        serde_json::from_str(include_str!("data/chains.json")).expect("the reference lexes");
    let (parameters, cases) = reference("planar10");
    let [m, l, j, g] = parameters;
    let sys = Planar10::from_parameters(Planar10Parameters { m, l, J: j, g });
    let mut worst = 0.0_f64;
    for (case, [q, rdot, _]) in data["planar10"]
        .as_array()
        .expect("cases")
        .iter()
        .zip(&cases)
    {
        let expected = case["energy"].as_f64().expect("an energy");
        let (q, rdot) = (
            SVector::from_column_slice(q),
            SVector::from_column_slice(rdot),
        );
        let energy = sys.energy(&q, &rdot);
        let err = (energy - expected).abs() / expected.abs();
        assert!(err <= 1e-12, "{energy} against {expected} ({err:.1e})");
        worst = worst.max(err);
    }
    eprintln!("planar10 energy: largest relative error {worst:.1e}");
}

/// The worst deviation of `sys`'s `jacobian` from central differences
/// (steps `step` max(1, |x_c|)) of its right side at 8 states, each
/// coordinate and speed drawn from (−`spread`, `spread`) by xorshift from
/// `seed`.
fn worst_jacobian_deviation<S, const D: usize>(
    sys: &S,
    mut seed: u64,
    spread: f64,
    step: f64,
) -> f64
where
    S: nonholonomic::runtime::OdeJacobian<f64, D>,
{
    let mut uniform = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        spread * (2.0 * (seed >> 11) as f64 / (1u64 << 53) as f64 - 1.0)
    };
    let mut worst = 0.0_f64;
    for _ in 0..8 {
        let x = SVector::<f64, D>::from_fn(|_, _| uniform());
        let jac = sys.jacobian(0.0, &x);
        let deviation = central::jacobian_deviation_with_step(|y| sys.rhs(0.0, y), &jac, &x, step);
        worst = worst.max(deviation);
    }
    eprintln!("jacobian against central differences: worst {worst:.1e}");
    worst
}

/// `jacobian`, differentiated forward through the bodies' sums (Kane's
/// equations at the solved accelerations, DESIGN §8.1), against central
/// differences of the right side at 8 states.
#[test]
fn triple_pendulum_jacobian_matches_central_differences() {
    let sys = Planar3::new(1.3, 0.7, 0.05, 9.81);
    let worst = worst_jacobian_deviation(&sys, 0x5EED_1234_ABCD_0002, 2.0, 1e-6);
    assert!(worst < 1e-6, "deviation {worst:.1e}");
}

/// The same for 12 links, whose accelerations and Jacobian columns are
/// solved by the articulated-body recursion on the links' tree (DESIGN
/// §10), with steps of 1e-4 (at these states the differences' rounding at
/// steps of 1e-6 reaches 2e-6 and their truncation at 1e-3 2e-5, falling a
/// hundredfold to 1e-4, where the worst deviation is 3.1e-7: the h² of the
/// differences, not the Jacobian's).
#[test]
fn twelve_links_jacobian_matches_central_differences() {
    let sys = Planar12::new(1.3, 0.7, 0.05, 9.81);
    let worst = worst_jacobian_deviation(&sys, 0x5EED_1234_ABCD_0012, 1.5, 1e-4);
    assert!(worst < 1e-6, "deviation {worst:.1e}");
}
