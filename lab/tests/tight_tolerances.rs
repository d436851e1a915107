//! The Rosenbrock methods at tight tolerances on the stiff disc (k = 1e6 on
//! the lean, critically damped, t ∈ [0, 1], as in the work-precision report),
//! against an independent 16-digit reference: the final error follows the
//! tolerance down to rtol 1e-13, a tolerance below the methods' reach is a
//! typed outcome, and an error of 1e-9 costs at most 2,000 evaluations.
use nh_lab::scenes::stiff_disc::{State, initial_state as x0, reference, system as stiff_disc};
use nonholonomic::prelude::*;

/// The final error relative to `rtol` times the largest component.
fn error_over_tolerance(x: &State, rtol: f64) -> f64 {
    let r = reference();
    (x - r).amax() / (rtol * r.amax())
}

/// Measured (release, this reference, atol = rtol/100): error / (rtol·21.2)
///
/// | rtol | RODAS4 | steps | Rodas5P | steps |
/// |---|---|---|---|---|
/// | 1e-6 | 1.6e-4 | 326 | 1.7e-2 | 108 |
/// | 1e-8 | 3.1e-4 | 1,027 | 2.3e-2 | 262 |
/// | 1e-10 | 3.6e-4 | 3,244 | 2.8e-2 | 647 |
/// | 1e-11 | 3.7e-4 | 5,768 | 3.0e-2 | 1,020 |
/// | 1e-12 | 4.8e-4 | 10,262 | 4.0e-2 | 1,623 |
/// | 1e-13 | 6.7e-3 | 18,484 | 9.2e-2 | 2,649 |
/// | 1.2e-14 | 7.0e-2 | 33,899 | 0.63 | 5,315 |
///
/// The errors level off at 1.4e-14 (RODAS4) and 1.6e-13 (Rodas5P, whose
/// larger coefficients cost more rounding), hence the `50·eps` floor.
///
/// Before the state update was compensated, RODAS4 at 1e-12 ended 6.2e-12
/// away (0.29, and 2e-11 with other settings): the sum `x + Σ m_i U_i` was
/// rounded to the ulp of `|x| ≈ 21` six times per step, with the same sign
/// step after step.
#[test]
fn the_error_follows_the_tolerance_down_to_1e_13() {
    let (sys, x0) = (stiff_disc(), x0());
    for rtol in [1e-6, 1e-8, 1e-10, 1e-12, 1e-13] {
        let atol = rtol * 1e-2;
        let rodas4 = Rodas4::new(rtol, atol)
            .with_max_steps(1_000_000)
            .integrate_with_jacobian(&sys, 0.0, x0, 1.0)
            .expect("RODAS4");
        let rodas5 = Rodas5P::new(rtol, atol)
            .with_max_steps(1_000_000)
            .integrate_with_jacobian(&sys, 0.0, x0, 1.0)
            .expect("Rodas5P");
        let (e4, e5) = (
            error_over_tolerance(&rodas4.x, rtol),
            error_over_tolerance(&rodas5.x, rtol),
        );
        println!(
            "rtol {rtol:.0e}: RODAS4 error/tolerance {e4:.1e} ({} steps), Rodas5P {e5:.1e} ({} steps)",
            rodas4.stats.steps, rodas5.stats.steps
        );
        assert!(e4 <= 10.0 && e5 <= 10.0, "rtol {rtol:e}: {e4:e}, {e5:e}");
    }
}

#[test]
fn a_tolerance_below_reach_is_a_typed_outcome() {
    let (sys, x0) = (stiff_disc(), x0());
    let rtol_min = 50.0 * f64::EPSILON;
    for rtol in [1e-15, 5e-15] {
        let expected = Err(SimError::ToleranceTooTight {
            t: 0.0,
            x: x0,
            rtol_min,
        });
        let rodas4 = Rodas4::new(rtol, 1e-17).integrate_with_jacobian(&sys, 0.0, x0, 1.0);
        let rodas5 = Rodas5P::new(rtol, 1e-17).integrate_with_jacobian(&sys, 0.0, x0, 1.0);
        assert_eq!(rodas4, expected);
        assert_eq!(rodas5, expected);
    }
    // At the smallest tolerance accepted, the error is still within 10×.
    let out = Rodas5P::new(rtol_min, rtol_min * 1e-2)
        .with_max_steps(1_000_000)
        .integrate_with_jacobian(&sys, 0.0, x0, 1.0)
        .expect("Rodas5P at rtol_min");
    let ratio = error_over_tolerance(&out.x, rtol_min);
    println!(
        "Rodas5P at rtol {rtol_min:.1e}: error/tolerance {ratio:.2}, {:?}",
        out.stats
    );
    assert!(ratio <= 10.0, "{ratio}");
}

/// Right-hand sides plus Jacobians (the generated analytic one) of a run.
fn evaluations(stats: &Stats) -> usize {
    stats.rhs_evals + stats.jacobian_evals
}

#[test]
fn an_error_of_1e_9_costs_at_most_2000_evaluations() {
    let (sys, x0) = (stiff_disc(), x0());
    let rodas4 = Rodas4::new(5e-8, 5e-7)
        .integrate_with_jacobian(&sys, 0.0, x0, 1.0)
        .unwrap();
    let rodas5 = Rodas5P::new(1e-9, 3e-9)
        .integrate_with_jacobian(&sys, 0.0, x0, 1.0)
        .unwrap();
    for (name, out) in [("RODAS4", rodas4), ("Rodas5P", rodas5)] {
        let error = (out.x - reference()).amax();
        println!(
            "{name}: error {error:.2e} with {} evaluations ({} right-hand sides, {} Jacobians, {} steps)",
            evaluations(&out.stats),
            out.stats.rhs_evals,
            out.stats.jacobian_evals,
            out.stats.steps
        );
        assert!(error <= 1e-9, "{name}: {error:e}");
        assert!(evaluations(&out.stats) <= 2000, "{name}: {:?}", out.stats);
    }
    // The disc's equations do not depend on t: no evaluation goes to ∂f/∂t.
    // An attempt costs its stages but the first (5 or 7), an accepted step
    // f at its end and a Jacobian; the start f(t0, x0) and the probe of the
    // initial step.
    for (stages, s) in [(6, rodas4.stats), (8, rodas5.stats)] {
        assert_eq!(
            s.rhs_evals,
            (stages - 1) * (s.steps + s.rejected) + s.steps + 2
        );
        assert_eq!(s.jacobian_evals, s.steps);
    }
}
