//! Measured orders of convergence of every integrator on the analytic
//! solutions in the reference data (the Chaplygin sled and the knife edge on
//! an incline), and adaptive methods' errors tracking the requested tolerance.
#![allow(clippy::excessive_precision)] // reference values as in refdata, digit for digit
use nh_lab::systems::{ChaplyginSled, KnifeEdge};
use nonholonomic::prelude::*;

/// refdata/chaplygin_sled.json, case 2: start and the state at t = 5. (On
/// case 1 RODAS4 converges at ≈ 5.2 over every step ladder above the
/// rounding floor, a problem-specific superconvergence, so case 2 is used.)
fn sled_case() -> (ChaplyginSled, SVector<f64, 5>, f64, SVector<f64, 5>) {
    (
        ChaplyginSled::new(2.0, 0.3, 0.5),
        SVector::from([0.0, -0.9, 0.0, 0.0, 0.5]),
        5.0,
        SVector::from([
            0.92961324993113887,
            0.73859354927176042,
            0.28976384624333552,
            0.22501425223878088,
            0.13595361680168894,
        ]),
    )
}

/// refdata/knife_edge_incline.json, case 2: start and the state at t = 2.
fn knife_case() -> (KnifeEdge, SVector<f64, 5>, f64, SVector<f64, 5>) {
    (
        KnifeEdge::new(1.5, 0.2, 9.81, 0.35),
        SVector::from([0.1, -0.6, -0.2, 0.66026849192774264, 0.35]),
        2.0,
        SVector::from([
            7.6809437718780205,
            0.1,
            -1.36984671803667,
            7.1503338034971839,
            0.35,
        ]),
    )
}

/// The observed order from errors at step sizes h, h/2, h/4, ...:
/// log2(e(h)/e(h/2)) for the finest halving whose errors both lie above the
/// rounding floor (1e-13): the most asymptotic estimate the data allow.
fn observed_order(errors: &[f64]) -> f64 {
    let orders: Vec<f64> = errors
        .windows(2)
        .filter(|w| w[1] > 1e-13)
        .map(|w| (w[0] / w[1]).log2())
        .collect();
    assert!(
        !orders.is_empty(),
        "no step halving above the rounding floor: {errors:?}"
    );
    orders[orders.len() - 1]
}

/// A scene with a known solution: system, start, end time, state at the end.
type Case<S, const D: usize> = (S, SVector<f64, D>, f64, SVector<f64, D>);

fn check_order<S, const D: usize>(
    name: &str,
    theory: f64,
    steps: &[f64],
    case: &Case<S, D>,
    mut integrate: impl FnMut(
        f64,
        &S,
        SVector<f64, D>,
        f64,
    ) -> Result<Outcome<f64, D>, SimError<f64, D>>,
) {
    let (sys, x0, t1, reference) = (&case.0, case.1, case.2, &case.3);
    let errors: Vec<f64> = steps
        .iter()
        .map(|&h| {
            let out =
                integrate(h, sys, x0, t1).unwrap_or_else(|e| panic!("{name} at h = {h}: {e}"));
            (out.x - reference).amax()
        })
        .collect();
    let order = observed_order(&errors);
    let shown: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
    println!(
        "{name}: errors [{}], observed order {order:.2} (theory {theory})",
        shown.join(", ")
    );
    assert!(
        (order - theory).abs() <= 0.3,
        "{name}: order {order:.2}, expected {theory} ± 0.3"
    );
}

