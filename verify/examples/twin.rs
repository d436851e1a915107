//! Development aid: two systems' texts (separated by a line `---`) with the
//! same coordinates, parameters and inputs, and their accelerations at a
//! few random states, side by side.
use nh_verify::generate::Rng;
use nh_verify::interp::{Arg, Expansion};

fn main() {
    let path = std::env::args().nth(1).expect("a file");
    let text = std::fs::read_to_string(path).expect("readable");
    let parts: Vec<&str> = text.split("\n---\n").collect();
    let exps: Vec<Expansion> = parts
        .iter()
        .map(|p| {
            let out = nh_core::expand(p.parse().expect("lexes"));
            for e in nh_core::reported_errors(&out) {
                println!("error: {}", e.message);
            }
            Expansion::new(&out).expect("interpretable")
        })
        .collect();
    let mut rng = Rng::new(7);
    for _ in 0..3 {
        let e0 = &exps[0];
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
            ("q", Arg::Vector(q.clone())),
            ("rdot", Arg::Vector(v.clone())),
            ("u", Arg::Vector(u.clone())),
        ];
        for (i, e) in exps.iter().enumerate() {
            let takes = e.arguments("accelerations").expect("accelerations");
            let given: Vec<(&str, Arg<f64>)> = all
                .iter()
                .filter(|(a, _)| takes.iter().any(|(b, _)| a == b))
                .cloned()
                .collect();
            println!(
                "{i}: {:?} (dependent {:?})",
                e.call("accelerations", &params, &given),
                e.dependent()
            );
        }
    }
}
