//! The side-by-side at equal error: see the crate's documentation (`src/lib.rs`).
#![forbid(unsafe_code)]

use std::path::PathBuf;

use nonholonomic::prelude::*;

use nh_peers::analysis::Row;
use nh_peers::measure::{self, Counted, Sys};
use nh_peers::methods::{self, Method, Setting};
use nh_peers::output::{self, ProblemInfo};
use nh_peers::problems::{self, Problem};

/// A method's ladder stops after this many runs in a row with an error
/// below [`STOP_ERROR`] (ten times below the smallest target)…
const STOP_AFTER: usize = 2;
const STOP_ERROR: f64 = 1e-11;
/// …or after a run whose median time exceeds this many seconds.
const SLOW_SECONDS: f64 = 2.0;

/// Which problems and methods to run (`--problems a,b`, `--methods x,y`:
/// substrings, case-insensitive; everything by default).
struct Filter {
    problems: Vec<String>,
    methods: Vec<String>,
}

impl Filter {
    fn from_args() -> Self {
        let mut f = Filter {
            problems: Vec::new(),
            methods: Vec::new(),
        };
        let args: Vec<String> = std::env::args().skip(1).collect();
        for w in args.windows(2) {
            let list = || w[1].split(',').map(|s| s.to_lowercase()).collect();
            match w[0].as_str() {
                "--problems" => f.problems = list(),
                "--methods" => f.methods = list(),
                _ => {}
            }
        }
        f
    }

    fn wants(list: &[String], name: &str) -> bool {
        list.is_empty() || list.iter().any(|w| name.to_lowercase().contains(w))
    }
}

/// States along the problem's trajectory where the cost of one right-hand
/// side and one Jacobian is measured.
fn sample_states<S: Sys<D>, const D: usize>(p: &Problem<S, D>) -> Vec<(f64, SVector<f64, D>)> {
    let n = 32;
    let mut x = p.start.x0;
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let (t0, t1) = (
            p.start.t1 * k as f64 / n as f64,
            p.start.t1 * (k + 1) as f64 / n as f64,
        );
        out.push((t0, x));
        x = Dopri5::new(1e-10, 1e-12)
            .with_max_steps(1_000_000)
            .integrate(&p.sys, t0, x, t1)
            .map_or(x, |o| o.x);
    }
    out
}

/// One method at one setting: counted once, then timed; `Err` with the
/// reason when it fails or ends in a non-finite state.
fn run_one<S: Sys<D>, const D: usize>(
    p: &Problem<S, D>,
    m: &Method<S, D>,
    setting: f64,
    costs: (f64, f64),
) -> Result<Row, String> {
    let counted = Counted::new(&p.sys);
    let (result, calls) = counted.count(|| (m.run)(&counted, &p.start, setting));
    let finish = result?;
    let error = (finish.x - p.reference).amax();
    if !error.is_finite() {
        return Err("non-finite final state".into());
    }
    let (time, _) = measure::median_time(|| (m.run)(&counted, &p.start, setting));
    let seconds = time.cpu;
    Ok(with_costs(
        Row {
            problem: p.name,
            suite: m.suite,
            method: m.name,
            setting,
            steps: finish.steps,
            rhs: calls.rhs,
            jacobian: calls.jacobian,
            seconds,
            wall_seconds: time.wall,
            error,
            overhead_per_step: 0.0,
        },
        costs,
    ))
}

/// `row` with its own work per step for these costs of one right-hand side
/// and one Jacobian.
fn with_costs(row: Row, costs: (f64, f64)) -> Row {
    let own = row.seconds - row.rhs as f64 * costs.0 - row.jacobian as f64 * costs.1;
    Row {
        overhead_per_step: own / row.steps.max(1) as f64,
        ..row
    }
}

/// The costs of one right-hand side and one Jacobian at `states`.
fn costs<S: Sys<D>, const D: usize>(sys: &S, states: &[(f64, SVector<f64, D>)]) -> (f64, f64) {
    (
        measure::rhs_cost(sys, states),
        measure::jacobian_cost(sys, states),
    )
}

