//! A differential-drive robot following a figure eight: two wheels driven by
//! torques, the chassis's centre of mass ahead of the axle, a kinematic
//! tracking law (Kanayama's) giving the forward speed and turn rate it wants,
//! and a PI loop on each wheel's rate turning them into torques.
//!
//! **Model.** The axle midpoint is at (x, y), the heading is θ; the wheels
//! (radius r, at ±b along the axle, left at +b) are turned by φ_l and φ_r,
//! positive forward. The chassis has mass m and yaw inertia Ic about its
//! centre of mass, a distance d ahead of the axle; each wheel has mass mw,
//! spin inertia Iw and inertia Id about a diameter. Neither wheel slips: the
//! axle midpoint moves along the heading at v = r (φ̇_l + φ̇_r)/2 and the
//! chassis turns at ω = r (φ̇_r − φ̇_l)/(2b), three constraints on five
//! velocities, so the wheel rates are the state's velocities. The motors
//! apply torques τ_l, τ_r between chassis and wheels; the bearings have
//! viscous friction c. The wheels are bodies that turn about the axle; their
//! rolling is written as the three constraints (a `rolls` line per wheel would
//! give four rows of rank three, since both wheels' sideways rows are the
//! rigid axle's one).
//!
//! **Controller**, every [`PERIOD`] = 10 ms with the torques held by `Driven`
//! in between: with the pose error in the robot's frame,
//! e_x = cos θ Δx + sin θ Δy, e_y = −sin θ Δx + cos θ Δy, e_θ = θ_r − θ,
//! Kanayama's law asks for
//! v* = v_r cos e_θ + k_x e_x and ω* = ω_r + v_r (k_y e_y + k_θ sin e_θ);
//! the wheel rates that give them, (v* ∓ b ω*)/r, are tracked by
//! τ = k_p e + k_i ∫e on each wheel's rate error e, saturated at ±[`TAU_MAX`]
//! (the integral stops while saturated).
//!
//! **Reference**: the figure eight x_r = A sin Ωt, y_r = A sin Ωt cos Ωt
//! (A = 1.5 m, one lap in 24 s, up to 0.56 m/s), with the heading and turn
//! rate of its tangent. The robot starts 0.4 m behind and 0.3 m beside the
//! start of the eight, heading along x at 0.2 m/s.
//!
//! It prints the axle midpoint's position error (max and RMS over the last
//! two laps, after the transient), the peak torques and the friction the
//! ground must supply (from the constraint forces), and writes the path
//! against the reference to `target/diff_drive.svg`.
//!
//! ```text
//! cargo run --release --example diff_drive
//! ```
use nonholonomic::prelude::*;
use plotters::prelude::*;

nonholonomic_system! {
    /// A differential-drive robot on level ground, driven by wheel torques.
    pub struct DiffDrive {
        parameters { m, Ic, d, mw, Iw, Id, r, b, c }
        coordinates { x, y, theta, phi_l, phi_r }
        inputs { tau_l, tau_r }

        let heading = [cos(theta), sin(theta), 0];
        let axle = [-sin(theta), cos(theta), 0];      // to the left
        let O = [x, y, r];                            // axle midpoint
        body chassis {
            mass: m, centre: O + d*heading, orientation: rot_z(theta),
            inertia: diag(0, 0, Ic),                  // only the yaw inertia moves
        }
        body wheel_l {
            mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l),
            inertia: diag(Id, Iw, Id),
        }
        body wheel_r {
            mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r),
            inertia: diag(Id, Iw, Id),
        }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r);

        constraints {
            dot(x) = r/2*(dot(phi_l) + dot(phi_r))*cos(theta);   // along the heading,
            dot(y) = r/2*(dot(phi_l) + dot(phi_r))*sin(theta);   // never sideways
            dot(theta) = r/(2*b)*(dot(phi_r) - dot(phi_l));
        }
        forces {
            phi_l: tau_l - c*dot(phi_l);
            phi_r: tau_r - c*dot(phi_r);
        }
        outputs { energy, multipliers }
    }
}

