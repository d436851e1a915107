//! A 1 kHz control loop: a Chaplygin sled steered along a path by a
//! gain-scheduled LQR designed from the generated linearisation.
//!
//! The sled (knife edge at (x, y), heading θ, centre of mass a distance `a`
//! ahead of the edge) has two inputs: a push along its heading and a steering
//! torque, with viscous damping on both. `outputs { linearization }` makes the
//! macro emit `linearization(t, x, u) -> (A, B)`, the symbolic ∂f/∂x and ∂f/∂u
//! of ẋ = f(t, x, u) for the state x = [x, θ, y, ẋ, θ̇].
//!
//! **Objective.** Drive along the line y = y_ref at the forward speed v_ref,
//! where the reference changes every 5 s (a lane change, then a speed-up):
//!
//! | segment | time | y_ref | v_ref |
//! |---|---|---|---|
//! | 0 | 0–5 s | 0 m | 1.0 m/s |
//! | 1 | 5–10 s | 0.5 m | 1.0 m/s |
//! | 2 | 10–15 s | 0.5 m | 1.5 m/s |
//!
//! starting off the path (y = −0.2 m, θ = 0.2 rad, ẋ = 0.6 m/s). Each change
//! is blended in along a minimum-jerk profile over [`BLEND`] = 2.5 s, and the
//! controller tracks the reference state of the blend: y_r, v_r, the path's
//! heading θ_r = atan(ẏ_r / v_r) and its rate ω_r. The bound the run asserts:
//! from [`SETTLE`] = 4 s after each change on (from 4 s for the initial
//! error), the lateral offset |y − y_ref|, the heading |θ| and the speed error
//! |v − v_ref| all stay below [`BOUND`] = 1e-3 (m, rad, m/s).
//!
//! **Design.** For each segment the steady motion is x* = [0, 0, y_ref, v_ref, 0]
//! (straight along x). The sled is invariant under translations, so x and y do
//! not enter f: the columns of A for x and y are zero (checked) and x is
//! dropped, leaving the error state z = [θ − θ_r, y − y_r, ẋ − v_r cos θ_r, θ̇ − ω_r].
//! The holding input u* solves f(x*, u*) = 0 exactly (the accelerations are
//! affine in u: u* = −B⁻¹ r̈(x*, 0), from the generated `accelerations` and B).
//! (A, B) is discretised exactly for the zero-order hold of one 1 ms period
//! (matrix exponential of the augmented matrix), the discrete Riccati equation
//! is solved by the structure-preserving doubling algorithm (Bryson's-rule
//! weights), and the loop applies u = u* − K z. The gain depends on v_ref
//! (ẏ = v θ), so one gain per segment is designed at start-up: gain scheduling
//! by reference, with no design work and no allocation in the loop.
//!
//! **Chart.** The constraint is written as ẏ = tan θ ẋ, a chart singular at
//! θ = ±π/2. The path runs along x, so the heading stays far from it (the run
//! asserts |θ| < 1). For a path along y, write the constraint for x instead.
//!
//! **Loop.** Each 1 ms iteration reads the state, evaluates the reference,
//! computes u, and advances one `Rk4` step with the input held by `Driven`.
//! The latency of controller + dynamics step is measured around every
//! iteration with `Instant` into a preallocated buffer; `tests/control_loop.rs`
//! runs this same loop under a counting allocator and asserts that it
//! allocates nothing. The loop is not paced to the wall clock (a real-time
//! loop would wait for the next tick): the latency is the part of the 1 ms
//! period the computation uses. Its maximum is set by the operating system
//! (preemption), not by the code.
//!
//! ```text
//! cargo run --release --example control_loop
//! ```
use std::time::Instant;

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Chaplygin sled pushed along its heading and steered by a torque, with
    /// linear damping `c` on the edge's velocity and `d` on the rotation.
    pub struct SteeredSled {
        parameters { m, J, a, c, d }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2
            + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces {
            x: push*cos(theta) - c*dot(x);
            y: push*sin(theta) - c*dot(y);
            theta: steer - d*dot(theta);
        }
        outputs { linearization }
    }
}

