//! Automatic stiffness switching (`AutoSwitch`): where it switches, what it
//! costs and how accurate it is, against independent references.

mod common;

use common::{VDPOL_AT_2, VanDerPolTestSet};
use nalgebra::{Vector1, Vector2};
use nh_runtime::{AutoSwitch, Dopri5, Integrator, Regime, Rodas4, SimError, Switch};

/// Half the period of the relaxation oscillation in VDPOL's time, from the
/// asymptotic expansion `T = (3 − 2 ln 2) μ + 3 a μ^(−1/3)` (`a = 2.33811`,
/// the first zero of Ai(−x); Grasman, *Asymptotic Methods for Relaxation
/// Oscillations*, 1987) divided by `μ = 1000`.
fn vdpol_half_period() -> f64 {
    let mu: f64 = 1e3;
    ((3.0 - 2.0 * 2f64.ln()) * mu + 3.0 * 2.33811 * mu.powf(-1.0 / 3.0)) / mu / 2.0
}

/// `y2 − y1/(1 − y1²)`: zero on the slow manifold `f2 = 0` (up to `O(ε)`).
fn off_slow_manifold(y: &Vector2<f64>) -> f64 {
    y[1] - y[0] / (1.0 - y[0] * y[0])
}

/// The state at each switch of the last run, from the step ends.
fn states_at(switches: &[Switch<f64>], ends: &[(f64, Vector2<f64>)]) -> Vec<Vector2<f64>> {
    let at = |t: f64| {
        ends.iter()
            .find(|e| e.0 == t)
            .expect("a step ends at a switch")
            .1
    };
    switches.iter().map(|s| at(s.t)).collect()
}

#[test]
fn van_der_pol_switches_at_its_phases() {
    let y0 = Vector2::new(2.0, 0.0);
    let half = vdpol_half_period();
    for rtol in [1e-4, 1e-6, 1e-8] {
        let mut auto = AutoSwitch::new(rtol, rtol);
        let mut ends = Vec::new();
        let out = auto
            .integrate_with_jacobian_and_steps(&VanDerPolTestSet, 0.0, y0, 2.0, |s| {
                ends.push((s.t(), *s.x()))
            })
            .unwrap();
        let switches = auto.last_switches();
        let states = states_at(switches, &ends);
        let order: Vec<Regime> = switches.iter().map(|s| s.to).collect();
        println!("rtol {rtol:e}: {:?}", out.stats);
        for (s, y) in switches.iter().zip(&states) {
            println!("  {:?} at t = {:.6}, y = {:?}", s.to, s.t, y.as_slice());
        }
        // Stiff on the slow branches, explicit through the two jumps.
        use Regime::{NonStiff, Stiff};
        assert_eq!(order, [Stiff, NonStiff, Stiff, NonStiff, Stiff]);
        assert_eq!(out.stats.switches_to_stiff, 3);
        assert_eq!(out.stats.switches_to_nonstiff, 2);
        // First: as soon as the initial layer (time ~ε) has reached the
        // slow manifold.
        assert!(switches[0].t < 1e-4, "{:?}", switches[0]);
        assert!(off_slow_manifold(&states[0]).abs() < 1e-3);
        // Explicit where the slow branch approaches its fold |y1| = 1
        // (ρ(J) ≈ |1 − y1²|/ε falls), just before the jump at k·T/2.
        for (k, i) in [(1.0, 1), (2.0, 3)] {
            let (t, y1) = (switches[i].t, states[i][0]);
            assert!(t > k * half - 0.01 && t < k * half, "{t} vs {}", k * half);
            assert!(y1.abs() > 1.0 && y1.abs() < 1.1, "y1 = {y1}");
            assert_eq!(y1.signum(), if k == 1.0 { 1.0 } else { -1.0 });
        }
        // Implicit again once landed on the other slow branch, |y1| ≈ 2.
        for (k, i) in [(1.0, 2), (2.0, 4)] {
            let (t, y) = (switches[i].t, states[i]);
            assert!((t - k * half).abs() < 1e-3, "{t} vs {}", k * half);
            assert!((y[0].abs() - 2.0).abs() < 1e-3, "y1 = {}", y[0]);
            assert!(off_slow_manifold(&y).abs() < 1e-2);
        }
        // The explicit member took the jumps, the implicit one the rest.
        assert_eq!(
            out.stats.stiff_steps,
            out.stats.jacobian_evals - out.stats.switches_to_stiff + 1
        );
        let error = (out.x - Vector2::from(VDPOL_AT_2)).amax();
        assert!(error < 10.0 * rtol, "error {error:e} at rtol {rtol:e}");
    }
}

