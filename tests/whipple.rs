//! The Whipple bicycle written with bodies and rolling contacts
//! (`examples/whipple_bicycle/model.rs`) against the published benchmark of
//! Meijaard, Papadopoulos, Ruina and Schwab (2007): the linearisation of the
//! generated nonlinear system about upright straight-ahead running gives
//! their M, C1, K0 and K2 and the eigenvalues of their Table 2 to ≥ 10
//! significant digits, and the weave and capsize speeds.
#[path = "common/differences.rs"]
mod central;
#[path = "../examples/whipple_bicycle/model.rs"]
mod model;

use nonholonomic::prelude::*;
use serde_json::Value;

fn published() -> Value {
    serde_json::from_str(include_str!("data/whipple_benchmark.json")).expect("valid JSON")
}

fn matrix(v: &Value) -> SMatrix<f64, 2, 2> {
    SMatrix::from_fn(|r, c| v[r][c].as_f64().expect("a number"))
}

/// Largest difference relative to the largest entry of the published matrix.
fn rel(got: SMatrix<f64, 2, 2>, want: SMatrix<f64, 2, 2>) -> f64 {
    (got - want).amax() / want.amax()
}

#[test]
fn linearisation_reproduces_the_benchmark_matrices() {
    let data = published();
    let b = model::benchmark();
    let g = data["g"].as_f64().unwrap();
    let (m, c1, k0, k2) = (
        matrix(&data["M"]),
        matrix(&data["C1"]),
        matrix(&data["K0"]),
        matrix(&data["K2"]),
    );
    let (m_got, _, stiff0) = model::linearised(&b, 0.0);
    let (_, damp, stiff) = model::linearised(&b, 3.0);
    let k0_got = stiff0 / g;
    let k2_got = (stiff - stiff0) / 9.0;
    let c1_got = damp / 3.0;
    let errs = [
        rel(m_got, m),
        rel(c1_got, c1),
        rel(k0_got, k0),
        rel(k2_got, k2),
    ];
    eprintln!("M, C1, K0, K2 against the benchmark (relative): {errs:?}");
    // every entry to ten significant digits of itself
    for (got, want, name) in [
        (m_got, m, "M"),
        (c1_got, c1, "C1"),
        (k0_got, k0, "K0"),
        (k2_got, k2, "K2"),
    ] {
        for (a, w) in got.iter().zip(want.iter()) {
            assert!(
                (a - w).abs() <= 1e-10 * w.abs().max(1e-3),
                "{name}: {a} vs {w}"
            );
        }
    }
}

/// Table 2 of the paper: (v, its four eigenvalues sorted) per row.
fn table_2() -> Vec<(f64, Vec<(f64, f64)>)> {
    let data = published();
    data["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let want: Vec<(f64, f64)> = row["eigenvalues"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| (e[0].as_f64().unwrap(), e[1].as_f64().unwrap()))
                .collect();
            (row["v"].as_f64().unwrap(), sorted(want))
        })
        .collect()
}

/// Eigenvalues sorted by real part, then imaginary part.
fn sorted(mut ev: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    ev.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
    ev
}

/// The largest relative distance between `got` and Table 2's `want` at
/// speed `v`, asserting each is below `tol`.
fn worst_against(v: f64, got: &[(f64, f64)], want: &[(f64, f64)], tol: f64) -> f64 {
    let mut worst = 0.0_f64;
    for (g, w) in got.iter().zip(want) {
        let d = ((g.0 - w.0).powi(2) + (g.1 - w.1).powi(2)).sqrt() / (w.0.hypot(w.1));
        worst = worst.max(d);
        assert!(d < tol, "v = {v}: {g:?} vs {w:?}");
    }
    worst
}

#[test]
fn eigenvalues_match_table_2() {
    let b = model::benchmark();
    let mut worst = 0.0_f64;
    for (v, want) in table_2() {
        let got = model::eigenvalues(&b, v);
        worst = worst.max(worst_against(v, &got, &want, 1e-10));
    }
    eprintln!("eigenvalues at v = 0..10 against Table 2: worst relative difference {worst:.1e}");
}

