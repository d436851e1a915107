//! Measured convergence orders and tolerance proportionality of every
//! integrator.
//!
//! Orders are measured with fixed steps (`Rk4`, `GaussLegendre4`, and the
//! `with_fixed_step` mode of `Dop853` and `Rodas4`): halving `h` divides
//! the global error by `2^p`, so `p = log2(e(h)/e(h/2))`. Fixed steps make
//! the measurement clean; with adaptive steps the error is driven by the
//! tolerance, not by `h`, and only the proportionality `error ∝ tol` can be
//! checked (second half of this file).

mod common;

use common::{Oscillator, max_err, oscillator_exact};
use nalgebra::{Matrix2, Vector2};
use nh_runtime::{Dop853, Dopri5, GaussLegendre4, Integrator, OdeJacobian, OdeSystem, Rk4, Rodas4};

/// A smooth, nonlinear, non-autonomous test problem with a closed-form
/// solution: logistic growth and `y' = y cos t`.
struct LogisticCos;

impl OdeSystem<f64, 2> for LogisticCos {
    fn rhs(&self, t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x[0] * (1.0 - x[0]), x[1] * t.cos())
    }
}

impl OdeJacobian<f64, 2> for LogisticCos {
    fn jacobian(&self, t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(1.0 - 2.0 * x[0], 0.0, 0.0, t.cos())
    }
}

const LC_X0: [f64; 2] = [0.2, 1.0];

fn logistic_cos_exact(t: f64) -> Vector2<f64> {
    let x1 = 1.0 / (1.0 + (1.0 / LC_X0[0] - 1.0) * (-t).exp());
    Vector2::new(x1, LC_X0[1] * t.sin().exp())
}

/// Observed orders from the errors at `h, h/2, h/4, …`.
fn orders(errs: &[f64]) -> Vec<f64> {
    errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn check_order(name: &str, errs: &[f64], p: f64) {
    let ps = orders(errs);
    let es: Vec<String> = errs.iter().map(|e| format!("{e:.3e}")).collect();
    println!("{name}: errors {es:?}, measured orders {ps:.3?} (theory {p})");
    for q in ps {
        assert!(
            (q - p).abs() < 0.3,
            "{name}: measured order {q:.3}, expected {p}"
        );
    }
}

/// Global errors at `t1` for the step sizes `hs` on both test problems.
fn errors(mut run: impl FnMut(f64, bool) -> Vector2<f64>, hs: &[f64], t1: f64) -> [Vec<f64>; 2] {
    let osc = hs
        .iter()
        .map(|&h| max_err(&run(h, true), &oscillator_exact(t1)))
        .collect();
    let lc = hs
        .iter()
        .map(|&h| max_err(&run(h, false), &logistic_cos_exact(t1)))
        .collect();
    [osc, lc]
}

#[test]
fn rk4_order_4() {
    let t1 = 2.0;
    let [osc, lc] = errors(
        |h, osc| {
            let mut i = Rk4::new(h);
            if osc {
                i.integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), t1)
            } else {
                i.integrate(&LogisticCos, 0.0, Vector2::from(LC_X0), t1)
            }
            .unwrap()
            .x
        },
        &[0.1, 0.05, 0.025],
        t1,
    );
    check_order("rk4 oscillator", &osc, 4.0);
    check_order("rk4 logistic/cos", &lc, 4.0);
}

#[test]
fn dop853_order_8() {
    // Errors must stay well above round-off (≥ 1e-13): large steps, and a
    // span per problem on which the error constant does not nearly cancel.
    let run = |h: f64, osc: bool, t1: f64| {
        let mut i = Dop853::new(1.0, 1.0).with_fixed_step(h);
        if osc {
            i.integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), t1)
        } else {
            i.integrate(&LogisticCos, 0.0, Vector2::from(LC_X0), t1)
        }
        .unwrap()
        .x
    };
    let [osc, _] = errors(|h, osc| run(h, osc, 8.0), &[0.8, 0.4, 0.2], 8.0);
    let [_, lc] = errors(|h, osc| run(h, osc, 2.0), &[0.5, 0.25, 0.125], 2.0);
    check_order("dop853 oscillator", &osc, 8.0);
    check_order("dop853 logistic/cos", &lc, 8.0);
}

