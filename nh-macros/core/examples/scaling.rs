//! How the expansion scales: synthetic systems with n coordinates and
//! p = n/3 constraints — a dense mass matrix with entries cos(q_i − q_j)/c_ij,
//! gravity-like potentials, and dense constraints with entries
//! sin(q_α + s_a)/c_aα — expanded for n = 3, 6, 9, 12, 16:
//!
//! ```text
//! cargo run --release -p nh-core --example scaling
//! ```
//!
//! Prints a Markdown table of expansion time (median of 5), operation counts
//! of `accelerations` by both routes and generated lines.
use std::time::Instant;

fn synthetic(n: usize) -> String {
    let p = n / 3;
    let k = n - p;
    let q: Vec<String> = (1..=n).map(|i| format!("q{i}")).collect();
    let mut terms = Vec::new();
    for i in 0..n {
        terms.push(format!("({}/10)*dot({})^2/2", 20 + i, q[i]));
        for j in (i + 1)..n {
            terms.push(format!(
                "cos({} - {})*dot({})*dot({})/{}",
                q[i],
                q[j],
                q[i],
                q[j],
                (i + j + 2) * 2
            ));
        }
        terms.push(format!("g*cos({})/{}", q[i], i + 1));
    }
    let mut constraints = Vec::new();
    for a in 0..p {
        let s = &q[k + a];
        let rhs: Vec<String> = (0..k)
            .map(|al| format!("sin({} + {s})/{}*dot({})", q[al], a + al + 2, q[al]))
            .collect();
        constraints.push(format!("dot({s}) = {};", rhs.join(" + ")));
    }
    format!(
        "pub struct Synth{n} {{ parameters {{ g }} coordinates {{ {} }} lagrangian = {}; constraints {{ {} }} }}",
        q.join(", "),
        terms.join(" + "),
        constraints.join(" ")
    )
}

fn main() {
    println!(
        "| n (p) | expansion (median of 5) | ops of `accelerations` (multiplier / curvature route) | route | generated lines |"
    );
    println!("|---|---|---|---|---|");
    for n in [3, 6, 9, 12, 16] {
        let tokens: proc_macro2::TokenStream = match synthetic(n).parse() {
            Ok(t) => t,
            Err(e) => {
                eprintln!("synthetic system {n} does not lex: {e}");
                std::process::exit(2);
            }
        };
        let mut times = Vec::new();
        let mut stats = None;
        for _ in 0..5 {
            let start = Instant::now();
            let (_, s) = nh_core::expand_with_stats(tokens.clone());
            times.push(start.elapsed().as_secs_f64() * 1e3);
            stats = Some(s);
        }
        times.sort_by(f64::total_cmp);
        if let Some(s) = stats {
            println!(
                "| {n} ({}) | {:.1} ms | {} / {} | {:?} | {} |",
                n / 3,
                times[2],
                s.ops_multiplier,
                s.ops_curvature,
                s.route.unwrap_or(nh_core::generate::Route::Multiplier),
                s.lines
            );
        }
    }
}