/// Control period: 1 kHz.
pub const H: f64 = 1e-3;
/// Length of one reference segment.
pub const SEGMENT: f64 = 5.0;
/// (y_ref, v_ref) of each segment.
pub const REFERENCES: [(f64, f64); 3] = [(0.0, 1.0), (0.5, 1.0), (0.5, 1.5)];
/// Duration of the minimum-jerk blend from one reference to the next.
pub const BLEND: f64 = 2.5;
/// Time after each reference change from which the bound must hold.
pub const SETTLE: f64 = 4.0;
/// Bound on |y − y_ref| (m), |θ| (rad) and |v − v_ref| (m/s) once settled.
pub const BOUND: f64 = 1e-3;
/// Initial state [x, θ, y, ẋ, θ̇]: off the path, turned and slow.
pub const X0: [f64; 5] = [0.0, 0.2, -0.2, 0.6, 0.0];

type State = SVector<f64, 5>;
type Input = SVector<f64, 2>;
type M4 = SMatrix<f64, 4, 4>;
type M42 = SMatrix<f64, 4, 2>;
type M2 = SMatrix<f64, 2, 2>;

/// The sled of the example: 2 kg, 0.3 kg m², centre of mass 0.5 m ahead of the edge.
pub fn sled() -> SteeredSled {
    SteeredSled::new(2.0, 0.3, 0.5, 0.4, 0.05)
}

/// State feedback about one steady motion: u = u* − K z.
#[derive(Debug, Clone, Copy)]
pub struct Gain {
    /// Lateral reference.
    pub y_ref: f64,
    /// Forward-speed reference.
    pub v_ref: f64,
    /// Input holding the steady motion.
    pub u_star: Input,
    /// LQR gain on z = [θ, y − y_ref, ẋ − v_ref, θ̇].
    pub k: SMatrix<f64, 2, 4>,
    /// Residual of the discrete Riccati equation, relative to ‖P‖.
    pub riccati_residual: f64,
    /// Real part of the slowest closed-loop pole (1/s).
    pub slowest_pole: f64,
}

impl Gain {
    /// LQR about the steady motion along y = `y_ref` at speed `v_ref`.
    pub fn design(sled: &SteeredSled, y_ref: f64, v_ref: f64) -> Self {
        let x_star = State::from([0.0, 0.0, y_ref, v_ref, 0.0]);
        let q = x_star.fixed_rows::<3>(0).into_owned();
        let rdot = x_star.fixed_rows::<2>(3).into_owned();
        // Accelerations are affine in u: solve r̈(x*, u*) = 0 with B's acceleration rows.
        let (_, b0) = sled.linearization(0.0, &x_star, &Input::zeros());
        let b_acc: M2 = b0.fixed_rows::<2>(3).into_owned();
        let u_star = -b_acc
            .try_inverse()
            .expect("inputs act on both accelerations")
            * sled.accelerations(0.0, &q, &rdot, &Input::zeros());
        let rest = sled.rhs_with_input(0.0, &x_star, &u_star);
        assert!(
            rest.fixed_rows::<2>(3).norm() < 1e-12,
            "not a steady motion"
        );

        let (a, b) = sled.linearization(0.0, &x_star, &u_star);
        assert!(
            a.column(0).norm() < 1e-12 && a.column(2).norm() < 1e-12,
            "x and y are cyclic"
        );
        // Reduced error state z = [θ, y, ẋ, θ̇] = x[1..5].
        let ar: M4 = a.fixed_view::<4, 4>(1, 1).into_owned();
        let br: M42 = b.fixed_view::<4, 2>(1, 0).into_owned();
        let (ad, bd) = zero_order_hold(&ar, &br, H);

        // Bryson's rule: the squared reciprocal of the acceptable excursion.
        let q = M4::from_diagonal(&SVector::from([
            1.0 / 0.05f64.powi(2), // heading, rad
            1.0 / 0.01f64.powi(2), // lateral offset, m
            1.0 / 0.1f64.powi(2),  // speed, m/s
            1.0 / 1.0f64.powi(2),  // yaw rate, rad/s
        ]));
        let r = M2::from_diagonal(&SVector::from([
            1.0 / 2.0f64.powi(2), // push, N
            1.0 / 1.0f64.powi(2), // steering torque, N m
        ]));
        let p = dare(&ad, &bd, &q, &r);
        let btp = bd.transpose() * p;
        let k = (r + btp * bd).try_inverse().expect("R + BᵀPB > 0") * btp * ad;
        // Slowest closed-loop pole, as a continuous-time rate: ln|λ| / h.
        let slowest_pole = (ad - bd * k)
            .complex_eigenvalues()
            .iter()
            .map(|l| l.norm().ln() / H)
            .fold(f64::NEG_INFINITY, f64::max);
        let residual = ad.transpose() * p * ad - p + q - ad.transpose() * p * bd * k;
        Gain {
            y_ref,
            v_ref,
            u_star,
            k,
            riccati_residual: residual.norm() / p.norm(),
            slowest_pole,
        }
    }

