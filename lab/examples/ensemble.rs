//! An ensemble: the Whipple bicycle's self-stability over a grid of forward
//! speeds × initial roll rates, 10 s each from upright straight-ahead
//! running, as one sweep of independent runs on all cores.
//!
//! ```text
//! cargo run --release -p nh-lab --example ensemble                # the sweep, sequential then parallel
//! cargo run --release -p nh-lab --example ensemble -- --shard 3/8 # shard 3 of 8 only
//! ```
//!
//! The full sweep runs sequentially and in parallel (three times each, the
//! fastest counts), with a progress bar on standard error (when it is a
//! terminal), checks that both give the same results bit for bit, prints
//! how each run ended (a table: the roll angle at 10 s, or when the bicycle
//! fell) and the runs per second of both with the speed-up.
//!
//! **Sharding.** `--shard K/N` runs only shard K of N (K from 0): the
//! contiguous run indices `Shard::range` gives, in parallel, printing one
//! CSV line per run keyed by its global index. The N shards' outputs,
//! concatenated in shard order, are the full sweep's, so a batch
//! scheduler's job array runs a sweep too large for one machine, one shard
//! per task, e.g. with Slurm (tasks numbered from 0):
//!
//! ```text
//! #SBATCH --array=0-7
//! ensemble --shard ${SLURM_ARRAY_TASK_ID}/${SLURM_ARRAY_TASK_COUNT} > shard_${SLURM_ARRAY_TASK_ID}.csv
//! # afterwards: cat shard_{0..7}.csv > sweep.csv
//! ```
//!
//! or `Shard::from_env("SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT")` in
//! a program of your own.
#[path = "../../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)] // the linearisation helpers are the eigenvalue example's
mod model;

use std::time::Instant;

use nh_lab::report::progress_bar;
use nonholonomic::prelude::*;

/// Forward speeds, m/s: 0.5 to 9 in steps of 0.5 (the linearised benchmark
/// bicycle is self-stable between 4.29 and 6.02 m/s).
const SPEEDS: usize = 18;
/// Initial roll rates, rad/s.
const ROLL_RATES: [f64; 4] = [0.1, 0.5, 1.0, 2.0];
/// Seconds per run.
const T1: f64 = 10.0;

type Run = Result<Outcome<f64, 11>, SimError<f64, 11>>;

fn speed(i: usize) -> f64 {
    0.5 * (i / ROLL_RATES.len() + 1) as f64
}

fn roll_rate(i: usize) -> f64 {
    ROLL_RATES[i % ROLL_RATES.len()]
}

/// Run `i` of the sweep: its own bicycle and integrator.
fn run(i: usize) -> Run {
    let bike = model::benchmark();
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = roll_rate(i);
    x0[10] = speed(i) / bike.rR; // the rear wheel's rate
    Dopri5::new(1e-8, 1e-10).integrate(&bike, 0.0, x0, T1)
}

/// How a run ended, in a table cell: the roll angle at 10 s, or the time
/// it fell (the run's typed failure: the chart of the dependent velocities
/// turns singular as the bicycle lies down).
fn cell(run: &Run) -> String {
    match run {
        Ok(o) => format!("roll {:+.4}", o.x[0]),
        Err(SimError::Singular { t, .. }) => format!("fell at {t:.2} s"),
        Err(e) => format!("{e}"),
    }
}

/// One CSV line of run `i`: index, speed, roll rate, how it ended, the
/// time reached, roll and steer there, steps.
fn csv_line(i: usize, run: &Run) -> String {
    let (ending, t, x, steps) = match run {
        Ok(o) => ("ok", o.t, Some(o.x), o.stats.steps.to_string()),
        Err(e) => (
            match e {
                SimError::Singular { .. } => "fell",
                _ => "failed",
            },
            e.time().unwrap_or(f64::NAN),
            e.state().copied(),
            String::new(), // a failure reports no statistics
        ),
    };
    let (roll, steer) = x.map_or((f64::NAN, f64::NAN), |x| (x[0], x[1]));
    format!(
        "{i},{},{},{ending},{t},{roll},{steer},{steps}",
        speed(i),
        roll_rate(i)
    )
}

