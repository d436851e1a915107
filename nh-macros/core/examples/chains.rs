//! How the expansion scales with the number of bodies in a chain (issue 34):
//! the three families of `tests/synthetic/mod.rs`,
//!
//! * planar: a compound n-pendulum, one angle per link (`synthetic::planar`);
//! * spatial: links joined by universal joints, two angles per link
//!   (`synthetic::spatial`);
//! * manipulator: an arm of N links on a differential-drive base with its
//!   three rolling constraints (`synthetic::manipulator`), N = 6 by default,
//!
//! at links 2, 3, 4, 6, 8, 10, 12, 16, 20, 24 (planar and spatial).
//!
//! ```text
//! cargo run --release -p nh-core --example chains -- [--family planar|spatial|manipulator]...
//!     [--links 2,3,4] [--arm 6] [--outputs LIST]... [--limit-s 120] [--mem-kb 8000000] [--csv PATH]
//! cargo run --release -p nh-core --example chains -- --one planar 12 [--outputs LIST]
//! ```
//!
//! Every size is expanded in a child process (this binary again, with
//! `--one FAMILY LINKS`) started by `sh -c 'ulimit -v KB; exec ..'`, so that
//! its peak memory is its own and a size that runs away is stopped: the
//! child is killed after `--limit-s` seconds (default 120, reported as
//! "> limit"), and an allocation beyond `--mem-kb` KiB of address space
//! (default 8,000,000) ends it (reported as "> memory cap"). The larger sizes
//! of a family that hit either are not run. The child reports:
//!
//! * expansion: wall time of `nh_core::expand_with_stats`, on a thread with
//!   an 8 MiB stack as inside rustc; the median of 5 runs when the first
//!   takes under a second, else that one run;
//! * CPU: that thread's CPU time over its runs divided by the runs
//!   (`/proc/thread-self/schedstat`, which the kernel brings up to date at
//!   its ticks: a few ms off, divided by the runs), the figure to compare
//!   when other work shares the machine;
//! * peak memory: the child's peak resident set (`VmHWM` of `/proc/self/status`
//!   at its end), the whole process: token parsing and the output included;
//! * operations of `accelerations` after CSE by the formulation it uses,
//!   and of them those of Cᵀ M C and the right side of (5.9) before the
//!   k × k solve (`nh_core::Stats::ops_projection`; the right side alone
//!   where the articulated-body recursion solves it, which does not form
//!   Cᵀ M C: formulation `multipliers/articulated`)
//!   (and of `jacobian`, when the outputs derive it), and
//!   the generated lines (`nh_core::Stats`).
//!
//! `--outputs LIST` (repeatable) measures each family with
//! `outputs { LIST }` (`--outputs none`: no outputs, the default); e.g.
//! `--outputs none --outputs jacobian --outputs energy`. `--family` (repeatable)
//! picks families, `--links` the sizes of the chains, `--arm` the manipulator's
//! links. Prints a Markdown table (with the machine's cores and load average
//! before and after; a compile error's message shortened to its first
//! clause) and `--csv PATH` also writes the rows as CSV, messages in full.
//!
//! A separate tool from `examples/scaling.rs`, whose table is in-process
//! medians of many runs of small synthetic systems: a chain's large sizes run
//! for minutes and gigabytes, which only a child process can bound and
//! measure.
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[path = "figures/mod.rs"]
mod figures;
#[path = "../tests/synthetic/mod.rs"]
mod synthetic;
use figures::{fmt_ms, thousands};

const SIZES: [usize; 10] = [2, 3, 4, 6, 8, 10, 12, 16, 20, 24];

/// A family of systems indexed by their number of links.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Family {
    Planar,
    Spatial,
    Manipulator,
}

impl Family {
    const ALL: [Family; 3] = [Family::Planar, Family::Spatial, Family::Manipulator];

