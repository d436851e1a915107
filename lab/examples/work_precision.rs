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
//! shows a progress bar on standard error when it is a terminal.
// The reference values are the refdata's 17-digit decimals, kept digit for digit.
#![allow(clippy::excessive_precision)]
use nh_lab::report::{self, Progress, Run};
use nh_lab::systems::{ChaplyginSled, KnifeEdge, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;
use std::path::Path;

/// Timing repeats per run (the median is reported).
const REPEATS: usize = 5;

/// The energy of a state, where it is conserved.
type EnergyFn<'a, const D: usize> = &'a dyn Fn(&SVector<f64, D>) -> f64;

/// A scene: a system, its initial state, span, reference final state and energy.
struct Scene<'a, S, const D: usize> {
    name: &'a str,
    sys: &'a S,
    x0: SVector<f64, D>,
    t1: f64,
    reference: SVector<f64, D>,
    energy: Option<EnergyFn<'a, D>>,
    /// Tolerance ladder for adaptive methods, step ladders for fixed-step ones.
    rtols: &'a [f64],
    rk4_steps: &'a [f64],
    gauss_steps: &'a [f64],
    /// Whether explicit methods are expected to be hopeless (stiff scene):
    /// they get a step budget and their failures are reported as such.
    stiff: bool,
}

fn max_abs<const D: usize>(a: &SVector<f64, D>, b: &SVector<f64, D>) -> f64 {
    (a - b).amax()
}

