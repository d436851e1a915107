//! Expands a `nonholonomic_system!` body read from standard input and prints
//! the generated code and the expansion's figures:
//! `cargo run -p nh-core --example expand < system.txt`.
use std::io::Read;

fn main() {
    let mut src = String::new();
    if std::io::stdin().read_to_string(&mut src).is_err() {
        eprintln!("could not read standard input");
        std::process::exit(2);
    }
    let tokens: proc_macro2::TokenStream = match src.parse() {
        Ok(t) => t,
        Err(e) => {
            eprintln!("not Rust tokens: {e}");
            std::process::exit(2);
        }
    };
    let start = std::time::Instant::now();
    let (out, stats) = nh_core::expand_with_stats(tokens);
    let elapsed = start.elapsed();
    println!("{out}");
    eprintln!(
        "expansion: {:.2} ms; {stats:?}",
        elapsed.as_secs_f64() * 1e3
    );
}
