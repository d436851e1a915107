//! The rolling disc of Flygare (2012), section 6, derived at compile time and
//! integrated.
//!
//! Part 1 integrates a generic (non-steady) rolling motion for 10 s with the
//! adaptive Dormand–Prince 5(4) method at `rtol = 1e-10` and prints the state,
//! the energy and the work every 0.5 s. Part 2 starts on the steady motions of
//! the thesis's equation (6.67) — constant lean ψ₀, the contact point running
//! round a circle — for both roots of the quadratic in φ̇, and checks that the
//! generated equations keep the disc there.
//!
//! Run it with
//!
//! ```text
//! cargo run --release --example thesis_disc
//! ```
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Rolling disc of the thesis, section 6 (its simplified rotational
    /// kinetic energy, as published).
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }

        let X = x - R*sin(phi)*sin(psi);      // (6.12)
        let Y = y + R*cos(phi)*sin(psi);      // (6.13), sign as (6.16) uses it
        let Z = R*cos(psi);                   // (6.14)

        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;

        constraints {
            dot(x) = R*cos(phi)*dot(theta);   // (6.27)
            dot(y) = R*sin(phi)*dot(theta);   // (6.28)
        }
        outputs { energy, multipliers }
    }
}

/// State length n + k = 5 + 3.
const D: usize = ThesisDisc::<f64>::STATE_DIM;

/// Parameters of `refdata/thesis_disc.json`. (Not named `m`, `R`, `g`: a
/// constant named like a parameter would shadow the generated bindings.)
const MASS: f64 = 1.7;
const RADIUS: f64 = 0.35;
const GRAVITY: f64 = 9.81;

const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;

fn split(x: &SVector<f64, D>) -> (SVector<f64, 5>, SVector<f64, 3>) {
    (
        x.fixed_rows::<5>(0).into_owned(),
        x.fixed_rows::<3>(5).into_owned(),
    )
}

fn state(q: [f64; 5], rdot: [f64; 3]) -> SVector<f64, D> {
    let mut x = SVector::<f64, D>::zeros();
    x.fixed_rows_mut::<5>(0).copy_from_slice(&q);
    x.fixed_rows_mut::<3>(5).copy_from_slice(&rdot);
    x
}

/// Integrates `[t0, t1]` with Dormand–Prince, continuing with the step size
/// the controller proposed at the end of the previous segment.
fn segment(
    dp: &mut Dopri5<f64>,
    disc: &ThesisDisc,
    t0: f64,
    x0: SVector<f64, D>,
    t1: f64,
    mut observe: impl FnMut(f64, &SVector<f64, D>),
) -> Outcome<f64, D> {
    let out = match dp.integrate_with_observer(disc, t0, x0, t1, &mut observe) {
        Ok(out) => out,
        Err(e) => {
            eprintln!("integration of the thesis disc failed on [{t0}, {t1}]: {e}");
            if let Some(x) = e.state() {
                eprintln!("last good state: {:?}", x.as_slice());
            }
            std::process::exit(1);
        }
    };
    if let Some(h) = dp.last_step() {
        *dp = dp.with_initial_step(h);
    }
    out
}

fn main() {
    let disc = ThesisDisc::new(MASS, RADIUS, GRAVITY);
    println!(
        "Rolling disc of Flygare (2012), section 6: equations of motion derived at compile time"
    );
    println!(
        "by nonholonomic_system!, integrated with Dormand-Prince 5(4), rtol = {RTOL:e}, atol = {ATOL:e}."
    );
    println!(
        "Parameters m = {MASS}, R = {RADIUS}, g = {GRAVITY}. Coordinates {:?}; independent velocities (θ̇, φ̇, ψ̇).",
        ThesisDisc::<f64>::COORDINATES
    );
    println!();

    part1(&disc);
    println!();
    part2(&disc);
}