fn record<const D: usize>(
    runs: &mut Vec<Run>,
    scene: &Scene<'_, impl OdeSystem<f64, D>, D>,
    integrator: &str,
    tolerance: f64,
    seconds: f64,
    result: Result<Outcome<f64, D>, SimError<f64, D>>,
) {
    match result {
        Ok(out) => {
            let energy_error = scene
                .energy
                .map(|e| ((e(&out.x) - e(&scene.x0)) / e(&scene.x0)).abs());
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
        Err(e) => eprintln!("{}: {integrator} at {tolerance:e}: {e}", scene.name),
    }
}

fn run_scene<S, const D: usize>(
    scene: &Scene<'_, S, D>,
    runs: &mut Vec<Run>,
    progress: &mut Progress,
) where
    S: OdeSystem<f64, D> + OdeJacobian<f64, D>,
{
    let sys = scene.sys;
    let (x0, t1) = (scene.x0, scene.t1);
    let budget = if scene.stiff { 200_000 } else { 10_000_000 };
    for &rtol in scene.rtols {
        let atol = rtol * 1e-2;
        let (s, r) = report::median_time(REPEATS, || {
            DormandPrince::new(rtol, atol)
                .with_max_steps(budget)
                .integrate(sys, 0.0, x0, t1)
        });
        record(runs, scene, "DormandPrince 5(4)", rtol, s, r);
        progress.tick(scene.name);
        let (s, r) = report::median_time(REPEATS, || {
            Dop853::new(rtol, atol)
                .with_max_steps(budget)
                .integrate(sys, 0.0, x0, t1)
        });
        record(runs, scene, "Dop853", rtol, s, r);
        progress.tick(scene.name);
        let (s, r) = report::median_time(REPEATS, || {
            Rosenbrock::new(rtol, atol)
                .with_max_steps(budget)
                .integrate_with_jacobian(sys, 0.0, x0, t1)
        });
        record(runs, scene, "Rosenbrock (Rodas)", rtol, s, r);
        progress.tick(scene.name);
    }
    for &h in scene.rk4_steps {
        let max = if scene.stiff { budget } else { usize::MAX };
        let (s, r) = report::median_time(REPEATS, || {
            Rk4::new(h).with_max_steps(max).integrate(sys, 0.0, x0, t1)
        });
        record(runs, scene, "Rk4", h, s, r);
        progress.tick(scene.name);
    }
    for &h in scene.gauss_steps {
        let (s, r) = report::median_time(REPEATS, || {
            GaussLegendre4::new(h).integrate_with_jacobian(sys, 0.0, x0, t1)
        });
        record(runs, scene, "Gauss-Legendre 4", h, s, r);
        progress.tick(scene.name);
    }
}

fn state<const N: usize, const K: usize, const D: usize>(
    q: [f64; N],
    rdot: [f64; K],
) -> SVector<f64, D> {
    SVector::<f64, D>::from_fn(|i, _| if i < N { q[i] } else { rdot[i - N] })
}

fn main() {
    let rtols = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    let mut runs = Vec::new();
    let ladder_len = |s: &[f64], h: &[f64], g: &[f64]| 3 * s.len() + h.len() + g.len();

    // ---- the thesis's disc: reference by Dop853 at 1e-13, cross-checked by Rosenbrock
    let disc: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let x0_disc: SVector<f64, 8> = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let t_disc = 5.0;
    let reference = Dop853::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(&disc, 0.0, x0_disc, t_disc)
        .expect("reference integration of the disc")
        .x;
    let check = DormandPrince::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(&disc, 0.0, x0_disc, t_disc)
        .expect("cross-check of the disc's reference")
        .x;
    let disc_energy = |x: &SVector<f64, 8>| {
        disc.energy(
            &x.fixed_rows::<5>(0).into_owned(),
            &x.fixed_rows::<3>(5).into_owned(),
        )
    };
    let disc_scene = Scene {
        name: "thesis_disc",
        sys: &disc,
        x0: x0_disc,
        t1: t_disc,
        reference,
        energy: Some(&disc_energy),
        rtols: &rtols,
        rk4_steps: &[0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625],
        gauss_steps: &[0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625],
        stiff: false,
    };

    // ---- Chaplygin sled: refdata/chaplygin_sled.json, case 1, t = 10 (closed form + quadrature)
    let sled: ChaplyginSled = ChaplyginSled::new(2.0, 0.3, 0.5);
    let sled_energy = |x: &SVector<f64, 5>| {
        sled.energy(
            &x.fixed_rows::<3>(0).into_owned(),
            &x.fixed_rows::<2>(3).into_owned(),
        )
    };
    let sled_scene = Scene {
        name: "chaplygin_sled",
        sys: &sled,
        x0: state([0.1, -0.6, -0.2], [0.33013424596387132, 0.9]),
        t1: 10.0,
        reference: state(
            [5.9094155990977516, 0.61187063615560456, 2.8943783902106599],
            [0.56948347789456302, 0.00019110137470178163],
        ),
        energy: Some(&sled_energy),
        rtols: &rtols,
        rk4_steps: &[0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625],
        gauss_steps: &[0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625],
        stiff: false,
    };

    // ---- knife edge on an incline: refdata/knife_edge_incline.json, case 1, t = 3
    let knife: KnifeEdge = KnifeEdge::new(1.5, 0.2, 9.81, 0.35);
    let knife_energy = |x: &SVector<f64, 5>| {
        knife.energy(
            &x.fixed_rows::<3>(0).into_owned(),
            &x.fixed_rows::<2>(3).into_owned(),
        )
    };
    let knife_scene = Scene {
        name: "knife_edge",
        sys: &knife,
        x0: state([0.0, 0.0, 0.0], [0.0, 0.4]),
        t1: 3.0,
        reference: state(
            [9.1317074113562456, 1.2, 9.0641318167838901],
            [2.8401770199868211, 0.4],
        ),
        energy: Some(&knife_energy),
        rtols: &rtols,
        rk4_steps: &[0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125],
        gauss_steps: &[0.1, 0.05, 0.025, 0.0125, 0.00625, 0.003125],
        stiff: false,
    };

    // ---- stiff disc: k = 1e6 on the lean, critically damped; reference by Rosenbrock at 1e-12
    let (m, r) = (1.7, 0.35);
    let inertia = 1.25 * m * r * r; // the lean's inertia in the thesis model
    let k = 1e6;
    let stiff: StiffDisc = StiffDisc::new(m, r, 9.81, k, 2.0 * (k * inertia).sqrt(), 0.2);
    let x0_stiff: SVector<f64, 8> = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let t_stiff = 1.0;
    let stiff_reference = Rosenbrock::new(1e-12, 1e-14)
        .with_max_steps(10_000_000)
        .integrate_with_jacobian(&stiff, 0.0, x0_stiff, t_stiff)
        .expect("reference integration of the stiff disc")
        .x;
    let stiff_check = GaussLegendre4::new(1e-4)
        .integrate_with_jacobian(&stiff, 0.0, x0_stiff, t_stiff)
        .expect("cross-check of the stiff disc's reference")
        .x;
    let stiff_scene = Scene {
        name: "stiff_disc",
        sys: &stiff,
        x0: x0_stiff,
        t1: t_stiff,
        reference: stiff_reference,
        energy: None,
        rtols: &rtols[..6],
        rk4_steps: &[0.004, 0.002, 0.001, 0.0005, 0.00025, 0.000125],
        gauss_steps: &[0.05, 0.02, 0.01, 0.005, 0.0025, 0.00125],
        stiff: true,
    };

    let total = ladder_len(
        disc_scene.rtols,
        disc_scene.rk4_steps,
        disc_scene.gauss_steps,
    ) + ladder_len(
        sled_scene.rtols,
        sled_scene.rk4_steps,
        sled_scene.gauss_steps,
    ) + ladder_len(
        knife_scene.rtols,
        knife_scene.rk4_steps,
        knife_scene.gauss_steps,
    ) + ladder_len(
        stiff_scene.rtols,
        stiff_scene.rk4_steps,
        stiff_scene.gauss_steps,
    );
    let mut progress = Progress::new(total);
    run_scene(&disc_scene, &mut runs, &mut progress);
    run_scene(&sled_scene, &mut runs, &mut progress);
    run_scene(&knife_scene, &mut runs, &mut progress);
    run_scene(&stiff_scene, &mut runs, &mut progress);
    progress.finish();

    println!("# Work–precision ({REPEATS} repeats, median wall time)\n");
    println!(
        "References: thesis_disc by Dop853 at rtol 1e-13 (DormandPrince at 1e-13 differs by {:.1e}); chaplygin_sled and knife_edge analytic (refdata); stiff_disc by Rosenbrock at rtol 1e-12 (Gauss–Legendre h = 1e-4 differs by {:.1e}).",
        max_abs(&disc_scene.reference, &check),
        max_abs(&stiff_scene.reference, &stiff_check)
    );
    println!(
        "The constraint residual max |ṡ + A ṙ| is not tabulated: ṡ is not integrated but computed from the constraints at every evaluation, so it is zero by construction.\n"
    );
    println!("{}", report::markdown_table(&runs));

    let dir = Path::new("target/reports");
    if let Err(e) = report::write_csv(&dir.join("work_precision.csv"), &runs) {
        eprintln!("could not write the CSV: {e}");
    }
    for scene in ["thesis_disc", "chaplygin_sled", "knife_edge", "stiff_disc"] {
        let svg = report::svg_work_precision(scene, &runs);
        let path = dir.join(format!("work_precision_{scene}.svg"));
        if let Err(e) = std::fs::write(&path, svg) {
            eprintln!("could not write {}: {e}", path.display());
        }
    }
    // cheapest integrator reaching 1e-6 and 1e-10 per scene
    println!("\n| scene | cheapest to error ≤ 1e-6 | cheapest to error ≤ 1e-10 |\n|---|---|---|");
    for scene in ["thesis_disc", "chaplygin_sled", "knife_edge", "stiff_disc"] {
        let best = |bound: f64| {
            runs.iter()
                .filter(|r| r.scene == scene && r.error <= bound)
                .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
                .map(|r| format!("{} at {:e}: {:.3e} s", r.integrator, r.tolerance, r.seconds))
                .unwrap_or_else(|| "none".into())
        };
        println!("| {scene} | {} | {} |", best(1e-6), best(1e-10));
    }
    println!(
        "\nWrote target/reports/work_precision.csv and target/reports/work_precision_<scene>.svg"
    );
}
