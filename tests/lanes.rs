//! Lanes (DESIGN §6.8): the bicycle's generated methods at four states per
//! call, with `T = WideF64x4`, agree lane by lane with the scalar methods
//! at each state; `Rk4::integrate_lanes` follows the scalar `Rk4` of each
//! lane's state, and a lane that fails stops at its last good state while
//! the others finish.
#[path = "../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)] // the linearisation helpers are tests/whipple.rs's
mod model;

use nonholonomic::nalgebra::SimdValue;
use nonholonomic::prelude::*;
use nonholonomic::runtime::{LaneSystem, WideF64x4};

type L = WideF64x4;

/// Four states about upright running at 4.6, 5, 5.5 and 5.9 m/s (in the
/// self-stable window), leaning, steered and pitched as the holonomic
/// contact requires.
fn states() -> [SVector<f64, 11>; 4] {
    let b = model::benchmark();
    let speeds = [4.6, 5.0, 5.5, 5.9];
    core::array::from_fn(|i| {
        let v = speeds[i];
        let mut x = SVector::<f64, 11>::zeros();
        let q = [
            0.02 * i as f64 - 0.03,
            0.02 - 0.01 * i as f64,
            0.3,
            0.2 * i as f64,
        ];
        x.fixed_rows_mut::<4>(0).copy_from_slice(&q);
        x[4] = 0.0;
        x.fixed_rows_mut::<3>(8)
            .copy_from_slice(&[0.2, -0.1 + 0.05 * i as f64, v / 0.3]);
        b.project(0.0, &mut x)
            .expect("the front contact touches the ground");
        x
    })
}

/// The four states as one state of lanes.
fn in_lanes<const D: usize>(x: &[SVector<f64, D>; 4]) -> SVector<L, D> {
    SVector::from_fn(|r, _| L::from([x[0][r], x[1][r], x[2][r], x[3][r]]))
}

/// The largest difference between lane `i` of `lanes` and `scalar`,
/// relative to the largest entry of `scalar` (at least 1).
fn lane_error<const R: usize, const C: usize>(
    lanes: &SMatrix<L, R, C>,
    i: usize,
    scalar: &SMatrix<f64, R, C>,
) -> f64 {
    let scale = scalar.amax().max(1.0);
    let lane = lanes.map(|v| v.extract(i));
    (lane - scalar).amax() / scale
}

