//! Generated code against hand-written code, measured in the same run:
//! per-call `accelerations` of the thesis's disc, the Chaplygin sled, the
//! physically correct rolling disc and the largest reference system
//! (random_03: six coordinates, two constraints), and a whole Dormand–Prince
//! integration of the thesis's disc over 10 s at rtol 1e-8.
//!
//! ```text
//! cargo bench -p nh-lab --bench accelerations
//! ```
//!
//! The hand-written versions are written from the closed forms (the thesis's
//! (6.60)–(6.62), the sled's reduced equations, the rolling disc's equations
//! derived by hand in tests/rolling_disc.rs) or, for random_03, the way a
//! careful person writes a constrained Euler–Lagrange system: M(q) and its
//! derivatives typed in from the mass matrix of refdata/random_03.json,
//! Christoffel terms, projection onto the constraints and nalgebra's
//! Cholesky. Each pair is timed interleaved (generated, hand, generated,
//! hand, ...) so that drift of the machine affects both alike; the ratio is
//! of medians, with the min–max spread of the repeats.
//!
//! This is deliberately a small paired harness of its own (`harness = false`)
//! rather than a criterion bench: criterion measures one function at a time,
//! so the generated and the hand-written side of a pair would run minutes
//! apart and see different machine noise, which is what the interleaving is
//! there to avoid. (The per-call route timings, where that does not matter,
//! are the criterion bench `routes`.)
#![allow(clippy::excessive_precision)]
use nalgebra::{Matrix4, SMatrix, SVector, Vector4};
use nh_lab::systems::{ChaplyginSled, Random03, RollingDisc, ThesisDisc};
use nonholonomic::prelude::*;
use std::hint::black_box;
use std::time::Instant;

// ---------------------------------------------------------------- hand-written

/// (6.60)–(6.62) solved for the accelerations.
#[inline(never)]
fn thesis_hand(r: f64, g: f64, q: &SVector<f64, 5>, rdot: &SVector<f64, 3>) -> SVector<f64, 3> {
    let (s, c) = q[2].sin_cos();
    let (td, pd, sd) = (rdot[0], rdot[1], rdot[2]);
    let den = 4.0 / (4.0 * s * s + 3.0);
    SVector::from([
        den * c * pd * sd,
        -2.0 * den * s * c * pd * sd,
        0.8 * ((s * pd - td) * c * pd + g / r * s),
    ])
}

/// The sled: u = ẋ / cos θ, u̇ = a ω², ω̇ = −m a u ω / (J + m a²), ẍ = u̇ cos θ − u ω sin θ.
#[inline(never)]
fn sled_hand(
    m: f64,
    j: f64,
    a: f64,
    q: &SVector<f64, 3>,
    rdot: &SVector<f64, 2>,
) -> SVector<f64, 2> {
    let (s, c) = q[1].sin_cos();
    let (xd, w) = (rdot[0], rdot[1]);
    let u = xd / c;
    let udot = a * w * w;
    SVector::from([udot * c - u * w * s, -m * a * u * w / (j + m * a * a)])
}

/// The rolling disc: φ̈ = 2 ψ̇ θ̇ / cos ψ, θ̈ = sin ψ φ̈ + (5/3) cos ψ φ̇ ψ̇,
/// ψ̈ = sin ψ cos ψ φ̇² − (6/5) cos ψ θ̇ φ̇ + (4g / 5R) sin ψ.
#[inline(never)]
fn rolling_hand(r: f64, g: f64, q: &SVector<f64, 5>, rdot: &SVector<f64, 3>) -> SVector<f64, 3> {
    let (s, c) = q[2].sin_cos();
    let (td, pd, sd) = (rdot[0], rdot[1], rdot[2]);
    let phi_dd = 2.0 * sd * td / c;
    SVector::from([
        s * phi_dd + 5.0 / 3.0 * c * pd * sd,
        phi_dd,
        c * pd * (s * pd - 1.2 * td) + 0.8 * g / r * s,
    ])
}

type M6 = SMatrix<f64, 6, 6>;
type V6 = SVector<f64, 6>;

