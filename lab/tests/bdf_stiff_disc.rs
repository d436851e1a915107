//! The BDF integrator on the stiff disc (k = 1e6 on the lean, critically
//! damped, t ∈ [0, 1], as in `tight_tolerances.rs` and the side-by-side
//! benchmark), against the independent 16-digit reference of
//! `tests/data/stiff_disc_reference.py`.
use nh_lab::scenes::stiff_disc::{initial_state as x0, reference, system as stiff_disc};
use nonholonomic::prelude::*;

/// Right-hand sides plus Jacobians of a run.
fn evaluations(stats: &Stats) -> usize {
    stats.rhs_evals + stats.jacobian_evals
}

/// A run with the side-by-side benchmark's `atol = rtol/100`.
fn run(rtol: f64) -> Outcome<f64, 8> {
    Bdf::new(rtol, rtol * 1e-2)
        .with_max_steps(1_000_000)
        .integrate_with_jacobian(&stiff_disc(), 0.0, x0(), 1.0)
        .expect("BDF")
}

/// Measured (debug or release, the counts are the same): error / (rtol·21.2)
/// is 0.037, 0.075, 0.28, 0.78 at rtol 1e-6, 1e-8, 1e-10, 1e-12.
#[test]
fn the_error_is_within_ten_times_the_tolerance() {
    for rtol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let out = run(rtol);
        let error = (out.x - reference()).amax();
        let ratio = error / (rtol * reference().amax());
        println!(
            "rtol {rtol:.0e}: error/tolerance {ratio:.3}, {:?}",
            out.stats
        );
        assert!(ratio <= 10.0, "rtol {rtol:e}: {ratio}");
    }
}

/// What an error of 1e-6, 1e-8 and 1e-10 costs, on the benchmark's ladder
/// of tolerances (rtol = 10^(−k/4)): right-hand sides plus Jacobians (one
/// Jacobian in each of these runs: the disc's changes too little to slow
/// the Newton iteration down).
///
/// | error | rtol | error reached | evaluations | steps | diffsol's BDF (RHS, side-by-side) |
/// |---|---|---|---|---|---|
/// | 1e-6 | 1.778e-6 | 5.4e-7 | 436 | 382 | 399 |
/// | 1e-8 | 3.162e-9 | 6.2e-9 | 1,107 | 986 | 1,176 |
/// | 1e-10 | 5.623e-12 | 4.6e-11 | 3,149 | 2,611 | 2,544 |
///
/// (The side-by-side benchmark interpolates between the rungs.) About 1.1
/// to 1.2 Newton iterations, i.e. right-hand sides, per step.
#[test]
fn an_error_costs_about_what_diffsols_bdf_needs() {
    for (target, rtol, budget) in [
        (1e-6, 1.778e-6, 470),
        (1e-8, 3.162e-9, 1150),
        (1e-10, 5.623e-12, 3300),
    ] {
        let out = run(rtol);
        let error = (out.x - reference()).amax();
        let evals = evaluations(&out.stats);
        println!(
            "rtol {rtol:.2e}: error {error:.2e}, {evals} evaluations, {:?}",
            out.stats
        );
        assert!(error <= target, "rtol {rtol:e}: {error:e}");
        assert!(evals <= budget, "rtol {rtol:e}: {evals}");
        // About one Newton iteration (one right-hand side) per step.
        assert!(
            out.stats.newton_iterations * 4 <= out.stats.steps * 5,
            "{:?}",
            out.stats
        );
    }
}

/// The error levels off near 3e-12 (the rounding of the difference
/// arrays): measured error/tolerance 1.2 at rtol 1e-13 (5,596 steps), 4.3 at
/// 3e-14, 19 at 1e-14 and 118 at 3e-15, with a rejected step for every four
/// accepted. Hence `rtol ≥ 400·eps` (8.9e-14), below which a run is a typed
/// outcome before the first step.
#[test]
fn a_tolerance_below_reach_is_a_typed_outcome() {
    let rtol_min = 400.0 * f64::EPSILON;
    for rtol in [1e-14, 5e-14] {
        let r = Bdf::new(rtol, rtol * 1e-2).integrate_with_jacobian(&stiff_disc(), 0.0, x0(), 1.0);
        assert_eq!(
            r,
            Err(SimError::ToleranceTooTight {
                t: 0.0,
                x: x0(),
                rtol_min
            })
        );
    }
    let out = run(1e-13);
    let ratio = (out.x - reference()).amax() / (1e-13 * reference().amax());
    println!("rtol 1e-13: error/tolerance {ratio:.2}, {:?}", out.stats);
    assert!(ratio <= 10.0, "{ratio}");
}