#[test]
fn gauss_legendre_order_4() {
    let t1 = 2.0;
    let [osc, lc] = errors(
        |h, osc| {
            let mut i = GaussLegendre4::new(h);
            if osc {
                i.integrate(&Oscillator, 0.0, Vector2::new(1.0, 0.0), t1)
            } else {
                i.integrate(&LogisticCos, 0.0, Vector2::from(LC_X0), t1)
            }
            .unwrap()
            .x
        },
        &[0.2, 0.1, 0.05],
        t1,
    );
    check_order("gauss4 oscillator", &osc, 4.0);
    check_order("gauss4 logistic/cos", &lc, 4.0);
}

#[test]
fn rosenbrock_order_4() {
    // The order of a Rosenbrock method holds with the exact Jacobian; the
    // analytic one is used here (`∂f/∂t` by forward differences).
    struct Osc;
    impl OdeSystem<f64, 2> for Osc {
        fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
            Vector2::new(x[1], -x[0])
        }
    }
    impl OdeJacobian<f64, 2> for Osc {
        fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
            Matrix2::new(0.0, 1.0, -1.0, 0.0)
        }
    }
    // The `y' = y cos t` component is pre-asymptotic for h ≥ 0.1 (its error
    // constant nearly cancels there), hence the smaller steps.
    let t1 = 2.0;
    let hs = [0.05, 0.025, 0.0125];
    let [osc, lc] = errors(
        |h, osc| {
            let mut i = Rodas4::new(1.0, 1.0).with_fixed_step(h);
            if osc {
                i.integrate_with_jacobian(&Osc, 0.0, Vector2::new(1.0, 0.0), t1)
            } else {
                i.integrate_with_jacobian(&LogisticCos, 0.0, Vector2::from(LC_X0), t1)
            }
            .unwrap()
            .x
        },
        &hs,
        t1,
    );
    check_order("rodas4 oscillator", &osc, 4.0);
    check_order("rodas4 logistic/cos", &lc, 4.0);
    // With the finite-difference Jacobian the order is the same at these
    // error levels (its O(sqrt(eps)) error is far below the truncation error).
    let fd: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let out = Rodas4::new(1.0, 1.0)
                .with_fixed_step(h)
                .integrate(&LogisticCos, 0.0, Vector2::from(LC_X0), t1)
                .unwrap();
            max_err(&out.x, &logistic_cos_exact(t1))
        })
        .collect();
    check_order("rodas4 logistic/cos (fd Jacobian)", &fd, 4.0);
}

/// Global error on the oscillator over `[0, 10]` at `rtol`, `atol = rtol/100`.
fn tracking<I: Integrator<f64>>(name: &str, mut make: impl FnMut(f64) -> I) {
    let x0 = Vector2::new(1.0, 0.0);
    let exact = oscillator_exact(10.0);
    let mut prev_steps = 0;
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let out = make(rtol).integrate(&Oscillator, 0.0, x0, 10.0).unwrap();
        let err = max_err(&out.x, &exact);
        println!(
            "{name} rtol {rtol:e}: err {err:.3e} (err/rtol {:.3}), steps {}, rejected {}, rhs_evals {}",
            err / rtol,
            out.stats.steps,
            out.stats.rejected,
            out.stats.rhs_evals
        );
        assert!(
            err < 100.0 * rtol && err > rtol / 100.0,
            "{name}: err {err:e} not within a factor 100 of rtol {rtol:e}"
        );
        assert!(out.stats.steps >= prev_steps);
        prev_steps = out.stats.steps;
    }
}

#[test]
fn error_tracks_tolerance() {
    tracking("dopri5", |rtol| Dopri5::new(rtol, rtol * 1e-2));
    tracking("dop853", |rtol| Dop853::new(rtol, rtol * 1e-2));
    tracking("rodas4", |rtol| Rodas4::new(rtol, rtol * 1e-2));
}