    /// The control law about the reference state; straight-line code on stack values.
    #[inline]
    pub fn control(&self, x: &State, r: &Reference) -> Input {
        let z = SVector::<f64, 4>::from([
            x[1] - r.theta,
            x[2] - r.y,
            x[3] - r.v * r.theta.cos(),
            x[4] - r.omega,
        ]);
        self.u_star - self.k * z
    }
}

/// The reference state at one instant: lateral position and forward speed,
/// and the heading and yaw rate of the path they trace.
#[derive(Debug, Clone, Copy, Default)]
pub struct Reference {
    /// Lateral position y_r (m).
    pub y: f64,
    /// Forward speed v_r (m/s).
    pub v: f64,
    /// Heading of the path, atan(ẏ_r / v_r) (rad).
    pub theta: f64,
    /// Its rate (rad/s).
    pub omega: f64,
}

/// Minimum-jerk blend s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its first two derivatives in τ.
#[inline]
fn min_jerk(tau: f64) -> (f64, f64, f64) {
    let t = tau.clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    (
        t3 * (10.0 - 15.0 * t + 6.0 * t2),
        30.0 * t2 * (1.0 - t) * (1.0 - t),
        60.0 * t * (1.0 - t) * (1.0 - 2.0 * t),
    )
}

/// The reference at time `t`: each segment's (y, v) is approached from the
/// previous one along a minimum-jerk blend of length [`BLEND`].
#[inline]
pub fn reference(t: f64) -> (usize, Reference) {
    let segment = ((t / SEGMENT) as usize).min(REFERENCES.len() - 1);
    let (y1, v1) = REFERENCES[segment];
    let (y0, v0) = if segment == 0 {
        (y1, v1)
    } else {
        REFERENCES[segment - 1]
    };
    let (s, ds, dds) = min_jerk((t - segment as f64 * SEGMENT) / BLEND);
    let y = y0 + (y1 - y0) * s;
    let v = v0 + (v1 - v0) * s;
    let dy = (y1 - y0) * ds / BLEND;
    let ddy = (y1 - y0) * dds / (BLEND * BLEND);
    let dv = (v1 - v0) * ds / BLEND;
    // θ_r = atan(ẏ_r / v_r): θ̇_r = (ÿ_r v_r − ẏ_r v̇_r) / (v_r² + ẏ_r²).
    let r = Reference {
        y,
        v,
        theta: dy.atan2(v),
        omega: (ddy * v - dy * dv) / (v * v + dy * dy),
    };
    (segment, r)
}

/// Exact zero-order-hold discretisation: exp([[A, B], [0, 0]] h) = [[A_d, B_d], [0, I]].
fn zero_order_hold(a: &M4, b: &M42, h: f64) -> (M4, M42) {
    let mut m = SMatrix::<f64, 6, 6>::zeros();
    m.fixed_view_mut::<4, 4>(0, 0).copy_from(&(a * h));
    m.fixed_view_mut::<4, 2>(0, 4).copy_from(&(b * h));
    // ‖M h‖ is about 1e-2: the Taylor series converges to rounding in a few terms.
    let (mut e, mut term) = (
        SMatrix::<f64, 6, 6>::identity(),
        SMatrix::<f64, 6, 6>::identity(),
    );
    for j in 1..20 {
        term = term * m / j as f64;
        e += term;
    }
    (
        e.fixed_view::<4, 4>(0, 0).into_owned(),
        e.fixed_view::<4, 2>(0, 4).into_owned(),
    )
}

