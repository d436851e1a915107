//! Systems the differential verification (`verify/`, DESIGN §11) found
//! wrong, shrunk to their core, against SymPy (`tests/data/regressions_sympy.py`).
//!
//! Both turned on a dependent velocity written as a negation (ż0 = −z1,
//! ż2 = −z1 ż0). Kane's terms take the rates of frames and chains along the
//! motion with every velocity held; the graph held the dependent velocity's
//! node, but folding it into its users (a + (−b) → a − b) made it vanish
//! into a subtraction of coordinates, whose rate was then taken: the bias
//! of s̈ was counted twice.
use nonholonomic::prelude::*;
use serde_json::Value;

nonholonomic_system! {
    /// A rotating body whose heading is a sum with a dependent coordinate,
    /// a constant last factor and products of inertia.
    pub struct HeldVelocity {
        parameters { k0, k1 }
        coordinates { z0, z1 }
        let R = rot_z(z1 + z0)*rot_x(z0)*rot_y(1);
        body b { mass: 1, centre: [0, 0, 0], orientation: R, inertia: [[1, k1/10, 0], [k1/10, 2, 0], [0, 0, k0]] }
        lagrangian = kinetic_energy(b);
        constraints { dot(z0) = -z1; }
    }
}

nonholonomic_system! {
    /// A point carried by a frame whose height is dependent.
    pub struct AnchoredPoint {
        parameters { k0 }
        coordinates { z0, z1, z2 }
        let R = rot_x(z2)*rot_x(z1);
        let C = [0, 0, z2];
        let P = C + R*[0, -1/2, k0];
        body p { mass: 1, centre: P }
        lagrangian = kinetic_energy(p) + dot(z0)^2/2;
        constraints { dot(z2) = -(z1*dot(z0)); }
    }
}

fn numbers(v: &Value) -> Vec<f64> {
    (v.as_array().expect("a list").iter())
        .map(|x| match x {
            Value::String(s) => s.parse().expect("a number"),
            other => other.as_f64().expect("a number"),
        })
        .collect()
}

fn cases(name: &str) -> Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let data: Value = serde_json::from_str(include_str!("data/regressions.json")).expect("JSON");
    (data[name].as_array().expect("cases").iter())
        .map(|c| (numbers(&c["q"]), numbers(&c["v"]), numbers(&c["rdd"])))
        .collect()
}

#[test]
fn a_held_dependent_velocity_in_a_frame() {
    let sys = HeldVelocity::new(1.5, 0.8);
    for (q, v, want) in cases("held_velocity") {
        let acc = sys.accelerations(
            0.0,
            &SVector::from_column_slice(&q),
            &SVector::from_column_slice(&v),
        );
        assert!(
            (acc[0] - want[0]).abs() < 1e-13 * want[0].abs().max(1.0),
            "{} against {}",
            acc[0],
            want[0]
        );
    }
}

#[test]
fn a_held_dependent_velocity_in_a_chain() {
    let sys = AnchoredPoint::new(1.2);
    for (q, v, want) in cases("anchored_point") {
        let acc = sys.accelerations(
            0.0,
            &SVector::from_column_slice(&q),
            &SVector::from_column_slice(&v),
        );
        for i in 0..2 {
            assert!(
                (acc[i] - want[i]).abs() < 1e-13 * want[i].abs().max(1.0),
                "{acc} against {want:?}"
            );
        }
    }
}