/// A generic rolling motion, tabulated every 0.5 s.
fn part1(disc: &ThesisDisc) {
    let q0 = [0.0, 0.0, 0.3, 0.0, 0.0];
    let rdot0 = [6.0, 20.0, 0.5];
    println!(
        "Part 1: non-steady rolling for 10 s: the disc nutates about a steady motion (ψ oscillates)."
    );
    println!(
        "  (In this model a disc that turns slowly falls over, see the '-' root in part 2; this one"
    );
    println!("  turns fast enough, φ̇ = 20 rad/s, to stay up.)");
    println!(
        "  initial state: θ = {}, φ = {}, ψ = {} (lean), x = {}, y = {}; θ̇ = {}, φ̇ = {}, ψ̇ = {}",
        q0[0], q0[1], q0[2], q0[3], q0[4], rdot0[0], rdot0[1], rdot0[2]
    );
    println!(
        "  ẋ, ẏ are not state variables: the rolling constraints (6.27)-(6.28) are imposed exactly"
    );
    println!(
        "  at every right-hand-side evaluation, so their residual is zero by construction. The check"
    );
    println!("  on the integration is the energy E, conserved because the constraints do no work;");
    println!("  ΔE/E₀ is its relative drift. Steps and rhs evaluations are cumulative.");
    println!();

    let x0 = state(q0, rdot0);
    let (q, r) = split(&x0);
    let e0 = disc.energy(&q, &r);

    println!(
        "  {:>5} {:>11} {:>11} {:>9} {:>10} {:>10} {:>16} {:>10} {:>7} {:>9}",
        "t", "θ", "φ", "ψ", "x", "y", "E", "ΔE/E₀", "steps", "rhs evals"
    );
    let row = |t: f64, x: &SVector<f64, D>, steps: usize, evals: usize| {
        let (q, r) = split(x);
        let e = disc.energy(&q, &r);
        println!(
            "  {:>5.1} {:>11.6} {:>11.6} {:>9.6} {:>10.6} {:>10.6} {:>16.12} {:>10.2e} {:>7} {:>9}",
            t,
            q[0],
            q[1],
            q[2],
            q[3],
            q[4],
            e,
            (e - e0) / e0,
            steps,
            evals
        );
    };

    let mut dp = Dopri5::new(RTOL, ATOL);
    let (mut t, mut x) = (0.0, x0);
    let (mut steps, mut rejected, mut evals) = (0usize, 0usize, 0usize);
    let (mut psi_min, mut psi_max, mut max_drift) = (q0[2], q0[2], 0.0f64);
    row(t, &x, steps, evals);
    for i in 1..=20 {
        let t1 = 0.5 * f64::from(i);
        let out = segment(&mut dp, disc, t, x, t1, |_, xs| {
            let (q, r) = split(xs);
            psi_min = psi_min.min(q[2]);
            psi_max = psi_max.max(q[2]);
            max_drift = max_drift.max(((disc.energy(&q, &r) - e0) / e0).abs());
        });
        steps += out.stats.steps;
        rejected += out.stats.rejected;
        evals += out.stats.rhs_evals;
        (t, x) = (out.t, out.x);
        row(t, &x, steps, evals);
    }
    println!();
    println!(
        "  lean angle stayed in [{psi_min:.6}, {psi_max:.6}] rad (upright is 0, lying flat is π/2 = {:.6})",
        std::f64::consts::FRAC_PI_2
    );
    println!("  max |ΔE/E₀| over all accepted steps: {max_drift:.2e}  (E₀ = {e0:.15})");
    println!("  work: {steps} accepted steps, {rejected} rejected, {evals} rhs evaluations");
    let (q, r) = split(&x);
    let lambda = disc.multipliers(t, &q, &r);
    println!(
        "  contact forces at t = {t}: λ_x = {:.6}, λ_y = {:.6} (Lagrange multipliers (5.10))",
        lambda[0], lambda[1]
    );
}

