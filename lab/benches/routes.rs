//! Per-call time of the two derivation routes of `accelerations`, measured
//! by criterion: `cargo bench -p nh-lab --bench routes`. The macro chooses
//! the route with fewer operations after CSE; this bench checks that choice
//! against the clock. For each system it times the multiplier route, the
//! curvature route (the reduced system solved by the generated unrolled
//! LDLᵀ), and the reduced system built and handed to nalgebra's static
//! Cholesky and LU. The operation counts and the chosen route are printed
//! first. Criterion's reports go to `target/criterion/`.
use criterion::{Criterion, criterion_group, criterion_main};
use nh_lab::systems::{ChaplyginSled, Random03, ThesisDisc};
use nonholonomic::prelude::*;
use std::hint::black_box;

/// A ring of 64 states so the branch predictor and constant folding see
/// varied input.
fn states<const N: usize, const K: usize>() -> Vec<(SVector<f64, N>, SVector<f64, K>)> {
    (0..64)
        .map(|j| {
            let s = j as f64 * 0.1;
            (
                SVector::<f64, N>::from_fn(|i, _| 0.3 + 0.1 * (s + i as f64).sin()),
                SVector::<f64, K>::from_fn(|i, _| 1.0 + 0.5 * (s * 1.3 + i as f64).cos()),
            )
        })
        .collect()
}

/// Benchmarks one system's routes and solvers in a criterion group named
/// after it, each call on the next state of the ring.
macro_rules! bench_system {
    ($c:expr, $ty:ty, $sys:expr, $n:literal, $k:literal) => {{
        let sys: $ty = $sys;
        let states = states::<$n, $k>();
        println!(
            "{}: {} operations on the multiplier route, {} on the curvature route; chosen: {}",
            stringify!($ty),
            <$ty>::OPS_MULTIPLIER_ROUTE,
            <$ty>::OPS_CURVATURE_ROUTE,
            <$ty>::ROUTE
        );
        let mut group = $c.benchmark_group(stringify!($ty));
        let mut i = 0;
        let mut next = || {
            i = (i + 1) & 63;
            let (q, r) = &states[i];
            (black_box(q), black_box(r))
        };
        group.bench_function("multiplier route", |b| {
            b.iter(|| {
                let (q, r) = next();
                black_box(&sys).accelerations_multiplier_route(0.0, q, r)
            })
        });
        group.bench_function("curvature route (generated LDLt)", |b| {
            b.iter(|| {
                let (q, r) = next();
                black_box(&sys).accelerations_curvature_route(0.0, q, r)
            })
        });
        group.bench_function("reduced system + nalgebra Cholesky", |b| {
            b.iter(|| {
                let (q, r) = next();
                let (mm, f) = black_box(&sys).reduced_system(0.0, q, r);
                mm.cholesky().map(|c| c.solve(&f))
            })
        });
        group.bench_function("reduced system + nalgebra LU", |b| {
            b.iter(|| {
                let (q, r) = next();
                let (mm, f) = black_box(&sys).reduced_system(0.0, q, r);
                mm.lu().solve(&f)
            })
        });
        group.finish();
    }};
}

fn routes(c: &mut Criterion) {
    bench_system!(c, ThesisDisc<f64>, ThesisDisc::new(1.7, 0.35, 9.81), 5, 3);
    bench_system!(
        c,
        ChaplyginSled<f64>,
        ChaplyginSled::new(2.0, 0.3, 0.5),
        3,
        2
    );
    bench_system!(c, Random03<f64>, Random03::new(1.495, 0.319), 6, 4);
}

criterion_group!(benches, routes);
criterion_main!(benches);
