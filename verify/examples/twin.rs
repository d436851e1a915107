//! Development aid: the accelerations of several systems at the same random
//! states, side by side. Each argument is a file holding a system's text
//! (`pub struct ..`), or, with the suffix `.expanded`, an expansion as the
//! engine's `expand` example prints it with `--code` (to compare the code of
//! another revision of the engine).
//!
//! ```text
//! cargo run --release -p nh-verify --example twin -- A.txt B.txt [OLD.expanded]
//! ```
use nh_verify::generate::Rng;
use nh_verify::interp::{Arg, Expansion};

fn expansion(path: &str) -> Expansion {
    let text = std::fs::read_to_string(path).expect("readable");
    let tokens: proc_macro2::TokenStream = if path.ends_with(".expanded") {
        let code = text.lines().next().expect("the code on its first line");
        code.parse().expect("lexes")
    } else {
        let out = nh_core::expand(text.parse().expect("lexes"));
        for e in nh_core::reported_errors(&out) {
            println!("{path}: error: {}", e.message);
        }
        out
    };
    Expansion::new(&tokens).expect("interpretable")
}

fn main() {
    let exps: Vec<(String, Expansion)> = std::env::args()
        .skip(1)
        .map(|p| (p.clone(), expansion(&p)))
        .collect();
    let mut rng = Rng::new(7);
    for _ in 0..3 {
        let e0 = &exps[0].1;
        let params: Vec<f64> = e0
            .parameters()
            .iter()
            .map(|_| rng.uniform(0.6, 1.4))
            .collect();
        let q: Vec<f64> = e0
            .coordinates()
            .iter()
            .map(|_| rng.uniform(-1.2, 1.2))
            .collect();
        let v: Vec<f64> = e0
            .independent()
            .iter()
            .map(|_| rng.uniform(-1.0, 1.0))
            .collect();
        let u: Vec<f64> = e0.inputs().iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
        let all = [
            ("t", Arg::Scalar(0.3)),
            ("q", Arg::Vector(q)),
            ("rdot", Arg::Vector(v)),
            ("u", Arg::Vector(u)),
        ];
        for (path, e) in &exps {
            let takes = e.arguments("accelerations").expect("accelerations");
            let given: Vec<(&str, Arg<f64>)> = all
                .iter()
                .filter(|(a, _)| takes.iter().any(|(b, _)| a == b))
                .cloned()
                .collect();
            println!("{path}: {:?}", e.call("accelerations", &params, &given));
        }
    }
}