/// Stabilising solution of P = AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA + Q by the
/// structure-preserving doubling algorithm (quadratic convergence; plain
/// Riccati iteration would need thousands of sweeps at a 1 ms period).
fn dare(a: &M4, b: &M42, q: &M4, r: &M2) -> M4 {
    let mut ak = *a;
    let mut gk = b * r.try_inverse().expect("R > 0") * b.transpose();
    let mut hk = *q;
    for _ in 0..100 {
        let w = (M4::identity() + gk * hk)
            .try_inverse()
            .expect("I + GH invertible");
        let a_next = ak * w * ak;
        let g_next = gk + ak * w * gk * ak.transpose();
        let h_next = hk + ak.transpose() * hk * w * ak;
        let change = (h_next - hk).norm() / h_next.norm();
        (ak, gk, hk) = (a_next, g_next, h_next);
        if change < 1e-15 {
            return (hk + hk.transpose()) / 2.0;
        }
    }
    panic!("doubling did not converge");
}

/// Objective and extremes of one run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Objective {
    /// Max |y − y_ref| once settled (m); the blend is over by then, so the
    /// reference state is the segment's steady motion.
    pub lateral: f64,
    /// Max |θ| once settled (rad).
    pub heading: f64,
    /// Max |v − v_ref| once settled (m/s).
    pub speed: f64,
    /// Max |θ| over the whole run (the chart's singularity is at π/2).
    pub heading_peak: f64,
    /// Max |push| (N) and |steer| (N m) over the whole run.
    pub push_peak: f64,
    /// See `push_peak`.
    pub steer_peak: f64,
    /// Iterations run.
    pub steps: usize,
}

impl Objective {
    /// The largest of the three settled errors.
    pub fn worst(&self) -> f64 {
        self.lateral.max(self.heading).max(self.speed)
    }
}

/// A sample of the trajectory, logged once per simulated second.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// State [x, θ, y, ẋ, θ̇].
    pub x: State,
    /// Input applied from `t`.
    pub u: Input,
}

/// Everything the loop needs, allocated before it starts.
pub struct Scenario {
    /// The plant.
    pub sled: SteeredSled,
    /// One gain per reference segment.
    pub gains: [Gain; REFERENCES.len()],
    /// Iterations to run (1 kHz).
    pub steps: usize,
    /// Latency of each iteration (controller + dynamics step), ns.
    pub latencies: Vec<u64>,
    /// Trajectory samples, one per simulated second.
    pub samples: Vec<Sample>,
}

impl Scenario {
    /// Designs the gains and preallocates the logs for `duration` seconds.
    pub fn new(duration: f64) -> Self {
        let sled = sled();
        let gains = REFERENCES.map(|(y_ref, v_ref)| Gain::design(&sled, y_ref, v_ref));
        let steps = (duration / H).round() as usize;
        Scenario {
            sled,
            gains,
            steps,
            latencies: Vec::with_capacity(steps),
            samples: Vec::with_capacity(steps / 1000 + 2),
        }
    }

    /// The control loop. Allocates nothing: the logs were reserved in `new`.
    pub fn run(&mut self) -> Objective {
        let mut x = State::from(X0);
        let mut obj = Objective::default();
        let mut rk4 = Rk4::new(H);
        self.latencies.clear();
        self.samples.clear();
        for i in 0..self.steps {
            let t = i as f64 * H;

            let start = Instant::now();
            let (segment, r) = reference(t);
            let gain = &self.gains[segment];
            let u = gain.control(&x, &r);
            let next = rk4.integrate(&Driven::new(&self.sled, u), t, x, t + H);
            let elapsed = start.elapsed();

            self.latencies.push(elapsed.as_nanos() as u64);
            if i % 1000 == 0 {
                self.samples.push(Sample { t, x, u });
            }
            x = match next {
                Ok(out) => out.x,
                Err(_) => panic!("the sled left the chart or blew up"),
            };

            // Objective at the end of the step, against the reference in force.
            let t_end = t + H;
            let theta = x[1];
            let speed = x[3] / theta.cos();
            obj.heading_peak = obj.heading_peak.max(theta.abs());
            obj.push_peak = obj.push_peak.max(u[0].abs());
            obj.steer_peak = obj.steer_peak.max(u[1].abs());
            if t_end - segment as f64 * SEGMENT >= SETTLE - 1e-9 {
                obj.lateral = obj.lateral.max((x[2] - gain.y_ref).abs());
                obj.heading = obj.heading.max(theta.abs());
                obj.speed = obj.speed.max((speed - gain.v_ref).abs());
            }
            obj.steps += 1;
        }
        self.samples.push(Sample {
            t: self.steps as f64 * H,
            x,
            u: self.gains[REFERENCES.len() - 1].control(&x, &reference(self.steps as f64 * H).1),
        });
        obj
    }