    fn name(self) -> &'static str {
        match self {
            Family::Planar => "planar",
            Family::Spatial => "spatial",
            Family::Manipulator => "manipulator",
        }
    }

    fn parse(s: &str) -> Option<Family> {
        Family::ALL.into_iter().find(|f| f.name() == s)
    }

    /// The macro body with `links` links and `outputs { outputs }`.
    fn body(self, links: usize, outputs: &str) -> String {
        match self {
            Family::Planar => synthetic::planar(links, outputs),
            Family::Spatial => synthetic::spatial(links, outputs),
            Family::Manipulator => synthetic::manipulator(links, outputs),
        }
    }

    /// Coordinates, independent velocities.
    fn dimensions(self, links: usize) -> (usize, usize) {
        match self {
            Family::Planar => (links, links),
            Family::Spatial => (2 * links, 2 * links),
            Family::Manipulator => (5 + links, 2 + links),
        }
    }
}

/// What a child reports of one expansion.
#[derive(Clone, Debug, Default)]
struct Measured {
    runs: usize,
    ms: f64,
    cpu_ms: Option<f64>,
    hwm_kb: u64,
    ops: usize,
    /// Of `ops`, those of Cᵀ M C and the right side before the solve
    /// (multiplier route; 0 otherwise).
    projection_ops: usize,
    /// The operations of `jacobian`, when it is derived.
    jacobian_ops: Option<usize>,
    formulation: String,
    lines: usize,
    /// The message of the first `compile_error!` in the expansion.
    error: Option<String>,
}

/// How the child of one size ended.
enum Outcome {
    Done(Measured),
    /// Killed at the time limit.
    TimedOut,
    /// An allocation failed under the memory cap.
    OutOfMemory,
    /// Anything else: the exit status and the end of the child's stderr.
    Crashed(String),
}

/// This thread's CPU time in ms, if the kernel reports it.
fn thread_cpu_ms() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns / 1e6)
}

/// This process's peak resident set in KiB (`VmHWM`), 0 if unknown.
fn peak_rss_kb() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

/// The message of the first `compile_error!` in `code`.
fn compile_error(code: &str) -> Option<String> {
    let rest = &code[code.find("compile_error")?..];
    let start = rest.find('"')? + 1;
    let len = rest[start..].find('"').unwrap_or(rest.len() - start);
    Some(rest[start..start + len].to_string())
}

/// The figures of one expansion's result.
fn figures(out: &proc_macro2::TokenStream, stats: &nh_core::Stats) -> Measured {
    let curvature = stats.route == Some(nh_core::Route::Curvature)
        || stats.formulation == Some(nh_core::Formulation::Maggi);
    Measured {
        ops: if curvature {
            stats.ops_curvature
        } else {
            stats.ops_multiplier
        },
        formulation: match stats.formulation {
            // (the articulated-body recursion solves the multiplier route's (5.9))
            Some(f) if stats.articulated && !curvature => {
                format!("{f:?}/articulated").to_lowercase()
            }
            Some(f) => format!("{f:?}").to_lowercase(),
            None => "—".into(),
        },
        lines: stats.lines,
        projection_ops: if curvature { 0 } else { stats.ops_projection },
        jacobian_ops: stats.jacobian_ops,
        error: compile_error(&out.to_string()),
        ..Measured::default()
    }
}