/// random_03 by hand: M q̈ + c(q, q̇) + ∇V = Cᵀλ with q̇ = C ṙ, C = [I; −A],
/// reduced to Cᵀ M C r̈ = −Cᵀ (M b + c + ∇V), b = (0, −Ȧ ṙ), solved by Cholesky.
#[inline(never)]
fn random03_hand(k2: f64, q: &V6, rdot: &Vector4<f64>) -> Vector4<f64> {
    let (xi, eta, q1, q2, r1, s1) = (q[0], q[1], q[2], q[3], q[4], q[5]);
    let (sxi, cxi) = xi.sin_cos();
    let (seta, ceta) = eta.sin_cos();
    let (sq1, cq1) = q1.sin_cos();
    let (sq2, cq2) = q2.sin_cos();
    let (sr1, cr1) = r1.sin_cos();
    let (ss1, cs1) = s1.sin_cos();
    // the mass matrix (refdata mass_matrix)
    let mut m = M6::zeros();
    m[(0, 0)] = q2 * q2 + 3.5;
    m[(0, 3)] = ss1 * ceta / 4.0;
    m[(0, 5)] = seta * cr1 / 4.0;
    m[(1, 1)] = q2 * q2 + 4.5;
    m[(1, 2)] = -0.25;
    m[(1, 3)] = -sr1 / 3.0;
    m[(1, 4)] = -1.0 / 3.0;
    m[(1, 5)] = -ceta * cs1 / 3.0;
    m[(2, 2)] = sq2 * cxi / 2.0 + 5.0;
    m[(2, 3)] = -0.4;
    m[(2, 5)] = -0.4 * cs1 * cxi;
    m[(3, 3)] = 3.5;
    m[(3, 4)] = -0.4 * ceta;
    m[(4, 4)] = sq1 * sq1 + 5.5;
    m[(4, 5)] = 0.4;
    m[(5, 5)] = 3.5;
    for i in 0..6 {
        for j in 0..i {
            m[(i, j)] = m[(j, i)];
        }
    }
    // ∂M/∂q_k, upper triangles (symmetrised below)
    let mut dm = [M6::zeros(); 6];
    dm[3][(0, 0)] = 2.0 * q2;
    dm[5][(0, 3)] = cs1 * ceta / 4.0;
    dm[1][(0, 3)] = -ss1 * seta / 4.0;
    dm[1][(0, 5)] = ceta * cr1 / 4.0;
    dm[4][(0, 5)] = -seta * sr1 / 4.0;
    dm[3][(1, 1)] = 2.0 * q2;
    dm[4][(1, 3)] = -cr1 / 3.0;
    dm[1][(1, 5)] = seta * cs1 / 3.0;
    dm[5][(1, 5)] = ceta * ss1 / 3.0;
    dm[3][(2, 2)] = cq2 * cxi / 2.0;
    dm[0][(2, 2)] = -sq2 * sxi / 2.0;
    dm[5][(2, 5)] = 0.4 * ss1 * cxi;
    dm[0][(2, 5)] = 0.4 * cs1 * sxi;
    dm[1][(3, 4)] = 0.4 * seta;
    dm[2][(4, 4)] = 2.0 * sq1 * cq1;
    for d in dm.iter_mut() {
        for i in 0..6 {
            for j in 0..i {
                d[(i, j)] = d[(j, i)];
            }
        }
    }
    // the constraint matrix A (ṡ = −A ṙ) and its derivatives
    let a = SMatrix::<f64, 2, 4>::new(
        -1.5 * s1 * s1,
        2.0 * xi * cq1,
        1.0 / 3.0,
        0.0,
        0.5,
        -2.0 / 3.0 * cr1,
        0.0,
        -q2 * q2 - 1.0,
    );
    let sdot = -(a * rdot);
    let qd = V6::from([rdot[0], rdot[1], rdot[2], rdot[3], sdot[0], sdot[1]]);
    // Ȧ ṙ: d/dt of A along q̇
    let adot = SMatrix::<f64, 2, 4>::new(
        -3.0 * s1 * qd[5],
        2.0 * cq1 * qd[0] - 2.0 * xi * sq1 * qd[2],
        0.0,
        0.0,
        0.0,
        2.0 / 3.0 * sr1 * qd[4],
        0.0,
        -2.0 * q2 * qd[3],
    );
    let adot_r = adot * rdot;
    let b = V6::from([0.0, 0.0, 0.0, 0.0, -adot_r[0], -adot_r[1]]);
    // Christoffel terms c_i = Σ_k (∂M/∂q_k q̇_k) q̇ − ½ q̇ᵀ ∂M/∂q_i q̇
    let mut mdot = M6::zeros();
    for k in 0..6 {
        mdot += dm[k] * qd[k];
    }
    let mut c = mdot * qd;
    for i in 0..6 {
        c[i] -= 0.5 * qd.dot(&(dm[i] * qd));
    }
    let mut grad_v = V6::zeros();
    grad_v[0] = -k2 * sxi;
    grad_v[3] = 0.4;
    // projection onto the constraints
    let mut cm = SMatrix::<f64, 6, 4>::zeros();
    for i in 0..4 {
        cm[(i, i)] = 1.0;
    }
    for al in 0..4 {
        cm[(4, al)] = -a[(0, al)];
        cm[(5, al)] = -a[(1, al)];
    }
    let mr: Matrix4<f64> = cm.transpose() * m * cm;
    let f: Vector4<f64> = -(cm.transpose() * (m * b + c + grad_v));
    match mr.cholesky() {
        Some(ch) => ch.solve(&f),
        None => Vector4::from_element(f64::NAN),
    }
}

