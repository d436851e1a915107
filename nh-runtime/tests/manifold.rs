//! The system hooks every integrator honours through the step driver:
//! projection onto holonomic constraints after accepted steps, the reported
//! constraint residual, and singular charts ending in a typed
//! `SimError::Singular` with the last good state.
use nalgebra::{SVector, Vector1, Vector2, Vector4};
use nh_runtime::{
    AutoSwitch, Bdf, ControlledSystem, Dop853, Dopri5, Driven, GaussLegendre4, Integrator,
    OdeJacobian, OdeSystem, Outcome, ProjectionFailure, Rk4, Rodas4, Rodas5P, SimError,
    Singularity,
};

const G: f64 = 9.81;
const L: f64 = 1.3;

/// A planar pendulum in Cartesian coordinates, x = [x, y, ẋ, ẏ], with the rod
/// force from the twice-differentiated constraint x² + y² = l²: the index-1
/// form, whose solutions drift off the circle unless projected.
struct CartesianPendulum;

impl CartesianPendulum {
    fn tension_over_mass(x: &Vector4<f64>) -> f64 {
        (x[2] * x[2] + x[3] * x[3] - G * x[1]) / (L * L)
    }
}

impl OdeSystem<f64, 4> for CartesianPendulum {
    fn rhs(&self, _t: f64, x: &Vector4<f64>) -> Vector4<f64> {
        let lam = Self::tension_over_mass(x);
        Vector4::new(x[2], x[3], -lam * x[0], -G - lam * x[1])
    }

    fn constraint_residual(&self, _t: f64, x: &Vector4<f64>) -> Option<f64> {
        let position = (x[0] * x[0] + x[1] * x[1] - L * L).abs();
        let velocity = (x[0] * x[2] + x[1] * x[3]).abs();
        Some(position.max(velocity))
    }

    fn project(&self, _t: f64, x: &mut Vector4<f64>) -> Result<bool, ProjectionFailure<f64>> {
        let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
        let (ex, ey) = (x[0] / r, x[1] / r);
        let radial = x[2] * ex + x[3] * ey;
        *x = Vector4::new(L * ex, L * ey, x[2] - radial * ex, x[3] - radial * ey);
        Ok(true)
    }
}

impl OdeJacobian<f64, 4> for CartesianPendulum {
    fn jacobian(&self, t: f64, x: &Vector4<f64>) -> nalgebra::Matrix4<f64> {
        central_differences(self, t, x)
    }
}

fn central_differences<S: OdeSystem<f64, D>, const D: usize>(
    s: &S,
    t: f64,
    x: &SVector<f64, D>,
) -> nalgebra::SMatrix<f64, D, D> {
    let mut j = nalgebra::SMatrix::<f64, D, D>::zeros();
    for i in 0..D {
        let h = 1e-6 * x[i].abs().max(1.0);
        let (mut a, mut b) = (*x, *x);
        a[i] += h;
        b[i] -= h;
        j.set_column(i, &((s.rhs(t, &a) - s.rhs(t, &b)) / (2.0 * h)));
    }
    j
}

/// The angle from the downward vertical, θ̈ = −(g/l) sin θ, as reference.
fn angle_reference(theta0: f64, t1: f64) -> f64 {
    let f = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -G / L * x[0].sin());
    Dopri5::new(1e-13, 1e-14)
        .integrate(&f, 0.0, Vector2::new(theta0, 0.0), t1)
        .unwrap()
        .x[0]
}

fn pendulum_start(theta0: f64) -> Vector4<f64> {
    Vector4::new(L * theta0.sin(), -L * theta0.cos(), 0.0, 0.0)
}

fn angle(out: &Outcome<f64, 4>) -> f64 {
    out.x[0].atan2(-out.x[1])
}

