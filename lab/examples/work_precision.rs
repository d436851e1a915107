//! Work–precision report: every integrator's error against its run time on
//! four scenes — the thesis's rolling disc, the Chaplygin sled and the knife
//! edge on an incline (both against their analytic solutions) and a stiff
//! disc (a spring-damper with k = 1e6 on the lean) — each over a ladder of
//! tolerances or step sizes, in the manner of DiffEqDevTools'
//! `WorkPrecisionSet`.
//!
//! ```text
//! cargo run --release -p nh-lab --example work_precision
//! ```
//!
//! Prints a Markdown table, writes `target/reports/work_precision.csv` and one
//! SVG diagram per scene (`target/reports/work_precision_<scene>.svg`), and
//! shows a progress bar on standard error when it is a terminal. The diagrams
//! in the repository's `docs/` are copies of these SVGs.
// The reference values are the refdata's 17-digit decimals, kept digit for digit.
#![allow(clippy::excessive_precision)]
use indicatif::ProgressBar;
use nh_lab::report::{self, Run};
use nh_lab::systems::{ChaplyginSled, KnifeEdge, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;
use std::path::Path;

/// Timing repeats per run (the median is reported).
const REPEATS: usize = 5;

/// The tolerance ladder of the adaptive methods.
const RTOLS: [f64; 8] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];

/// The scenes, in report order.
const SCENES: [&str; 4] = ["thesis_disc", "chaplygin_sled", "knife_edge", "stiff_disc"];

/// A scene: a system, its initial state, span, reference final state and energy.
struct Scene<S, const D: usize> {
    name: &'static str,
    sys: S,
    x0: SVector<f64, D>,
    t1: f64,
    reference: SVector<f64, D>,
    /// The energy of a state, where it is conserved.
    energy: Option<fn(&S, &SVector<f64, D>) -> f64>,
    /// Tolerance ladder for adaptive methods, step ladders for fixed-step ones.
    rtols: &'static [f64],
    rk4_steps: &'static [f64],
    gauss_steps: &'static [f64],
    /// Whether explicit methods are expected to be hopeless (stiff scene):
    /// they get a step budget and their failures are reported as such.
    stiff: bool,
}

impl<S, const D: usize> Scene<S, D> {
    /// The number of runs of the scene (six adaptive methods per tolerance).
    fn runs(&self) -> usize {
        6 * self.rtols.len() + self.rk4_steps.len() + self.gauss_steps.len()
    }
}

fn max_abs<const D: usize>(a: &SVector<f64, D>, b: &SVector<f64, D>) -> f64 {
    (a - b).amax()
}

/// Times one run (median of [`REPEATS`]), records it (or reports its error
/// on standard error) and advances the progress bar.
fn timed<S, const D: usize>(
    scene: &Scene<S, D>,
    runs: &mut Vec<Run>,
    bar: &ProgressBar,
    integrator: &str,
    tolerance: f64,
    run: impl FnMut() -> Result<Outcome<f64, D>, SimError<f64, D>>,
) {
    bar.set_message(scene.name);
    let (seconds, result) = report::median_time(REPEATS, run);
    match result {
        Ok(out) => {
            let energy_error = scene.energy.map(|e| {
                let e0 = e(&scene.sys, &scene.x0);
                ((e(&scene.sys, &out.x) - e0) / e0).abs()
            });
            runs.push(Run {
                scene: scene.name.into(),
                integrator: integrator.into(),
                tolerance,
                steps: out.stats.steps,
                rhs_evals: out.stats.rhs_evals,
                seconds,
                error: max_abs(&out.x, &scene.reference),
                energy_error,
            });
        }
        Err(e) => bar.suspend(|| eprintln!("{}: {integrator} at {tolerance:e}: {e}", scene.name)),
    }
    bar.inc(1);
}

