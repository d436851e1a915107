//! Rigid bodies in the language (DESIGN §10): a Chaplygin sphere written
//! with a body and a rolling contact, against an independent SymPy
//! derivation (`tests/data/chaplygin_sphere_sympy.py`: the multiplier method
//! with ω from Rᵀ Ṙ, cross-checked against SymPy's `KanesMethod`, at 24
//! random states and parameter sets, 40 digits); and the angular velocity of
//! a chain of rotations against its Euler-angle closed form.
use nonholonomic::prelude::*;
use serde_json::Value;

nonholonomic_system! {
    /// A ball of radius r rolling without slipping on z = 0, its centre of
    /// mass offset by b (body axes) from its geometric centre C, with a full
    /// inertia tensor about the centre of mass (products of inertia included).
    pub struct ChaplyginSphere {
        parameters { m, r, g, b1, b2, b3, I11, I22, I33, I12, I13, I23 }
        coordinates { yaw, pitch, roll, x, y }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);   // body → world
        let C = [x, y, r];                                  // geometric centre
        let G = C + Q*[b1, b2, b3];                         // centre of mass
        body ball {
            mass: m, centre: G, orientation: Q,
            inertia: [[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]],
        }
        lagrangian = kinetic_energy(ball) - m*g*G.z;
        constraints { rolls(ball, radius: r, centre: C); }
        outputs { energy, contact_points }
    }
}

fn numbers<const L: usize>(v: &Value) -> SVector<f64, L> {
    let a = v.as_array().expect("an array");
    assert_eq!(a.len(), L);
    SVector::from_fn(|i, _| a[i].as_f64().expect("a number"))
}

#[test]
fn chaplygin_sphere_agrees_with_sympy() {
    let data: Value =
        serde_json::from_str(include_str!("data/chaplygin_sphere.json")).expect("valid JSON");
    assert_eq!(ChaplyginSphere::<f64>::DEPENDENT, [3, 4]);
    let cases = data["cases"].as_array().expect("cases");
    assert!(cases.len() >= 20);
    let rel = |a: f64, b: f64| (a - b).abs() / (1.0 + b.abs());
    let (mut worst_acc, mut worst_vel, mut worst_energy) = (0.0_f64, 0.0_f64, 0.0_f64);
    for case in cases {
        let p: SVector<f64, 12> = numbers(&case["params"]);
        let ball = ChaplyginSphere::new(
            p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11],
        );
        let q: SVector<f64, 5> = numbers(&case["q"]);
        let rdot: SVector<f64, 3> = numbers(&case["rdot"]);
        let qdot: SVector<f64, 5> = numbers(&case["qdot"]);
        let qddot: SVector<f64, 5> = numbers(&case["qddot"]);
        let acc = ball.accelerations(0.0, &q, &rdot);
        let sdot = ball.dependent_velocities(&q, &rdot);
        for i in 0..3 {
            worst_acc = worst_acc.max(rel(acc[i], qddot[i]));
        }
        for i in 0..2 {
            worst_vel = worst_vel.max(rel(sdot[i], qdot[3 + i]));
        }
        // the contact point is below the geometric centre
        let p = ball.contact_points(&q);
        assert!((p[(0, 0)] - q[3]).abs() + (p[(1, 0)] - q[4]).abs() + p[(2, 0)].abs() < 1e-15);
        let e = case["energy"].as_f64().expect("energy");
        worst_energy = worst_energy.max(rel(ball.energy(&q, &rdot), e));
    }
    eprintln!(
        "Chaplygin sphere vs SymPy at {} states: accelerations {worst_acc:.1e}, dependent velocities {worst_vel:.1e}, energy {worst_energy:.1e}",
        cases.len()
    );
    assert!(worst_acc < 1e-12, "accelerations differ by {worst_acc:e}");
    assert!(
        worst_vel < 1e-12,
        "dependent velocities differ by {worst_vel:e}"
    );
    assert!(worst_energy < 1e-12, "energy differs by {worst_energy:e}");
}

nonholonomic_system! {
    /// The same ball written as two bodies: a shell of mass m1 centred on
    /// its geometric centre and a point mass m2 fixed in it at offset a (body
    /// axes). The engine moves the point mass with the shell (DESIGN §10:
    /// a centre fixed in another body's frame is folded into it).
    pub struct WeightedShell {
        parameters { m1, m2, r, g, a1, a2, a3, J11, J22, J33, J12, J13, J23 }
        coordinates { yaw, pitch, roll, x, y }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        let C = [x, y, r];
        let P = C + Q*[a1, a2, a3];
        body shell {
            mass: m1, centre: C, orientation: Q,
            inertia: [[J11, J12, J13], [J12, J22, J23], [J13, J23, J33]],
        }
        body weight { mass: m2, centre: P }
        lagrangian = kinetic_energy(shell) + kinetic_energy(weight) - g*(m1*C.z + m2*P.z);
        constraints { rolls(shell, radius: r); }
    }
}

