//! The functions of the language beyond sin, cos, tan, exp, ln and sqrt:
//! `atan2`, `abs`, `cot`, `sec`, `csc`, `sinh`, `cosh`, `tanh`, `asin`,
//! `acos`, `atan`. Accelerations whose derivation differentiates each of
//! them agree with SymPy's (tests/data/functions_sympy.py, 30 digits, in
//! tests/data/functions.json); `abs` has the derivative 0 at 0, and
//! `sqrt(x^2)` is `abs(x)`; names of the new functions still name
//! coordinates and parameters.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A particle in the plane with an inertia cosh(y)² on y and a potential
    /// that uses every new function.
    pub struct Gauntlet {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + cosh(y)^2*dot(y)^2)
            - k*(atan2(y, x + 2) + abs(x*y - 1/5) + cot(x + 1) + sec(y/2) + csc(x + 2)
                 + sinh(x*y) + tanh(x - y) + asin(x/3) + acos(y/4) + atan(x*y));
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// A particle held by a torsion spring on its polar angle and a conical
    /// potential on its distance from the origin.
    pub struct PolarSpring {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) - k*atan2(y, x)^2/2 - sqrt(x^2 + y^2);
    }
}

/// A decimal or a fraction `n/d` of the reference file.
fn number(v: &serde_json::Value) -> f64 {
    let s = v.as_str().expect("a number as a string");
    match s.split_once('/') {
        Some((n, d)) => n.parse::<f64>().unwrap() / d.parse::<f64>().unwrap(),
        None => s.parse().unwrap(),
    }
}

/// The reference points of one system: (q, q̇, q̈).
fn reference(system: &str) -> Vec<([f64; 2], [f64; 2], [f64; 2])> {
    let text = include_str!("data/functions.json");
    let data: serde_json::Value = serde_json::from_str(text).unwrap();
    assert_eq!((number(&data["m"]), number(&data["k"])), (1.5, 0.7));
    let pair = |v: &serde_json::Value| [number(&v[0]), number(&v[1])];
    data[system]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (pair(&p["q"]), pair(&p["qdot"]), pair(&p["qddot"])))
        .collect()
}

fn assert_close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12 * want.abs().max(1.0),
        "{what}: {got} vs {want}"
    );
}

#[test]
fn every_new_function_differentiates_as_sympy_does() {
    let s = Gauntlet::new(1.5, 0.7);
    let points = reference("gauntlet");
    assert_eq!(points.len(), 3);
    for (q, v, want) in points {
        let a = s.accelerations(0.0, &SVector::from(q), &SVector::from(v));
        for i in 0..2 {
            assert_close(a[i], want[i], &format!("gauntlet q̈{i} at {q:?}"));
        }
    }
}

#[test]
fn second_derivatives_agree_with_central_differences() {
    // the Jacobian of the right side differentiates every function twice
    // (the sign, the derivative of abs, has the derivative 0 away from 0)
    let s = Gauntlet::new(1.5, 0.7);
    for (q, v, _) in reference("gauntlet") {
        let x = SVector::<f64, 4>::from([q[0], q[1], v[0], v[1]]);
        let jac = s.jacobian(0.0, &x);
        for c in 0..4 {
            let h = 1e-6;
            let (mut xp, mut xm) = (x, x);
            xp[c] += h;
            xm[c] -= h;
            let column = (s.rhs(0.0, &xp) - s.rhs(0.0, &xm)) / (2.0 * h);
            for r in 0..4 {
                let (got, want) = (jac[(r, c)], column[r]);
                assert!(
                    (got - want).abs() <= 1e-6 * want.abs().max(1.0),
                    "∂ẋ{r}/∂x{c} at {x:?}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn atan2_differentiates_in_every_quadrant() {
    let s = PolarSpring::new(1.5, 0.7);
    for (q, v, want) in reference("polar_spring") {
        let a = s.accelerations(0.0, &SVector::from(q), &SVector::from(v));
        for i in 0..2 {
            assert_close(a[i], want[i], &format!("polar spring q̈{i} at {q:?}"));
        }
    }
}

nonholonomic_system! {
    /// A particle in a V-shaped potential k|x|, written twice.
    pub struct Vee {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) - k*abs(x) - k*sqrt(y^2);
    }
}

#[test]
fn abs_has_the_derivative_sign_and_zero_at_zero() {
    let s = Vee::new(2.0, 3.0);
    let v = SVector::from([0.0, 0.0]);
    for (x, expect) in [(0.5, -1.5), (-0.25, 1.5), (0.0, 0.0)] {
        // the force is −k sign(x), taken as 0 at x = 0 (not NaN)
        let a = s.accelerations(0.0, &SVector::from([x, x]), &v);
        assert_eq!(a[0], expect, "abs at {x}");
        // sqrt(y²) is |y|: the same force, also at 0
        assert_eq!(a[1], expect, "sqrt(y^2) at {x}");
    }
}

nonholonomic_system! {
    /// Names of the new functions used as names: they are functions only
    /// where they are called.
    pub struct NamedLikeFunctions {
        parameters { m, cosh }
        coordinates { atan, sinh }
        let abs = atan^2 + sinh^2;
        lagrangian = m/2*(dot(atan)^2 + dot(sinh)^2) - cosh*abs(atan) - abs;
    }
}

#[test]
fn function_names_still_name_coordinates_parameters_and_lets() {
    let s = NamedLikeFunctions::new(2.0, 3.0);
    let (a, b) = (-0.5, 0.25);
    let acc = s.accelerations(0.0, &SVector::from([a, b]), &SVector::from([0.1, 0.2]));
    // m ä = cosh·1 − 2a (a < 0), m b̈ = −2b
    assert_close(acc[0], (3.0 - 2.0 * a) / 2.0, "atan");
    assert_close(acc[1], -2.0 * b / 2.0, "sinh");
    assert_eq!(NamedLikeFunctions::<f64>::COORDINATES, ["atan", "sinh"]);
}

nonholonomic_system! {
    /// A pendulum of length l whose exact values at constant arguments fold:
    /// acos(0) = π/2, atan2(1, 0) = π/2, atan(1) = π/4, asin(1/2) = π/6.
    pub struct FoldedConstants {
        parameters { m, g, l }
        coordinates { theta }
        lagrangian = m*l^2/2*dot(theta)^2 + m*g*l*cos(theta - acos(0) + atan2(1, 0) - 4*atan(1) + 6*asin(1/2));
    }
}

#[test]
fn exact_values_at_constant_arguments() {
    let s = FoldedConstants::new(1.0, 9.81, 2.0);
    // the shift −π/2 + π/2 − π + π is 0: a plain pendulum, θ̈ = −g/l sin θ
    let theta = 0.4_f64;
    let a = s.accelerations(0.0, &SVector::from([theta]), &SVector::from([0.0]))[0];
    assert_close(a, -9.81 / 2.0 * theta.sin(), "pendulum");
}