// ---------------------------------------------------------------- timing

/// Interleaved timing of two functions: `reps` rounds of `calls` calls each;
/// returns (median, min, max) nanoseconds per call for both.
fn paired(
    calls: usize,
    reps: usize,
    mut a: impl FnMut(usize) -> f64,
    mut b: impl FnMut(usize) -> f64,
) -> ([f64; 3], [f64; 3]) {
    let mut ta = Vec::with_capacity(reps);
    let mut tb = Vec::with_capacity(reps);
    let mut sink = 0.0;
    for _ in 0..reps {
        let start = Instant::now();
        for i in 0..calls {
            sink += a(i);
        }
        ta.push(start.elapsed().as_secs_f64() * 1e9 / calls as f64);
        let start = Instant::now();
        for i in 0..calls {
            sink += b(i);
        }
        tb.push(start.elapsed().as_secs_f64() * 1e9 / calls as f64);
    }
    black_box(sink);
    let stats = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        [v[v.len() / 2], v[0], v[v.len() - 1]]
    };
    (stats(ta), stats(tb))
}

fn row(name: &str, unit: &str, g: [f64; 3], h: [f64; 3]) {
    println!(
        "| {name} | {:.2} {unit} ({:.2}–{:.2}) | {:.2} {unit} ({:.2}–{:.2}) | {:.3} |",
        g[0],
        g[1],
        g[2],
        h[0],
        h[1],
        h[2],
        g[0] / h[0]
    );
}

fn states<const N: usize, const K: usize>(
    scale_q: f64,
    scale_v: f64,
) -> Vec<(SVector<f64, N>, SVector<f64, K>)> {
    (0..64)
        .map(|j| {
            let s = j as f64 * 0.1;
            (
                SVector::<f64, N>::from_fn(|i, _| scale_q * (s + i as f64).sin()),
                SVector::<f64, K>::from_fn(|i, _| {
                    scale_v * (1.0 + 0.5 * (1.3 * s + i as f64).cos())
                }),
            )
        })
        .collect()
}

/// One system: checks that the generated and the hand-written accelerations
/// agree on every state (to `tol`, relative to the largest component), then
/// times them interleaved, `calls` calls per round, and prints the row.
fn compare<const N: usize, const K: usize>(
    name: &str,
    (calls, reps): (usize, usize),
    tol: f64,
    states: &[(SVector<f64, N>, SVector<f64, K>)],
    generated: impl Fn(&SVector<f64, N>, &SVector<f64, K>) -> SVector<f64, K>,
    hand: impl Fn(&SVector<f64, N>, &SVector<f64, K>) -> SVector<f64, K>,
) {
    for (q, v) in states {
        let (a, b) = (generated(q, v), hand(q, v));
        assert!(
            (a - b).amax() <= tol * b.amax().max(1.0),
            "{name} mismatch: {a} vs {b}"
        );
    }
    assert_eq!(states.len(), 64, "a ring of 64 states (indexed by i & 63)");
    let (g, h) = paired(
        calls,
        reps,
        |i| generated(black_box(&states[i & 63].0), black_box(&states[i & 63].1))[0],
        |i| hand(black_box(&states[i & 63].0), black_box(&states[i & 63].1))[0],
    );
    row(&format!("{name} `accelerations`"), "ns", g, h);
}

