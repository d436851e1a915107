//! The stability suite's report: every case of `nh_lab::stability`
//! at full effort (1e4 s long horizon, 100 revolutions of fast spin).
//!
//! ```text
//! cargo run --release -p nh-lab --example stability_report
//! ```
//!
//! Prints a Markdown table (case, expected outcome, method, outcome, error
//! against the reference, steps, seconds, whether the expectation held,
//! notes) and writes `target/reports/stability.csv`. Exits with status 1 if
//! any expectation failed.
use nh_lab::stability::{self, Effort, Row};
use std::path::Path;

/// A case family of the suite.
type Family = fn(Effort) -> Vec<Row>;

fn main() {
    let families: [(&str, Family); 7] = [
        ("stiff", stability::stiff),
        ("fast spin", stability::fast_spin),
        ("scale extremes", stability::scale_extremes),
        ("long horizon", stability::long_horizon),
        ("near-singular", stability::near_singular),
        ("bad input", stability::bad_input),
        ("single precision", stability::single_precision),
    ];
    let bar = nh_lab::report::progress_bar(families.len());
    let mut rows = Vec::new();
    for (name, family) in families {
        bar.set_message(name);
        rows.extend(family(Effort::Report));
        bar.inc(1);
    }
    bar.finish();
    println!("# Stability suite (release, one run per row)\n");
    println!("{}", stability::markdown_table(&rows));
    let failed = rows.iter().filter(|r| !r.pass).count();
    println!("{} rows, {failed} failed.", rows.len());
    let path = Path::new("target/reports/stability.csv");
    match stability::write_csv(path, &rows) {
        Ok(()) => println!("Wrote {}", path.display()),
        Err(e) => eprintln!("could not write {}: {e}", path.display()),
    }
    if failed > 0 {
        std::process::exit(1);
    }
}
