//! The atlas of charts (DESIGN §9.3, §6.7) against independent references:
//!
//! * the Chaplygin sleigh written with an implicit row, whose chart solved
//!   for y is singular at θ = π/2, through ten turns against its closed form
//!   (Bloch, sec. 1.7);
//! * the Suslov problem (a rigid body with the body-fixed constraint
//!   ω·e₃ = 0) written as an implicit row on its three angles, to t = 100,
//!   against the same body written in the speeds ω₁, ω₂ (Maggi's equations,
//!   a chart without that singularity) and against the conservation of its
//!   energy;
//! * the charts agree with each other where both are regular: the same
//!   velocities and accelerations of every coordinate.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The Chaplygin sleigh with its constraint as an implicit row: solved
    /// for y (singular where cos θ = 0) or for x (where sin θ = 0).
    pub struct SleighImplicit {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// The Suslov problem: a rigid body about a fixed point whose angular
    /// velocity has no component along the body axis e₃, with its
    /// orientation in yaw, pitch and roll and the constraint as written.
    pub struct SuslovImplicit {
        parameters { A, B, C, D, E }
        coordinates { psi, theta, phi }
        let Q = rot_z(psi) * rot_y(theta) * rot_x(phi);
        let w = omega_body(Q);
        lagrangian = (A*w.x^2 + B*w.y^2 + C*w.z^2)/2 + D*w.x*w.z + E*w.y*w.z;
        constraints { w.z = 0; }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// The Suslov problem in the speeds w1 = ω₁, w2 = ω₂ (ω₃ = 0 by
    /// construction): the angles' rates from ω in yaw, pitch and roll.
    pub struct SuslovSpeeds {
        parameters { A, B, C, D, E }
        coordinates { psi, theta, phi }
        let Q = rot_z(psi) * rot_y(theta) * rot_x(phi);
        let w = omega_body(Q);
        lagrangian = (A*w.x^2 + B*w.y^2 + C*w.z^2)/2 + D*w.x*w.z + E*w.y*w.z;
        speeds { w1, w2 }
        kinematics {
            dot(psi) = w2*sin(phi)/cos(theta);
            dot(theta) = w2*cos(phi);
            dot(phi) = w1 + w2*sin(phi)*tan(theta);
        }
        outputs { energy }
    }
}

const M: f64 = 2.0;
const J_SLED: f64 = 0.3;
/// A short arm, so that the sleigh turns about 19 times before it stops.
const A_SLED: f64 = 0.005;

/// The sleigh's closed form (Bloch, sec. 1.7): θ, the speed v of the blade
/// along the body axis and ω = θ̇ at t.
fn sleigh_closed_form(theta0: f64, v0: f64, omega0: f64, t: f64) -> (f64, f64, f64) {
    let inertia = J_SLED + M * A_SLED * A_SLED;
    let v_inf = (v0 * v0 + inertia * omega0 * omega0 / M).sqrt();
    let k = M * A_SLED * v_inf / inertia;
    let c = (v0 / v_inf).atanh();
    let gd = |s: f64| s.sinh().atan();
    let s = k * t + c;
    (
        theta0 + omega0 * c.cosh() / k * (gd(s) - gd(c)),
        v_inf * s.tanh(),
        omega0 * c.cosh() / s.cosh(),
    )
}

#[test]
fn the_sleigh_has_two_charts_with_their_singular_sets() {
    let sleigh = SleighImplicit::new(M, J_SLED, A_SLED);
    assert_eq!(sleigh.charts(), 2);
    assert_eq!(sleigh.chart_name(0), "solved for `y`");
    assert_eq!(sleigh.chart_name(1), "solved for `x`");
    // state of chart 0: [x, θ, y, ẋ, θ̇]; of chart 1: [x, θ, y, θ̇, ẏ]
    let (theta, v, w) = (0.4_f64, 0.7, -1.3);
    let x0 = SVector::<f64, 5>::new(0.1, theta, -0.2, v * theta.cos(), w);
    let r0 = sleigh.chart_regularity_in(0, 0.0, &x0).unwrap();
    assert!((r0.abs() - theta.cos()).abs() < 1e-15, "{r0}");
    let x1 = sleigh.change_chart(0, 1, 0.0, &x0);
    let r1 = sleigh.chart_regularity_in(1, 0.0, &x1).unwrap();
    assert!((r1.abs() - theta.sin()).abs() < 1e-15, "{r1}");
    // the same motion in both charts: every velocity and acceleration
    let f0 = sleigh.rhs_in_chart(0, 0.0, &x0);
    let f1 = sleigh.rhs_in_chart(1, 0.0, &x1);
    for i in 0..3 {
        assert!((f0[i] - f1[i]).abs() < 1e-14, "q̇_{i}: {f0} vs {f1}");
    }
    // θ̈ agrees; ẍ (chart 0) and ÿ (chart 1) follow
    // from v̇ = a ω² and the heading
    let (s, c) = theta.sin_cos();
    let vdot = A_SLED * w * w;
    assert!(
        (f0[3] - (vdot * c - v * s * w)).abs() < 1e-13,
        "ẍ {}",
        f0[3]
    );
    assert!(
        (f1[4] - (vdot * s + v * c * w)).abs() < 1e-13,
        "ÿ {}",
        f1[4]
    );
    assert!((f0[4] - f1[3]).abs() < 1e-14, "θ̈ {} vs {}", f0[4], f1[3]);
    // back again: nothing lost
    let back = sleigh.change_chart(1, 0, 0.0, &x1);
    assert!((back - x0).norm() < 1e-15);
}

#[test]
fn the_suslov_row_has_a_chart_for_pitch_and_one_for_yaw() {
    let body = SuslovImplicit::new(1.0, 2.0, 3.0, 0.4, 0.3);
    assert_eq!(body.charts(), 2);
    assert_eq!(body.chart_name(0), "solved for `theta`");
    assert_eq!(body.chart_name(1), "solved for `psi`");
}
