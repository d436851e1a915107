//! How the expansion scales with the size of a system, on two synthetic
//! families (the same as the regression tests in `tests/scale.rs`):
//!
//! * dense: n coordinates, p = n/3 constraints, a dense mass matrix with
//!   entries cos(q_i − q_j)/c_ij, gravity-like potentials and dense
//!   constraints with entries sin(q_α + s_a)/c_aα, for n = 3 … 30, each with
//!   no outputs and with every output;
//! * chain: N `let`s chained through sines, `let a{i+1} = a{i} + sin(a{i})/2;`,
//!   for N = 2 … 50, the Lagrangian using only the last one.
//!
//! ```text
//! cargo run --release -p nh-core --example scaling [-- --quick] [--csv PATH]
//! ```
//!
//! Prints a Markdown table: expansion time (median of 5 runs, of 3 when one
//! run takes over a second, a single run with `--quick`), wall time of all runs
//! of the case, generated lines, operations of `accelerations` by both routes
//! after CSE (— where the curvature route is not derived) and the route used.
//! `--csv PATH` also writes the rows as CSV. Each expansion runs on a thread
//! with an 8 MiB stack, as inside rustc.
use std::time::Instant;

const ALL_OUTPUTS: &str = "multipliers, curvature, energy, constraint_matrix, mass_matrix, jacobian, linearization, routes";

#[path = "figures/mod.rs"]
mod figures;
#[path = "../tests/synthetic/mod.rs"]
mod synthetic;
use figures::{fmt_ms, thousands};
use synthetic::{chain, dense};

/// One row of the table.
struct Row {
    family: &'static str,
    size: usize,
    outputs: &'static str,
    runs: usize,
    median_ms: f64,
    wall_s: f64,
    stats: nh_core::Stats,
    /// The message of the first `compile_error!` in the expansion.
    error: Option<String>,
}

/// The message of the first `compile_error!` in `code`.
fn compile_error(code: &str) -> Option<String> {
    let rest = &code[code.find("compile_error")?..];
    let start = rest.find('"')? + 1;
    let len = rest[start..].find('"').unwrap_or(rest.len() - start);
    Some(rest[start..start + len].to_string())
}

/// Expands `body` once on an 8 MiB stack: time in ms, statistics, and (if
/// `check`) the compile error the expansion ends in, if any.
fn expand_once(body: &str, check: bool) -> (f64, nh_core::Stats, Option<String>) {
    let body = body.to_string();
    let worker = std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(move || {
            let tokens: proc_macro2::TokenStream = body.parse().expect("the generated body lexes");
            let start = Instant::now();
            let (out, stats) = nh_core::expand_with_stats(tokens);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let error = if check {
                compile_error(&out.to_string())
            } else {
                None
            };
            (ms, stats, error)
        });
    worker
        .expect("spawn")
        .join()
        .expect("the expansion panicked")
}

fn measure(
    family: &'static str,
    size: usize,
    outputs: &'static str,
    body: &str,
    quick: bool,
) -> Row {
    let wall = Instant::now();
    let (first, stats, error) = expand_once(body, true);
    let runs = if quick {
        1
    } else if first > 1000.0 {
        3
    } else {
        5
    };
    let mut times = vec![first];
    times.extend((1..runs).map(|_| expand_once(body, false).0));
    times.sort_by(f64::total_cmp);
    let median_ms = times[runs / 2];
    let wall_s = wall.elapsed().as_secs_f64();
    Row {
        family,
        size,
        outputs,
        runs,
        median_ms,
        wall_s,
        stats,
        error,
    }
}

fn route(row: &Row) -> String {
    if row.error.is_some() {
        return "compile error".into();
    }
    match row.stats.route {
        Some(r) => format!("{r:?}").to_lowercase(),
        None => "—".into(),
    }
}

fn print_row(row: &Row) {
    let s = &row.stats;
    let curvature = if s.ops_curvature == 0 {
        "—".to_string()
    } else {
        thousands(s.ops_curvature)
    };
    let label = match row.family {
        "dense" => format!("dense n = {} (p = {})", row.size, row.size / 3),
        _ => format!("chain N = {}", row.size),
    };
    println!(
        "| {label} | {} | {} ({}) | {:.2} s | {} | {} / {curvature} | {} |",
        row.outputs,
        fmt_ms(row.median_ms),
        row.runs,
        row.wall_s,
        thousands(s.lines),
        thousands(s.ops_multiplier),
        route(row)
    );
}

fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "family,size,outputs,runs,median_ms,wall_s,lines,ops_multiplier,ops_curvature,route\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{:.3},{:.3},{},{},{},{}\n",
            r.family,
            r.size,
            r.outputs,
            r.runs,
            r.median_ms,
            r.wall_s,
            r.stats.lines,
            r.stats.ops_multiplier,
            r.stats.ops_curvature,
            route(r)
        );
    }
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let csv_path = args
        .iter()
        .position(|a| a == "--csv")
        .and_then(|i| args.get(i + 1));
    println!(
        "| system | outputs | expansion (runs) | wall, all runs | generated lines | ops of `accelerations` (multiplier / curvature route) | route |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for n in [3, 6, 9, 12, 16, 20, 30] {
        for (label, outputs) in [("none", ""), ("all", ALL_OUTPUTS)] {
            rows.push(measure("dense", n, label, &dense(n, outputs), quick));
            print_row(&rows[rows.len() - 1]);
        }
    }
    for n in [2, 4, 8, 16, 32, 50] {
        rows.push(measure("chain", n, "none", &chain(n), quick));
        print_row(&rows[rows.len() - 1]);
    }
    for (i, r) in rows.iter().filter(|r| r.error.is_some()).enumerate() {
        let msg = r.error.as_deref().unwrap_or_default();
        let head = if i == 0 { "\nCompile errors:\n" } else { "" };
        println!(
            "{head}* {} {} (outputs: {}): {msg}",
            r.family, r.size, r.outputs
        );
    }
    if let Some(path) = csv_path
        && let Err(e) = std::fs::write(path, csv(&rows))
    {
        eprintln!("cannot write {path}: {e}");
        std::process::exit(2);
    }
}
