//! Shrinks the failing systems of the seeds given and prints each.
//!
//! ```text
//! cargo run --release -p nh-verify --example shrink -- SEED..
//! ```
use nh_verify::{check, generate, shrink};

fn main() {
    for seed in std::env::args()
        .skip(1)
        .filter_map(|a| a.parse::<u64>().ok())
    {
        let sys = generate::system(seed);
        if !shrink::disagrees(&sys, seed) {
            println!("// seed {seed}: no disagreement");
            continue;
        }
        let small = shrink::shrink(&sys, &|s| shrink::disagrees(s, seed));
        println!(
            "// seed {seed}: {:?}\n{}\n",
            check::check_system(&small, seed).finding,
            small.text()
        );
    }
}