/// Timed repeats of a sweep (the fastest is reported: the machine may be
/// shared).
const REPEATS: usize = 3;

/// Runs `ensemble` with a progress bar; returns the results and seconds.
fn timed(ensemble: &Ensemble, label: &str) -> (Vec<Run>, f64) {
    let bar = progress_bar(ensemble.len());
    bar.set_message(label.to_string());
    let start = Instant::now();
    let results = ensemble.clone().on_progress(|_, _| bar.inc(1)).run(run);
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    (results, seconds)
}

/// The results of `ensemble` and its fastest time of [`REPEATS`] runs.
fn fastest(ensemble: &Ensemble, label: &str) -> (Vec<Run>, f64) {
    let (results, mut best) = timed(ensemble, &format!("{label} 1/{REPEATS}"));
    for k in 2..=REPEATS {
        best = best.min(timed(ensemble, &format!("{label} {k}/{REPEATS}")).1);
    }
    (results, best)
}

fn bits(results: &[Run]) -> Vec<String> {
    // Debug prints every float with the shortest text that reads back to
    // the same bits: equal texts are bit-identical results
    results.iter().map(|r| format!("{r:?}")).collect()
}

fn full_sweep(runs: usize) {
    let (sequential, t_seq) = fastest(&Ensemble::new(runs), "sequential");
    let (parallel, t_par) = fastest(&Ensemble::new(runs).parallel(), "parallel");
    assert_eq!(bits(&parallel), bits(&sequential), "parallel ≠ sequential");

    println!(
        "Whipple bicycle, {T1} s from upright with an initial roll rate (Dormand–Prince, rtol 1e-8):\n"
    );
    print!("| v m/s |");
    for r in ROLL_RATES {
        print!(" roll rate {r} |");
    }
    println!("\n|---:|{}", "---|".repeat(ROLL_RATES.len()));
    for row in parallel.chunks(ROLL_RATES.len()).enumerate() {
        let (k, runs) = row;
        let cells: Vec<String> = runs.iter().map(cell).collect();
        println!(
            "| {} | {} |",
            speed(k * ROLL_RATES.len()),
            cells.join(" | ")
        );
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "\n{runs} runs: sequential {:.2} s ({:.1} runs/s), parallel on {cores} cores {:.2} s ({:.1} runs/s), the fastest of {REPEATS} each: speed-up {:.2}×; results identical bit for bit",
        t_seq,
        runs as f64 / t_seq,
        t_par,
        runs as f64 / t_par,
        t_seq / t_par
    );
    println!(
        "one shard of 8 (index 3): cargo run --release -p nh-lab --example ensemble -- --shard 3/8"
    );
}

fn one_shard(runs: usize, shard: Shard) {
    let ensemble = Ensemble::shard(runs, shard).parallel();
    eprintln!("shard {shard}: runs {:?} of 0..{runs}", ensemble.indices());
    let first = ensemble.indices().start;
    let (results, _) = timed(&ensemble, &format!("shard {shard}"));
    if shard.index() == 0 {
        println!("index,speed,roll_rate,ending,t,roll,steer,steps");
    }
    for (k, r) in results.iter().enumerate() {
        println!("{}", csv_line(first + k, r));
    }
}

fn main() {
    let runs = SPEEDS * ROLL_RATES.len();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => full_sweep(runs),
        [flag, shard] if flag == "--shard" => match shard.parse::<Shard>() {
            Ok(shard) => one_shard(runs, shard),
            Err(e) => {
                eprintln!("--shard {shard}: {e}");
                std::process::exit(2);
            }
        },
        _ => {
            eprintln!("usage: ensemble [--shard INDEX/COUNT]");
            std::process::exit(2);
        }
    }
}
