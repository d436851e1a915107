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

nonholonomic_system! {
    /// The sleigh written with its knife edge explicit, `dot(y) =
    /// tan(theta)*dot(x)`, and a slider z tied to x and the heading by a
    /// holonomic row; `dependent` names the slider only, as it did when the
    /// knife edge was an explicit row.
    pub struct TanSleighWithSlider {
        parameters { m, J, a, k }
        coordinates { x, theta, y, z }
        lagrangian = J*dot(theta)^2/2 + dot(z)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints {
            dot(y) = tan(theta)*dot(x);
            z = k*x + theta;
        }
        dependent { z }
    }
}

const M: f64 = 2.0;
const J_SLED: f64 = 0.3;
/// A short arm, so that the sleigh turns about 19 times before it stops.
const A_SLED: f64 = 0.005;

#[path = "common/sleigh.rs"]
mod sleigh;

/// The closed form of the sleigh of these tests.
fn sleigh_closed_form(theta0: f64, v0: f64, omega0: f64, t: f64) -> (f64, f64, f64) {
    sleigh::sleigh_closed_form((M, J_SLED, A_SLED), (theta0, v0, omega0), t)
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

/// The sleigh started at θ = 0.3 with v = 0.2, ω = 2 turns about 19 times
/// before it stops (a = 0.005): through ten turns (θ = 0.3 + 20π) it passes
/// cos θ = 0 twenty times and sin θ = 0 twenty times. Its chart solved for
/// y alone ends at the first quarter turn; the atlas moves between the
/// chart solved for y and the one solved for x, and the motion stays on the
/// closed form (θ, ω, and ẋ = v cos θ of the state's layout).
#[test]
fn the_implicit_sleigh_runs_through_ten_turns_on_its_closed_form() {
    let sleigh = SleighImplicit::new(M, J_SLED, A_SLED);
    let (theta0, v0, omega0) = (0.3_f64, 0.2, 2.0);
    let x0 = SVector::<f64, 5>::new(0.0, theta0, 0.0, v0 * theta0.cos(), omega0);
    // the time θ reaches θ0 + 20π, by bisection on the closed form
    let (mut lo, mut hi) = (0.0, 200.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if sleigh_closed_form(theta0, v0, omega0, mid).0 < theta0 + 20.0 * std::f64::consts::PI {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t1 = hi;
    let times: Vec<f64> = (1..=400).map(|i| t1 * f64::from(i) / 400.0).collect();
    let mut worst: f64 = 0.0;
    let out = Dop853::new(1e-11, 1e-13)
        .integrate_with_outputs(&sleigh, 0.0, x0, t1, &times, |t, x| {
            let (theta, v, omega) = sleigh_closed_form(theta0, v0, omega0, t);
            worst = worst
                .max((x[1] - theta).abs())
                .max((x[3] - v * theta.cos()).abs())
                .max((x[4] - omega).abs());
        })
        .expect("the atlas carries the sleigh through every quarter turn");
    let switches = out.stats.chart_switches;
    eprintln!(
        "implicit sleigh, ten turns (t = {t1:.3}): {switches} chart switches, {} steps, max error against the closed form {worst:.1e}",
        out.stats.steps
    );
    for s in out.switches.iter().take(6) {
        eprintln!("  t = {:.4}: chart {} -> {}", s.t, s.from, s.to);
    }
    assert!(worst < 1e-8, "max error against the closed form {worst:e}");
    assert!((30..=60).contains(&switches), "{switches} switches");
    // one chart alone: the run ends at the first quarter turn, typed
    let one = Dop853::new(1e-11, 1e-13)
        .with_chart_switching(false)
        .integrate(&sleigh, 0.0, x0, t1);
    match one {
        Err(SimError::Singular { x, .. }) => {
            assert!(
                (x[1] - std::f64::consts::FRAC_PI_2).abs() < 0.1,
                "θ = {}",
                x[1]
            )
        }
        other => panic!("one chart should end at cos θ = 0: {other:?}"),
    }
}

/// The Suslov problem as an implicit row to t = 100: its chart solved for
/// the pitch is singular where the roll passes 0 (the run of that chart
/// alone ends there), the atlas carries it through, its energy
/// ½(Aω₁² + Bω₂²) stays constant and it agrees with the body written in the
/// speeds ω₁, ω₂ at equal tolerance.
#[test]
fn the_implicit_suslov_problem_runs_to_t_100_with_its_speeds_form() {
    const RTOL: f64 = 1e-13;
    let (a, b, c, d, e) = (1.0, 2.0, 3.0, 0.4, 0.3);
    let body = SuslovImplicit::new(a, b, c, d, e);
    let speeds = SuslovSpeeds::new(a, b, c, d, e);
    let (psi, theta, phi, w1, w2) = (0.0_f64, 0.1_f64, 0.3_f64, 0.5, 0.2);
    let xs = SVector::<f64, 5>::new(psi, theta, phi, w1, w2);
    let (st, ct) = theta.sin_cos();
    let (sp, _) = phi.sin_cos();
    // the implicit chart's state: [ψ, θ, φ, ψ̇, φ̇]
    let xi = SVector::<f64, 5>::new(psi, theta, phi, w2 * sp / ct, w1 + w2 * sp * st / ct);
    let times: Vec<f64> = (1..=1000).map(|i| 0.1 * f64::from(i)).collect();
    let e0 = 0.5 * (a * w1 * w1 + b * w2 * w2);
    let mut implicit = Vec::new();
    let mut drift: f64 = 0.0;
    let out = Dop853::new(RTOL, 1e-14)
        .integrate_with_outputs(&body, 0.0, xi, 100.0, &times, |_, x| {
            implicit.push(*x);
            if body
                .chart_regularity_in(0, 0.0, x)
                .is_some_and(|r| r.abs() > 0.05)
            {
                let q = x.fixed_rows::<3>(0).into_owned();
                let r = x.fixed_rows::<2>(3).into_owned();
                drift = drift.max((body.energy(&q, &r) - e0).abs() / e0);
            }
        })
        .expect("the atlas carries the Suslov body through roll = 0");
    let mut worst: f64 = 0.0;
    let mut k = 0;
    let mut drift_speeds: f64 = 0.0;
    Dop853::new(RTOL, 1e-14)
        .integrate_with_outputs(&speeds, 0.0, xs, 100.0, &times, |_, x| {
            let e = 0.5 * (a * x[3] * x[3] + b * x[4] * x[4]);
            drift_speeds = drift_speeds.max((e - e0).abs() / e0);
            let (st, ct) = x[1].sin_cos();
            let (sp, _) = x[2].sin_cos();
            let rates = [x[4] * sp / ct, x[3] + x[4] * sp * st / ct];
            let y = implicit[k];
            worst = worst
                .max((y[0] - x[0]).abs())
                .max((y[1] - x[1]).abs())
                .max((y[2] - x[2]).abs())
                .max((y[3] - rates[0]).abs())
                .max((y[4] - rates[1]).abs());
            k += 1;
        })
        .expect("the speeds form has no singularity on this motion");
    eprintln!(
        "Suslov to t = 100: {} chart switches, {} steps; energy drift {drift:.1e} (speeds form {drift_speeds:.1e}); max difference to the speeds form {worst:.1e}",
        out.stats.chart_switches, out.stats.steps
    );
    for s in out.switches.iter().take(6) {
        eprintln!("  t = {:.4}: chart {} -> {}", s.t, s.from, s.to);
    }
    assert!(out.stats.chart_switches > 0);
    assert!(drift <= 1e-10, "energy drift {drift:e}");
    assert!(worst <= 1e-9, "difference to the speeds form {worst:e}");
}

#[test]
fn an_explicit_row_with_a_denominator_keeps_its_coordinate_and_gets_charts() {
    // the cleared row is pinned to y in the system's own chart; the list
    // written for the holonomic row alone still works
    assert_eq!(TanSleighWithSlider::<f64>::DEPENDENT, [2, 3]);
    let s = TanSleighWithSlider::new(M, J_SLED, 0.4, 0.5);
    assert!(s.charts() >= 2, "{}", s.charts());
    assert_eq!(s.chart_name(0), "solved for `y`, `z`");
    // through θ = π/2 with the slider held on its row
    let (theta, v, w) = (1.2_f64, 0.5, 1.5);
    // at x = 0 the slider's row gives z = θ
    let x0 = SVector::<f64, 6>::new(0.0, theta, 0.0, theta, v * theta.cos(), w);
    let out = Dop853::new(1e-10, 1e-12)
        .integrate(&s, 0.0, x0, 1.0)
        .unwrap();
    println!(
        "θ = {:.6} at t = 1, {} switches, residual {:?}",
        out.x[1], out.stats.chart_switches, out.max_residual
    );
    assert!(out.x[1] > std::f64::consts::FRAC_PI_2 + 0.5);
    assert!(out.stats.chart_switches >= 1);
    // the slider's row and the knife edge hold at the end
    let (q, r) = (
        out.x.fixed_rows::<4>(0).into_owned(),
        out.x.fixed_rows::<2>(4).into_owned(),
    );
    assert!((q[3] - 0.5 * q[0] - q[1]).abs() < 1e-9);
    let sdot = s.dependent_velocities(&q, &r);
    let (xdot, ydot) = (r[0], sdot[0]);
    assert!((q[1].cos() * ydot - q[1].sin() * xdot).abs() < 1e-9);
}