/// The eigenvalues from central differences of the generated right-hand
/// side, which takes Kane's form body by body and solves the contact block
/// numerically (DESIGN §9, §10), as `jacobian` does by differentiating that
/// graph forward: both reproduce Table 2, to the differences' accuracy.
#[test]
fn the_right_hand_side_linearises_to_table_2() {
    use nonholonomic::runtime::OdeSystem;
    let b = model::benchmark();
    let mut worst = 0.0_f64;
    for (v, want) in table_2() {
        let mut x0 = SVector::<f64, 11>::zeros();
        x0[10] = v / b.rR;
        let idx = [0, 1, 8, 9];
        let h = 1e-6;
        let a = SMatrix::<f64, 4, 4>::from_fn(|r, c| {
            let (mut xp, mut xm) = (x0, x0);
            xp[idx[c]] += h;
            xm[idx[c]] -= h;
            (b.rhs(0.0, &xp)[idx[r]] - b.rhs(0.0, &xm)[idx[r]]) / (2.0 * h)
        });
        let got = sorted(
            a.complex_eigenvalues()
                .iter()
                .map(|e| (e.re, e.im))
                .collect(),
        );
        worst = worst.max(worst_against(v, &got, &want, 1e-7));
    }
    eprintln!(
        "eigenvalues of the differenced right-hand side against Table 2: worst relative difference {worst:.1e}"
    );
}