    /// p50, p99 and max of the recorded latencies (ns), and how many
    /// iterations overran the 1 ms period; sorts the log.
    pub fn latency_percentiles(&mut self) -> (u64, u64, u64, usize) {
        let l = &mut self.latencies;
        l.sort_unstable();
        let n = l.len();
        let overruns = l.iter().filter(|&&ns| ns as f64 > H * 1e9).count();
        (l[n / 2], l[(n * 99) / 100], l[n - 1], overruns)
    }
}

/// Total simulated time of the example.
pub const DURATION: f64 = SEGMENT * REFERENCES.len() as f64;

fn main() {
    let mut scenario = Scenario::new(DURATION);
    println!(
        "Chaplygin sled, gain-scheduled LQR from the generated linearisation, 1 kHz, Rk4 step"
    );
    println!("gains (u = u* − K [θ − θ_r, y − y_r, ẋ − v_r cos θ_r, θ̇ − ω_r]):");
    for (i, g) in scenario.gains.iter().enumerate() {
        println!(
            "  segment {i}: y_ref {:.1} m, v_ref {:.1} m/s, u* = [{:.3} N, {:.3} N m], \
             slowest pole {:.2}/s, Riccati residual {:.0e}",
            g.y_ref,
            g.v_ref,
            g.u_star[0],
            g.u_star[1] + 0.0, // no "-0.000"
            g.slowest_pole,
            g.riccati_residual,
        );
        for row in 0..2 {
            println!(
                "    K[{row}] = [{:8.3} {:8.3} {:8.3} {:8.3}]",
                g.k[(row, 0)],
                g.k[(row, 1)],
                g.k[(row, 2)],
                g.k[(row, 3)]
            );
        }
    }

    let obj = scenario.run();

    println!();
    println!("     t      x       y     θ       v      push    steer");
    for s in &scenario.samples {
        let v = s.x[3] / s.x[1].cos();
        println!(
            "{:6.1} {:6.3} {:7.4} {:7.4} {:6.4} {:7.3} {:8.4}",
            s.t, s.x[0], s.x[2], s.x[1], v, s.u[0], s.u[1]
        );
    }
    println!();
    println!(
        "simulated {:.1} s in {} steps of {} ms",
        obj.steps as f64 * H,
        obj.steps,
        H * 1e3
    );
    println!("objective, from {SETTLE} s after each reference change on (bound {BOUND:.0e}):");
    println!("  max |y − y_ref| = {:.2e} m", obj.lateral);
    println!("  max |θ|         = {:.2e} rad", obj.heading);
    println!("  max |v − v_ref| = {:.2e} m/s", obj.speed);
    println!(
        "  peaks over the run: |θ| {:.3} rad, |push| {:.2} N, |steer| {:.3} N m",
        obj.heading_peak, obj.push_peak, obj.steer_peak
    );
    let (p50, p99, max, overruns) = scenario.latency_percentiles();
    println!(
        "latency of controller + Rk4 step per iteration: p50 {p50} ns, p99 {p99} ns, max {max} ns \
         ({overruns} of {} over the 1 ms period)",
        obj.steps
    );
    assert!(
        obj.heading_peak < 1.0,
        "heading left the safe part of the chart"
    );
    assert!(
        obj.worst() < BOUND,
        "objective {:.2e} exceeds the bound {BOUND:.0e}",
        obj.worst()
    );
    println!("bound met: {:.2e} < {BOUND:.0e}", obj.worst());
}
