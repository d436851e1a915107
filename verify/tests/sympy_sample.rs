//! The plain derivation the differential test trusts, checked against
//! SymPy: a sample of 48 random systems (every family: Lagrangians written
//! out, bodies, rolling contacts, speeds), derived symbolically and
//! evaluated at 40 digits by `data/sympy_reference.py`, against the plain
//! derivation in double-double at the same states.
use nh_core::sym::dd::Dd;
use nh_verify::check;
use nh_verify::generate;
use nh_verify::plain::{Plain, Point};
use serde_json::Value;

fn dd(v: &Value) -> Dd {
    let hi = v[0].as_f64().expect("hi");
    let lo = v[1].as_f64().expect("lo");
    Dd::from_f64(hi) + Dd::from_f64(lo)
}

fn widen(v: &[f64]) -> Vec<Dd> {
    v.iter().map(|&x| Dd::from_f64(x)).collect()
}

/// |a − b| relative to max(1, |b|), in double-double.
fn relative(a: Dd, b: Dd) -> f64 {
    (a - b).to_f64().abs() / b.to_f64().abs().max(1.0)
}

#[test]
fn the_plain_derivation_agrees_with_sympy() {
    let sample: Value =
        serde_json::from_str(include_str!("../data/sympy_sample.json")).expect("the sample");
    let reference: Value =
        serde_json::from_str(include_str!("../data/sympy_reference.json")).expect("the reference");
    let (sample, reference) = (
        sample.as_array().expect("list"),
        reference.as_array().expect("list"),
    );
    assert_eq!(sample.len(), reference.len());
    let (mut worst, mut compared) = (0.0f64, 0);
    for (entry, want) in sample.iter().zip(reference) {
        let seed = entry["seed"].as_u64().expect("seed");
        let sys = generate::system(seed);
        assert_eq!(
            entry["text"].as_str(),
            Some(sys.text().as_str()),
            "seed {seed}: the generator changed; regenerate the sample (see data/sympy_reference.py)"
        );
        let dependent: Vec<usize> = (entry["dependent"].as_array().expect("dependent").iter())
            .map(|d| d.as_u64().expect("index") as usize)
            .collect();
        let k = entry["states"][0]["v"].as_array().expect("v").len();
        let states = check::states(&sys, seed, k);
        for (p, values) in states
            .iter()
            .zip(want["values"].as_array().expect("values"))
        {
            if values.get("error").is_some() {
                continue;
            }
            let point = Point {
                params: widen(&p.params),
                inputs: widen(&p.inputs),
                t: Dd::from_f64(p.t),
                q: widen(&p.q),
                v: widen(&p.v),
            };
            let plain = Plain::new(&sys, &point);
            let motion = match sys.speeds {
                Some(_) => plain.speeds_motion(&point),
                None => plain.motion(&point, &dependent),
            }
            .unwrap_or_else(|e| panic!("seed {seed}: {e:?}"));
            let mut pairs: Vec<(Dd, Dd)> = Vec::new();
            let list = |key: &str| -> Vec<Dd> {
                values[key]
                    .as_array()
                    .map_or(Vec::new(), |a| a.iter().map(dd).collect())
            };
            pairs.extend(
                motion
                    .accelerations
                    .iter()
                    .copied()
                    .zip(list("accelerations")),
            );
            pairs.extend(motion.multipliers.iter().copied().zip(list("multipliers")));
            pairs.extend(motion.sdot.iter().copied().zip(list("sdot")));
            pairs.push((motion.energy, dd(&values["energy"])));
            assert_eq!(
                motion.accelerations.len(),
                list("accelerations").len(),
                "seed {seed}"
            );
            for (a, b) in pairs {
                let r = relative(a, b);
                assert!(
                    r < 1e-24,
                    "seed {seed}: plain {a:?}, SymPy {b:?} ({r:.1e})\n{}",
                    sys.text()
                );
                worst = worst.max(r);
            }
            compared += 1;
        }
    }
    println!(
        "{compared} states of {} systems: worst relative difference {worst:.1e}",
        sample.len()
    );
    assert!(compared >= 100, "{compared}");
}