/// Every wanted method over its ladder on `p`; returns what the report
/// needs to know about the problem.
fn bench<S: Sys<D>, const D: usize>(
    p: &Problem<S, D>,
    filter: &Filter,
    rows: &mut Vec<Row>,
) -> ProblemInfo {
    let states = sample_states(p);
    let before = costs(&p.sys, &states);
    eprintln!(
        "{}: one RHS {:.0} ns, one Jacobian {:.0} ns",
        p.name,
        before.0 * 1e9,
        before.1 * 1e9
    );
    let first = rows.len();
    let methods: Vec<Method<S, D>> = methods::our_methods()
        .into_iter()
        .chain(methods::peer_methods())
        .collect();
    for m in methods
        .iter()
        .filter(|m| Filter::wants(&filter.methods, m.name))
    {
        let ladder = match m.setting {
            Setting::Tolerance => problems::tolerances(),
            Setting::StepSize => p.step_sizes.clone(),
        };
        let (mut below, mut failures) = (0, Vec::new());
        let start = std::time::Instant::now();
        for v in ladder {
            match run_one(p, m, v, before) {
                Ok(row) => {
                    below = if row.error < STOP_ERROR { below + 1 } else { 0 };
                    let slow = row.seconds > SLOW_SECONDS;
                    rows.push(row);
                    if below >= STOP_AFTER || slow {
                        break;
                    }
                }
                Err(e) => failures.push(format!("{v:e}: {e}")),
            }
        }
        eprintln!(
            "{}: {} done in {:.1} s",
            p.name,
            m.name,
            start.elapsed().as_secs_f64()
        );
        for f in failures {
            eprintln!("    failed at {f}");
        }
    }
    // measured again after the methods, the smaller of the two: a transient
    // slowdown of the machine would have to hit both measurements (the
    // smaller cost makes the limit the harder to reach)
    let after = costs(&p.sys, &states);
    let (rhs_cost, jacobian_cost) = (before.0.min(after.0), before.1.min(after.1));
    eprintln!(
        "{}: one RHS {:.0} ns, one Jacobian {:.0} ns after the methods",
        p.name,
        after.0 * 1e9,
        after.1 * 1e9
    );
    for row in rows[first..].iter_mut() {
        *row = with_costs(row.clone(), (rhs_cost, jacobian_cost));
    }
    ProblemInfo {
        name: p.name,
        rhs_cost,
        jacobian_cost,
        reference_note: p.reference_note.clone(),
    }
}

/// `target/reports` of the repository (whatever the working directory).
fn reports_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/reports")
}

fn main() {
    let filter = Filter::from_args();
    let before = measure::machine_state();
    let started = std::time::Instant::now();
    let mut rows = Vec::new();
    let mut infos = Vec::new();
    if Filter::wants(&filter.problems, "thesis_disc") {
        infos.push(bench(&problems::thesis_disc(), &filter, &mut rows));
    }
    if Filter::wants(&filter.problems, "rolling_disc") {
        infos.push(bench(&problems::rolling_disc(), &filter, &mut rows));
    }
    if Filter::wants(&filter.problems, "stiff_disc") {
        infos.push(bench(&problems::stiff_disc(), &filter, &mut rows));
    }
    let after = measure::machine_state();

    println!(
        "# Side by side at equal error: ours against ode_solvers, diffsol, russell_ode and the physical limit\n"
    );
    println!(
        "Machine before: {before}.  \nMachine after ({:.0} s): {after}.\n",
        started.elapsed().as_secs_f64()
    );
    println!(
        "Times are CPU times of the measuring thread (every method runs on one thread; on a shared machine this leaves out the time other processes held the core; the CSV has wall times too), medians of repeated runs (≥ {} repeats and ≥ {} s per run). Tolerance ladder 1e-3 … 1e-13 in half decades, atol = {} × rtol. A time at an error is interpolated on the method's ladder (log time linear in log error, the best bracketing pair); ≤ marks a bound (every run of the method was already more accurate). Ratios < 1: ours is faster.\n",
        measure::MIN_REPEATS,
        measure::MIN_SECONDS,
        methods::ATOL_PER_RTOL
    );
    for info in &infos {
        println!(
            "- {}: one RHS {:.0} ns, one Jacobian {:.0} ns (each the smaller of a measurement before and one after the methods); reference: {}.",
            info.name,
            info.rhs_cost * 1e9,
            info.jacobian_cost * 1e9,
            info.reference_note
        );
    }
    println!(
        "\n## Side by side\n\n{}",
        output::side_by_side(&rows, &infos)
    );
    println!(
        "## Every method at the target errors\n\n{}",
        output::per_method(&rows, &infos)
    );
    println!(
        "## Own work per step (time per step less its RHS and Jacobians at their measured costs)\n\n{}",
        output::overheads(
            &rows,
            &infos,
            &[
                "Rodas4",
                "Bdf (NDF 1-5)",
                "diffsol bdf",
                "russell Radau5",
                "Gauss-Legendre 4"
            ]
        )
    );
    let dir = reports_dir();
    if let Err(e) = output::write_csv(&dir.join("peers.csv"), &rows) {
        eprintln!("could not write the CSV: {e}");
    }
    for info in &infos {
        let path = dir.join(format!("peers_{}.svg", info.name));
        if let Err(e) = std::fs::write(&path, output::svg(&rows, info)) {
            eprintln!("could not write {}: {e}", path.display());
        }
    }
    println!("Wrote target/reports/peers.csv and target/reports/peers_<problem>.svg");
}