/// The shell and weight that make up the ball of SymPy's case `p`
/// (m, r, g, b, I about the centre of mass): a fifth of the mass in the
/// weight at a = m b/m2, the shell's inertia what the parallel-axis theorem
/// leaves of I.
fn shell_and_weight(p: &SVector<f64, 12>) -> WeightedShell {
    let (m, b) = (p[0], Vector3::new(p[3], p[4], p[5]));
    let (m2, m1) = (0.2 * m, 0.8 * m);
    let a = b * (m / m2);
    let i = Matrix3::new(p[6], p[9], p[10], p[9], p[7], p[11], p[10], p[11], p[8]);
    let steiner =
        |mass: f64, d: Vector3<f64>| (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * mass;
    // I about G = shell's I about C shifted to G + the weight's point inertia about G
    let j = i - steiner(m1, b) - steiner(m2, a - b);
    WeightedShell::new(
        m1,
        m2,
        p[1],
        p[2],
        a[0],
        a[1],
        a[2],
        j[(0, 0)],
        j[(1, 1)],
        j[(2, 2)],
        j[(0, 1)],
        j[(0, 2)],
        j[(1, 2)],
    )
}

#[test]
fn a_point_mass_fixed_in_a_body_agrees_with_sympy() {
    let data: Value =
        serde_json::from_str(include_str!("data/chaplygin_sphere.json")).expect("valid JSON");
    let rel = |a: f64, b: f64| (a - b).abs() / (1.0 + b.abs());
    let mut worst = 0.0_f64;
    for case in data["cases"].as_array().expect("cases") {
        let ball = shell_and_weight(&numbers(&case["params"]));
        let q: SVector<f64, 5> = numbers(&case["q"]);
        let rdot: SVector<f64, 3> = numbers(&case["rdot"]);
        let qddot: SVector<f64, 5> = numbers(&case["qddot"]);
        let acc = ball.accelerations(0.0, &q, &rdot);
        for i in 0..3 {
            worst = worst.max(rel(acc[i], qddot[i]));
        }
    }
    eprintln!("shell with a point mass vs SymPy's Chaplygin sphere: accelerations {worst:.1e}");
    assert!(worst < 1e-11, "accelerations differ by {worst:e}");
}

nonholonomic_system! {
    /// A heavy top about a fixed point, its Lagrangian written with the body
    /// components of its angular velocity, `omega_body`.
    pub struct SpinningTop {
        parameters { A, B, C3, m, g, l }
        coordinates { psi, theta, phi }
        let Q = rot_z(psi) * rot_y(theta) * rot_x(phi);
        let w = omega_body(Q);
        lagrangian = (A*w.x^2 + B*w.y^2 + C3*w.z^2)/2 - m*g*l*(Q*[0, 0, 1]).z;
    }
}

nonholonomic_system! {
    /// [`SpinningTop`] with the world components `omega` and the inertia
    /// tensor turned into world axes, Q I Qᵀ.
    pub struct SpinningTopWorld {
        parameters { A, B, C3, m, g, l }
        coordinates { psi, theta, phi }
        let Q = rot_z(psi) * rot_y(theta) * rot_x(phi);
        let W = omega(Q);
        let I_world = Q * diag(A, B, C3) * transpose(Q);
        lagrangian = dot(W, I_world*W)/2 - m*g*l*(Q*[0, 0, 1]).z;
    }
}

nonholonomic_system! {
    /// [`SpinningTop`] with the body rates written out:
    /// w1 = φ̇ − ψ̇ sin θ, w2 = θ̇ cos φ + ψ̇ cos θ sin φ, w3 = ψ̇ cos θ cos φ − θ̇ sin φ.
    pub struct SpinningTopByHand {
        parameters { A, B, C3, m, g, l }
        coordinates { psi, theta, phi }
        let w1 = dot(phi) - dot(psi)*sin(theta);
        let w2 = dot(theta)*cos(phi) + dot(psi)*cos(theta)*sin(phi);
        let w3 = dot(psi)*cos(theta)*cos(phi) - dot(theta)*sin(phi);
        lagrangian = (A*w1^2 + B*w2^2 + C3*w3^2)/2 - m*g*l*cos(theta)*cos(phi);
    }
}

#[test]
fn body_rates_of_euler_angles_match_the_textbook() {
    let a = SpinningTop::new(0.3, 0.5, 0.7, 1.2, 9.81, 0.4);
    let world = SpinningTopWorld::new(0.3, 0.5, 0.7, 1.2, 9.81, 0.4);
    let b = SpinningTopByHand::new(0.3, 0.5, 0.7, 1.2, 9.81, 0.4);
    let mut worst = 0.0_f64;
    let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..20 {
        let q = SVector::<f64, 3>::from_fn(|_, _| next());
        let v = SVector::<f64, 3>::from_fn(|_, _| 4.0 * next());
        let y = b.accelerations(0.0, &q, &v);
        for x in [
            a.accelerations(0.0, &q, &v),
            world.accelerations(0.0, &q, &v),
        ] {
            worst = worst.max((x - y).amax() / (1.0 + y.amax()));
        }
    }
    assert!(
        worst < 1e-13,
        "omega/omega_body differ from the textbook body rates: {worst:e}"
    );
}