/// Every integrator over the scene's ladders.
fn run_scene<S, const D: usize>(scene: &Scene<S, D>, runs: &mut Vec<Run>, bar: &ProgressBar)
where
    S: OdeSystem<f64, D> + OdeJacobian<f64, D>,
{
    let (sys, x0, t1) = (&scene.sys, scene.x0, scene.t1);
    let budget = if scene.stiff { 200_000 } else { 10_000_000 };
    for &rtol in scene.rtols {
        let atol = rtol * 1e-2;
        timed(scene, runs, bar, "Dopri5", rtol, || {
            Dopri5::new(rtol, atol)
                .with_max_steps(budget)
                .integrate(sys, 0.0, x0, t1)
        });
        timed(scene, runs, bar, "Dop853", rtol, || {
            Dop853::new(rtol, atol)
                .with_max_steps(budget)
                .integrate(sys, 0.0, x0, t1)
        });
        timed(scene, runs, bar, "Rodas4", rtol, || {
            Rodas4::new(rtol, atol)
                .with_max_steps(budget)
                .integrate_with_jacobian(sys, 0.0, x0, t1)
        });
        timed(scene, runs, bar, "AutoSwitch (DP5/Rodas)", rtol, || {
            AutoSwitch::new(rtol, atol)
                .with_max_steps(budget)
                .integrate_with_jacobian(sys, 0.0, x0, t1)
        });
        timed(scene, runs, bar, "Rodas5P", rtol, || {
            Rodas5P::new(rtol, atol)
                .with_max_steps(budget)
                .integrate_with_jacobian(sys, 0.0, x0, t1)
        });
        timed(scene, runs, bar, "Bdf", rtol, || {
            Bdf::new(rtol, atol)
                .with_max_steps(budget)
                .integrate_with_jacobian(sys, 0.0, x0, t1)
        });
    }
    let max = if scene.stiff { budget } else { usize::MAX };
    for &h in scene.rk4_steps {
        timed(scene, runs, bar, "Rk4", h, || {
            Rk4::new(h).with_max_steps(max).integrate(sys, 0.0, x0, t1)
        });
    }
    for &h in scene.gauss_steps {
        timed(scene, runs, bar, "Gauss-Legendre 4", h, || {
            GaussLegendre4::new(h).integrate_with_jacobian(sys, 0.0, x0, t1)
        });
    }
}

fn state<const N: usize, const K: usize, const D: usize>(
    q: [f64; N],
    rdot: [f64; K],
) -> SVector<f64, D> {
    SVector::<f64, D>::from_fn(|i, _| if i < N { q[i] } else { rdot[i - N] })
}

/// The thesis's disc: reference by Dop853 at 1e-13, with the difference of
/// Dopri5 at 1e-13 as its cross-check.
fn thesis_disc() -> (Scene<ThesisDisc, 8>, f64) {
    let sys: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let x0: SVector<f64, 8> = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let t1 = 5.0;
    let reference = Dop853::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(&sys, 0.0, x0, t1)
        .expect("reference integration of the disc")
        .x;
    let check = Dopri5::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(&sys, 0.0, x0, t1)
        .expect("cross-check of the disc's reference")
        .x;
    let scene = Scene {
        name: "thesis_disc",
        sys,
        x0,
        t1,
        reference,
        energy: Some(|s: &ThesisDisc, x| {
            s.energy(
                &x.fixed_rows::<5>(0).into_owned(),
                &x.fixed_rows::<3>(5).into_owned(),
            )
        }),
        rtols: &RTOLS,
        rk4_steps: &[0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625],
        gauss_steps: &[0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625],
        stiff: false,
    };
    (scene, max_abs(&reference, &check))
}

/// Chaplygin sled: refdata/chaplygin_sled.json, case 1, t = 10 (closed form + quadrature).
fn chaplygin_sled() -> Scene<ChaplyginSled, 5> {
    Scene {
        name: "chaplygin_sled",
        sys: ChaplyginSled::new(2.0, 0.3, 0.5),
        x0: state([0.1, -0.6, -0.2], [0.33013424596387132, 0.9]),
        t1: 10.0,
        reference: state(
            [5.9094155990977516, 0.61187063615560456, 2.8943783902106599],
            [0.56948347789456302, 0.00019110137470178163],
        ),
        energy: Some(|s: &ChaplyginSled, x| {
            s.energy(
                &x.fixed_rows::<3>(0).into_owned(),
                &x.fixed_rows::<2>(3).into_owned(),
            )
        }),
        rtols: &RTOLS,
        rk4_steps: &[0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625],
        gauss_steps: &[0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625],
        stiff: false,
    }
}