#[test]
fn van_der_pol_costs_less_than_either_member() {
    let y0 = Vector2::new(2.0, 0.0);
    for rtol in [1e-4, 1e-6, 1e-8] {
        let mut auto = AutoSwitch::new(rtol, rtol);
        let a = auto
            .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
            .unwrap();
        let r = Rodas4::new(rtol, rtol)
            .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
            .unwrap();
        let work = |s: nh_runtime::Stats| s.rhs_evals + s.jacobian_evals;
        println!(
            "rtol {rtol:e}: auto {} + {} J, Rodas4 {} + {} J",
            a.stats.rhs_evals, a.stats.jacobian_evals, r.stats.rhs_evals, r.stats.jacobian_evals
        );
        // Measured: 1815 vs 2264, 4776 vs 7477, 23791 vs 35068.
        assert!(
            work(a.stats) < work(r.stats),
            "{:?} vs {:?}",
            a.stats,
            r.stats
        );
        assert!(a.stats.jacobian_evals < r.stats.jacobian_evals / 2);
        // Dormand–Prince alone needs about 1.16 million steps (measured);
        // it does not get through in a hundred times the switching steps.
        let budget = 100 * (a.stats.steps + a.stats.rejected);
        let dp = Dopri5::new(rtol, rtol).with_max_steps(budget).integrate(
            &VanDerPolTestSet,
            0.0,
            y0,
            2.0,
        );
        assert!(matches!(dp, Err(SimError::MaxSteps { .. })), "{dp:?}");
    }
}

#[test]
fn finite_difference_jacobian_switches_alike() {
    let y0 = Vector2::new(2.0, 0.0);
    let mut auto = AutoSwitch::new(1e-6, 1e-6);
    let fd = auto.integrate(&VanDerPolTestSet, 0.0, y0, 2.0).unwrap();
    let fd_switches = auto.last_switches().to_vec();
    let an = auto
        .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
        .unwrap();
    assert_eq!(fd_switches.len(), auto.last_switches().len());
    for (a, b) in fd_switches.iter().zip(auto.last_switches()) {
        assert_eq!(a.to, b.to);
        assert!((a.t - b.t).abs() < 1e-3, "{a:?} vs {b:?}");
    }
    assert!((fd.x - an.x).amax() < 1e-5);
    // Each finite-difference Jacobian costs D = 2 right-hand sides (the
    // system is autonomous: no ∂f/∂t), otherwise the runs are alike.
    let without_jacobians = fd.stats.rhs_evals - 2 * fd.stats.jacobian_evals;
    let ratio = without_jacobians as f64 / an.stats.rhs_evals as f64;
    assert!(
        (ratio - 1.0).abs() < 0.05,
        "{:?} vs {:?}",
        fd.stats,
        an.stats
    );
}

/// Prothero–Robinson with a stiffness that rises smoothly around `t = 3`:
/// `x' = −λ(t)(x − cos t) − sin t`, `λ = 1 + 1e5·exp(−((t − 3)/0.8)⁸)`
/// (above 1e4 on `[2.2, 3.8]`, below 2 outside `[1.5, 4.5]`); the solution
/// from `x(0) = 1` is `cos t` whatever `λ` is.
fn prothero_robinson(t: f64, x: &Vector1<f64>) -> Vector1<f64> {
    let lambda = 1.0 + 1e5 * (-((t - 3.0) / 0.8).powi(8)).exp();
    Vector1::new(-lambda * (x[0] - t.cos()) - t.sin())
}

