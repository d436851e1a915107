//! Writes the sample of systems whose plain derivation SymPy checks:
//! `verify/data/sympy_sample.json`, read by `verify/data/sympy_reference.py`
//! (which writes `sympy_reference.json`, read by `tests/sympy_sample.rs`).
//!
//! ```text
//! cargo run --release -p nh-verify --example sympy_sample
//! python3 verify/data/sympy_reference.py
//! ```
use nh_verify::check::{self, Finding};
use nh_verify::{generate, interp::Expansion, sample};

/// Systems in the sample, and the first seed looked at.
const SIZE: usize = 48;
const FIRST: u64 = 0;

fn main() {
    // seeds given on the command line: those systems, whatever their check
    // says (to look into a disagreement), written to the path given first
    let args: Vec<String> = std::env::args().skip(1).collect();
    let chosen: Vec<u64> = args.iter().skip(1).filter_map(|a| a.parse().ok()).collect();
    let mut entries = Vec::new();
    let mut seed = FIRST;
    while entries.len()
        < SIZE.min(if chosen.is_empty() {
            SIZE
        } else {
            chosen.len()
        })
    {
        if !chosen.is_empty() {
            seed = chosen[entries.len()];
        }
        let report = check::check(seed);
        if !chosen.is_empty() || matches!(report.finding, Finding::Agree { .. }) {
            let sys = generate::system(seed);
            let out = nh_core::expand(sys.text().parse().expect("lexes"));
            let exp = Expansion::new(&out).expect("interpretable");
            let k = match &sys.speeds {
                Some(s) => s.names.len(),
                None => exp.independent().len(),
            };
            let states = check::states(&sys, seed, k);
            entries.push(sample::entry(seed, &sys, exp.dependent(), &states));
        }
        seed += 1;
    }
    let default = concat!(env!("CARGO_MANIFEST_DIR"), "/data/sympy_sample.json");
    let path = args.first().map_or(default, |p| p.as_str());
    std::fs::write(path, format!("[\n{}\n]\n", entries.join(",\n"))).expect("writes the sample");
    println!(
        "{} systems (seeds {FIRST}..{seed}) written to {path}",
        entries.len()
    );
}
