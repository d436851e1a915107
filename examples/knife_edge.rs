//! A knife edge on an inclined plane against its closed-form solution.
//!
//! A blade slides on a plane tilted by `alpha`: x points down the slope, y
//! across it, φ is the heading of the blade; the blade cannot move sideways
//! (ẏ = tan φ · ẋ). The equations of motion are derived at compile time by
//! `nonholonomic_system!`. The heading turns uniformly (φ̈ = 0) and the speed
//! along the blade follows from gravity, so the motion has a closed form
//! (Bloch, *Nonholonomic Mechanics and Control*, sec. 1.6; the general case
//! is in `refdata/knife_edge_incline.json`, `analytic.solution`). This example
//! integrates both analytic cases of that file with Dormand–Prince at three
//! tolerances and with classical Runge–Kutta at four step sizes and prints
//! the errors over time and the work.
//!
//! Run it with
//!
//! ```text
//! cargo run --release --example knife_edge
//! ```
// Reference values are copied digit for digit from the JSON (17 significant
// digits), so they can be found there; f64 rounds them correctly.
#![allow(clippy::excessive_precision)]

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Knife edge on a plane inclined by alpha: x down the slope, y across,
    /// phi = blade heading from the x axis.
    pub struct KnifeEdge {
        parameters { m, J, g, alpha }
        coordinates { x, phi, y }
        lagrangian = J*dot(phi)^2/2 + g*m*x*sin(alpha) + m*(dot(x)^2 + dot(y)^2)/2;
        constraints { dot(y) = tan(phi)*dot(x); }
    }
}

/// State [x, φ, y, ẋ, φ̇].
const D: usize = KnifeEdge::<f64>::STATE_DIM;

/// Parameters of `refdata/knife_edge_incline.json`. (Not named `m`, `J`, `g`,
/// `alpha`: a constant named like a parameter would shadow the generated bindings.)
const MASS: f64 = 1.5;
const INERTIA: f64 = 0.2;
const GRAVITY: f64 = 9.81;
const SLOPE: f64 = 0.35;

/// One analytic case of the reference file. The end time keeps |φ| < π/2,
/// where the chart (x, φ | y) is regular.
struct Case {
    x0: f64,
    y0: f64,
    phi0: f64,
    v0: f64,
    omega: f64,
    t_end: f64,
    /// (t, x, y, φ, v) from `refdata/knife_edge_incline.json`,
    /// `analytic.cases[i].values` (exact arithmetic, 17 digits); used to check
    /// the closed form implemented below.
    reference: [(f64, f64, f64, f64, f64); 2],
}

const CASES: [Case; 2] = [
    Case {
        x0: 0.0,
        y0: 0.0,
        phi0: 0.0,
        v0: 0.0,
        omega: 0.4,
        t_end: 3.0,
        reference: [
            (
                1.0,
                1.5941036077745406,
                0.43437477094889599,
                0.4,
                3.274840313528045,
            ),
            (
                3.0,
                9.1317074113562456,
                9.0641318167838901,
                1.2,
                7.8380467504791724,
            ),
        ],
    },
    Case {
        x0: 0.1,
        y0: -0.2,
        phi0: -0.6,
        v0: 0.8,
        omega: 0.35,
        t_end: 5.0,
        reference: [
            (
                2.0,
                7.6809437718780205,
                -1.36984671803667,
                0.1,
                7.1862350460605614,
            ),
            (
                5.0,
                33.445607345324546,
                19.725719516305391,
                1.15,
                14.999258028108936,
            ),
        ],
    },
];

/// Closed form (`analytic.solution`): G = g sin α, φ = φ₀ + ωt,
/// v = v₀ + G/ω (sin φ − sin φ₀), K = v₀ − G/ω sin φ₀,
/// x = x₀ + K/ω (sin φ − sin φ₀) + G/(2ω²)(sin²φ − sin²φ₀),
/// y = y₀ − K/ω (cos φ − cos φ₀) + G/ω² ((φ − φ₀)/2 − (sin 2φ − sin 2φ₀)/4).
/// Returns (x, y, φ, v); v is the speed along the blade, ẋ = v cos φ.
fn exact(case: &Case, t: f64) -> (f64, f64, f64, f64) {
    let big_g = GRAVITY * SLOPE.sin();
    let (p0, w) = (case.phi0, case.omega);
    let phi = p0 + w * t;
    let v = case.v0 + big_g / w * (phi.sin() - p0.sin());
    let k = case.v0 - big_g / w * p0.sin();
    let x = case.x0
        + k / w * (phi.sin() - p0.sin())
        + big_g / (2.0 * w * w) * (phi.sin().powi(2) - p0.sin().powi(2));
    let y = case.y0 - k / w * (phi.cos() - p0.cos())
        + big_g / (w * w) * ((phi - p0) / 2.0 - ((2.0 * phi).sin() - (2.0 * p0).sin()) / 4.0);
    (x, y, phi, v)
}

/// Max of |Δx|, |Δy|, |Δφ|, |Δv| between a state and the closed form at t.
fn error(case: &Case, t: f64, s: &SVector<f64, D>) -> f64 {
    let (x, y, phi, v) = exact(case, t);
    let v_num = s[3] / s[1].cos();
    (s[0] - x)
        .abs()
        .max((s[2] - y).abs())
        .max((s[1] - phi).abs())
        .max((v_num - v).abs())
}

enum Method {
    Dopri(f64),
    Rk4(f64),
}

