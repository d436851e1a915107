//! Orientations without gimbal lock (DESIGN §9.4): a ball on a turntable
//! with its orientation in yaw, pitch and roll, whose chart is singular
//! where the pitch is ±π/2, runs through that pole in the chart of another
//! sequence, against
//!
//! * the closed form of its centre, which circles at 2Ω/7 of the table's
//!   rate;
//! * the same ball with the rates of three fictitious angles as velocities
//!   (no singularity): the same centre, the same angular velocity, and the
//!   steps it takes;
//! * itself held in one chart, away from the pole.
use nonholonomic::prelude::*;
use std::f64::consts::FRAC_PI_2;

#[path = "common/turntable.rs"]
mod turntable;
use turntable::{TurntableBall, ball_centre};

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
    let tol = Dop853::new(1e-12, 1e-14);
    let (free_states, free_out) = sampled(tol, &TurntableBall::new(M, R, OMEGA), free_start());
    // from the upright orientation, and from 0.01 short of the pole
    for (angles, name) in [
        ([0.0, 0.0, 0.0], "upright"),
        ([0.3, FRAC_PI_2 - 0.01, -0.2], "near the pole"),
    ] {
        let x0 = euler_start(angles);
        let (states, out) = sampled(tol, &euler, x0);
        let (centre, spin) = errors(&states, &free_states);
        let held = tol
            .with_chart_switching(false)
            .integrate(&euler, 0.0, x0, 10.0);
        let switches: Vec<(f64, usize, usize)> =
            out.switches.iter().map(|s| (s.t, s.from, s.to)).collect();
        println!(
            "{name}: {} steps + {} rejected, switches {switches:.4?}; held in chart 0: {}; \
             the free ball {} + {}; centre {centre:.1e}, ω {spin:.1e}",
            out.stats.steps,
            out.stats.rejected,
            match &held {
                Ok(o) => format!("{} steps + {} rejected", o.stats.steps, o.stats.rejected),
                Err(e) => format!("{e}"),
            },
            free_out.stats.steps,
            free_out.stats.rejected,
        );
        assert!(centre <= 1e-9, "{name}: {centre:e}");
        assert!(spin <= 1e-8, "{name}: {spin:e}");
        assert!(!switches.is_empty(), "{name}");
        // the pole costs held runs at least twice the steps
        if let Ok(o) = held {
            assert!(2 * out.stats.steps <= o.stats.steps, "{name}");
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

#[test]
fn the_angles_seen_are_continuous_across_switches() {
    // outputs every millisecond through 30 s and its switches (10, the
    // first at 0.19 s; from 28.07 s on, a spin about the body's z axis
    // while it lies horizontal takes its x and y axes through the vertical
    // in turn, the poles of the first two sequences, and the run keeps to
    // the ones whose poles are on the z axis): no jump by a whole turn
    // where chart 0 is far from its pole (|cos θ| > 0.5, where the rates
    // stay below a few hundred rad/s)
    let euler = EulerBall::new(M, R, OMEGA);
    let x0 = euler_start([0.0, 0.0, 0.0]);
    let times: Vec<f64> = (1..=30_000).map(|i| 1e-3 * i as f64).collect();
    let mut last: Option<SVector<f64, 8>> = None;
    let mut jump = 0.0f64;
    let out = Dop853::new(1e-10, 1e-12)
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
    println!(
        "{} switches; largest step of an angle between outputs: {jump:.3}",
        out.stats.chart_switches
    );
    assert!(out.stats.chart_switches >= 5);
    assert!(jump < 1.0, "{jump}");
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
    assert!(out.stats.chart_switches >= 1);
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