macro_rules! orders_on {
    ($case:expr, $label:literal, $dop853:expr) => {{
        let case = $case;
        check_order(
            concat!($label, ": Rk4"),
            4.0,
            &[0.1, 0.05, 0.025, 0.0125],
            &case,
            |h, s, x, t| Rk4::new(h).integrate(s, 0.0, x, t),
        );
        check_order(
            concat!($label, ": Dopri5"),
            5.0,
            &[0.1, 0.05, 0.025, 0.0125],
            &case,
            |h, s, x, t| {
                Dopri5::new(1.0, 1.0)
                    .with_fixed_step(h)
                    .integrate(s, 0.0, x, t)
            },
        );
        check_order(
            concat!($label, ": Dop853"),
            8.0,
            $dop853,
            &case,
            |h, s, x, t| {
                Dop853::new(1.0, 1.0)
                    .with_fixed_step(h)
                    .integrate(s, 0.0, x, t)
            },
        );
        check_order(
            concat!($label, ": Rodas4"),
            4.0,
            &[0.4, 0.2, 0.1, 0.05, 0.025, 0.0125],
            &case,
            |h, s, x, t| {
                Rodas4::new(1.0, 1.0)
                    .with_fixed_step(h)
                    .integrate_with_jacobian(s, 0.0, x, t)
            },
        );
        check_order(
            concat!($label, ": Rodas5P"),
            5.0,
            &[0.4, 0.2, 0.1, 0.05, 0.025],
            &case,
            |h, s, x, t| {
                Rodas5P::new(1.0, 1.0)
                    .with_fixed_step(h)
                    .integrate_with_jacobian(s, 0.0, x, t)
            },
        );
        check_order(
            concat!($label, ": GaussLegendre4"),
            4.0,
            &[0.1, 0.05, 0.025, 0.0125],
            &case,
            |h, s, x, t| GaussLegendre4::new(h).integrate_with_jacobian(s, 0.0, x, t),
        );
    }};
}

#[test]
fn orders_on_the_chaplygin_sled() {
    orders_on!(sled_case(), "sled", &[1.25, 0.625, 0.3125, 0.15625]);
}

#[test]
fn orders_on_the_knife_edge() {
    orders_on!(knife_case(), "knife edge", &[1.0, 0.5, 0.25, 0.125]);
}

/// The relative final-time errors of the four adaptive methods at `rtol`,
/// `atol` on one case, labelled `"{label} {method}"`.
fn adaptive_errors<S: OdeJacobian<f64, D>, const D: usize>(
    label: &str,
    (sys, x0, t1, reference): &(S, SVector<f64, D>, f64, SVector<f64, D>),
    rtol: f64,
    atol: f64,
) -> Vec<(String, f64)> {
    let scale = reference.amax().max(1.0);
    let error = |x: SVector<f64, D>| (x - reference).amax() / scale;
    let dp = Dopri5::new(rtol, atol).integrate(sys, 0.0, *x0, *t1);
    let dop = Dop853::new(rtol, atol).integrate(sys, 0.0, *x0, *t1);
    let rodas = Rodas4::new(rtol, atol).integrate_with_jacobian(sys, 0.0, *x0, *t1);
    let rodas5 = Rodas5P::new(rtol, atol).integrate_with_jacobian(sys, 0.0, *x0, *t1);
    vec![
        (format!("{label} Dopri5"), error(dp.expect("dp").x)),
        (format!("{label} Dop853"), error(dop.expect("dop853").x)),
        (format!("{label} Rodas4"), error(rodas.expect("rodas").x)),
        (
            format!("{label} Rodas5P"),
            error(rodas5.expect("rodas5p").x),
        ),
    ]
}

#[test]
fn adaptive_errors_track_the_tolerance() {
    let (sled, knife) = (sled_case(), knife_case());
    for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let atol = rtol * 1e-3;
        let mut results = adaptive_errors("sled", &sled, rtol, atol);
        results.extend(adaptive_errors("knife", &knife, rtol, atol));
        for (name, err) in results {
            println!(
                "rtol {rtol:.0e}: {name} relative error {err:.2e} ({:.2} × rtol)",
                err / rtol
            );
            assert!(
                err <= 100.0 * rtol,
                "{name}: error {err:.2e} at rtol {rtol:.0e}"
            );
        }
    }
}