/// Control period (s): the torques are held over it.
pub const PERIOD: f64 = 0.01;
/// Step of the fixed-step integrator inside one period (s).
pub const STEP: f64 = 0.001;
/// Half width of the figure eight (m).
pub const A: f64 = 1.5;
/// Time of one lap (s).
pub const LAP: f64 = 24.0;
/// Length of the run: three laps (s).
pub const DURATION: f64 = 3.0 * LAP;
/// The errors are measured from here on: the last two laps (s).
pub const SETTLED: f64 = LAP;
/// Motor torque limit (N m).
pub const TAU_MAX: f64 = 1.0;
/// Standard gravity, for the friction the ground must supply (m/s²).
pub const G: f64 = 9.81;

/// The robot of the example: 12 kg chassis, centre of mass 10 cm ahead of
/// the axle, wheels of 5 cm radius and 0.5 kg, 30 cm track.
pub fn robot() -> DiffDrive {
    DiffDrive::from_parameters(DiffDriveParameters {
        m: 12.0,
        Ic: 0.3,
        d: 0.1,
        mw: 0.5,
        Iw: 6.25e-4,  // mw r²/2: uniform discs
        Id: 3.125e-4, // mw r²/4
        r: 0.05,
        b: 0.15,
        c: 0.01,
    })
}

/// The reference pose and its velocities at one instant.
#[derive(Debug, Clone, Copy)]
pub struct Reference {
    /// Position (m).
    pub x: f64,
    /// See `x`.
    pub y: f64,
    /// Heading of the path (rad).
    pub theta: f64,
    /// Speed along the path (m/s).
    pub v: f64,
    /// Turn rate of the path's heading (rad/s).
    pub omega: f64,
}

/// The figure eight x = A sin Ωt, y = A sin Ωt cos Ωt = (A/2) sin 2Ωt.
pub fn figure_eight(t: f64) -> Reference {
    let w = 2.0 * std::f64::consts::PI / LAP;
    let (s, c) = (w * t).sin_cos();
    let (s2, c2) = (2.0 * w * t).sin_cos();
    let (dx, dy) = (A * w * c, A * w * c2);
    let (ddx, ddy) = (-A * w * w * s, -2.0 * A * w * w * s2);
    let speed2 = dx * dx + dy * dy;
    Reference {
        x: A * s,
        y: A * s * c,
        theta: dy.atan2(dx),
        v: speed2.sqrt(),
        omega: (dx * ddy - dy * ddx) / speed2,
    }
}

/// Gains of the tracking law and of the wheel-rate loops.
#[derive(Debug, Clone, Copy)]
pub struct Gains {
    /// Along-track gain k_x (1/s).
    pub kx: f64,
    /// Cross-track gain k_y (1/m²).
    pub ky: f64,
    /// Heading gain k_θ (1/m).
    pub ktheta: f64,
    /// Proportional gain of the wheel-rate loop (N m s/rad).
    pub kp: f64,
    /// Integral gain of the wheel-rate loop (N m/rad).
    pub ki: f64,
}

/// The gains of the example.
pub const GAINS: Gains = Gains {
    kx: 1.5,
    ky: 6.0,
    ktheta: 3.0,
    kp: 0.6,
    ki: 6.0,
};

/// The controller's memory: the integrals of the wheel-rate errors.
#[derive(Debug, Clone, Copy, Default)]
pub struct Tracker {
    integral: [f64; 2],
}

