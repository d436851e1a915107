//! Per-call time of the Whipple bicycle's generated `accelerations` and
//! right-hand side (`examples/whipple_bicycle/model.rs`):
//! `cargo bench -p nh-lab --bench bicycle`. It first prints the median, min
//! and max ns/call over 31 batches of 20,000 calls, on a ring of 64 states
//! near upright running at 5 m/s, then hands the same calls to criterion
//! (reports in `target/criterion/`).
#[path = "../../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use nonholonomic::prelude::*;
use std::hint::black_box;

/// States near upright running at 5 m/s: small roll and steer, their rates,
/// the rear wheel's rate for 5 m/s.
fn states() -> Vec<SVector<f64, 11>> {
    (0..64)
        .map(|j| {
            let s = f64::from(j) * 0.1;
            let mut x = SVector::<f64, 11>::zeros();
            x[0] = 0.05 * s.sin();
            x[1] = 0.05 * (1.3 * s).cos();
            x[8] = 0.2 * (0.7 * s).sin();
            x[9] = 0.2 * (1.1 * s).cos();
            x[10] = 5.0 / 0.3;
            x
        })
        .collect()
}

/// Median, min and max ns per call of `f` over 31 batches of 20,000 calls.
fn batches(mut f: impl FnMut(usize) -> f64) -> (f64, f64, f64) {
    let mut ns = Vec::with_capacity(31);
    let mut sink = 0.0;
    for _ in 0..31 {
        let t0 = std::time::Instant::now();
        for k in 0..20_000 {
            sink += f(k & 63);
        }
        ns.push(t0.elapsed().as_nanos() as f64 / 20_000.0);
    }
    black_box(sink);
    ns.sort_by(f64::total_cmp);
    (ns[15], ns[0], ns[30])
}

fn bench(c: &mut Criterion) {
    let bike = model::benchmark();
    let xs = states();
    let split = |x: &SVector<f64, 11>| {
        (
            x.fixed_rows::<8>(0).into_owned(),
            x.fixed_rows::<3>(8).into_owned(),
        )
    };
    let qr: Vec<_> = xs.iter().map(split).collect();
    let (med, lo, hi) = batches(|i| {
        let (q, r) = &qr[i];
        black_box(&bike).accelerations(0.0, black_box(q), black_box(r))[0]
    });
    println!("Whipple accelerations: {med:.0} ns/call (min {lo:.0}, max {hi:.0})");
    let (med, lo, hi) = batches(|i| black_box(&bike).rhs(0.0, black_box(&xs[i]))[8]);
    println!("Whipple right-hand side: {med:.0} ns/call (min {lo:.0}, max {hi:.0})");
    let mut group = c.benchmark_group("Whipple");
    let mut i = 0;
    group.bench_function("accelerations", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let (q, r) = &qr[i];
            black_box(&bike).accelerations(0.0, black_box(q), black_box(r))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