impl Method {
    fn label(&self) -> String {
        match self {
            Method::Dopri(tol) => format!("DP rtol {tol:e}"),
            Method::Rk4(h) => format!("RK4 h {h}"),
        }
    }
}

const METHODS: [Method; 7] = [
    Method::Dopri(1e-6),
    Method::Dopri(1e-8),
    Method::Dopri(1e-10),
    Method::Rk4(0.1),
    Method::Rk4(0.05),
    Method::Rk4(0.025),
    Method::Rk4(0.0125),
];

/// Output step (s).
const DT: f64 = 0.5;

/// Integrates one case with one method, segment by segment; returns the
/// error at every output time and the accumulated work.
fn run(knife: &KnifeEdge, case: &Case, method: &Method) -> (Vec<(f64, f64)>, Stats) {
    let x0 = SVector::<f64, D>::from([
        case.x0,
        case.phi0,
        case.y0,
        case.v0 * case.phi0.cos(),
        case.omega,
    ]);
    let mut dp = match method {
        Method::Dopri(tol) => Some(Dopri5::new(*tol, 1e-3 * tol)),
        Method::Rk4(_) => None,
    };
    let (mut t, mut x) = (0.0, x0);
    let mut stats = Stats::default();
    let mut errors = vec![(0.0, error(case, 0.0, &x0))];
    let segments = (case.t_end / DT).round() as u32;
    for i in 1..=segments {
        let t1 = DT * f64::from(i);
        let result = match (method, dp.as_mut()) {
            (Method::Dopri(_), Some(dp)) => {
                let r = dp.integrate(knife, t, x, t1);
                if let Some(h) = dp.last_step() {
                    *dp = dp.with_initial_step(h);
                }
                r
            }
            (Method::Rk4(h), _) => Rk4::new(*h).integrate(knife, t, x, t1),
            (Method::Dopri(_), None) => unreachable!("Dormand-Prince is set up above"),
        };
        let out = match result {
            Ok(out) => out,
            Err(e) => panic!(
                "knife-edge integration with {} failed on [{t}, {t1}]: {e}",
                method.label()
            ),
        };
        stats.steps += out.stats.steps;
        stats.rejected += out.stats.rejected;
        stats.rhs_evals += out.stats.rhs_evals;
        (t, x) = (out.t, out.x);
        errors.push((t, error(case, t, &x)));
    }
    (errors, stats)
}

fn main() {
    let knife = KnifeEdge::new(MASS, INERTIA, GRAVITY, SLOPE);
    println!(
        "Knife edge on an inclined plane (m = {MASS}, J = {INERTIA}, g = {GRAVITY}, α = {SLOPE}),"
    );
    println!(
        "equations derived by nonholonomic_system!, compared with the closed-form x(t), y(t), φ(t), v(t)"
    );
    println!(
        "(refdata/knife_edge_incline.json). Error = max(|Δx|, |Δy|, |Δφ|, |Δv|); v = speed along the blade."
    );
    println!(
        "DP = Dormand-Prince 5(4) with atol = 1e-3 rtol, RK4 = classical Runge-Kutta with fixed step h."
    );

    for (i, case) in CASES.iter().enumerate() {
        println!();
        println!(
            "Case {}: x₀ = {}, y₀ = {}, φ₀ = {}, v₀ = {}, φ̇ = ω = {}, t in [0, {}]",
            i + 1,
            case.x0,
            case.y0,
            case.phi0,
            case.v0,
            case.omega,
            case.t_end
        );
        let formula_check = case
            .reference
            .iter()
            .map(|&(t, x, y, phi, v)| {
                let (ex, ey, ephi, ev) = exact(case, t);
                (ex - x)
                    .abs()
                    .max((ey - y).abs())
                    .max((ephi - phi).abs())
                    .max((ev - v).abs())
            })
            .fold(0.0, f64::max);
        println!("  closed form vs refdata values: max difference {formula_check:.1e}");

        let runs: Vec<_> = METHODS.iter().map(|m| run(&knife, case, m)).collect();

        print!("  {:>4}", "t");
        for m in &METHODS {
            print!(" {:>13}", m.label());
        }
        println!();
        for row in 1..runs[0].0.len() {
            print!("  {:>4.1}", runs[0].0[row].0);
            for (errors, _) in &runs {
                print!(" {:>13.2e}", errors[row].1);
            }
            println!();
        }
        println!();
        println!(
            "  {:>13} {:>10} {:>7} {:>8} {:>9} {:>14}",
            "method", "max error", "steps", "rejected", "rhs evals", "observed order"
        );
        let mut previous: Option<(f64, f64)> = None;
        for (m, (errors, stats)) in METHODS.iter().zip(&runs) {
            let max = errors.iter().map(|e| e.1).fold(0.0, f64::max);
            // For the fixed-step method: log2 of the error ratio when h halves.
            let order = match (m, previous) {
                (Method::Rk4(h), Some((ph, pe))) if (ph / h - 2.0).abs() < 1e-12 => {
                    format!("{:.2}", (pe / max).log2())
                }
                _ => "-".to_string(),
            };
            if let Method::Rk4(h) = m {
                previous = Some((*h, max));
            }
            println!(
                "  {:>13} {:>10.2e} {:>7} {:>8} {:>9} {:>14}",
                m.label(),
                max,
                stats.steps,
                stats.rejected,
                stats.rhs_evals,
                order
            );
        }
    }
}