/// The child's side: expands one system on a thread with an 8 MiB stack
/// (5 times when the first takes under a second), prints its figures on
/// stdout.
fn child(family: Family, links: usize, outputs: &str) {
    let body = family.body(links, outputs);
    let worker = std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(move || {
            let tokens: proc_macro2::TokenStream = body.parse().expect("the generated body lexes");
            let (mut times, mut m) = (Vec::new(), Measured::default());
            let cpu0 = thread_cpu_ms();
            loop {
                let start = Instant::now();
                let (out, stats) = nh_core::expand_with_stats(tokens.clone());
                times.push(start.elapsed().as_secs_f64() * 1e3);
                if times.len() == 1 {
                    m = figures(&out, &stats);
                }
                if times.len() == 5 || times[0] >= 1000.0 {
                    break;
                }
            }
            let cpu = thread_cpu_ms().zip(cpu0).map(|(b, a)| b - a);
            (times, cpu, m)
        });
    let (mut times, cpu, mut m) = worker
        .expect("spawn the expansion thread")
        .join()
        .expect("the expansion panicked");
    m.runs = times.len();
    m.cpu_ms = cpu.map(|c| c / m.runs as f64);
    times.sort_by(f64::total_cmp);
    m.ms = times[m.runs / 2];
    m.hwm_kb = peak_rss_kb();
    let cpu = m.cpu_ms.map_or("-".into(), |c| format!("{c:.3}"));
    let jacobian = m.jacobian_ops.map_or("-".into(), |j| j.to_string());
    println!(
        "NH_RESULT runs={} ms={:.3} cpu_ms={cpu} hwm_kb={} ops={} projection_ops={} jacobian_ops={jacobian} lines={} formulation={}",
        m.runs, m.ms, m.hwm_kb, m.ops, m.projection_ops, m.lines, m.formulation
    );
    if let Some(e) = m.error {
        println!("NH_ERROR {e}");
    }
}

/// Parses the child's `NH_RESULT` (and `NH_ERROR`) lines.
fn parse_child(stdout: &str) -> Option<Measured> {
    let line = stdout.lines().find_map(|l| l.strip_prefix("NH_RESULT "))?;
    let field = |name: &str| {
        line.split_whitespace()
            .find_map(|kv| kv.strip_prefix(name)?.strip_prefix('='))
    };
    Some(Measured {
        runs: field("runs")?.parse().ok()?,
        ms: field("ms")?.parse().ok()?,
        cpu_ms: field("cpu_ms")?.parse().ok(),
        hwm_kb: field("hwm_kb")?.parse().ok()?,
        ops: field("ops")?.parse().ok()?,
        projection_ops: field("projection_ops")?.parse().ok()?,
        jacobian_ops: field("jacobian_ops").and_then(|j| j.parse().ok()),
        lines: field("lines")?.parse().ok()?,
        formulation: field("formulation")?.to_string(),
        error: stdout
            .lines()
            .find_map(|l| l.strip_prefix("NH_ERROR "))
            .map(str::to_string),
    })
}

/// Runs `--one family links` in a child under the options' memory cap and
/// time limit.
fn run_child(family: Family, links: usize, outputs: &str, opts: &Options) -> Outcome {
    let exe = std::env::current_exe().expect("the example's own path");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(r#"ulimit -v "$1" && shift && exec "$@""#)
        .arg("sh")
        .arg(opts.mem_kb.to_string())
        .arg(exe)
        .args([
            "--one",
            family.name(),
            &links.to_string(),
            "--outputs",
            outputs,
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the child");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for the child") {
            break status;
        }
        if start.elapsed() > opts.limit {
            let _ = child.kill();
            let _ = child.wait();
            return Outcome::TimedOut;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let (mut stdout, mut stderr) = (String::new(), String::new());
    if let Some(mut out) = child.stdout.take() {
        let _ = out.read_to_string(&mut stdout);
    }
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_string(&mut stderr);
    }
    match parse_child(&stdout) {
        Some(m) if status.success() => Outcome::Done(m),
        _ if stderr.contains("memory allocation of") => Outcome::OutOfMemory,
        _ => {
            let tail: Vec<&str> = stderr.lines().rev().take(3).collect();
            Outcome::Crashed(format!("{status}: {}", tail.join(" / ")))
        }
    }
}

/// The command line of the parent.
struct Options {
    families: Vec<Family>,
    links: Vec<usize>,
    arm: usize,
    /// Each variant's outputs list ("" for none).
    outputs: Vec<String>,
    limit: Duration,
    mem_kb: u64,
    csv: Option<String>,
}

/// Every value following `flag` in `args`.
fn values<'a>(args: &'a [String], flag: &str) -> Vec<&'a str> {
    args.windows(2)
        .filter(|w| w[0] == flag)
        .map(|w| w[1].as_str())
        .collect()
}

