//! Three bodies whose equations Kane's form got wrong (issue 29), each
//! against a hand derivation: a coordinate of the orientation's chain made
//! dependent by an implicit constraint (against the same kinetic energy
//! written out with `omega_body` and `dot(C)`, and against SymPy), an
//! orientation turning with t (closed form) and a mass that depends on a
//! coordinate (closed form).
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Repeated z axes, the second angle made dependent by an implicit row.
    pub struct ChainBody {
        parameters { m, g }
        coordinates { q0, q1, q2 }
        let R = rot_z(q0)*rot_z(q2)*rot_y(q1);
        let C = [cos(q0), q1, sin(q2)/2];
        body b {
            mass: m, centre: C, orientation: R,
            inertia: [[2, 1/10, 1/5], [1/10, 3, 3/10], [1/5, 3/10, 4]],
        }
        lagrangian = kinetic_energy(b) + dot(q1)^2/2 - m*g*C.z;
        constraints { cos(q1)*dot(q0) + 2*dot(q2) = 0; }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// The same kinetic energy written out.
    pub struct ChainWritten {
        parameters { m, g }
        coordinates { q0, q1, q2 }
        let R = rot_z(q0)*rot_z(q2)*rot_y(q1);
        let C = [cos(q0), q1, sin(q2)/2];
        let w = omega_body(R);
        let V = dot(C);
        lagrangian = m/2*(V.x^2 + V.y^2 + V.z^2)
            + (w.x*(2*w.x + w.y/10 + w.z/5) + w.y*(w.x/10 + 3*w.y + 3*w.z/10)
               + w.z*(w.x/5 + 3*w.y/10 + 4*w.z))/2
            + dot(q1)^2/2 - m*g*C.z;
        constraints { cos(q1)*dot(q0) + 2*dot(q2) = 0; }
    }
}

nonholonomic_system! {
    /// A body spun about the vertical at the constant rate w.
    pub struct Spun {
        parameters { w }
        coordinates { b }
        body top {
            mass: 1, centre: [0, 0, 0], orientation: rot_z(w*t)*rot_x(b),
            inertia: diag(1, 2, 3),
        }
        lagrangian = kinetic_energy(top);
    }
}

nonholonomic_system! {
    /// A point whose mass grows with its distance.
    pub struct Growing {
        coordinates { x }
        body p { mass: 1 + x^2, centre: [x, 0, 0] }
        lagrangian = kinetic_energy(p) - x^2/2;
    }
}

#[test]
fn a_dependent_angle_of_a_chain_gives_the_written_out_equations() {
    let (body, written) = (ChainBody::new(1.3, 9.81), ChainWritten::new(1.3, 9.81));
    let mut worst = 0.0f64;
    for k in 0..16 {
        let f = k as f64;
        let q = SVector::<f64, 3>::new((0.7 * f).sin(), (1.3 * f).cos() * 0.9, 0.2 * f - 1.5);
        let v = SVector::<f64, 2>::new((0.4 * f).cos(), 0.5 - 0.1 * f);
        let (a, b) = (
            body.accelerations(0.0, &q, &v),
            written.accelerations(0.0, &q, &v),
        );
        worst = worst.max((a - b).amax() / b.amax().max(1.0));
        let (sa, sb) = (
            body.dependent_velocities(&q, &v),
            written.dependent_velocities(&q, &v),
        );
        assert!((sa - sb).amax() < 1e-14, "{sa} {sb}");
    }
    println!("body form against written-out form: {worst:.1e}");
    assert!(worst < 1e-13, "{worst}");
}

#[test]
fn a_dependent_angle_of_a_chain_keeps_its_energy() {
    let sys = ChainBody::new(1.3, 9.81);
    let q0 = SVector::<f64, 3>::new(0.3, -0.4, 0.2);
    let v0 = SVector::<f64, 2>::new(0.8, -0.6);
    let x0 = ChainBody::state(q0.into(), v0.into());
    let out = Dopri5::new(1e-12, 1e-12)
        .integrate(&sys, 0.0, x0, 1.0)
        .expect("integrates");
    let (q1, v1) = ChainBody::split(&out.x);
    let (q1, v1): (SVector<f64, 3>, SVector<f64, 2>) = (q1.into(), v1.into());
    let drift = (sys.energy(&q1, &v1) - sys.energy(&q0, &v0)).abs();
    println!("energy drift over 1 s: {drift:.1e}");
    assert!(drift < 1e-10, "{drift}");
}

#[test]
fn an_orientation_turning_with_time_keeps_its_rate() {
    // T = ½(I₁ḃ² + I₂w² sin²b + I₃w² cos²b): I₁ b̈ = w²(I₂ − I₃) sin b cos b
    let (w, b) = (2.0f64, 0.2f64);
    let sys = Spun::new(w);
    let acc = sys.accelerations(
        0.7,
        &SVector::<f64, 1>::new(b),
        &SVector::<f64, 1>::new(0.3),
    );
    let exact = w * w * (2.0 - 3.0) * b.sin() * b.cos();
    assert!((acc[0] - exact).abs() < 1e-14, "{} against {exact}", acc[0]);
    assert!((exact + 0.7788).abs() < 1e-4);
}

#[test]
fn a_mass_depending_on_a_coordinate_gives_the_lagrangians_equations() {
    // L = ½(1 + x²)ẋ² − x²/2: ẍ = −(x ẋ² + x)/(1 + x²)
    let sys = Growing::new();
    for (x, v) in [(0.5f64, 2.0f64), (-1.2, 0.3), (2.0, -1.0)] {
        let acc = sys.accelerations(0.0, &SVector::<f64, 1>::new(x), &SVector::<f64, 1>::new(v));
        let exact = -(x * v * v + x) / (1.0 + x * x);
        assert!((acc[0] - exact).abs() < 1e-14, "{} against {exact}", acc[0]);
    }
}
