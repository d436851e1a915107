//! Work–precision report of a fast-spinning body through gimbal lock: a
//! homogeneous ball on a table turning at Ω = 2π (its spin runs up to
//! ~80 rad/s) with its orientation in yaw, pitch and roll, integrated for
//! 10 s by DOP853 at tolerances from 1e-4 to 1e-12 in three ways:
//!
//! * the generated system as it is: the rotation advanced in its canonical
//!   coordinates (the Lie-group step, DESIGN §9.4);
//! * the same system switching Euler sequences (`with_lie_step(false)`);
//! * the same ball written here by hand with a unit quaternion.
//!
//! The error is the largest entry of the orientation's difference at
//! t = 10 from the quaternion ball's at rtol 1e-14.
//!
//! ```text
//! cargo run --release -p nh-lab --example spinning_ball
//! ```
//!
//! Prints a Markdown table and writes `target/reports/spinning_ball.csv`
//! and `target/reports/work_precision_spinning_ball.svg`, of which
//! `docs/work_precision_spinning_ball.svg` is a copy.
use nalgebra::{Matrix3, Quaternion, UnitQuaternion};
use nh_lab::report::{self, Run};
use nonholonomic::prelude::*;
use std::path::Path;

// the hand-written quaternion ball the tests compare with
#[allow(dead_code)]
#[path = "../../tests/common/turntable.rs"]
mod turntable;

nonholonomic_system! {
    /// A homogeneous ball on a table turning at `Omega`, in yaw, pitch and
    /// roll.
    pub struct EulerBall {
        parameters { m, R, Omega }
        coordinates { x, y, phi, theta, psi }
        let Q = rot_z(phi) * rot_y(theta) * rot_x(psi);
        let w = omega(Q);
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + m*R^2/5*(w.x^2 + w.y^2 + w.z^2);
        constraints {
            dot(x) = R*w.y - Omega*y;
            dot(y) = -R*w.x + Omega*x;
        }
    }
}

const RADIUS: f64 = 0.1;
const TABLE: f64 = 2.0 * std::f64::consts::PI;
const T1: f64 = 10.0;
const REPEATS: usize = 5;
const RTOLS: [f64; 9] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12];

/// The quaternion ball's orientation at `T1` with `rtol`, and its outcome.
fn quaternion_run(rtol: f64) -> (Matrix3<f64>, Outcome<f64, 9>) {
    let s0 = SVector::<f64, 9>::from([0.3, -0.1, 0.7, -0.4, 1.1, 1.0, 0.0, 0.0, 0.0]);
    let out = Dop853::new(rtol, rtol * 1e-2)
        .integrate(&turntable::quaternion_ball(RADIUS, TABLE), 0.0, s0, T1)
        .expect("the quaternion ball runs");
    let q = Quaternion::new(out.x[5], out.x[6], out.x[7], out.x[8]);
    let r = UnitQuaternion::from_quaternion(q).to_rotation_matrix();
    (r.into_inner(), out)
}

/// One timed run of the Euler ball (`lie_step`: in canonical coordinates)
/// against the reference orientation.
fn euler_run(ball: &EulerBall<f64>, rtol: f64, lie_step: bool, reference: &Matrix3<f64>) -> Run {
    // upright, the world ω (0.7, −0.4, 1.1) as yaw, pitch and roll rates
    let x0 = SVector::<f64, 8>::from([0.3, -0.1, 0.0, 0.0, 0.0, 1.1, -0.4, 0.7]);
    let (seconds, out) = report::median_time(REPEATS, || {
        Dop853::new(rtol, rtol * 1e-2)
            .with_lie_step(lie_step)
            .integrate(ball, 0.0, x0, T1)
            .expect("the Euler ball runs")
    });
    let r = EulerSequence::ZYX.matrix(&[out.x[2], out.x[3], out.x[4]]);
    let integrator = if lie_step {
        "canonical coordinates"
    } else {
        "switching sequences"
    };
    run(
        integrator,
        rtol,
        (seconds, &out.stats),
        (r - reference).amax(),
    )
}

fn run(integrator: &str, tolerance: f64, (seconds, stats): (f64, &Stats), error: f64) -> Run {
    Run {
        scene: "spinning_ball".into(),
        integrator: integrator.into(),
        tolerance,
        steps: stats.steps,
        rhs_evals: stats.rhs_evals,
        seconds,
        error,
        energy_error: None,
    }
}

fn main() {
    let ball = EulerBall::new(1.0, RADIUS, TABLE);
    let (reference, _) = quaternion_run(1e-14);
    let bar = report::progress_bar(3 * RTOLS.len());
    let mut runs = Vec::new();
    for rtol in RTOLS {
        runs.push(euler_run(&ball, rtol, true, &reference));
        runs.push(euler_run(&ball, rtol, false, &reference));
        let (seconds, (r, out)) = report::median_time(REPEATS, || quaternion_run(rtol));
        let error = (r - reference).amax();
        runs.push(run(
            "quaternion by hand",
            rtol,
            (seconds, &out.stats),
            error,
        ));
        bar.inc(3);
    }
    bar.finish();
    println!("# A ball spinning through gimbal lock (DOP853, {REPEATS} repeats, median)\n");
    println!("{}", report::markdown_table(&runs));
    let dir = Path::new("target/reports");
    if let Err(e) = report::write_csv(&dir.join("spinning_ball.csv"), &runs) {
        eprintln!("spinning_ball.csv: {e}");
    }
    let svg = report::svg_work_precision("spinning_ball", &runs);
    if let Err(e) = std::fs::write(dir.join("work_precision_spinning_ball.svg"), svg) {
        eprintln!("work_precision_spinning_ball.svg: {e}");
    }
    println!(
        "\nWrote target/reports/spinning_ball.csv and target/reports/work_precision_spinning_ball.svg"
    );
}
