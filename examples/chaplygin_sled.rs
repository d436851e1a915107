//! The Chaplygin sled against its closed-form solution.
//!
//! A rigid body on a plane, resting on a knife edge at (x, y) that cannot slip
//! sideways, with its centre of mass a distance `a` ahead of the edge. The
//! equations of motion are derived at compile time by `nonholonomic_system!`;
//! this example integrates the two analytic cases of
//! `refdata/chaplygin_sled.json` with Dormand–Prince at three tolerances and
//! prints the error against the closed form u(t), ω(t), θ(t) (Bloch, sec. 1.7)
//! and against the reference positions x, y (no elementary closed form; the
//! reference values were computed by mpmath quadrature).
//!
//! Run it with
//!
//! ```text
//! cargo run --release --example chaplygin_sled
//! ```
// Reference values are copied digit for digit from the JSON (17 significant
// digits), so they can be found there; f64 rounds them correctly.
#![allow(clippy::excessive_precision)]

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Chaplygin sled: knife edge at (x, y), heading theta, centre of mass at
    /// distance a ahead of the edge, moment of inertia J about the centre of mass.
    pub struct Sled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
    }
}

/// State [x, θ, y, ẋ, θ̇].
const D: usize = Sled::<f64>::STATE_DIM;

/// Parameters of `refdata/chaplygin_sled.json`. (Not named `m`, `J`, `a`: a
/// constant named like a parameter would shadow the generated bindings.)
const MASS: f64 = 2.0;
const INERTIA: f64 = 0.3;
const OFFSET: f64 = 0.5;

const TOLERANCES: [f64; 3] = [1e-6, 1e-8, 1e-10];
const T_END: f64 = 10.0;

/// One analytic case: initial values and the reference positions.
struct Case {
    x0: f64,
    y0: f64,
    theta0: f64,
    u0: f64,
    omega0: f64,
    /// (t, x, y) from `refdata/chaplygin_sled.json`, `analytic.cases[i].values`:
    /// computed there by mpmath quadrature of the closed-form u, θ (40 digits).
    reference_xy: [(f64, f64, f64); 4],
    /// (t, θ, u, ω) from the same file, used to check the closed form below.
    reference_theta_u_omega: [(f64, f64, f64, f64); 4],
}

const CASES: [Case; 2] = [
    Case {
        x0: 0.1,
        y0: -0.2,
        theta0: -0.6,
        u0: 0.4,
        omega0: 0.9,
        reference_xy: [
            (1.0, 0.62110208428757033, -0.30747992219846338),
            (2.0, 1.2632690320351074, -0.14406049316066382),
            (5.0, 3.0548039072430295, 0.90673674348933513),
            (10.0, 5.9094155990977516, 2.8943783902106599),
        ],
        reference_theta_u_omega: [
            (
                1.0,
                0.069751090087017276,
                0.6327285018140123,
                0.45731456075713202,
            ),
            (
                2.0,
                0.38188182109960732,
                0.68421117625464993,
                0.19909210361179805,
            ),
            (
                5.0,
                0.59509644151714078,
                0.69563830042099655,
                0.014777938573034497,
            ),
            (
                10.0,
                0.61187063615560456,
                0.69570107473835761,
                0.00019110137470178163,
            ),
        ],
    },
    Case {
        x0: 0.0,
        y0: 0.0,
        theta0: -0.9,
        u0: 0.0,
        omega0: 0.5,
        reference_xy: [
            (1.0, 0.050861766695959615, -0.032831917861686623),
            (2.0, 0.21381659933900499, -0.061661765753304791),
            (5.0, 0.92961324993113887, 0.28976384624333552),
            (10.0, 1.8559428869904041, 1.545878956588221),
        ],
        reference_theta_u_omega: [
            (
                1.0,
                -0.41253421048579238,
                0.11887228267328427,
                0.46332866415764415,
            ),
            (
                2.0,
                0.0096374029047709442,
                0.2083091866187107,
                0.37618905742409348,
            ),
            (
                5.0,
                0.73859354927176042,
                0.3043134003480882,
                0.13595361680168894,
            ),
            (
                10.0,
                1.0383511363420436,
                0.31599470449263881,
                0.019192884919278898,
            ),
        ],
    },
];

/// The closed form of `analytic.solution` in refdata/chaplygin_sled.json:
/// u = u∞ tanh(kt + c), ω = ω₀ cosh c / cosh(kt + c),
/// θ = θ₀ + ω₀ cosh c / k · (gd(kt + c) − gd(c)), gd(s) = atan(sinh s),
/// with u∞ = sqrt(u₀² + (J + m a²) ω₀² / m), k = m a u∞ / (J + m a²), c = atanh(u₀/u∞).
struct ClosedForm {
    theta0: f64,
    omega0: f64,
    u_inf: f64,
    k: f64,
    c: f64,
}

impl ClosedForm {
    fn new(case: &Case) -> Self {
        let inertia = INERTIA + MASS * OFFSET * OFFSET;
        let u_inf = (case.u0 * case.u0 + inertia * case.omega0 * case.omega0 / MASS).sqrt();
        Self {
            theta0: case.theta0,
            omega0: case.omega0,
            u_inf,
            k: MASS * OFFSET * u_inf / inertia,
            c: (case.u0 / u_inf).atanh(),
        }
    }

