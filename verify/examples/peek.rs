//! Development aid: prints generated systems and what the engine says.
use nh_verify::generate;
use std::collections::BTreeMap;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let from: u64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(0);
    let count: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(20);
    let show = args.iter().any(|a| a == "--show");
    let mut reasons: BTreeMap<String, (usize, u64)> = BTreeMap::new();
    let mut ok = 0;
    for seed in from..from + count {
        let sys = generate::system(seed);
        let text = sys.text();
        if show {
            println!("// seed {seed}\n{text}\n");
        }
        let out = nh_core::expand(text.parse().expect("lexes"));
        let errors = nh_core::reported_errors(&out);
        if errors.is_empty() {
            ok += 1;
        }
        for e in errors {
            let key: String = e.message.chars().take(90).collect();
            let entry = reasons.entry(key).or_insert((0, seed));
            entry.0 += 1;
        }
    }
    println!("{ok} of {count} expanded without errors");
    for (k, (n, seed)) in reasons {
        println!("{n:5} (seed {seed}) {k}");
    }
}