/// A whole Dormand–Prince integration of the thesis's disc over 10 s at rtol
/// 1e-8: the generated system against a hand-written right side (which must
/// take the same steps).
fn whole_integration(disc: &ThesisDisc) {
    let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5]);
    let hand_rhs = |_t: f64, x: &SVector<f64, 8>| {
        let q = x.fixed_rows::<5>(0).into_owned();
        let v = x.fixed_rows::<3>(5).into_owned();
        let a = thesis_hand(0.35, 9.81, &q, &v);
        let c = 0.35 * v[0];
        let (sp, cp) = q[1].sin_cos();
        SVector::<f64, 8>::from([v[0], v[1], v[2], c * cp, c * sp, a[0], a[1], a[2]])
    };
    let gen_out = Dopri5::new(1e-8, 1e-10)
        .integrate(disc, 0.0, x0, 10.0)
        .expect("generated integration");
    let hand_out = Dopri5::new(1e-8, 1e-10)
        .integrate(&hand_rhs, 0.0, x0, 10.0)
        .expect("hand-written integration");
    assert_eq!(
        gen_out.stats.steps, hand_out.stats.steps,
        "the two right sides must take the same steps"
    );
    let (g, h) = paired(
        1,
        31,
        |_| {
            Dopri5::new(1e-8, 1e-10)
                .integrate(black_box(disc), 0.0, x0, 10.0)
                .map_or(f64::NAN, |o| o.x[0])
        },
        |_| {
            Dopri5::new(1e-8, 1e-10)
                .integrate(black_box(&hand_rhs), 0.0, x0, 10.0)
                .map_or(f64::NAN, |o| o.x[0])
        },
    );
    row(
        &format!(
            "ThesisDisc, Dopri5 10 s at rtol 1e-8 ({} steps)",
            gen_out.stats.steps
        ),
        "µs",
        g.map(|x| x / 1e3),
        h.map(|x| x / 1e3),
    );
}

fn main() {
    if std::env::args().any(|a| a == "--test" || a == "--list") {
        return;
    }
    let rounds = (2_000_000, 11);
    println!("| system | generated | hand-written | generated / hand-written |\n|---|---|---|---|");

    let disc: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let discs = states::<5, 3>(1.0, 2.0);
    compare(
        "ThesisDisc",
        rounds,
        1e-12,
        &discs,
        |q, v| black_box(&disc).accelerations(0.0, q, v),
        |q, v| thesis_hand(black_box(disc.R), black_box(disc.g), q, v),
    );

    let sled: ChaplyginSled = ChaplyginSled::new(2.0, 0.3, 0.5);
    compare(
        "Chaplygin sled",
        rounds,
        1e-12,
        &states::<3, 2>(1.0, 1.0),
        |q, v| black_box(&sled).accelerations(0.0, q, v),
        |q, v| {
            sled_hand(
                black_box(sled.m),
                black_box(sled.J),
                black_box(sled.a),
                q,
                v,
            )
        },
    );

    let rolling: RollingDisc = RollingDisc::new(1.7, 0.35, 9.81);
    compare(
        "RollingDisc",
        rounds,
        1e-12,
        &discs,
        |q, v| black_box(&rolling).accelerations(0.0, q, v),
        |q, v| rolling_hand(black_box(rolling.R), black_box(rolling.g), q, v),
    );

    let r03: Random03 = Random03::new(1.495, 0.319);
    compare(
        "random_03",
        (rounds.0 / 4, rounds.1),
        1e-10,
        &states::<6, 4>(1.0, 1.0),
        |q, v| black_box(&r03).accelerations(0.0, q, v),
        |q, v| random03_hand(black_box(r03.k2), q, v),
    );

    whole_integration(&disc);
}