#[test]
fn projection_keeps_the_pendulum_on_its_circle_in_every_integrator() {
    let x0 = pendulum_start(1.0);
    let sys = CartesianPendulum;
    let t1 = 100.0;
    let runs: [(&str, Outcome<f64, 4>); 8] = [
        ("Rk4", Rk4::new(1e-3).integrate(&sys, 0.0, x0, t1).unwrap()),
        (
            "Dopri5",
            Dopri5::new(1e-9, 1e-11)
                .integrate(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            "Dop853",
            Dop853::new(1e-9, 1e-11)
                .integrate(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            "Rodas4",
            Rodas4::new(1e-7, 1e-9)
                .integrate_with_jacobian(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            "Rodas5P",
            Rodas5P::new(1e-7, 1e-9)
                .integrate_with_jacobian(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            // Projected after every step (the projection always reports a
            // move): it used to restart at order 1 each time, with 0.9× the
            // step, and end in StepSizeTooSmall at t = 1.1e-6.
            "Bdf",
            Bdf::new(1e-9, 1e-11)
                .integrate_with_jacobian(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            "GaussLegendre4",
            GaussLegendre4::new(2e-3)
                .integrate(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
        (
            "AutoSwitch",
            AutoSwitch::new(1e-8, 1e-10)
                .integrate(&sys, 0.0, x0, t1)
                .unwrap(),
        ),
    ];
    let reference = angle_reference(1.0, t1);
    for (name, out) in runs {
        let residual = out.max_residual.unwrap();
        assert!(residual <= 1e-12, "{name}: residual {residual:e}");
        let err = (angle(&out) - reference).abs();
        println!(
            "{name}: residual {residual:.1e}, angle error {err:.1e}, {} steps",
            out.stats.steps
        );
        assert!(err < 1e-6, "{name}: angle {} vs {reference}", angle(&out));
    }
}

#[test]
fn bdf_keeps_its_history_through_projections_within_the_tolerance() {
    // The pendulum's projection moves every accepted state (by rounding
    // at least, and by the step's error): Bdf keeps its differences, the
    // polynomial shifted by the correction, so the run costs what it costs
    // unprojected (no restart: the one Jacobian of the start) and ends
    // closer to the reference. Before, every step restarted at order 1
    // with 0.9× the step: StepSizeTooSmall at t = 1.1e-5 after 299 steps
    // (rtol 1e-7).
    let x0 = pendulum_start(1.0);
    let sys = CartesianPendulum;
    let t1 = 100.0;
    let reference = angle_reference(1.0, t1);
    for (rtol, atol) in [(1e-7, 1e-9), (1e-9, 1e-11)] {
        let on = Bdf::new(rtol, atol)
            .integrate_with_jacobian(&sys, 0.0, x0, t1)
            .unwrap();
        let off = Bdf::new(rtol, atol)
            .with_projection(false)
            .integrate_with_jacobian(&sys, 0.0, x0, t1)
            .unwrap();
        let (err_on, err_off) = (
            (angle(&on) - reference).abs(),
            (angle(&off) - reference).abs(),
        );
        println!(
            "Bdf {rtol:e}: projected {} steps, error {err_on:.1e}; unprojected {} steps, error {err_off:.1e}",
            on.stats.steps, off.stats.steps
        );
        assert_eq!(on.stats.jacobian_evals, off.stats.jacobian_evals);
        assert!(on.stats.steps as f64 <= 1.1 * off.stats.steps as f64);
        assert!(err_on < err_off, "{err_on:e} vs {err_off:e}");
        assert!(on.max_residual.unwrap() <= 1e-12);
    }
    // A start 1 % off the circle: the first projection moves the state far
    // beyond the tolerance, so Bdf restarts there (the Jacobian again) and
    // goes on.
    let off_circle = x0 * 1.01;
    let out = Bdf::new(1e-9, 1e-11)
        .integrate_with_jacobian(&sys, 0.0, off_circle, t1)
        .unwrap();
    assert_eq!(out.stats.jacobian_evals, 2);
    assert!((angle(&out) - reference).abs() < 1e-6);
}

#[test]
fn without_projection_the_drift_is_reported_not_hidden() {
    let x0 = pendulum_start(1.0);
    let sys = CartesianPendulum;
    let out = Dopri5::new(1e-6, 1e-8)
        .with_projection(false)
        .integrate(&sys, 0.0, x0, 100.0)
        .unwrap();
    let drift = out.max_residual.unwrap();
    let direct = sys.constraint_residual(out.t, &out.x).unwrap();
    assert!(
        drift >= direct && drift > 1e-6,
        "drift {drift:e}, final {direct:e}"
    );
    let projected = Dopri5::new(1e-6, 1e-8)
        .integrate(&sys, 0.0, x0, 100.0)
        .unwrap();
    assert!(projected.max_residual.unwrap() <= 1e-12);
}

#[test]
fn a_projection_restarts_the_method_at_the_projected_state() {
    // First same as last no longer holds after a projection: the derivative
    // at the projected state costs one more evaluation per step.
    let x0 = pendulum_start(0.5);
    let sys = CartesianPendulum;
    let mut on = Dopri5::new(1e-8, 1e-10);
    let a = on.integrate(&sys, 0.0, x0, 2.0).unwrap();
    let b = Dopri5::new(1e-8, 1e-10)
        .with_projection(false)
        .integrate(&sys, 0.0, x0, 2.0)
        .unwrap();
    let per_step = |o: &Outcome<f64, 4>| o.stats.rhs_evals as f64 / o.stats.steps as f64;
    assert!(
        per_step(&a) > per_step(&b) + 0.9,
        "{} vs {}",
        per_step(&a),
        per_step(&b)
    );
    assert!(b.max_residual.unwrap() > a.max_residual.unwrap());
}

/// A system whose chart is singular at θ = π/2: θ̇ = 1, and a coordinate
/// computed through the chart, ẏ = tan θ (y = −ln cos θ).
struct Chart;

impl OdeSystem<f64, 2> for Chart {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(1.0, x[0].tan())
    }

    fn chart_regularity(&self, _t: f64, x: &Vector2<f64>) -> Option<f64> {
        Some(x[0].cos())
    }
}

impl OdeJacobian<f64, 2> for Chart {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(0.0, 0.0, 1.0 / x[0].cos().powi(2), 0.0)
    }
}

fn assert_chart_singular(name: &str, r: Result<Outcome<f64, 2>, SimError<f64, 2>>) {
    match r {
        Err(SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        }) => {
            assert!(x.iter().all(|v| v.is_finite()), "{name}: {x}");
            assert!(
                t < std::f64::consts::FRAC_PI_2 && t > 1.4,
                "{name}: t = {t}"
            );
            assert!(x[0] < std::f64::consts::FRAC_PI_2, "{name}: θ = {}", x[0]);
        }
        other => panic!("{name}: expected a singular chart, got {other:?}"),
    }
}

#[test]
fn a_singular_chart_ends_every_integrator_with_the_last_good_state() {
    let x0 = Vector2::new(0.0, 0.0);
    let t1 = 3.0;
    assert_chart_singular("Rk4", Rk4::new(0.01).integrate(&Chart, 0.0, x0, t1));
    assert_chart_singular("Rk4 coarse", Rk4::new(0.25).integrate(&Chart, 0.0, x0, t1));
    assert_chart_singular(
        "Dopri5",
        Dopri5::new(1e-8, 1e-10).integrate(&Chart, 0.0, x0, t1),
    );
    assert_chart_singular(
        "Dop853",
        Dop853::new(1e-10, 1e-12).integrate(&Chart, 0.0, x0, t1),
    );
    assert_chart_singular(
        "Rodas4",
        Rodas4::new(1e-6, 1e-8).integrate_with_jacobian(&Chart, 0.0, x0, t1),
    );
    assert_chart_singular(
        "Rodas4 (finite differences)",
        Rodas4::new(1e-6, 1e-8).integrate(&Chart, 0.0, x0, t1),
    );
    assert_chart_singular(
        "GaussLegendre4",
        GaussLegendre4::new(0.05).integrate(&Chart, 0.0, x0, t1),
    );
    assert_chart_singular(
        "Dopri5 fixed step",
        Dopri5::new(1e-8, 1e-10)
            .with_fixed_step(0.3)
            .integrate(&Chart, 0.0, x0, t1),
    );
}

#[test]
fn a_start_on_a_singular_chart_is_refused() {
    let x0 = Vector2::new(std::f64::consts::FRAC_PI_2, 0.0);
    let err = Dopri5::new(1e-8, 1e-10)
        .integrate(&Chart, 0.0, x0, 1.0)
        .unwrap_err();
    assert!(matches!(
        err,
        SimError::Singular {
            t: 0.0,
            cause: Singularity::Chart,
            ..
        }
    ));
    assert!(err.to_string().contains("chart is singular"), "{err}");
}

/// A projection that cannot converge.
struct Unprojectable;

impl OdeSystem<f64, 1> for Unprojectable {
    fn rhs(&self, _t: f64, _x: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(1.0)
    }

    fn project(&self, _t: f64, x: &mut Vector1<f64>) -> Result<bool, ProjectionFailure<f64>> {
        if x[0] > 0.5 {
            Err(ProjectionFailure { residual: x[0] })
        } else {
            Ok(false)
        }
    }
}

#[test]
fn a_failed_projection_is_a_typed_error_with_the_last_good_state() {
    let err = Rk4::new(0.1)
        .integrate(&Unprojectable, 0.0, Vector1::new(0.0), 1.0)
        .unwrap_err();
    match err {
        SimError::ProjectionFailed { t, x, residual } => {
            assert!(
                (t - 0.5).abs() < 1e-12 && (x[0] - 0.5).abs() < 1e-12,
                "{t} {x}"
            );
            assert!((residual - 0.6).abs() < 1e-12);
        }
        other => panic!("expected ProjectionFailed, got {other:?}"),
    }
    // with projection off, nothing is projected and the run succeeds
    let out = Rk4::new(0.1)
        .with_projection(false)
        .integrate(&Unprojectable, 0.0, Vector1::new(0.0), 1.0)
        .unwrap();
    assert!((out.x[0] - 1.0).abs() < 1e-12);
    assert_eq!(out.max_residual, None);
}

/// The chart test through the input adapter.
struct SteeredChart;

impl ControlledSystem<f64, 2, 1> for SteeredChart {
    fn rhs_with_input(&self, t: f64, x: &Vector2<f64>, u: &Vector1<f64>) -> Vector2<f64> {
        Chart.rhs(t, x) * u[0]
    }

    fn chart_regularity(&self, t: f64, x: &Vector2<f64>) -> Option<f64> {
        Chart.chart_regularity(t, x)
    }
}

#[test]
fn the_input_adapter_forwards_the_hooks() {
    let driven = Driven::new(&SteeredChart, Vector1::new(1.0));
    assert_chart_singular(
        "Driven",
        Dopri5::new(1e-8, 1e-10).integrate(&driven, 0.0, Vector2::zeros(), 3.0),
    );
}