    /// (θ, u, ω) at time t.
    fn at(&self, t: f64) -> (f64, f64, f64) {
        let gd = |s: f64| s.sinh().atan();
        let s = self.k * t + self.c;
        let u = self.u_inf * s.tanh();
        let omega = self.omega0 * self.c.cosh() / s.cosh();
        let theta = self.theta0 + self.omega0 * self.c.cosh() / self.k * (gd(s) - gd(self.c));
        (theta, u, omega)
    }
}

/// Output times: every 0.5 s up to T_END (the reference times 1, 2, 5, 10 are among them).
fn output_times() -> impl Iterator<Item = f64> {
    (1..=20).map(|i| 0.5 * f64::from(i))
}

/// Errors of one integration: per output time the max error of (θ, ẋ, θ̇)
/// against the closed form, and of (x, y) against the reference values.
struct Run {
    per_time: Vec<(f64, f64, Option<f64>)>,
    stats: Stats,
}

fn run(sled: &Sled, case: &Case, exact: &ClosedForm, rtol: f64) -> Run {
    let x0 = SVector::<f64, D>::from([
        case.x0,
        case.theta0,
        case.y0,
        case.u0 * case.theta0.cos(),
        case.omega0,
    ]);
    let mut dp = Dopri5::new(rtol, 1e-3 * rtol);
    let (mut t, mut x) = (0.0, x0);
    let mut stats = Stats::default();
    let mut per_time = Vec::new();
    for t1 in output_times() {
        let out = match dp.integrate(sled, t, x, t1) {
            Ok(out) => out,
            Err(e) => panic!("sled integration failed on [{t}, {t1}] at rtol {rtol:e}: {e}"),
        };
        if let Some(h) = dp.last_step() {
            dp = dp.with_initial_step(h);
        }
        stats.steps += out.stats.steps;
        stats.rejected += out.stats.rejected;
        stats.rhs_evals += out.stats.rhs_evals;
        (t, x) = (out.t, out.x);

        let (theta, u, omega) = exact.at(t);
        let err_closed = (x[1] - theta)
            .abs()
            .max((x[3] - u * theta.cos()).abs())
            .max((x[4] - omega).abs());
        let err_xy = case
            .reference_xy
            .iter()
            .find(|r| r.0 == t)
            .map(|&(_, rx, ry)| (x[0] - rx).abs().max((x[2] - ry).abs()));
        per_time.push((t, err_closed, err_xy));
    }
    Run { per_time, stats }
}

fn main() {
    let sled = Sled::new(MASS, INERTIA, OFFSET);
    println!(
        "Chaplygin sled (m = {MASS}, J = {INERTIA}, a = {OFFSET}), equations derived by nonholonomic_system!,"
    );
    println!(
        "integrated with Dormand-Prince 5(4) (atol = 1e-3 rtol) and compared with the closed form"
    );
    println!(
        "u(t), ω(t), θ(t) and with reference positions x, y (refdata/chaplygin_sled.json). All times in s."
    );

    for (i, case) in CASES.iter().enumerate() {
        let exact = ClosedForm::new(case);
        println!();
        println!(
            "Case {}: x₀ = {}, y₀ = {}, θ₀ = {}, u₀ = {}, ω₀ = {}  (u∞ = {:.6}, k = {:.6})",
            i + 1,
            case.x0,
            case.y0,
            case.theta0,
            case.u0,
            case.omega0,
            exact.u_inf,
            exact.k
        );
        // The closed form as implemented here against the 17-digit reference values.
        let formula_check = case
            .reference_theta_u_omega
            .iter()
            .map(|&(t, th, u, om)| {
                let (a, b, c) = exact.at(t);
                (a - th).abs().max((b - u).abs()).max((c - om).abs())
            })
            .fold(0.0, f64::max);
        println!(
            "  closed form vs refdata (θ, u, ω at t = 1, 2, 5, 10): max difference {formula_check:.1e}"
        );

        let runs: Vec<Run> = TOLERANCES
            .iter()
            .map(|&tol| run(&sled, case, &exact, tol))
            .collect();

        println!(
            "  error per output time: max |Δθ|, |Δẋ|, |Δθ̇| vs the closed form; [max |Δx|, |Δy|] vs refdata"
        );
        print!("  {:>5}", "t");
        for tol in TOLERANCES {
            print!(" {:>22}", format!("rtol = {tol:e}"));
        }
        println!();
        for row in 0..runs[0].per_time.len() {
            let t = runs[0].per_time[row].0;
            let mut line = format!("  {t:>5.1}");
            for r in &runs {
                let (_, closed, xy) = r.per_time[row];
                let xy = xy.map_or_else(String::new, |e| format!("[{e:.1e}]"));
                line += &format!(" {:>12} {:>9}", format!("{closed:.2e}"), xy);
            }
            println!("{}", line.trim_end());
        }
        println!();
        println!(
            "  {:>8} {:>14} {:>14} {:>7} {:>8} {:>9}",
            "rtol", "max closed", "max x,y", "steps", "rejected", "rhs evals"
        );
        for (tol, r) in TOLERANCES.iter().zip(&runs) {
            let closed = r.per_time.iter().map(|p| p.1).fold(0.0, f64::max);
            let xy = r.per_time.iter().filter_map(|p| p.2).fold(0.0, f64::max);
            println!(
                "  {:>8} {:>14.2e} {:>14.2e} {:>7} {:>8} {:>9}",
                format!("{tol:e}"),
                closed,
                xy,
                r.stats.steps,
                r.stats.rejected,
                r.stats.rhs_evals
            );
        }
    }
    println!();
    println!("Over t in [0, {T_END}] the sled settles to straight-line motion: ω → 0, u → u∞.");
}
