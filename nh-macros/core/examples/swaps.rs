//! One swapped token, everywhere: for each valid system in the files given
//! (every `nonholonomic_system! { .. }` in them), two adjacent tokens are
//! swapped at every position (delimiters count as tokens; a swap the lexer
//! rejects, or of two equal tokens, is skipped), the result is expanded,
//! and the errors are counted. A mistake of one token should give one
//! error at that token: the tool reports how many expansions gave more
//! than one error, and how many gave an error that spans the whole input
//! (or the macro call), which points at nothing.
//!
//! ```text
//! cargo run --release -p nh-core --example swaps -- FILE.rs .. [--show N]
//! ```
//!
//! `--show N` prints up to N of the offending cases with their errors
//! (with `SWAPS_ALL` set, up to N of every case with an error).
//!
//! On the fuzz test's five seeds (the snakeboard without `energy`, which it
//! cannot have), `examples/*.rs`, `tests/pass/offset_ball.rs`,
//! `tests/diff_drive.rs` and `tests/bodies.rs`: 3,146 swaps lexed, 914 of
//! them with more than one error and 25 with an error spanning the whole
//! input before the parser's recovery of misplaced tokens, none of either
//! after; the bicycle (`examples/whipple_bicycle/model.rs`, 503 swaps): 209
//! and 10 before, none after. `tests/one_token_swapped.rs` keeps it so.
#[path = "../tests/tokens/mod.rs"]
mod tokens;

use proc_macro2::TokenStream;
use tokens::{extent, find_invocations, flatten};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let show: usize = args
        .iter()
        .position(|a| a == "--show")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let files: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| !a.starts_with("--") && (*i == 0 || args[i - 1] != "--show"))
        .map(|(_, a)| a)
        .collect();
    let mut shown = 0;
    let (mut total, mut with_errors, mut several, mut whole, mut clean) = (0, 0, 0, 0, 0);
    let mut histogram = std::collections::BTreeMap::<usize, usize>::new();
    for path in files {
        let src = std::fs::read_to_string(path).expect("read the file");
        let mut bodies = Vec::new();
        find_invocations(src.parse().expect("Rust tokens"), &mut bodies);
        for body in bodies {
            let mut toks = Vec::new();
            flatten(body, &mut toks);
            for i in 0..toks.len().saturating_sub(1) {
                if toks[i] == toks[i + 1] {
                    continue;
                }
                let mut m = toks.clone();
                m.swap(i, i + 1);
                let text = m.join(" ");
                let Ok(input) = text.parse::<TokenStream>() else {
                    continue;
                };
                total += 1;
                let (lo, hi) = extent(&input);
                let errors = nh_core::reported_errors(&nh_core::expand(input));
                *histogram.entry(errors.len()).or_default() += 1;
                if errors.is_empty() {
                    clean += 1;
                    continue;
                }
                with_errors += 1;
                let is_whole = errors.iter().any(|e| {
                    let (s, t) = (e.start.byte_range(), e.end.byte_range());
                    (s.start <= lo && t.end >= hi) || (s.start == 0 && t.end == 0)
                });
                if errors.len() > 1 {
                    several += 1;
                }
                if is_whole {
                    whole += 1;
                }
                if (errors.len() > 1 || is_whole || std::env::var_os("SWAPS_ALL").is_some())
                    && shown < show
                {
                    shown += 1;
                    let around = m[i.saturating_sub(6)..(i + 8).min(m.len())].join(" ");
                    println!(
                        "--- {path}: `{}` <-> `{}` at {i}: … {around} …",
                        toks[i],
                        toks[i + 1]
                    );
                    for e in &errors {
                        let (s, t) = (e.start.start(), e.end.end());
                        println!(
                            "  {}:{}-{}:{} {}",
                            s.line,
                            s.column,
                            t.line,
                            t.column,
                            e.message.chars().take(160).collect::<String>()
                        );
                    }
                }
            }
        }
    }
    println!(
        "{total} swaps expanded: {clean} without error, {with_errors} with errors; {several} with more than one error, {whole} with an error spanning the whole input; errors per expansion: {histogram:?}"
    );
}