#[test]
fn a_stiff_interval_is_entered_and_left() {
    let x0 = Vector1::new(1.0);
    let mut auto = AutoSwitch::new(1e-6, 1e-9);
    let (mut at_ends, mut inside): (f64, f64) = (0.0, 0.0);
    let out = auto
        .integrate_with_steps(&prothero_robinson, 0.0, x0, 6.0, |s| {
            at_ends = at_ends.max((s.x()[0] - s.t().cos()).abs());
            let mid = 0.5 * (s.t_prev() + s.t());
            inside = inside.max((s.interpolate(mid)[0] - mid.cos()).abs());
        })
        .unwrap();
    let s = auto.last_switches();
    println!("{:?}\n{s:?}\n{at_ends:e} {inside:e}", out.stats);
    // Measured: stiff from t = 2.038 (λ ≈ 1.3e3) to 4.059 (λ ≈ 9).
    assert_eq!(s.len(), 2);
    assert_eq!(s[0].to, Regime::Stiff);
    assert!(s[0].t > 1.5 && s[0].t < 2.2, "{:?}", s[0]);
    assert_eq!(s[1].to, Regime::NonStiff);
    assert!(s[1].t > 3.8 && s[1].t < 4.5, "{:?}", s[1]);
    // Measured: 4.5e-7 at the step ends, 1.2e-5 at the midpoints (RODAS4's
    // dense output of order 3); each member's own dense output is used.
    assert!(at_ends < 1e-6, "{at_ends:e}");
    assert!(inside < 1e-4, "{inside:e}");
    // The explicit member alone would need 1.6 / 3.3e-5 ≈ 50 000 steps on
    // [2.2, 3.8]; Rodas4 alone costs more (measured 1261 vs 890 RHS).
    let ros = Rodas4::new(1e-6, 1e-9)
        .integrate(&prothero_robinson, 0.0, x0, 6.0)
        .unwrap();
    assert!(out.stats.rhs_evals < ros.stats.rhs_evals, "{:?}", ros.stats);
    assert!(out.stats.steps < 200, "{:?}", out.stats);
}

#[test]
fn a_problem_that_is_never_stiff_costs_what_dormand_prince_costs() {
    let decay = |t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0] - 0.1 * x[1] + t.sin());
    for rtol in [1e-3, 1e-6, 1e-9, 1e-12] {
        let mut auto = AutoSwitch::new(rtol, rtol * 1e-2);
        let a = auto
            .integrate(&decay, 0.0, Vector2::new(1.0, 0.0), 20.0)
            .unwrap();
        let d = Dopri5::new(rtol, rtol * 1e-2)
            .integrate(&decay, 0.0, Vector2::new(1.0, 0.0), 20.0)
            .unwrap();
        assert_eq!(a.x, d.x);
        assert_eq!(a.stats, d.stats);
        assert!(auto.last_switches().is_empty());
    }
}

#[test]
fn the_switch_log_is_per_call_and_survives_a_failure() {
    let mut auto = AutoSwitch::new(1e-6, 1e-6).with_max_steps(300);
    let y0 = Vector2::new(2.0, 0.0);
    let err = auto
        .integrate_with_jacobian(&VanDerPolTestSet, 0.0, y0, 2.0)
        .unwrap_err();
    assert!(matches!(err, SimError::MaxSteps { .. }));
    // The first switch (to stiff) happened before the budget ran out.
    assert_eq!(auto.last_switches()[0].to, Regime::Stiff);
    assert_eq!(auto.last_stats().switches_to_stiff, 1);
    auto.integrate(&|_t: f64, x: &Vector2<f64>| -x, 0.0, y0, 1.0)
        .unwrap();
    assert!(auto.last_switches().is_empty());
}