impl Tracker {
    /// The torques [τ_l, τ_r] for the measured pose and wheel rates.
    pub fn torques(
        &mut self,
        robot: &DiffDrive,
        q: &DiffDriveCoordinates,
        rates: &DiffDriveVelocities,
        goal: &Reference,
    ) -> SVector<f64, 2> {
        let g = GAINS;
        let (s, c) = q.theta.sin_cos();
        let (dx, dy) = (goal.x - q.x, goal.y - q.y);
        let (ex, ey, eth) = (c * dx + s * dy, -s * dx + c * dy, goal.theta - q.theta);
        let v = goal.v * eth.cos() + g.kx * ex;
        let w = goal.omega + goal.v * (g.ky * ey + g.ktheta * eth.sin());
        let wanted = [(v - robot.b * w) / robot.r, (v + robot.b * w) / robot.r];
        let measured = [rates.phi_l, rates.phi_r];
        let mut tau = [0.0; 2];
        for i in 0..2 {
            let e = wanted[i] - measured[i];
            let raw = g.kp * e + g.ki * (self.integral[i] + e * PERIOD);
            tau[i] = raw.clamp(-TAU_MAX, TAU_MAX);
            if raw == tau[i] {
                self.integral[i] += e * PERIOD; // no wind-up while saturated
            }
        }
        SVector::from(tau)
    }
}

/// One control period's record.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// The robot's coordinates.
    pub q: DiffDriveCoordinates,
    /// The reference at `t`.
    pub goal: Reference,
    /// Torques applied from `t` (N m).
    pub tau: SVector<f64, 2>,
    /// Horizontal ground force on the robot, as a fraction of its weight.
    pub friction: f64,
}

impl Sample {
    /// Distance of the axle midpoint from the reference point (m).
    pub fn position_error(&self) -> f64 {
        (self.q.x - self.goal.x).hypot(self.q.y - self.goal.y)
    }
}

/// The starting state: behind and beside the eight, driving along x at
/// 0.2 m/s, given as the velocities of every coordinate and checked
/// against the rolling constraints.
pub fn start(robot: &DiffDrive) -> SVector<f64, 7> {
    let q = DiffDriveCoordinates {
        x: -0.4,
        y: -0.3,
        ..Default::default()
    };
    let v = 0.2;
    let qdot = DiffDriveCoordinates {
        x: v,
        y: 0.0,
        theta: 0.0,
        phi_l: v / robot.r,
        phi_r: v / robot.r,
    };
    robot
        .state_from_velocities(q, qdot)
        .expect("rolling straight ahead")
}

/// Runs the loop for `duration` seconds; one sample per control period.
pub fn run(robot: &DiffDrive, duration: f64) -> Vec<Sample> {
    let mut x = start(robot);
    let mut tracker = Tracker::default();
    let mut rk4 = Rk4::new(STEP);
    let periods = (duration / PERIOD).round() as usize;
    let mut samples = Vec::with_capacity(periods + 1);
    for k in 0..=periods {
        let t = k as f64 * PERIOD;
        let (q, rates) = DiffDrive::split(&x);
        let goal = figure_eight(t);
        let tau = tracker.torques(robot, &q, &rates, &goal);
        let friction = ground_force(robot, t, &x, &tau) / ((robot.m + 2.0 * robot.mw) * G);
        samples.push(Sample {
            t,
            q,
            goal,
            tau,
            friction,
        });
        if k == periods {
            break;
        }
        x = match rk4.integrate(&Driven::new(robot, tau), t, x, t + PERIOD) {
            Ok(out) => out.x,
            Err(e) => panic!("the run failed: {e}"),
        };
    }
    samples
}

/// The horizontal force the ground exerts on the robot (N): the
/// multipliers of the constraints of x and y are its world components.
pub fn ground_force(robot: &DiffDrive, t: f64, x: &SVector<f64, 7>, tau: &SVector<f64, 2>) -> f64 {
    let (q, rates) = DiffDrive::split(x);
    let lambda = robot.multipliers(t, &q.into(), &rates.into(), tau);
    lambda[0].hypot(lambda[1])
}

/// Tracking figures of a run.
#[derive(Debug, Clone, Copy)]
pub struct Figures {
    /// Max position error after [`SETTLED`] (m).
    pub max_error: f64,
    /// RMS position error after [`SETTLED`] (m).
    pub rms_error: f64,
    /// Max position error over the whole run (m).
    pub max_error_transient: f64,
    /// Peak |τ| (N m).
    pub peak_torque: f64,
    /// Peak horizontal ground force over the weight: the friction
    /// coefficient the wheels need not to skid.
    pub peak_friction: f64,
}