fn fail(msg: &str) -> ! {
    eprintln!("{msg}");
    std::process::exit(2)
}

/// The parent's options from the command line.
fn options(args: &[String]) -> Options {
    let number = |flag: &str, default: u64| match values(args, flag).last() {
        Some(v) => v
            .parse()
            .unwrap_or_else(|_| fail(&format!("{flag}: not a number: {v}"))),
        None => default,
    };
    let mut families: Vec<Family> = values(args, "--family")
        .into_iter()
        .map(|f| Family::parse(f).unwrap_or_else(|| fail(&format!("unknown family {f}"))))
        .collect();
    if families.is_empty() {
        families = Family::ALL.to_vec();
    }
    let links = match values(args, "--links").last() {
        Some(list) => list
            .split(',')
            .map(|s| {
                s.trim()
                    .parse()
                    .unwrap_or_else(|_| fail(&format!("--links: {s}")))
            })
            .collect(),
        None => SIZES.to_vec(),
    };
    let mut outputs: Vec<String> = values(args, "--outputs")
        .into_iter()
        .map(|o| {
            if o == "none" {
                String::new()
            } else {
                o.to_string()
            }
        })
        .collect();
    if outputs.is_empty() {
        outputs.push(String::new());
    }
    Options {
        families,
        links,
        arm: number("--arm", 6) as usize,
        outputs,
        limit: Duration::from_secs(number("--limit-s", 120)),
        mem_kb: number("--mem-kb", 8_000_000),
        csv: values(args, "--csv").last().map(|s| s.to_string()),
    }
}

/// One row of the table.
struct Row {
    family: Family,
    links: usize,
    outputs: String,
    outcome: Outcome,
}

fn fmt_mib(kb: u64) -> String {
    format!("{:.0} MiB", kb as f64 / 1024.0)
}

/// The operations of Cᵀ M C and its right side, "—" where the
/// multiplier route was not taken.
fn projection(m: &Measured) -> String {
    match m.projection_ops {
        0 => "—".into(),
        n => thousands(n),
    }
}

/// The row's Markdown line.
fn markdown(row: &Row, opts: &Options) -> String {
    let (n, k) = row.family.dimensions(row.links);
    let outputs = if row.outputs.is_empty() {
        "none"
    } else {
        &row.outputs
    };
    let head = format!(
        "| {} | {} | {n} / {k} | {outputs} |",
        row.family.name(),
        row.links
    );
    match &row.outcome {
        Outcome::Done(m) => {
            let cpu = m.cpu_ms.map_or("—".into(), fmt_ms);
            // a compile error's figures are those of the error, not of a system
            let (ops, formulation, lines, note) = match &m.error {
                None => (
                    match m.jacobian_ops {
                        Some(j) => format!(
                            "{} [{}] (`jacobian` {})",
                            thousands(m.ops),
                            projection(m),
                            thousands(j)
                        ),
                        None => format!("{} [{}]", thousands(m.ops), projection(m)),
                    },
                    m.formulation.clone(),
                    thousands(m.lines),
                    String::new(),
                ),
                Some(e) => {
                    let short = e.split(" (").next().unwrap_or(e);
                    let short = short.split(": ").next().unwrap_or(short);
                    let dash = || "—".to_string();
                    (dash(), dash(), dash(), format!("compile error: {short}"))
                }
            };
            format!(
                "{head} {} ({}) | {cpu} | {} | {ops} | {formulation} | {lines} | {note} |",
                fmt_ms(m.ms),
                m.runs,
                fmt_mib(m.hwm_kb),
            )
        }
        Outcome::TimedOut => format!(
            "{head} > {} s | | | | | | stopped at the time limit |",
            opts.limit.as_secs()
        ),
        Outcome::OutOfMemory => format!(
            "{head} | | > {} | | | | an allocation failed at the memory cap |",
            fmt_mib(opts.mem_kb)
        ),
        Outcome::Crashed(why) => format!("{head} | | | | | | crashed: {why} |"),
    }
}

