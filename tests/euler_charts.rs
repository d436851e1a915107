//! Orientations without gimbal lock (DESIGN §9.4): a ball on a turntable
//! with its orientation in yaw, pitch and roll, whose chart is singular
//! where the pitch is ±π/2, runs through that pole, advanced by the
//! one-step integrators in the rotation's canonical coordinates (a
//! Lie-group step) and by `Bdf` in the chart of another sequence, against
//!
//! * the closed form of its centre, which circles at 2Ω/7 of the table's
//!   rate;
//! * the same ball with its orientation a unit quaternion, written here by
//!   hand (no singularity, no engine): its orientation, and the steps it
//!   takes;
//! * the same ball with the rates of three fictitious angles as velocities
//!   (no orientation at all): the same centre, the same angular velocity;
//! * itself switching sequences (`with_lie_step(false)`), and held in one
//!   chart, away from the pole.
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};
use nonholonomic::prelude::*;
use std::f64::consts::FRAC_PI_2;

#[path = "common/turntable.rs"]
mod turntable;
use turntable::{TurntableBall, ball_centre, quaternion_ball};

/// A homogeneous ball rolling on a table that turns at `Omega`, its
/// orientation the rotation `$q` of the angles phi, theta, psi.
macro_rules! turntable_ball {
    ($(#[$doc:meta])* $name:ident, $($q:tt)*) => {
        nonholonomic_system! {
            $(#[$doc])*
            pub struct $name {
                parameters { m, R, Omega }
                coordinates { x, y, phi, theta, psi }
                let Q = $($q)*;
                let w = omega(Q);
                lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + m*R^2/5*(w.x^2 + w.y^2 + w.z^2);
                constraints {
                    dot(x) = R*w.y - Omega*y;
                    dot(y) = -R*w.x + Omega*x;
                }
            }
        }
    };
}

turntable_ball!(
    /// The ball in yaw, pitch and roll.
    EulerBall,
    rot_z(phi) * rot_y(theta) * rot_x(psi)
);
turntable_ball!(
    /// The ball in proper Euler angles z-x-z, singular where
    /// sin(theta) = 0: upright is its pole.
    ProperEulerBall,
    rot_z(phi) * rot_x(theta) * rot_z(psi)
);

const M: f64 = 1.0;
const R: f64 = 0.1;
const OMEGA: f64 = 2.0 * std::f64::consts::PI;
/// The centre and the angular velocity (world axes) at t = 0.
const START: (f64, f64, [f64; 3]) = (0.3, -0.1, [0.7, -0.4, 1.1]);

/// The quaternion ball's orientation at t = 10 from `rotation` at t = 0,
/// with `rtol` (atol rtol/100), and its steps.
fn quaternion_run(rotation: &Matrix3<f64>, rtol: f64) -> (Matrix3<f64>, usize) {
    quaternion_until(rotation, rtol, 10.0)
}

/// The quaternion ball's orientation at `t1` and its steps.
fn quaternion_until(rotation: &Matrix3<f64>, rtol: f64, t1: f64) -> (Matrix3<f64>, usize) {
    let (x0, y0, w) = START;
    let q = UnitQuaternion::from_matrix(rotation);
    let s0 = SVector::<f64, 9>::from([x0, y0, w[0], w[1], w[2], q.w, q.i, q.j, q.k]);
    let out = Dop853::new(rtol, rtol * 1e-2)
        .integrate(&quaternion_ball(R, OMEGA), 0.0, s0, t1)
        .unwrap();
    let q = Quaternion::new(out.x[5], out.x[6], out.x[7], out.x[8]);
    let r = UnitQuaternion::from_quaternion(q).to_rotation_matrix();
    (r.into_inner(), out.stats.steps)
}

/// The world angular velocity of a ball whose angles are of `seq`.
fn omega_in(seq: EulerSequence, x: &SVector<f64, 8>) -> Vector3<f64> {
    let angles = [x[2], x[3], x[4]];
    let rates = [x[5], x[6], x[7]];
    seq.matrix(&angles) * seq.body_rates(&angles, &rates)
}

/// The Euler ball's world angular velocity from its state.
fn omega_world(x: &SVector<f64, 8>) -> Vector3<f64> {
    omega_in(EulerSequence::ZYX, x)
}

/// The Euler ball's state at t = 0 with the orientation `angles`.
fn euler_start(angles: [f64; 3]) -> SVector<f64, 8> {
    start_in(EulerSequence::ZYX, angles)
}

/// The state at t = 0 of a ball whose angles are of `seq`, at `angles`.
fn start_in(seq: EulerSequence, angles: [f64; 3]) -> SVector<f64, 8> {
    let (x0, y0, w) = START;
    let q = seq.matrix(&angles);
    let rates = seq.rates(&angles, &(q.transpose() * Vector3::from(w)));
    SVector::<f64, 8>::from([
        x0, y0, angles[0], angles[1], angles[2], rates[0], rates[1], rates[2],
    ])
}

/// The free ball's state at t = 0.
fn free_start() -> SVector<f64, 8> {
    let (x0, y0, w) = START;
    SVector::<f64, 8>::from([x0, y0, 0.0, 0.0, 0.0, w[0], w[1], w[2]])
}

/// The largest errors of the Euler ball's states `euler` (at the times
/// of `free`'s) in its centre against the closed form and in its angular
/// velocity against the free ball's.
fn errors(euler: &[(f64, SVector<f64, 8>)], free: &[(f64, SVector<f64, 8>)]) -> (f64, f64) {
    let (x0, y0, w) = START;
    let v0 = (R * w[1] - OMEGA * y0, -R * w[0] + OMEGA * x0);
    let nu = 2.0 * OMEGA / 7.0;
    let (mut centre, mut spin) = (0.0f64, 0.0f64);
    for ((t, xe), (tf, xf)) in euler.iter().zip(free) {
        assert_eq!(t, tf);
        let (cx, cy) = ball_centre((x0, y0), v0, nu, *t);
        centre = centre.max((xe[0] - cx).abs()).max((xe[1] - cy).abs());
        let wf = Vector3::new(xf[5], xf[6], xf[7]);
        spin = spin.max((omega_world(xe) - wf).amax());
    }
    (centre, spin)
}

/// The states of a run of `sys` from `x0` to t = 10 at every 0.1, and the
/// outcome.
fn sampled<S: OdeSystem<f64, 8>>(
    mut method: Dop853<f64>,
    sys: &S,
    x0: SVector<f64, 8>,
) -> (Vec<(f64, SVector<f64, 8>)>, Outcome<f64, 8>) {
    let times: Vec<f64> = (1..=100).map(|i| 0.1 * i as f64).collect();
    let mut states = Vec::new();
    let out = method
        .integrate_with_outputs(sys, 0.0, x0, 10.0, &times, |t, x| states.push((t, *x)))
        .unwrap();
    (states, out)
}

#[test]
fn the_euler_ball_circles_at_two_sevenths_of_the_table_rate_through_gimbal_lock() {
    let euler = EulerBall::new(M, R, OMEGA);
    let names: Vec<&str> = (0..euler.charts()).map(|c| euler.chart_name(c)).collect();
    assert_eq!(
        names,
        [
            "the angles of `rot_z(phi)*rot_y(theta)*rot_x(psi)`",
            "the angles of `rot_z(phi)*rot_x(theta)*rot_y(psi)`",
            "the angles of `rot_x(phi)*rot_y(theta)*rot_z(psi)`",
            "the angles of `rot_y(phi)*rot_x(theta)*rot_z(psi)`",
        ]
    );
    let rotation = euler.free_rotation(0).unwrap();
    assert_eq!((rotation.angles, rotation.rates), ([2, 3, 4], [5, 6, 7]));
    assert!(rotation.world, "the ball writes omega(Q)");
    let tol = Dop853::new(1e-12, 1e-14);
    let (free_states, free_out) = sampled(tol, &TurntableBall::new(M, R, OMEGA), free_start());
    // from the upright orientation, and from 0.01 short of the pole
    for (angles, name) in [
        ([0.0, 0.0, 0.0], "upright"),
        ([0.3, FRAC_PI_2 - 0.01, -0.2], "near the pole"),
    ] {
        let x0 = euler_start(angles);
        let r0 = EulerSequence::ZYX.matrix(&angles);
        let (reference, _) = quaternion_run(&r0, 1e-14);
        let (quaternion, quaternion_steps) = quaternion_run(&r0, 1e-12);
        let turned = |x: &SVector<f64, 8>| {
            (EulerSequence::ZYX.matrix(&[x[2], x[3], x[4]]) - reference).amax()
        };
        let (states, out) = sampled(tol, &euler, x0);
        let (centre, spin) = errors(&states, &free_states);
        let (seq_states, sequences) = sampled(tol.with_lie_step(false), &euler, x0);
        let (seq_centre, _) = errors(&seq_states, &free_states);
        let held = tol
            .with_chart_switching(false)
            .integrate(&euler, 0.0, x0, 10.0);
        let switches: Vec<(f64, usize, usize)> = sequences
            .switches
            .iter()
            .map(|s| (s.t, s.from, s.to))
            .collect();
        println!(
            "{name}: canonical coordinates {} steps + {} rejected, orientation at t = 10 {:.1e}, \
             centre {centre:.1e}, ω {spin:.1e}; the quaternion ball {quaternion_steps} steps, \
             orientation {:.1e}; switching sequences {} + {} (switches {switches:.4?}), \
             orientation {:.1e}, centre {seq_centre:.1e}; held in chart 0: {}; \
             the fictitious-angle ball {} + {}",
            out.stats.steps,
            out.stats.rejected,
            turned(&out.x),
            (quaternion - reference).amax(),
            sequences.stats.steps,
            sequences.stats.rejected,
            turned(&sequences.x),
            match &held {
                Ok(o) => format!("{} steps + {} rejected", o.stats.steps, o.stats.rejected),
                Err(e) => format!("{e}"),
            },
            free_out.stats.steps,
            free_out.stats.rejected,
        );
        assert!(centre <= 1e-9, "{name}: {centre:e}");
        assert!(spin <= 1e-8, "{name}: {spin:e}");
        assert!(turned(&out.x) <= 1e-10, "{name}");
        assert_eq!(out.stats.chart_switches, 0, "{name}");
        // at most 3× the steps of the ball without the singularity
        assert!(out.stats.steps <= 3 * quaternion_steps, "{name}");
        // switching sequences: as right, at more steps
        assert!(!switches.is_empty(), "{name}");
        assert!(seq_centre <= 1e-9, "{name}: {seq_centre:e}");
        assert!(turned(&sequences.x) <= 1e-8, "{name}");
        // the pole costs held runs at least twice the steps
        if let Ok(o) = held {
            assert!(2 * sequences.stats.steps <= o.stats.steps, "{name}");
        }
    }
}

#[test]
fn the_sequences_agree_away_from_their_poles() {
    // each other chart's equations alone, from chart 0's state mapped
    // there, against chart 0's run, over 0.15 s (before the first switch
    // at 0.19)
    let euler = EulerBall::new(M, R, OMEGA);
    let x0 = euler_start([0.0, 0.0, 0.0]);
    let mut tol = Dop853::new(1e-13, 1e-15);
    for c in 1..euler.charts() {
        let chart = |t: f64, x: &SVector<f64, 8>| euler.rhs_in_chart(c, t, x);
        let y0 = euler.change_chart(0, c, 0.0, &x0);
        let mut worst = 0.0f64;
        for k in 1..=15 {
            let t = 0.01 * k as f64;
            let a = tol
                .with_chart_switching(false)
                .integrate(&euler, 0.0, x0, t)
                .unwrap()
                .x;
            let b = tol.integrate(&chart, 0.0, y0, t).unwrap().x;
            let b = euler.change_chart_near(c, 0, t, &b, &a);
            worst = worst.max((a - b).amax() / a.amax());
        }
        println!("chart 0 against chart {c} over 0.15 s: {worst:.1e} of the largest entry");
        assert!(worst < 1e-10, "chart {c}: {worst:e}");
    }
}

/// The run of `sys` from the Euler ball's upright start through 30 s
/// with outputs every millisecond: its chart switches and the largest
/// step of an angle between outputs where chart 0 is far from its pole
/// (|cos θ| > 0.5 at both, where the rates stay below a few hundred rad/s).
fn largest_output_step(lie_step: bool) -> (usize, f64) {
    let euler = EulerBall::new(M, R, OMEGA);
    let x0 = euler_start([0.0, 0.0, 0.0]);
    let times: Vec<f64> = (1..=30_000).map(|i| 1e-3 * i as f64).collect();
    let mut last: Option<SVector<f64, 8>> = None;
    let mut jump = 0.0f64;
    let out = Dop853::new(1e-10, 1e-12)
        .with_lie_step(lie_step)
        .integrate_with_outputs(&euler, 0.0, x0, 30.0, &times, |_, x| {
            if let Some(p) = last
                && p[3].cos().abs() > 0.5
                && x[3].cos().abs() > 0.5
            {
                jump = (2..5).map(|i| (x[i] - p[i]).abs()).fold(jump, f64::max);
            }
            last = Some(*x);
        })
        .unwrap();
    (out.stats.chart_switches, jump)
}

#[test]
fn the_angles_seen_are_continuous() {
    // In canonical coordinates each step turns the ball by up to half a
    // turn; the angles handed out are followed along it. Switching
    // sequences: 10 switches, the first at 0.19 s; from 28.07 s on, a spin
    // about the body's z axis while it lies horizontal takes its x and y
    // axes through the vertical in turn, the poles of the first two
    // sequences, and the run keeps to the ones whose poles are on the z
    // axis. Either way no jump by a whole turn or a mirror set.
    let (switches, jump) = largest_output_step(true);
    let (seq_switches, seq_jump) = largest_output_step(false);
    println!(
        "largest step of an angle between outputs: {jump:.3} in canonical coordinates \
         ({switches} switches), {seq_jump:.3} switching sequences ({seq_switches} switches)"
    );
    assert_eq!(switches, 0);
    assert!(jump < 1.0, "{jump}");
    assert!(seq_switches >= 5);
    assert!(seq_jump < 1.0, "{seq_jump}");
}

#[test]
fn proper_euler_angles_start_at_their_pole_and_run_through_it() {
    // z-x-z angles from θ = 0.01, next to their pole (upright): the other
    // charts are z-x-y, y-x-z and x-y-z
    let ball = ProperEulerBall::new(M, R, OMEGA);
    let names: Vec<&str> = (0..ball.charts()).map(|c| ball.chart_name(c)).collect();
    assert_eq!(
        names,
        [
            "the angles of `rot_z(phi)*rot_x(theta)*rot_z(psi)`",
            "the angles of `rot_z(phi)*rot_x(theta)*rot_y(psi)`",
            "the angles of `rot_y(phi)*rot_x(theta)*rot_z(psi)`",
            "the angles of `rot_x(phi)*rot_y(theta)*rot_z(psi)`",
        ]
    );
    let x0 = start_in(EulerSequence::ZXZ, [0.3, 0.01, -0.2]);
    let tol = Dop853::new(1e-12, 1e-14);
    let (free_states, _) = sampled(tol, &TurntableBall::new(M, R, OMEGA), free_start());
    let (states, out) = sampled(tol, &ball, x0);
    let (x0c, y0c, w) = START;
    let v0 = (R * w[1] - OMEGA * y0c, -R * w[0] + OMEGA * x0c);
    let nu = 2.0 * OMEGA / 7.0;
    let (mut centre, mut spin) = (0.0f64, 0.0f64);
    for ((t, x), (_, f)) in states.iter().zip(&free_states) {
        let (cx, cy) = ball_centre((x0c, y0c), v0, nu, *t);
        centre = centre.max((x[0] - cx).abs()).max((x[1] - cy).abs());
        let wf = Vector3::new(f[5], f[6], f[7]);
        spin = spin.max((omega_in(EulerSequence::ZXZ, x) - wf).amax());
    }
    let held = tol
        .with_chart_switching(false)
        .integrate(&ball, 0.0, x0, 10.0);
    println!(
        "z-x-z ball: {} steps + {} rejected, {} switches (first {:?}); held: {}; centre {centre:.1e}, ω {spin:.1e}",
        out.stats.steps,
        out.stats.rejected,
        out.stats.chart_switches,
        out.switches.iter().next().map(|s| (s.t, s.from, s.to)),
        match &held {
            Ok(o) => format!("{} steps + {} rejected", o.stats.steps, o.stats.rejected),
            Err(e) => format!("{e}"),
        },
    );
    assert_eq!(out.stats.chart_switches, 0);
    let sequences = tol
        .with_lie_step(false)
        .integrate(&ball, 0.0, x0, 10.0)
        .unwrap();
    println!(
        "switching sequences: {} steps, {} switches",
        sequences.stats.steps, sequences.stats.chart_switches
    );
    assert!(sequences.stats.chart_switches >= 1);
    assert!(centre <= 1e-9, "{centre:e}");
    assert!(spin <= 1e-8, "{spin:e}");
    // every other chart's equations agree with chart 0's away from poles
    let x1 = start_in(EulerSequence::ZXZ, [0.3, 1.0, -0.2]);
    for c in 1..ball.charts() {
        let y = ball.change_chart(0, c, 0.0, &x1);
        let back = ball.change_chart_near(c, 0, 0.0, &y, &x1);
        assert!((back - x1).amax() < 1e-13, "chart {c}: {back} vs {x1}");
        // the rates of the mapped state along chart c's motion, against
        // chart 0's: a central difference of the map over ±1e-6 s
        let h = 1e-6;
        let f0 = ball.rhs_in_chart(0, 0.0, &x1);
        let ahead = ball.change_chart_near(0, c, 0.0, &(x1 + f0 * h), &y);
        let behind = ball.change_chart_near(0, c, 0.0, &(x1 - f0 * h), &y);
        let fc = ball.rhs_in_chart(c, 0.0, &y);
        let gap = ((ahead - behind) / (2.0 * h) - fc).amax() / fc.amax();
        assert!(gap < 1e-7, "chart {c}: {gap:e}");
    }
}

#[test]
fn every_integrator_runs_the_ball_through_gimbal_lock() {
    // 2 s from 0.01 short of the pole: the one-step methods in canonical
    // coordinates, Bdf switching sequences; the orientation against the
    // quaternion ball's, the centre against the closed form
    let euler = EulerBall::new(M, R, OMEGA);
    let angles = [0.3, FRAC_PI_2 - 0.01, -0.2];
    let x0 = euler_start(angles);
    let (reference, _) = quaternion_until(&EulerSequence::ZYX.matrix(&angles), 1e-14, 2.0);
    let (x0c, y0c, w) = START;
    let v0 = (R * w[1] - OMEGA * y0c, -R * w[0] + OMEGA * x0c);
    let (cx, cy) = ball_centre((x0c, y0c), v0, 2.0 * OMEGA / 7.0, 2.0);
    let (rtol, atol, h) = (1e-9, 1e-11, 2e-3);
    let runs = [
        (
            "Dopri5",
            Dopri5::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            1e-7,
        ),
        (
            "Dop853",
            Dop853::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            1e-7,
        ),
        (
            "Rodas4",
            Rodas4::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            1e-6,
        ),
        (
            "Rodas5P",
            Rodas5P::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            1e-6,
        ),
        (
            "Bdf",
            Bdf::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            3e-5,
        ),
        (
            "AutoSwitch",
            AutoSwitch::new(rtol, atol).integrate(&euler, 0.0, x0, 2.0),
            1e-7,
        ),
        ("Rk4", Rk4::new(h).integrate(&euler, 0.0, x0, 2.0), 1e-6),
        (
            "GaussLegendre4",
            GaussLegendre4::new(h).integrate(&euler, 0.0, x0, 2.0),
            1e-6,
        ),
    ];
    for (name, out, bound) in runs {
        let out = out.unwrap();
        let turned =
            (EulerSequence::ZYX.matrix(&[out.x[2], out.x[3], out.x[4]]) - reference).amax();
        let centre = (out.x[0] - cx).abs().max((out.x[1] - cy).abs());
        println!(
            "{name}: {} steps + {} rejected, {} switches; orientation {turned:.1e}, centre {centre:.1e}",
            out.stats.steps, out.stats.rejected, out.stats.chart_switches
        );
        assert!(
            turned < bound && centre < bound,
            "{name}: {turned:e} {centre:e}"
        );
        assert_eq!(out.stats.chart_switches > 0, name == "Bdf", "{name}");
    }
}

nonholonomic_system! {
    /// A free rigid body with three different moments of inertia, its
    /// orientation in yaw, pitch and roll: its kinetic energy is in body
    /// components, so the canonical coordinates carry the body's.
    pub struct TumblingBody {
        parameters { A, B, C }
        coordinates { yaw, pitch, roll }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        body top { mass: 1, centre: [0, 0, 0], orientation: Q, inertia: diag(A, B, C) }
        lagrangian = kinetic_energy(top);
    }
}

/// Euler's equations for the principal moments `I` and `q̇ = ½ q (0, ω_b)`:
/// state ω_b, q.
fn euler_equations(i: [f64; 3]) -> impl Fn(f64, &SVector<f64, 7>) -> SVector<f64, 7> {
    move |_t, s| {
        let w = Vector3::new(s[0], s[1], s[2]);
        let iw = Vector3::new(i[0] * w.x, i[1] * w.y, i[2] * w.z);
        let torque_free = -w.cross(&iw);
        let (a, b, c, d) = (s[3], s[4], s[5], s[6]);
        SVector::<f64, 7>::from([
            torque_free.x / i[0],
            torque_free.y / i[1],
            torque_free.z / i[2],
            0.5 * (-b * w.x - c * w.y - d * w.z),
            0.5 * (a * w.x + c * w.z - d * w.y),
            0.5 * (a * w.y + d * w.x - b * w.z),
            0.5 * (a * w.z + b * w.y - c * w.x),
        ])
    }
}

#[test]
fn a_tumbling_body_keeps_its_momentum_through_gimbal_lock() {
    // inertia 1, 2, 3; ω_b = (0.3, 4, 0.2) about the unstable middle axis:
    // the body flips over and over through every orientation, the pitch
    // through ±π/2 among them, for 20 s
    let inertia = [1.0, 2.0, 3.0];
    let body = TumblingBody::new(inertia[0], inertia[1], inertia[2]);
    let rotation = body.free_rotation(0).unwrap();
    assert!(!rotation.world, "a body's inertia is in body axes");
    let angles = [0.2, 0.4, -0.1];
    let seq = EulerSequence::ZYX;
    let w0 = Vector3::new(0.3, 4.0, 0.2);
    let rates = seq.rates(&angles, &w0);
    let x0 = SVector::<f64, 6>::from([
        angles[0], angles[1], angles[2], rates[0], rates[1], rates[2],
    ]);
    let q0 = UnitQuaternion::from_matrix(&seq.matrix(&angles));
    let s0 = SVector::<f64, 7>::from([w0.x, w0.y, w0.z, q0.w, q0.i, q0.j, q0.k]);
    let reference = Dop853::new(1e-14, 1e-16)
        .integrate(&euler_equations(inertia), 0.0, s0, 20.0)
        .unwrap()
        .x;
    let r_ref = UnitQuaternion::from_quaternion(Quaternion::new(
        reference[3],
        reference[4],
        reference[5],
        reference[6],
    ))
    .to_rotation_matrix()
    .into_inner();
    let momentum = |x: &SVector<f64, 6>| {
        let (a, r) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]]);
        let w = seq.body_rates(&a, &r);
        seq.matrix(&a) * Vector3::new(inertia[0] * w.x, inertia[1] * w.y, inertia[2] * w.z)
    };
    let l0 = momentum(&x0);
    let mut worst = 0.0f64;
    let mut pole = 1.0f64;
    let times: Vec<f64> = (1..=2000).map(|i| 0.01 * i as f64).collect();
    let out = Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&body, 0.0, x0, 20.0, &times, |_, x| {
            worst = worst.max((momentum(x) - l0).amax());
            pole = pole.min(x[1].cos().abs());
        })
        .unwrap();
    let turned = (seq.matrix(&[out.x[0], out.x[1], out.x[2]]) - r_ref).amax();
    let sequences = Dop853::new(1e-12, 1e-14)
        .with_lie_step(false)
        .integrate(&body, 0.0, x0, 20.0)
        .unwrap();
    let seq_turned = (seq.matrix(&[sequences.x[0], sequences.x[1], sequences.x[2]]) - r_ref).amax();
    println!(
        "tumbling body: {} steps, orientation at t = 20 {turned:.1e}, momentum {worst:.1e}, \
         closest to the pole |cos(pitch)| = {pole:.1e}; switching sequences {} steps \
         ({} switches), orientation {seq_turned:.1e}",
        out.stats.steps, sequences.stats.steps, sequences.stats.chart_switches
    );
    assert!(pole < 0.05, "the run passes near gimbal lock: {pole}");
    assert!(turned < 1e-9, "{turned:e}");
    assert!(worst < 1e-9, "{worst:e}");
    assert!(seq_turned < 1e-8, "{seq_turned:e}");
}
