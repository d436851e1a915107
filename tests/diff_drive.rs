//! The differential-drive example (`examples/diff_drive.rs`, included below as
//! a module so the test runs the example's own model and loop):
//!
//! * the wheel accelerations and the constraint forces against an
//!   independent SymPy derivation (`tests/data/diff_drive_sympy.py`: the
//!   Euler–Lagrange equations with multipliers of the contact points' no-slip
//!   rows, solved at 50 digits; it also checks the closed form used below);
//! * closed forms: the run from rest under equal torques, and a steady turn
//!   held by the torques the reduced equations in (v, ω) give;
//! * the work–energy balance under the controller's torques;
//! * the tracking figures the example reports, against the bounds measured.
#[path = "../examples/diff_drive.rs"]
#[allow(dead_code)] // the example's `main` and plot
mod example;

use example::{DiffDrive, DiffDriveCoordinates, DiffDriveParameters, DiffDriveVelocities};
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The example's robot as a new user might write it: each wheel rolls
    /// (`rolls(..)`), instead of the constraints written out. The wheels'
    /// sideways rows coincide (one axle); the second is implied and dropped.
    pub struct RollingWheels {
        parameters { m, Ic, d, mw, Iw, Id, r, b, c }
        coordinates { x, y, theta, phi_l, phi_r }
        inputs { tau_l, tau_r }
        let heading = [cos(theta), sin(theta), 0];
        let axle = [-sin(theta), cos(theta), 0];
        let O = [x, y, r];
        body chassis { mass: m, centre: O + d*heading, orientation: rot_z(theta), inertia: diag(0, 0, Ic) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r);
        constraints {
            rolls(wheel_l, radius: r, axle: [0, 1, 0]);
            rolls(wheel_r, radius: r, axle: [0, 1, 0]);
        }
        dependent { x, y, theta }
        forces {
            phi_l: tau_l - c*dot(phi_l);
            phi_r: tau_r - c*dot(phi_r);
        }
        outputs { energy }
    }
}

fn from_json(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// The robot with the example's parameters but the bearing friction `c`.
fn robot_with_friction(c: f64) -> DiffDrive {
    DiffDrive::from_parameters(DiffDriveParameters {
        c,
        ..example::robot().parameters()
    })
}

/// One state of `tests/data/diff_drive.json` with SymPy's accelerations.
struct Case {
    q: SVector<f64, 5>,
    rdot: SVector<f64, 2>,
    u: SVector<f64, 2>,
    accelerations: Vec<f64>,
    /// The case as stored (for its other fields).
    json: serde_json::Value,
}

/// The parameters SymPy was given and its 24 cases.
fn sympy_cases() -> (serde_json::Value, Vec<Case>) {
    let data: serde_json::Value =
        serde_json::from_str(include_str!("data/diff_drive.json")).expect("json");
    let cases = data["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| Case {
            q: SVector::from_column_slice(&from_json(&case["q"])),
            rdot: SVector::from_column_slice(&from_json(&case["rdot"])),
            u: SVector::from_column_slice(&from_json(&case["inputs"])),
            accelerations: from_json(&case["accelerations"]),
            json: case.clone(),
        })
        .collect();
    (data["parameters"].clone(), cases)
}

/// The largest error of `a` against SymPy's accelerations, relative where
/// they exceed 1.
fn acceleration_error(a: &SVector<f64, 2>, case: &Case) -> f64 {
    (0..2)
        .map(|i| (a[i] - case.accelerations[i]).abs() / case.accelerations[i].abs().max(1.0))
        .fold(0.0, f64::max)
}

#[test]
fn accelerations_and_constraint_forces_agree_with_sympy() {
    let (p, cases) = sympy_cases();
    let get = |name: &str| p[name].as_f64().expect(name);
    let robot = DiffDrive::from_parameters(DiffDriveParameters {
        m: get("m"),
        Ic: get("Ic"),
        d: get("d"),
        mw: get("mw"),
        Iw: get("Iw"),
        Id: get("Id"),
        r: get("r"),
        b: get("b"),
        c: get("c"),
    });
    // the example's robot is the one SymPy was given
    assert_eq!(robot, example::robot());
    let (r, b) = (robot.r, robot.b);
    let (mut worst_acc, mut worst_force) = (0.0_f64, 0.0_f64);
    assert_eq!(cases.len(), 24);
    for case in &cases {
        let (q, rdot, u) = (case.q, case.rdot, case.u);
        let a = robot.accelerations(0.0, &q, &rdot, &u);
        worst_acc = worst_acc.max(acceleration_error(&a, case));
        // Cᵀλ, the constraint force on every coordinate: λ on x, y, θ;
        // on each wheel, Σ_a A^a λ_a with A^a minus the wheel rate's
        // coefficient in the constraint of x, y, θ
        let lambda = robot.multipliers(0.0, &q, &rdot, &u);
        let (s, c) = q[2].sin_cos();
        let along = r / 2.0 * (c * lambda[0] + s * lambda[1]);
        let turn = r / (2.0 * b) * lambda[2];
        let force = [
            lambda[0],
            lambda[1],
            lambda[2],
            -(along - turn),
            -(along + turn),
        ];
        let reference = from_json(&case.json["reaction_forces"]);
        let scale = reference.iter().fold(1.0_f64, |m, f| m.max(f.abs()));
        for i in 0..5 {
            worst_force = worst_force.max((force[i] - reference[i]).abs() / scale);
        }
    }
    println!("against SymPy: accelerations {worst_acc:.1e}, constraint forces {worst_force:.1e}");
    assert!(worst_acc < 1e-12, "accelerations off by {worst_acc:.1e}");
    assert!(
        worst_force < 1e-12,
        "constraint forces off by {worst_force:.1e}"
    );
}