/// `jacobian`, differentiated forward through the accelerations' graph,
/// against central differences of the generated right side at 16 states
/// away from upright (lean, steer and pitch off their upright values, every
/// rate non-zero), where no term of the linearisation vanishes.
#[test]
fn the_jacobian_matches_central_differences_away_from_upright() {
    use nonholonomic::runtime::OdeSystem;
    let b = model::benchmark();
    let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
    let mut uniform = |lo: f64, hi: f64| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        lo + (hi - lo) * (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut worst = 0.0_f64;
    for _ in 0..16 {
        let x = SVector::<f64, 11>::from_fn(|i, _| match i {
            0..=7 => uniform(-0.4, 0.4),
            _ => uniform(-2.0, 2.0),
        });
        let jac = b.jacobian(0.0, &x);
        worst = worst.max(central::jacobian_deviation(|y| b.rhs(0.0, y), &jac, &x));
    }
    eprintln!("jacobian against central differences at 16 states: worst {worst:.1e}");
    assert!(worst < 1e-6, "worst deviation {worst:.1e}");
}

#[test]
fn weave_and_capsize_speeds() {
    let data = published();
    let b = model::benchmark();
    let weave = model::stability_boundary(&b, 3.0, 5.0);
    let capsize = model::stability_boundary(&b, 5.0, 7.0);
    let (w, c) = (
        data["weave_speed"].as_f64().unwrap(),
        data["capsize_speed"].as_f64().unwrap(),
    );
    eprintln!("weave {weave:.14} (published {w}), capsize {capsize:.14} (published {c})");
    assert!((weave - w).abs() < 1e-10 * w, "weave {weave} vs {w}");
    assert!((capsize - c).abs() < 1e-10 * c, "capsize {capsize} vs {c}");
}

/// A run from upright, straight ahead at speed `v`, with roll rate `p`.
fn run(
    b: &model::Whipple,
    v: f64,
    p: f64,
    t1: f64,
    samples: &[f64],
) -> (Result<Outcome<f64, 11>, SimError<f64, 11>>, Vec<f64>, f64) {
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = p;
    x0[10] = v / b.rR;
    let energy = |x: &SVector<f64, 11>| {
        b.energy(
            &x.fixed_rows::<8>(0).into_owned(),
            &x.fixed_rows::<3>(8).into_owned(),
        )
    };
    let e0 = energy(&x0);
    let (mut drift, mut rolls) = (0.0_f64, vec![f64::NAN; samples.len()]);
    let out = Dop853::new(1e-11, 1e-13).integrate_with_observer(b, 0.0, x0, t1, |t, x| {
        drift = drift.max(((energy(x) - e0) / e0).abs());
        for (k, &s) in samples.iter().enumerate() {
            if rolls[k].is_nan() && t >= s {
                rolls[k] = x[0];
            }
        }
    });
    (out, rolls, drift)
}

/// Inside the self-stable range a small roll perturbation dies out at the
/// rate of the slowest linear eigenvalue (the capsize mode at 5 m/s,
/// −0.3229/s); the energy is conserved and the front wheel stays on the
/// ground (holonomic residual) to rounding.
#[test]
fn a_perturbation_decays_at_the_linear_rate_inside_the_stable_range() {
    let b = model::benchmark();
    let (out, rolls, drift) = run(&b, 5.0, 0.005, 14.0, &[10.0, 14.0]);
    let out = out.expect("a self-stable run");
    let rate = (rolls[1] / rolls[0]).abs().ln() / 4.0;
    let linear = -0.32286642900409;
    eprintln!(
        "v = 5: roll decays at {rate:.5}/s (linear {linear}); energy drift {drift:.1e}; residual {:?}",
        out.max_residual
    );
    assert!(
        (rate - linear).abs() < 0.03 * linear.abs(),
        "{rate} vs {linear}"
    );
    assert!(drift < 1e-10, "{drift:e}");
    assert!(out.max_residual.expect("a holonomic row") <= 1e-12);
}

/// Above the capsize speed the same perturbation grows, at the capsize
/// mode's rate (+0.1027/s at 7 m/s).
#[test]
fn a_perturbation_grows_above_the_capsize_speed() {
    let b = model::benchmark();
    let (out, rolls, drift) = run(&b, 7.0, 0.005, 12.0, &[6.0, 12.0]);
    assert!(out.is_ok(), "{out:?}");
    let rate = (rolls[1] / rolls[0]).abs().ln() / 6.0;
    let linear = 0.10268170574766;
    eprintln!("v = 7: roll grows at {rate:.5}/s (linear {linear}); energy drift {drift:.1e}");
    assert!((rate - linear).abs() < 0.03 * linear, "{rate} vs {linear}");
    assert!(drift < 1e-10, "{drift:e}");
}

/// Slow (1 m/s, roll rate 0.5 rad/s), the bicycle falls. Its own chart
/// (yaw among the dependent velocities) is singular when the handlebar
/// turns across the frame (about 0.77 s), but the bicycle is not: the atlas
/// moves to another chart and the run goes on until the bicycle lies at
/// roll = ±(π/2 − 0.1), a terminal event, conserving its energy.
#[test]
fn a_slow_bicycle_keeps_falling_until_it_lies_on_the_ground() {
    let b = model::benchmark();
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = 0.5;
    x0[10] = 1.0 / b.rR;
    let energy = |x: &SVector<f64, 11>| {
        b.energy(
            &x.fixed_rows::<8>(0).into_owned(),
            &x.fixed_rows::<3>(8).into_owned(),
        )
    };
    let e0 = energy(&x0);
    let lying = std::f64::consts::FRAC_PI_2 - 0.1;
    let events = Events::new(move |_t: f64, x: &SVector<f64, 11>| {
        nalgebra::Vector1::new(lying - x[0].abs())
    })
    .direction([Direction::Falling])
    .terminal([true]);
    let hit = Dop853::new(1e-11, 1e-13)
        .integrate_with_events(&b, 0.0, x0, 10.0, &events, |_| {})
        .expect("the atlas carries the fall through the chart's singularity");
    let ev = hit.event.expect("it lies on the ground before t = 10");
    // the energy along the same run up to the event, where the state's
    // chart (chart 0) is regular enough to give the velocities
    let (mut drift, mut measured) = (0.0_f64, 0);
    Dop853::new(1e-11, 1e-13)
        .integrate_with_observer(&b, 0.0, x0, ev.t, |_, x| {
            if b.chart_regularity(0.0, x).is_some_and(|r| r.abs() > 0.05) {
                drift = drift.max(((energy(x) - e0) / e0).abs());
                measured += 1;
            }
        })
        .expect("the same run");
    eprintln!(
        "v = 1: lies at roll {:.6} at t = {:.6}; {} chart switches, {} steps; energy drift {drift:.1e} over {measured} samples",
        ev.x[0], ev.t, hit.stats.chart_switches, hit.stats.steps
    );
    for s in hit.switches.iter() {
        eprintln!(
            "  t = {:.6}: chart {} ({}) -> {} ({})",
            s.t,
            s.from,
            b.chart_name(s.from),
            s.to,
            b.chart_name(s.to)
        );
    }
    assert!((ev.x[0].abs() - lying).abs() < 1e-9, "{}", ev.x[0]);
    assert!(hit.stats.chart_switches > 0);
    assert!(drift <= 1e-9, "energy drift {drift:e}");
}

/// The nonlinear accelerations and dependent velocities at 16 states away
/// from upright (roll and steer to ±0.5 rad, rear wheel to ±20 rad/s, four
/// of them heading along ±y and −x, where cos or sin of the yaw vanishes),
/// for the benchmark's parameters and a perturbed set, against an independent
/// SymPy/mpmath derivation (`tests/data/whipple_sympy.py`: the expanded
/// Lagrangian's M and h, the contact rows' A and rates, a KKT solve at 40
/// digits).
#[test]
fn nonlinear_accelerations_agree_with_sympy() {
    let data: Value =
        serde_json::from_str(include_str!("data/whipple_nonlinear.json")).expect("valid JSON");
    let numbers = |v: &Value| -> Vec<f64> {
        v.as_array()
            .expect("an array")
            .iter()
            .map(|x| x.as_f64().expect("a number"))
            .collect()
    };
    let cases = data["cases"].as_array().expect("cases");
    assert_eq!(cases.len(), 16);
    let (mut worst_acc, mut worst_vel) = (0.0_f64, 0.0_f64);
    for case in cases {
        let p = numbers(&case["params"]);
        let b = model::Whipple::new(
            p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13],
            p[14], p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23], p[24], p[25],
        );
        let q = SVector::<f64, 8>::from_vec(numbers(&case["q"]));
        let rdot = SVector::<f64, 3>::from_vec(numbers(&case["rdot"]));
        let (qdot, qddot) = (numbers(&case["qdot"]), numbers(&case["qddot"]));
        let acc = b.accelerations(0.0, &q, &rdot);
        let scale = 1.0 + qddot.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for i in 0..3 {
            worst_acc = worst_acc.max((acc[i] - qddot[i]).abs() / scale);
        }
        let sdot = b.dependent_velocities(&q, &rdot);
        for (a, &s) in model::Whipple::<f64>::DEPENDENT.iter().enumerate() {
            worst_vel = worst_vel.max((sdot[a] - qdot[s]).abs() / (1.0 + qdot[s].abs()));
        }
    }
    eprintln!(
        "Whipple vs SymPy at 16 states: accelerations {worst_acc:.1e} (of the largest), dependent velocities {worst_vel:.1e}"
    );
    assert!(worst_acc < 1e-12, "accelerations differ by {worst_acc:e}");
    assert!(
        worst_vel < 1e-13,
        "dependent velocities differ by {worst_vel:e}"
    );
}

