//! Structure preservation: the symplectic Gauss–Legendre method keeps the
//! energy of a pendulum bounded where RK4 drifts.

use nalgebra::{Matrix2, Vector2};
use nh_runtime::{GaussLegendre4, Integrator, OdeJacobian, OdeSystem, Rk4, SimError};

/// Pendulum `θ'' = −sin θ` as `(θ, ω)`.
struct Pendulum;

impl OdeSystem<f64, 2> for Pendulum {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x[1], -x[0].sin())
    }
}

impl OdeJacobian<f64, 2> for Pendulum {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(0.0, 1.0, -x[0].cos(), 0.0)
    }
}

fn energy(x: &Vector2<f64>) -> f64 {
    0.5 * x[1] * x[1] - x[0].cos()
}

/// Max |ΔE| over the first tenth of `[0, t1]` and over all of it, and the
/// final |ΔE|.
fn energy_errors<I: Integrator<f64>>(i: &mut I, t1: f64) -> (f64, f64, f64) {
    let x0 = Vector2::new(1.0, 0.0);
    let e0 = energy(&x0);
    let (mut first, mut all) = (0.0f64, 0.0f64);
    let out = i
        .integrate_with_observer(&Pendulum, 0.0, x0, t1, |t, x| {
            let de = (energy(x) - e0).abs();
            all = all.max(de);
            if t <= 0.1 * t1 {
                first = first.max(de);
            }
        })
        .unwrap();
    (first, all, (energy(&out.x) - e0).abs())
}

#[test]
fn gauss_energy_bounded_over_10000_periods_rk4_drifts() {
    // Amplitude 1 rad: period ≈ 6.74, so 1e4 periods ≈ 6.74e4 time units,
    // 6.74e5 steps of h = 0.1.
    let t1 = 6.74e4;
    let mut gauss = GaussLegendre4::new(0.1);
    let (g_first, g_all, g_final) = energy_errors(&mut gauss, t1);
    let s = gauss.last_stats();
    println!(
        "gauss4: max |ΔE| first 10% {g_first:.3e}, all {g_all:.3e}, final {g_final:.3e}; {s:?}, {:.2} Newton iterations/step",
        s.newton_iterations as f64 / s.steps as f64
    );
    let (r_first, r_all, r_final) = energy_errors(&mut Rk4::new(0.1), t1);
    println!("rk4:    max |ΔE| first 10% {r_first:.3e}, all {r_all:.3e}, final {r_final:.3e}");

    // Bounded: the error over the whole run is that of the first tenth (no
    // linear growth), and small.
    assert!(g_all < 1e-6, "{g_all:e}");
    assert!(
        g_all < 1.5 * g_first,
        "{g_all:e} vs {g_first:e}: energy drifts"
    );
    // RK4 drifts linearly: ten times the time, about ten times the error.
    assert!(r_all > 5.0 * r_first, "{r_all:e} vs {r_first:e}");
    assert!(r_final > 10.0 * g_all, "rk4 {r_final:e} vs gauss {g_all:e}");
}

#[test]
fn gauss_analytic_jacobian_matches_finite_differences() {
    let x0 = Vector2::new(1.0, 0.0);
    let mut g = GaussLegendre4::new(0.05);
    let a = g.integrate_with_jacobian(&Pendulum, 0.0, x0, 50.0).unwrap();
    let f = g.integrate(&Pendulum, 0.0, x0, 50.0).unwrap();
    println!("analytic {:?}\nfd       {:?}", a.stats, f.stats);
    assert!((a.x - f.x).amax() < 1e-11, "{}", (a.x - f.x).amax());
    assert_eq!(a.stats.steps, 1000);
    assert!(a.stats.jacobian_evals >= 1 && a.stats.jacobian_evals <= a.stats.steps);
    assert_eq!(
        a.stats.rhs_evals,
        1 + a.stats.steps + 2 * a.stats.newton_iterations
    );
}

#[test]
fn gauss_failure_modes() {
    // Newton cannot converge for a stiff decay with a huge step (the
    // stage equations are fine, but simplified Newton with a frozen J works
    // on linear problems in one iteration, so use a nonlinear blow-up).
    let blow_up = |_t: f64, x: &nalgebra::Vector1<f64>| x.component_mul(x);
    let e = GaussLegendre4::new(0.5)
        .integrate(&blow_up, 0.0, nalgebra::Vector1::new(1.0), 2.0)
        .unwrap_err();
    println!("blow-up: {e:?}: {e}");
    assert!(matches!(
        e,
        SimError::NoConvergence { h: 0.5, .. } | SimError::NonFinite { .. }
    ));
    if matches!(e, SimError::NoConvergence { .. }) {
        let message = e.to_string();
        assert!(message.contains("did not converge"), "{message}");
        assert!(message.contains("reduce h"), "{message}");
    }
    assert!(e.time().unwrap() < 1.0);
    assert!(e.state().unwrap()[0].is_finite());

    // A Jacobian making Δ = I − (h/2)J + (h²/12)J² singular is impossible
    // for real eigenvalues; a NaN Jacobian reports NonFinite at t0.
    struct NanJac;
    impl OdeSystem<f64, 1> for NanJac {
        fn rhs(&self, _t: f64, x: &nalgebra::Vector1<f64>) -> nalgebra::Vector1<f64> {
            -x
        }
    }
    impl OdeJacobian<f64, 1> for NanJac {
        fn jacobian(&self, _t: f64, _x: &nalgebra::Vector1<f64>) -> nalgebra::Matrix1<f64> {
            nalgebra::Matrix1::new(f64::NAN)
        }
    }
    let e = GaussLegendre4::new(0.1)
        .integrate_with_jacobian(&NanJac, 0.0, nalgebra::Vector1::new(1.0), 1.0)
        .unwrap_err();
    assert!(matches!(e, SimError::NonFinite { t: 0.0, .. }), "{e:?}");

    // Invalid step sizes.
    for h in [0.0, -1.0, f64::NAN] {
        let e = GaussLegendre4::new(h)
            .integrate(&Pendulum, 0.0, Vector2::new(1.0, 0.0), 1.0)
            .unwrap_err();
        assert!(matches!(e, SimError::InvalidInput { .. }));
    }
}