/// Both wheels written as rolling bodies: the implied sideways row of the
/// second wheel is dropped, and the accelerations are SymPy's.
#[test]
fn two_rolling_wheels_on_one_axle_give_sympys_accelerations() {
    let p = example::robot();
    let robot = RollingWheels::new(p.m, p.Ic, p.d, p.mw, p.Iw, p.Id, p.r, p.b, p.c);
    assert_eq!(RollingWheels::INDEPENDENT, [3, 4]);
    assert_eq!(RollingWheels::P, 3);
    let worst = sympy_cases()
        .1
        .iter()
        .map(|c| acceleration_error(&robot.accelerations(0.0, &c.q, &c.rdot, &c.u), c))
        .fold(0.0, f64::max);
    println!("two rolling wheels against SymPy: accelerations {worst:.1e}");
    assert!(worst < 1e-12, "accelerations off by {worst:.1e}");
}

/// Equal torques τ from rest: the robot runs straight, and each wheel obeys
/// J φ̈ = τ − c φ̇ with J = Iw + r² (m + 2 mw)/2 (the wheel's share of the
/// robot's mass, seen through its radius): φ̇ = (τ/c)(1 − e^(−ct/J)).
#[test]
fn equal_torques_from_rest_drive_straight_as_the_closed_form() {
    let robot = example::robot();
    let (tau, theta0) = (0.3, 0.4_f64);
    let j = robot.Iw + robot.r * robot.r * (robot.m + 2.0 * robot.mw) / 2.0;
    let c = robot.c;
    let q0 = DiffDriveCoordinates {
        x: 0.5,
        y: -0.2,
        theta: theta0,
        ..Default::default()
    };
    let x0 = DiffDrive::state(q0, DiffDriveVelocities::default());
    let u = SVector::from([tau, tau]);
    let a0 = robot.accelerations(0.0, &q0.into(), &SVector::zeros(), &u);
    assert!((a0[0] - tau / j).abs() < 1e-13 && (a0[1] - tau / j).abs() < 1e-13);

    let t1 = 3.0;
    let out = Dopri5::new(1e-12, 1e-14)
        .integrate(&Driven::new(&robot, u), 0.0, x0, t1)
        .expect("run");
    let (q, v) = DiffDrive::split(&out.x);
    let decay = (-c * t1 / j).exp();
    let rate = tau / c * (1.0 - decay);
    let angle = tau / c * (t1 - j / c * (1.0 - decay));
    let travel = robot.r * angle;
    let errors = [
        (v.phi_l - rate) / rate,
        (v.phi_r - rate) / rate,
        (q.phi_l - angle) / angle,
        (q.phi_r - angle) / angle,
        (q.x - 0.5 - travel * theta0.cos()) / travel,
        (q.y + 0.2 - travel * theta0.sin()) / travel,
        q.theta - theta0,
    ];
    let worst = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    println!("straight run, {travel:.4} m in {t1} s: worst relative error {worst:.1e}");
    assert!(worst < 1e-10, "{errors:?}");
}