/// The figures of a run's samples.
pub fn figures(samples: &[Sample]) -> Figures {
    let settled: Vec<f64> = samples
        .iter()
        .filter(|s| s.t >= SETTLED)
        .map(Sample::position_error)
        .collect();
    let max = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0, f64::max);
    Figures {
        max_error: max(&mut settled.iter().copied()),
        rms_error: (settled.iter().map(|e| e * e).sum::<f64>() / settled.len() as f64).sqrt(),
        max_error_transient: max(&mut samples.iter().map(Sample::position_error)),
        peak_torque: max(&mut samples.iter().map(|s| s.tau.abs().max())),
        peak_friction: max(&mut samples.iter().map(|s| s.friction)),
    }
}

/// The path against the reference (left) and the position error against
/// time (right).
fn plot(samples: &[Sample], path: &str) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    let root = SVGBackend::new(path, (1000, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(480);

    let mut chart = ChartBuilder::on(&left)
        .caption("differential drive on a figure eight", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(-1.8..1.8, -1.6..1.6)?;
    chart
        .configure_mesh()
        .x_desc("x [m]")
        .y_desc("y [m]")
        .draw()?;
    chart
        .draw_series(LineSeries::new(
            samples.iter().step_by(5).map(|s| (s.goal.x, s.goal.y)),
            BLACK.mix(0.35).stroke_width(6),
        ))?
        .label("reference")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.mix(0.35).stroke_width(6)));
    chart
        .draw_series(LineSeries::new(
            samples.iter().step_by(5).map(|s| (s.q.x, s.q.y)),
            BLUE.stroke_width(1),
        ))?
        .label("axle midpoint")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE));
    let first = samples[0].q;
    chart.draw_series(std::iter::once(Circle::new(
        (first.x, first.y),
        4,
        RED.filled(),
    )))?;
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;

    let t_end = samples.last().map_or(1.0, |s| s.t);
    let mut err = ChartBuilder::on(&right)
        .caption("position error", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_end, (1e-4..1.0).log_scale())?;
    err.configure_mesh()
        .x_desc("t [s]")
        .y_desc("|p − p_ref| [m]")
        .draw()?;
    err.draw_series(LineSeries::new(
        samples
            .iter()
            .step_by(5)
            .map(|s| (s.t, s.position_error().max(1e-4))),
        BLUE,
    ))?;
    root.present()?;
    Ok(())
}

fn main() {
    let robot = robot();
    println!(
        "differential drive: {} coordinates {:?}, state [q, φ̇_l, φ̇_r] of {}",
        DiffDrive::N,
        DiffDrive::COORDINATES,
        DiffDrive::STATE_DIM
    );
    let samples = run(&robot, DURATION);
    println!("     t       x       y       θ   |error|    τ_l     τ_r");
    for s in samples.iter().step_by((4.0 / PERIOD) as usize) {
        println!(
            "{:6.1} {:7.3} {:7.3} {:7.3} {:9.2e} {:6.3} {:6.3}",
            s.t,
            s.q.x,
            s.q.y,
            s.q.theta,
            s.position_error(),
            s.tau[0],
            s.tau[1]
        );
    }
    let f = figures(&samples);
    println!("position error of the axle midpoint, t ≥ {SETTLED} s (two laps):");
    println!("  max {:.2e} m, RMS {:.2e} m", f.max_error, f.rms_error);
    println!(
        "  (max {:.3} m over the whole run, from the start off the path)",
        f.max_error_transient
    );
    println!(
        "peak torque {:.3} N m (limit {TAU_MAX}), peak ground force / weight {:.3} (the friction the wheels need)",
        f.peak_torque, f.peak_friction
    );
    let path = "target/diff_drive.svg";
    match plot(&samples, path) {
        Ok(()) => println!("wrote {path}"),
        Err(e) => println!("could not write the plot: {e}"),
    }
}
