//! The stability suite (`nh_lab::stability`) at test effort: every
//! case's expected outcome is asserted, plus direct checks of the error
//! variants a controller would match on. The full-span version is
//! `cargo run --release -p nh-lab --example stability_report`.
use nh_lab::stability::{self, Effort, Kind, Method, Row};
use nh_lab::systems::{RollingDisc, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;

fn assert_rows(family: &str, rows: &[Row]) {
    println!("{}", stability::markdown_table(rows));
    assert!(!rows.is_empty(), "{family}: no rows");
    let failed: Vec<String> = rows
        .iter()
        .filter(|r| !r.pass)
        .map(|r| {
            format!(
                "{} / {}: expected {}, got {} (error {:?}, steps {}) {}",
                r.case, r.method, r.expected, r.outcome, r.error, r.steps, r.notes
            )
        })
        .collect();
    assert!(failed.is_empty(), "{family}:\n{}", failed.join("\n"));
}

#[test]
fn stiff() {
    let rows = stability::stiff(Effort::Test);
    assert_rows("stiff", &rows);
    // Rodas4 finishes accurately at every k; Rk4 at h = 1e-3 blows up
    // (typed) at k = 1e8.
    assert_eq!(
        rows.iter()
            .filter(|r| r.method.starts_with("Rodas4") && r.outcome == "Ok")
            .count(),
        4
    );
    assert!(
        rows.iter()
            .any(|r| r.case == "stiff k=1e8" && r.outcome.starts_with("NonFinite"))
    );
}

#[test]
fn stiffness_is_readable_after_an_error() {
    // Dopri5 with a budget too small for k = 1e8: MaxSteps, and the
    // stiffness flag is still available from last_stats().
    let (m, r) = (1.7, 0.35);
    let k = 1e8;
    let sys: StiffDisc = StiffDisc::new(m, r, 9.81, k, 2.0 * (k * 1.25 * m * r * r).sqrt(), 0.2);
    let x0 = stability::state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let mut dp = Dopri5::new(1e-6, 1e-9).with_max_steps(3000);
    let err = dp.integrate(&sys, 0.0, x0, 2.0).unwrap_err();
    assert!(
        matches!(err, SimError::MaxSteps { steps: 3000, .. }),
        "{err}"
    );
    assert!(err.state().unwrap().iter().all(|v| v.is_finite()));
    let stats = dp.last_stats();
    assert!(stats.stiffness_detected, "{stats:?}");
    assert_eq!(stats.steps + stats.rejected, 3000);
}

#[test]
fn fast_spin() {
    assert_rows("fast spin", &stability::fast_spin(Effort::Test));
}

#[test]
fn scale_extremes() {
    let rows = stability::scale_extremes(Effort::Test);
    assert_rows("scale extremes", &rows);
    assert!(rows.iter().all(|r| r.error.is_some_and(|e| e <= 1e-7)));
}

#[test]
fn long_horizon() {
    let rows = stability::long_horizon(Effort::Test);
    assert_rows("long horizon", &rows);
    let gauss = rows
        .iter()
        .find(|r| r.method.starts_with("GaussLegendre4"))
        .unwrap();
    assert!(gauss.error.unwrap() < 1e-6);
}

#[test]
fn near_singular() {
    let rows = stability::near_singular(Effort::Test);
    assert_rows("near-singular", &rows);
    // The guarded fall stops with a typed error, never Ok, for every method.
    let guarded: Vec<&Row> = rows
        .iter()
        .filter(|r| r.case == "fall to flat, guarded")
        .collect();
    assert_eq!(guarded.len(), 5);
    assert!(guarded.iter().all(|r| r.outcome != "Ok"));
}

#[test]
fn guarded_fall_reports_the_last_state_before_flat() {
    let sys: RollingDisc = RollingDisc::new(1.7, 0.35, 9.81);
    let guarded = stability::Guarded {
        sys: &sys,
        inside: |x: &SVector<f64, 8>| x[2].cos() > 0.0,
    };
    let x0 = stability::state([0.0, 0.0, 1.2, 0.0, 0.0], [0.0, 0.0, 0.0]);
    let err = Dopri5::new(1e-8, 1e-11)
        .integrate(&guarded, 0.0, x0, 1.0)
        .unwrap_err();
    assert!(matches!(err, SimError::NonFinite { .. }), "{err}");
    let x = err.state().unwrap();
    assert!(x.iter().all(|v| v.is_finite()));
    let half_pi = std::f64::consts::FRAC_PI_2;
    assert!(x[2] < half_pi && x[2] > half_pi - 1e-6, "{}", x[2]);
    assert!((err.time().unwrap() - 0.1866).abs() < 1e-3);
}

#[test]
fn bad_input() {
    assert_rows("bad input", &stability::bad_input(Effort::Test));
}

#[test]
fn bad_input_variants_directly() {
    let disc: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let x0 = stability::state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
    let mut nan = x0;
    nan[2] = f64::NAN;
    let kind = |r: &Result<Outcome<f64, 8>, SimError<f64, 8>>| Kind::of(r);
    let mut dp = Dopri5::new(1e-6, 1e-9);
    assert_eq!(
        kind(&dp.integrate(&disc, 0.0, nan, 1.0)),
        Kind::InvalidInput
    );
    assert_eq!(
        kind(&Dopri5::new(0.0, 1e-9).integrate(&disc, 0.0, x0, 1.0)),
        Kind::InvalidInput
    );
    assert_eq!(
        kind(&Rk4::new(-0.1).integrate(&disc, 0.0, x0, 1.0)),
        Kind::InvalidInput
    );
    let empty = dp.integrate(&disc, 2.0, x0, 2.0).unwrap();
    assert_eq!((empty.t, empty.x, empty.stats.steps), (2.0, x0, 0));
    let bad_g: ThesisDisc = ThesisDisc::new(1.7, 0.35, f64::NAN);
    let e = dp.integrate(&bad_g, 0.0, x0, 1.0).unwrap_err();
    assert_eq!(e, SimError::NonFinite { t: 0.0, x: x0 });
    // atol = 0 on a disc at rest: Ok (the runtime fix).
    let rest = SVector::<f64, 8>::zeros();
    let out = Dopri5::new(1e-6, 0.0)
        .integrate(&disc, 0.0, rest, 1.0)
        .unwrap();
    assert_eq!(out.x, rest);
    assert!(
        Dop853::new(1e-6, 0.0)
            .integrate(&disc, 0.0, rest, 1.0)
            .is_ok()
    );
    assert!(
        Rodas4::new(1e-6, 0.0)
            .integrate_with_jacobian(&disc, 0.0, rest, 1.0)
            .is_ok()
    );
}

#[test]
fn single_precision() {
    assert_rows(
        "single precision",
        &stability::single_precision(Effort::Test),
    );
}

#[test]
fn table_and_csv() {
    let rows = stability::bad_input(Effort::Test);
    let dir = std::env::temp_dir().join(format!("nh-stability-{}", std::process::id()));
    let path = dir.join("stability.csv");
    stability::write_csv(&path, &rows).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("case,expected,method,outcome,error,steps,seconds,pass,notes\n"));
    assert_eq!(text.lines().count(), rows.len() + 1);
    assert_eq!(
        stability::markdown_table(&rows).lines().count(),
        rows.len() + 2
    );
    let _ = std::fs::remove_dir_all(dir);
    // Method labels are what the table shows.
    assert_eq!(
        Method::Dopri5 {
            rtol: 1e-6,
            atol: 1e-9
        }
        .label(),
        "Dopri5 1e-6"
    );
}