/// Riding north, south or west: the motion does not depend on the heading,
/// and the rear contact's velocity turns with it. The contact rows are
/// solved in the heading's frame; a static pivot on the x and y columns
/// there (cos ψ, sin ψ) would lose every digit where one of them vanishes.
#[test]
fn every_heading_gives_the_same_motion() {
    let b = model::benchmark();
    let rdot = SVector::<f64, 3>::new(0.5, -0.8, 12.0);
    let at = |yaw: f64| {
        let mut x = SVector::<f64, 11>::zeros();
        x.fixed_rows_mut::<8>(0)
            .copy_from_slice(&[0.3, -0.4, 1.0, yaw, 0.0, 0.5, 2.0, -1.0]);
        x.fixed_rows_mut::<3>(8).copy_from(&rdot);
        b.project(0.0, &mut x)
            .expect("the contact's height vanishes");
        let q = x.fixed_rows::<8>(0).into_owned();
        (
            b.accelerations(0.0, &q, &rdot),
            b.dependent_velocities(&q, &rdot),
        )
    };
    let (acc0, vel0) = at(0.0);
    let half = std::f64::consts::FRAC_PI_2;
    for yaw in [
        half,
        -half,
        std::f64::consts::PI,
        half + 1e-12,
        half - 1e-9,
        2.5,
        -2.0,
    ] {
        let (acc, vel) = at(yaw);
        assert!(
            (acc - acc0).norm() <= 1e-12 * acc0.norm(),
            "yaw {yaw}: {acc} vs {acc0}"
        );
        // DEPENDENT = yaw, pitch, front, x, y: all but (ẋ, ẏ) unchanged
        for a in 0..3 {
            assert!(
                (vel[a] - vel0[a]).abs() <= 1e-12 * (1.0 + vel0[a].abs()),
                "yaw {yaw}"
            );
        }
        let (c, s) = (yaw.cos(), yaw.sin());
        let turned = [c * vel0[3] - s * vel0[4], s * vel0[3] + c * vel0[4]];
        for (got, want) in [vel[3], vel[4]].iter().zip(turned) {
            assert!(
                (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "yaw {yaw}: {vel}"
            );
        }
    }
}
