//! The differential verification in long mode: checks a range of seeds on
//! every core and prints the figures and the first failures.
//!
//! ```text
//! cargo run --release -p nh-verify --example verify -- [SYSTEMS] [FIRST_SEED]
//! ```
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let systems: u64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let first: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let summary = nh_verify::run::run(first..first + systems, threads);
    print!("{}", summary.describe());
    if !summary.failures.is_empty() {
        std::process::exit(1);
    }
}
