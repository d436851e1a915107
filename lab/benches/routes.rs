//! Per-call time of the two derivation routes of `accelerations`, measured
//! in one run: `cargo bench -p nh-lab --bench routes`. The macro chooses the route with
//! fewer operations after CSE; this bench checks that choice against the
//! clock.
use nonholonomic::prelude::*;
use std::hint::black_box;
use std::time::Instant;

nonholonomic_system! {
    /// The thesis's rolling disc (DESIGN §2).
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { routes }
    }
}

nonholonomic_system! {
    /// Chaplygin sled (refdata/chaplygin_sled.json).
    pub struct ChaplyginSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { routes }
    }
}

nonholonomic_system! {
    /// refdata/random_03.json: six coupled coordinates, two constraints.
    pub struct Random03 {
        parameters { k1, k2 }
        coordinates { xi, eta, q_1, q_2, r1, s1 }
        lagrangian = dot(eta)^2*(q_2^2/2 + 9/4) - dot(eta)*dot(q_1)/4 - dot(eta)*dot(q_2)*sin(r1)/3 - dot(eta)*dot(r1)/3 - dot(eta)*dot(s1)*cos(eta)*cos(s1)/3 - k2*cos(xi) + dot(q_1)^2*(sin(q_2)*cos(xi)/4 + 5/2) - 2*dot(q_1)*dot(q_2)/5 - 2*dot(q_1)*dot(s1)*cos(s1)*cos(xi)/5 - 2*q_2/5 + 7*dot(q_2)^2/4 - 2*dot(q_2)*dot(r1)*cos(eta)/5 + dot(q_2)*dot(xi)*sin(s1)*cos(eta)/4 + dot(r1)^2*(sin(q_1)^2/2 + 11/4) + 2*dot(r1)*dot(s1)/5 + 7*dot(s1)^2/4 + dot(s1)*dot(xi)*sin(eta)*cos(r1)/4 + dot(xi)^2*(q_2^2/2 + 7/4);
        constraints {
            dot(r1) = 3*s1^2/2*dot(xi) - 2*xi*cos(q_1)*dot(eta) - 1/3*dot(q_1);
            dot(s1) = -1/2*dot(xi) + 2*cos(r1)/3*dot(eta) + (q_2^2 + 1)*dot(q_2);
        }
        outputs { routes }
    }
}

/// Median nanoseconds per call of `f` over `reps` repeats of `calls` calls.
fn time_per_call(calls: usize, reps: usize, mut f: impl FnMut(usize) -> f64) -> (f64, f64, f64) {
    let mut samples = Vec::with_capacity(reps);
    let mut sink = 0.0;
    for _ in 0..reps {
        let start = Instant::now();
        for i in 0..calls {
            sink += f(i);
        }
        samples.push(start.elapsed().as_secs_f64() * 1e9 / calls as f64);
    }
    black_box(sink);
    samples.sort_by(f64::total_cmp);
    (samples[0], samples[reps / 2], samples[reps - 1])
}

macro_rules! bench_system {
    ($solves:ident, $ty:ty, $sys:expr, $n:literal, $k:literal) => {{
        let solves = &mut $solves;
        let sys = $sys;
        // a ring of states so the branch predictor and constant folding see varied input
        let states: Vec<(SVector<f64, $n>, SVector<f64, $k>)> = (0..64)
            .map(|j| {
                let s = j as f64 * 0.1;
                (
                    SVector::<f64, $n>::from_fn(|i, _| 0.3 + 0.1 * (s + i as f64).sin()),
                    SVector::<f64, $k>::from_fn(|i, _| 1.0 + 0.5 * (s * 1.3 + i as f64).cos()),
                )
            })
            .collect();
        let calls = 2_000_000;
        let reps = 9;
        let m = time_per_call(calls, reps, |i| {
            let (q, r) = &states[i & 63];
            black_box(&sys).accelerations_multiplier_route(0.0, black_box(q), black_box(r))[0]
        });
        let c = time_per_call(calls, reps, |i| {
            let (q, r) = &states[i & 63];
            black_box(&sys).accelerations_curvature_route(0.0, black_box(q), black_box(r))[0]
        });
        let chol = time_per_call(calls, reps, |i| {
            let (q, r) = &states[i & 63];
            let (mm, f) = black_box(&sys).reduced_system(0.0, black_box(q), black_box(r));
            mm.cholesky().map(|c| c.solve(&f)[0]).unwrap_or(f64::NAN)
        });
        let lu = time_per_call(calls, reps, |i| {
            let (q, r) = &states[i & 63];
            let (mm, f) = black_box(&sys).reduced_system(0.0, black_box(q), black_box(r));
            mm.lu().solve(&f).map(|x| x[0]).unwrap_or(f64::NAN)
        });
        let ldl = time_per_call(calls, reps, |i| {
            let (q, r) = &states[i & 63];
            black_box(&sys).accelerations_curvature_route(0.0, black_box(q), black_box(r))[0]
        });
        solves.push(format!(
            "| {:<18} | {:>10.2} ({:.2}–{:.2}) | {:>10.2} ({:.2}–{:.2}) | {:>10.2} ({:.2}–{:.2}) |",
            stringify!($ty),
            ldl.1, ldl.0, ldl.2,
            chol.1, chol.0, chol.2,
            lu.1, lu.0, lu.2
        ));
        println!(
            "| {:<13} | {:>4} | {:>16.2} ({:.2}–{:.2}) | {:>4} | {:>16.2} ({:.2}–{:.2}) | {:>10} | {:>6.2}x |",
            stringify!($ty),
            <$ty>::OPS_MULTIPLIER_ROUTE,
            m.1, m.0, m.2,
            <$ty>::OPS_CURVATURE_ROUTE,
            c.1, c.0, c.2,
            <$ty>::ROUTE,
            m.1 / c.1
        );
    }};
}

fn main() {
    // `cargo test --benches` runs this with --test-like flags; keep it quick then.
    if std::env::args().any(|a| a == "--test" || a == "--list") {
        return;
    }
    println!(
        "| system        | ops (multiplier) | ns/call median (min–max) | ops (curvature) | ns/call median (min–max) | chosen | multiplier/curvature time |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mut solves: Vec<String> = Vec::new();
    bench_system!(
        solves,
        ThesisDisc<f64>,
        ThesisDisc::new(1.7, 0.35, 9.81),
        5,
        3
    );
    bench_system!(
        solves,
        ChaplyginSled<f64>,
        ChaplyginSled::new(2.0, 0.3, 0.5),
        3,
        2
    );
    bench_system!(solves, Random03<f64>, Random03::new(1.495, 0.319), 6, 4);
    println!();
    println!(
        "Curvature route, ns/call median (min–max): the reduced system solved by the generated unrolled LDLᵀ, or built and handed to nalgebra's static Cholesky / LU:"
    );
    println!("| system | generated LDLᵀ | nalgebra Cholesky | nalgebra LU |");
    println!("|---|---|---|---|");
    for line in solves {
        println!("{line}");
    }
}