#[test]
fn methods_agree_lane_by_lane_with_the_scalar_ones() {
    let (b, bl) = (model::benchmark(), model::benchmark_in::<L>());
    let xs = states();
    let x = in_lanes(&xs);
    let (q, rdot) = (
        x.fixed_rows::<8>(0).into_owned(),
        x.fixed_rows::<3>(8).into_owned(),
    );
    let t = L::from([0.0; 4]);
    let (acc, sdot, jac) = (
        bl.accelerations(t, &q, &rdot),
        bl.dependent_velocities(&q, &rdot),
        bl.jacobian(t, &x),
    );
    let (mass, energy, rhs) = (bl.mass_matrix(&q), bl.energy(&q, &rdot), bl.lane_rhs(t, &x));
    let mut worst = [0.0f64; 6];
    for (i, xi) in xs.iter().enumerate() {
        let (qi, ri) = (
            xi.fixed_rows::<8>(0).into_owned(),
            xi.fixed_rows::<3>(8).into_owned(),
        );
        let errors = [
            lane_error(&acc, i, &b.accelerations(0.0, &qi, &ri)),
            lane_error(&sdot, i, &b.dependent_velocities(&qi, &ri)),
            lane_error(&jac, i, &b.jacobian(0.0, xi)),
            lane_error(&mass, i, &b.mass_matrix(&qi)),
            (energy.extract(i) - b.energy(&qi, &ri)).abs() / b.energy(&qi, &ri).abs(),
            lane_error(&rhs, i, &OdeSystem::rhs(&b, 0.0, xi)),
        ];
        for (w, e) in worst.iter_mut().zip(errors) {
            *w = w.max(e);
        }
    }
    eprintln!(
        "lanes vs scalar (accelerations, dependent velocities, jacobian, mass matrix, energy, rhs): {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    // the lanes' sin and cos are polynomials of their own (about 1 ulp):
    // the results agree to rounding, not bit for bit
    for (name, e) in [
        "accelerations",
        "dependent velocities",
        "jacobian",
        "mass matrix",
        "energy",
        "rhs",
    ]
    .iter()
    .zip(worst)
    {
        assert!(
            e < 1e-12,
            "{name}: lanes differ from the scalar method by {e:e}"
        );
    }
}

#[test]
fn rk4_in_lanes_follows_the_scalar_rk4_of_each_lane() {
    let (b, bl) = (model::benchmark(), model::benchmark_in::<L>());
    let xs = states();
    let (h, t1) = (0.005, 3.0);
    let out = Rk4::new(h)
        .integrate_lanes(&bl, 0.0, in_lanes(&xs), t1)
        .expect("valid settings");
    assert_eq!(out.stats.steps, 600);
    let mut worst = 0.0f64;
    for (i, xi) in xs.iter().enumerate() {
        let scalar = Rk4::new(h)
            .with_projection(false)
            .integrate(&b, 0.0, *xi, t1)
            .expect("the scalar run finishes");
        assert!(scalar.switches.is_empty());
        let (t, x) = out.lane(i).expect("every lane finishes");
        assert_eq!(t, t1);
        worst = worst.max((x - scalar.x).amax() / scalar.x.amax());
    }
    eprintln!("Rk4 in lanes vs scalar Rk4 over {t1} s: {worst:.1e} (relative)");
    assert!(
        worst < 1e-10,
        "lanes drift from the scalar runs by {worst:e}"
    );
}

#[test]
fn a_failing_lane_stops_at_its_last_good_state_and_the_others_finish() {
    let bl = model::benchmark_in::<L>();
    let mut xs = states();
    // lane 2 starts with a velocity that overflows within a few steps
    xs[2][10] = 1e200;
    let out = Rk4::new(0.01)
        .integrate_lanes(&bl, 0.0, in_lanes(&xs), 1.0)
        .expect("valid settings");
    for i in [0, 1, 3] {
        assert_eq!(out.lane(i).expect("a good lane finishes").0, 1.0);
    }
    match out.lane(2) {
        Err(SimError::NonFinite { t, x }) => {
            assert!(
                t < 1.0 && x.iter().all(|v| v.is_finite()),
                "t = {t}, x = {x}"
            );
        }
        other => panic!("lane 2 should fail as non-finite, got {other:?}"),
    }
    // nothing integrated for a step that cannot advance
    assert!(matches!(
        Rk4::new(-0.1).integrate_lanes(&bl, 0.0, in_lanes(&xs), 1.0),
        Err(SimError::InvalidInput { .. })
    ));
}

nonholonomic_system! {
    /// A rolling wheel kept upright, driven about its axle and steered:
    /// inputs in lanes.
    pub struct DrivenWheel {
        parameters { m, R, I, J, b }
        coordinates { x, y, heading, spin }
        inputs { drive, turn }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + I/2*dot(spin)^2 + J/2*dot(heading)^2;
        constraints {
            dot(x) = R*cos(heading)*dot(spin);
            dot(y) = R*sin(heading)*dot(spin);
        }
        forces { spin: drive - b*dot(spin); heading: turn; }
    }
}

/// Four rollouts of a system with inputs, each under its own input (as in
/// sampling-based control): lanes against scalar `Rk4` runs.
#[test]
fn rollouts_under_sampled_inputs_agree_with_scalar_runs() {
    use nonholonomic::runtime::LaneControlledSystem;
    let s = |v: f64| L::splat(v);
    let wheel = DrivenWheel::new(2.0, 0.3, 0.05, 0.02, 0.1);
    let lanes = DrivenWheel::new(s(2.0), s(0.3), s(0.05), s(0.02), s(0.1));
    let drives = [0.5, 1.0, -0.3, 2.0];
    let turns = [0.01, -0.02, 0.03, 0.0];
    let u = SVector::<L, 2>::new(L::from(drives), L::from(turns));
    let rollout = |t: L, x: &SVector<L, 6>| lanes.lane_rhs_with_input(t, x, &u);
    let x0 = SVector::<f64, 6>::new(0.0, 0.0, 0.2, 0.0, 0.3, 1.0);
    let out = Rk4::new(0.01)
        .integrate_lanes(&rollout, 0.0, x0.map(s), 2.0)
        .expect("valid settings");
    for i in 0..4 {
        let ui = SVector::<f64, 2>::new(drives[i], turns[i]);
        let scalar = Rk4::new(0.01)
            .with_projection(false)
            .integrate(
                &|t: f64, x: &SVector<f64, 6>| wheel.rhs_with_input(t, x, &ui),
                0.0,
                x0,
                2.0,
            )
            .expect("the scalar run finishes");
        let (_, x) = out.lane(i).expect("every lane finishes");
        let e = (x - scalar.x).amax() / scalar.x.amax();
        assert!(e < 1e-13, "lane {i} differs by {e:e}");
    }
}