/// The rows as CSV (empty fields where a size did not finish).
fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "family,links,coordinates,independent,outputs,status,runs,ms,cpu_ms,peak_rss_kb,ops,projection_ops,jacobian_ops,formulation,lines,error\n",
    );
    for r in rows {
        let (n, k) = r.family.dimensions(r.links);
        let head = format!("{},{},{n},{k},\"{}\"", r.family.name(), r.links, r.outputs);
        let tail = match &r.outcome {
            Outcome::Done(m) => format!(
                "done,{},{:.3},{},{},{},{},{},{},{},\"{}\"",
                m.runs,
                m.ms,
                m.cpu_ms.map_or(String::new(), |c| format!("{c:.3}")),
                m.hwm_kb,
                m.ops,
                m.projection_ops,
                m.jacobian_ops.map_or(String::new(), |j| j.to_string()),
                m.formulation,
                m.lines,
                m.error.as_deref().unwrap_or_default().replace('"', "'")
            ),
            Outcome::TimedOut => "time limit,,,,,,,,,,".into(),
            Outcome::OutOfMemory => "memory cap,,,,,,,,,,".into(),
            Outcome::Crashed(why) => format!("crashed,,,,,,,,,,\"{}\"", why.replace('"', "'")),
        };
        out += &format!("{head},{tail}\n");
    }
    out
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// The parent's side: every family, variant and size, one child each.
fn parent(opts: &Options) -> Vec<Row> {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    println!(
        "{cores} cores, load average {} at the start; limit {} s, memory cap {} per size\n",
        load_average(),
        opts.limit.as_secs(),
        fmt_mib(opts.mem_kb)
    );
    println!(
        "| family | links | coordinates / independent | outputs | expansion (runs) | CPU | peak memory | ops of `accelerations` [of them Cᵀ M C and its right side, or the right side alone where articulated] (of `jacobian`) | formulation | generated lines | note |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for &family in &opts.families {
        let sizes = if family == Family::Manipulator {
            vec![opts.arm]
        } else {
            opts.links.clone()
        };
        for outputs in &opts.outputs {
            for &links in &sizes {
                let outcome = run_child(family, links, outputs, opts);
                let stop = matches!(outcome, Outcome::TimedOut | Outcome::OutOfMemory);
                let row = Row {
                    family,
                    links,
                    outputs: outputs.clone(),
                    outcome,
                };
                println!("{}", markdown(&row, opts));
                rows.push(row);
                if stop {
                    let rest: Vec<String> = sizes
                        .iter()
                        .filter(|&&s| s > links)
                        .map(|s| s.to_string())
                        .collect();
                    if !rest.is_empty() {
                        println!(
                            "| {} | {} | | | | | | | | | not run: {links} links did not finish |",
                            family.name(),
                            rest.join(", ")
                        );
                    }
                    break;
                }
            }
        }
    }
    println!("\nload average {} at the end", load_average());
    rows
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--one") {
        let family = args.get(i + 1).and_then(|f| Family::parse(f));
        let links = args.get(i + 2).and_then(|n| n.parse().ok());
        let (Some(family), Some(links)) = (family, links) else {
            fail("usage: chains --one planar|spatial|manipulator LINKS [--outputs LIST]");
        };
        let outputs = values(&args, "--outputs").last().copied().unwrap_or("");
        let outputs = if outputs == "none" { "" } else { outputs };
        child(family, links, outputs);
        return;
    }
    let opts = options(&args);
    let rows = parent(&opts);
    if let Some(path) = &opts.csv
        && let Err(e) = std::fs::write(path, csv(&rows))
    {
        fail(&format!("cannot write {path}: {e}"));
    }
}