/// The steady motions (6.67): ψ = ψ₀, ψ̇ = 0, θ̇ constant and
/// φ̇ = θ̇/(2 sin ψ₀) ± sqrt(θ̇²/(4 sin²ψ₀) − g/(R cos ψ₀)).
fn part2(disc: &ThesisDisc) {
    let psi0: f64 = 0.3;
    let theta_dot: f64 = 8.0;
    // Initial coordinates of refdata/thesis_disc.json `steady_motions`.
    let q0 = [0.1, 0.7, psi0, 0.2, -0.3];
    let b = theta_dot / (2.0 * psi0.sin());
    let disc_root = (b * b - GRAVITY / (RADIUS * psi0.cos())).sqrt();
    println!(
        "Part 2: steady motions (6.67), ψ₀ = {psi0}, θ̇ = {theta_dot}, ψ̇ = 0, integrated for 10 s."
    );
    println!(
        "  φ̇ = θ̇/(2 sin ψ₀) ± sqrt(θ̇²/(4 sin²ψ₀) − g/(R cos ψ₀)); closed-form trajectory: θ, φ linear in t,"
    );
    println!(
        "  contact point on a circle of radius ρ = R θ̇/φ̇ (refdata/thesis_disc.json `trajectory_formula`)."
    );
    println!();
    println!(
        "  {:>4} {:>20} {:>11} {:>11} {:>14} {:>11} {:>11} {:>7} {:>9}",
        "root",
        "φ̇",
        "max|r̈(0)|",
        "max|ψ-ψ₀|",
        "t(|ψ-ψ₀|>1e-6)",
        "max|x-x*|",
        "max|y-y*|",
        "steps",
        "rhs evals"
    );
    for (name, sign) in [("+", 1.0), ("-", -1.0)] {
        let phi_dot = b + sign * disc_root;
        let x0 = state(q0, [theta_dot, phi_dot, 0.0]);
        let (q, r) = split(&x0);
        let acc0 = disc.accelerations(0.0, &q, &r).amax();

        let rho = RADIUS * theta_dot / phi_dot;
        let exact_xy = |t: f64| {
            let phi = q0[1] + phi_dot * t;
            (
                q0[3] + rho * (phi.sin() - q0[1].sin()),
                q0[4] - rho * (phi.cos() - q0[1].cos()),
            )
        };
        let (mut dpsi, mut dx, mut dy) = (0.0f64, 0.0f64, 0.0f64);
        let mut t_leave: Option<f64> = None;
        let mut dp = Dopri5::new(RTOL, ATOL);
        let (mut t, mut x) = (0.0, x0);
        let (mut steps, mut evals) = (0usize, 0usize);
        for i in 1..=20 {
            let t1 = 0.5 * f64::from(i);
            let out = segment(&mut dp, disc, t, x, t1, |ts, xs| {
                let (ex, ey) = exact_xy(ts);
                let d = (xs[2] - psi0).abs();
                if d > 1e-6 && t_leave.is_none() {
                    t_leave = Some(ts);
                }
                dpsi = dpsi.max(d);
                dx = dx.max((xs[3] - ex).abs());
                dy = dy.max((xs[4] - ey).abs());
            });
            steps += out.stats.steps;
            evals += out.stats.rhs_evals;
            (t, x) = (out.t, out.x);
        }
        let leave = t_leave.map_or_else(|| "never".to_string(), |t| format!("{t:.2}"));
        println!(
            "  {:>4} {:>20.15} {:>11.2e} {:>11.2e} {:>14} {:>11.2e} {:>11.2e} {:>7} {:>9}",
            name, phi_dot, acc0, dpsi, leave, dx, dy, steps, evals
        );
    }
    println!();
    println!(
        "  '+' is the fast-turning root (tight circle, ρ = R θ̇/φ̇ small), '-' the slow one (wide circle)."
    );
    println!(
        "  max|r̈(0)|: the generated accelerations on the steady motion, zero up to rounding for both."
    );
    println!(
        "  The '+' motion is stable: ψ stays within one ulp of ψ₀ and the contact point on the"
    );
    println!("  closed-form circle (x*, y*), up to the integration tolerance.");
    println!(
        "  The '-' motion is unstable: rounding-level deviations grow until the disc leaves it and"
    );
    println!(
        "  falls over (ψ passes π/2, beyond which the model is unphysical); its later columns only"
    );
    println!(
        "  show that departure. Reference φ̇ values: refdata/thesis_disc.json `steady_motions`."
    );
}