/// A steady turn at speed v and rate ω: the reduced equations
/// (m + 2 mw + 2 Iw/r²) v̇ − m d ω² = (τ_l + τ_r − c (φ̇_l + φ̇_r))/r and
/// (It + 2 b² Iw/r²) ω̇ + m d ω v = b (τ_r − τ_l − c (φ̇_r − φ̇_l))/r
/// give the torques that hold it; the axle midpoint then runs on the circle
/// of radius v/ω.
#[test]
fn steady_turn_runs_on_its_circle() {
    let robot = example::robot();
    let (r, b, c, m, d) = (robot.r, robot.b, robot.c, robot.m, robot.d);
    let (v, w) = (0.4, 0.8);
    let (rate_l, rate_r) = ((v - b * w) / r, (v + b * w) / r);
    let sum = c * (rate_l + rate_r) - r * m * d * w * w;
    let diff = c * (rate_r - rate_l) + r * m * d * w * v / b;
    let u = SVector::from([(sum - diff) / 2.0, (sum + diff) / 2.0]);
    // the centre of mass ahead of the axle pulls outwards: the outer (right
    // for a left turn) wheel is driven harder, and both push back on the speed
    assert!(u[1] > u[0]);

    let q0 = DiffDriveCoordinates {
        x: 1.0,
        y: 2.0,
        theta: 0.3,
        ..Default::default()
    };
    let qdot = DiffDriveCoordinates {
        x: v * 0.3_f64.cos(),
        y: v * 0.3_f64.sin(),
        theta: w,
        phi_l: rate_l,
        phi_r: rate_r,
    };
    let x0 = robot
        .state_from_velocities(q0, qdot)
        .expect("a rolling state");
    let (_, rates) = DiffDrive::split(&x0);
    let a = robot.accelerations(0.0, &q0.into(), &rates.into(), &u);
    assert!(a.norm() < 1e-12, "not steady: {a:?}");

    let period = 2.0 * std::f64::consts::PI / w;
    let out = Dopri5::new(1e-12, 1e-14)
        .integrate(&Driven::new(&robot, u), 0.0, x0, period * 1.25)
        .expect("run");
    let (q, rates1) = DiffDrive::split(&out.x);
    let radius = v / w;
    let (cx, cy) = (
        q0.x - radius * q0.theta.sin(),
        q0.y + radius * q0.theta.cos(),
    );
    let theta = q0.theta + w * out.t;
    let errors = [
        q.x - (cx + radius * theta.sin()),
        q.y - (cy - radius * theta.cos()),
        q.theta - theta,
        rates1.phi_l - rate_l,
        rates1.phi_r - rate_r,
    ];
    let worst = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    println!("steady turn, radius {radius} m, 1.25 turns: worst error {worst:.1e}");
    assert!(worst < 1e-9, "{errors:?}");
}

/// Without bearing friction, the energy changes by the motors' work alone:
/// the torques are held over each period, so their work is τ · Δφ exactly.
#[test]
fn energy_changes_by_the_work_of_the_motors() {
    let robot = robot_with_friction(0.0);
    let mut x = example::start(&robot);
    let mut tracker = example::Tracker::default();
    let energy = |x: &SVector<f64, 7>| {
        let (q, v) = DiffDrive::split(x);
        robot.energy(&q.into(), &v.into())
    };
    let (e0, mut work, mut largest) = (energy(&x), 0.0, 0.0_f64);
    let mut dp = Dopri5::new(1e-12, 1e-14);
    for k in 0..1000 {
        let t = k as f64 * example::PERIOD;
        let (q, rates) = DiffDrive::split(&x);
        let tau = tracker.torques(&robot, &q, &rates, &example::figure_eight(t));
        let next = dp
            .integrate(&Driven::new(&robot, tau), t, x, t + example::PERIOD)
            .expect("run")
            .x;
        let (q1, _) = DiffDrive::split(&next);
        work += tau[0] * (q1.phi_l - q.phi_l) + tau[1] * (q1.phi_r - q.phi_r);
        largest = largest.max(energy(&next));
        x = next;
    }
    let gained = energy(&x) - e0;
    let error = (gained - work).abs() / largest;
    println!(
        "10 s: energy {e0:.6} → {:.6} J, work {work:.6} J, imbalance {error:.1e} of the largest energy",
        energy(&x)
    );
    assert!(work.abs() > 0.1, "the motors did work");
    assert!(error < 1e-10, "imbalance {error:.1e}");
}

#[test]
fn the_start_is_checked_against_the_rolling_constraints() {
    let robot = example::robot();
    let x0 = example::start(&robot);
    let (q, v) = DiffDrive::split(&x0);
    assert_eq!((q.x, q.y, q.theta), (-0.4, -0.3, 0.0));
    assert!((v.phi_l - 0.2 / robot.r).abs() < 1e-15 && (v.phi_r - v.phi_l).abs() < 1e-15);
    // sliding sideways is not a state of this robot
    let sliding = DiffDriveCoordinates {
        x: 0.2,
        y: 0.05,
        theta: 0.0,
        phi_l: 4.0,
        phi_r: 4.0,
    };
    let e = robot.state_from_velocities(q, sliding).unwrap_err();
    assert_eq!(e.coordinate, "y");
}

/// The bounds are the figures the example reports (max 7.4e-4 m, RMS
/// 5.2e-4 m over the last two laps, from an initial error of 0.5 m), with a
/// margin of about a third.
#[test]
fn the_tracker_holds_the_figure_eight() {
    let robot = example::robot();
    let samples = example::run(&robot, example::DURATION);
    assert_eq!(
        samples.len(),
        (example::DURATION / example::PERIOD).round() as usize + 1
    );
    let f = example::figures(&samples);
    println!("{f:?}");
    assert!(f.max_error_transient > 0.49, "it starts off the path");
    assert!(f.max_error < 1e-3, "max error {:.2e} m", f.max_error);
    assert!(f.rms_error < 7e-4, "RMS error {:.2e} m", f.rms_error);
    assert!(f.peak_torque <= example::TAU_MAX);
    assert!(f.peak_friction < 0.35, "friction {:.3}", f.peak_friction);
    // after three laps it is back at the start of the eight
    let last = samples.last().expect("samples");
    assert!(last.q.x.hypot(last.q.y) < 1e-3);
}
