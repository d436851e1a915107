//! Per-call time of the Whipple bicycle's generated `accelerations` and
//! right-hand side (`examples/whipple_bicycle/model.rs`):
//! `cargo bench -p nh-lab --bench bicycle`. It first prints the median, min
//! and max ns/call over 31 batches of 20,000 calls, on a ring of 64 states
//! near upright running at 5 m/s, then hands the same calls to criterion
//! (reports in `target/criterion/`). Beside them, the same states four per
//! call in lanes (`T = WideF64x4`, DESIGN §6.8), in ns per state, and the
//! throughput ratio of lanes to scalar calls on one core. The lanes use
//! whatever SIMD width the build targets: SSE2 by default on x86-64, AVX2
//! and FMA with `RUSTFLAGS="-C target-cpu=native"` on a machine that has
//! them.
#[path = "../../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)]
mod model;

use criterion::{Criterion, criterion_group, criterion_main};
use nonholonomic::prelude::*;
use nonholonomic::runtime::{LaneSystem, WideF64x4};
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
    let scalar_acc = med;
    let (med, lo, hi) = batches(|i| black_box(&bike).rhs(0.0, black_box(&xs[i]))[8]);
    println!("Whipple right-hand side: {med:.0} ns/call (min {lo:.0}, max {hi:.0})");
    let scalar_rhs = med;
    let lanes = model::benchmark_in::<WideF64x4>();
    let groups: Vec<SVector<WideF64x4, 11>> = (0..16)
        .map(|g| SVector::from_fn(|r, _| WideF64x4::from([0, 1, 2, 3].map(|l| xs[4 * g + l][r]))))
        .collect();
    let qr4: Vec<_> = groups
        .iter()
        .map(|x| {
            (
                x.fixed_rows::<8>(0).into_owned(),
                x.fixed_rows::<3>(8).into_owned(),
            )
        })
        .collect();
    let t4 = WideF64x4::from([0.0; 4]);
    let lane0 = |v: WideF64x4| <[f64; 4]>::from(v)[0];
    let (med, lo, hi) = batches(|i| {
        let (q, r) = &qr4[i & 15];
        lane0(black_box(&lanes).accelerations(t4, black_box(q), black_box(r))[0])
    });
    println!(
        "Whipple accelerations, 4 lanes: {:.0} ns/state (min {:.0}, max {:.0}): {:.2}x the scalar throughput",
        med / 4.0,
        lo / 4.0,
        hi / 4.0,
        scalar_acc / (med / 4.0)
    );
    let (med, lo, hi) =
        batches(|i| lane0(black_box(&lanes).lane_rhs(t4, black_box(&groups[i & 15]))[8]));
    println!(
        "Whipple right-hand side, 4 lanes: {:.0} ns/state (min {:.0}, max {:.0}): {:.2}x the scalar throughput",
        med / 4.0,
        lo / 4.0,
        hi / 4.0,
        scalar_rhs / (med / 4.0)
    );
    let mut group = c.benchmark_group("Whipple");
    let mut i = 0;
    group.bench_function("accelerations", |b| {
        b.iter(|| {
            i = (i + 1) & 63;
            let (q, r) = &qr[i];
            black_box(&bike).accelerations(0.0, black_box(q), black_box(r))
        })
    });
    let mut g = 0;
    group.bench_function("accelerations, 4 lanes", |b| {
        b.iter(|| {
            g = (g + 1) & 15;
            let (q, r) = &qr4[g];
            black_box(&lanes).accelerations(t4, black_box(q), black_box(r))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