/// Knife edge on an incline: refdata/knife_edge_incline.json, case 1, t = 3.
fn knife_edge() -> Scene<KnifeEdge, 5> {
    Scene {
        name: "knife_edge",
        sys: KnifeEdge::new(1.5, 0.2, 9.81, 0.35),
        x0: state([0.0, 0.0, 0.0], [0.0, 0.4]),
        t1: 3.0,
        reference: state(
            [9.1317074113562456, 1.2, 9.0641318167838901],
            [2.8401770199868211, 0.4],
        ),
        energy: Some(|s: &KnifeEdge, x| {
            s.energy(
                &x.fixed_rows::<3>(0).into_owned(),
                &x.fixed_rows::<2>(3).into_owned(),
            )
        }),
        rtols: &RTOLS,
        rk4_steps: &[0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125],
        gauss_steps: &[0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125],
        stiff: false,
    }
}

/// Stiff disc: k = 1e6 on the lean, critically damped; reference by
/// `tests/data/stiff_disc_reference.py` (SymPy equations, mpmath, Gragg–
/// Bulirsch–Stoer, 16 digits), with the difference of Gauss–Legendre at
/// h = 1e-4 as its cross-check.
fn stiff_disc() -> (Scene<StiffDisc, 8>, f64) {
    use nh_lab::scenes::stiff_disc as scene;
    let (sys, x0, t1, reference) = (
        scene::system(),
        scene::initial_state(),
        scene::END,
        scene::reference(),
    );
    let check = GaussLegendre4::new(1e-4)
        .integrate_with_jacobian(&sys, 0.0, x0, t1)
        .expect("cross-check of the stiff disc's reference")
        .x;
    let scene = Scene {
        name: "stiff_disc",
        sys,
        x0,
        t1,
        reference,
        energy: None,
        rtols: &RTOLS[..6],
        rk4_steps: &[0.004, 0.002, 0.001, 0.0005, 0.00025, 0.000125],
        gauss_steps: &[0.05, 0.02, 0.01, 0.005, 0.0025, 0.00125],
        stiff: true,
    };
    (scene, max_abs(&reference, &check))
}

/// Writes the CSV and one SVG diagram per scene under `target/reports`.
fn write_files(runs: &[Run]) {
    let dir = Path::new("target/reports");
    if let Err(e) = report::write_csv(&dir.join("work_precision.csv"), runs) {
        eprintln!("could not write the CSV: {e}");
    }
    for scene in SCENES {
        let svg = report::svg_work_precision(scene, runs);
        let path = dir.join(format!("work_precision_{scene}.svg"));
        if let Err(e) = std::fs::write(&path, svg) {
            eprintln!("could not write {}: {e}", path.display());
        }
    }
}

/// The cheapest integrator reaching 1e-6 and 1e-10 per scene, as a table.
fn print_cheapest(runs: &[Run]) {
    println!("\n| scene | cheapest to error ≤ 1e-6 | cheapest to error ≤ 1e-10 |\n|---|---|---|");
    for scene in SCENES {
        let best = |bound: f64| {
            runs.iter()
                .filter(|r| r.scene == scene && r.error <= bound)
                .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
                .map(|r| format!("{} at {:e}: {:.3e} s", r.integrator, r.tolerance, r.seconds))
                .unwrap_or_else(|| "none".into())
        };
        println!("| {scene} | {} | {} |", best(1e-6), best(1e-10));
    }
}

fn main() {
    let (disc, disc_check) = thesis_disc();
    let sled = chaplygin_sled();
    let knife = knife_edge();
    let (stiff, stiff_check) = stiff_disc();

    let bar = report::progress_bar(disc.runs() + sled.runs() + knife.runs() + stiff.runs());
    let mut runs = Vec::new();
    run_scene(&disc, &mut runs, &bar);
    run_scene(&sled, &mut runs, &bar);
    run_scene(&knife, &mut runs, &bar);
    run_scene(&stiff, &mut runs, &bar);
    bar.finish();

    println!("# Work–precision ({REPEATS} repeats, median wall time)\n");
    println!(
        "References: thesis_disc by Dop853 at rtol 1e-13 (Dopri5 at 1e-13 differs by {disc_check:.1e}); chaplygin_sled and knife_edge analytic (refdata); stiff_disc by SymPy + mpmath (tests/data/stiff_disc_reference.py; Gauss–Legendre h = 1e-4 differs by {stiff_check:.1e})."
    );
    println!(
        "The constraint residual max |ṡ + A ṙ| is not tabulated: ṡ is not integrated but computed from the constraints at every evaluation, so it is zero by construction.\n"
    );
    println!("{}", report::markdown_table(&runs));
    write_files(&runs);
    print_cheapest(&runs);
    println!(
        "\nWrote target/reports/work_precision.csv and target/reports/work_precision_<scene>.svg"
    );
}
