//! Expands `nonholonomic_system!` invocations outside the compiler and
//! prints each expansion's figures (expansion time, operation counts after
//! CSE of both routes, generated lines):
//!
//! ```text
//! cargo run --release -p nh-core --example expand -- FILE.rs [--code]
//! cargo run --release -p nh-core --example expand < BODY.txt
//! ```
//!
//! With a file, every `nonholonomic_system! { .. }` in it is expanded; with
//! standard input, the input is the macro's body. `--code` also prints the
//! generated code. Expansion time is the median of 21 runs.
//!
//! A system with errors is not measured: its errors are printed the way the
//! compiler prints them (message, `FILE:line:column`, the source line with
//! the culprit underlined), and the tool exits with status 1 after the other
//! systems.
use nh_core::ReportedError;
#[path = "../tests/tokens/mod.rs"]
mod tokens;

use proc_macro2::TokenStream;
use std::io::Read;
use std::time::Instant;
use tokens::find_invocations;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let show_code = args.iter().any(|a| a == "--code");
    let runs: usize = args
        .iter()
        .position(|a| a == "--runs")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(21)
        .max(1);
    let file = args
        .iter()
        .enumerate()
        .find(|(i, a)| !a.starts_with("--") && (*i == 0 || args[i - 1] != "--runs"))
        .map(|(_, a)| a);
    let src = match file {
        Some(path) => std::fs::read_to_string(path).unwrap_or_else(|e| {
            eprintln!("cannot read {path}: {e}");
            std::process::exit(2)
        }),
        None => {
            let mut s = String::new();
            if std::io::stdin().read_to_string(&mut s).is_err() {
                eprintln!("could not read standard input");
                std::process::exit(2);
            }
            s
        }
    };
    let tokens: TokenStream = src.parse().unwrap_or_else(|e| {
        eprintln!("not Rust tokens: {e}");
        std::process::exit(2)
    });
    let bodies = if file.is_some() {
        let mut v = Vec::new();
        find_invocations(tokens, &mut v);
        v
    } else {
        vec![tokens]
    };
    let source = file.map_or("<stdin>", String::as_str);
    if bodies.is_empty() {
        eprintln!("no `nonholonomic_system! {{ .. }}` in {source}");
        std::process::exit(2);
    }
    let mut failed = false;
    for body in bodies {
        let errors = nh_core::reported_errors(&nh_core::expand(body.clone()));
        if !errors.is_empty() {
            for e in &errors {
                eprintln!("{}", render(e, source, &src));
            }
            let s = if errors.len() == 1 { "" } else { "s" };
            eprintln!("{source}: the system has {} error{s}", errors.len());
            failed = true;
            continue;
        }
        let mut times = Vec::new();
        let mut result = None;
        for _ in 0..runs {
            let start = Instant::now();
            let r = nh_core::expand_with_stats(body.clone());
            times.push(start.elapsed().as_secs_f64() * 1e3);
            result = Some(r);
        }
        times.sort_by(f64::total_cmp);
        if let Some((code, stats)) = result {
            if show_code {
                println!("{code}");
            }
            println!(
                "{}: expansion {:.2} ms (median of {runs}; min {:.2}, max {:.2}); {}",
                stats.name,
                times[runs / 2],
                times[0],
                times[runs - 1],
                stats.summary()
            );
        }
    }
    if failed {
        std::process::exit(1);
    }
}

/// An error as the compiler prints it: the message, where it is, and the
/// source line with the culprit underlined (lines and columns from the
/// spans of the parsed source).
fn render(e: &ReportedError, source: &str, src: &str) -> String {
    let (start, end) = (e.start.start(), e.end.end());
    let num = start.line.to_string();
    let pad = " ".repeat(num.len());
    let (line, column) = (start.line, start.column + 1);
    let mut out = format!("error: {}\n{pad}--> {source}:{line}:{column}", e.message);
    if let Some(text) = src.lines().nth(start.line.wrapping_sub(1)) {
        let width = if end.line == start.line {
            end.column.saturating_sub(start.column).max(1)
        } else {
            text.chars().count().saturating_sub(start.column).max(1)
        };
        let (indent, marks) = (" ".repeat(start.column), "^".repeat(width));
        out += &format!("\n{pad} |\n{num} | {text}\n{pad} | {indent}{marks}");
    }
    out + "\n"
}
