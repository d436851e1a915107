//! Stiff problems: Rodas4 (RODAS4) against the classic test set.

mod common;

use common::Robertson;

use nalgebra::{Matrix2, SVector, Vector1, Vector2, Vector3};
use nh_runtime::{Dopri5, Integrator, OdeJacobian, OdeSystem, Rodas4, SimError, Singularity};

/// Van der Pol oscillator `x'' = μ(1 − x²)x' − x` with `μ = 1000`.
struct VanDerPol {
    mu: f64,
}

impl OdeSystem<f64, 2> for VanDerPol {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x[1], self.mu * (1.0 - x[0] * x[0]) * x[1] - x[0])
    }
}

impl OdeJacobian<f64, 2> for VanDerPol {
    fn jacobian(&self, _t: f64, x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(
            0.0,
            1.0,
            -2.0 * self.mu * x[0] * x[1] - 1.0,
            self.mu * (1.0 - x[0] * x[0]),
        )
    }
}

fn prothero_robinson(t: f64, x: &Vector1<f64>) -> Vector1<f64> {
    Vector1::new(-1e6 * (x[0] - t.cos()) - t.sin())
}

#[test]
fn van_der_pol_mu_1000() {
    let vdp = VanDerPol { mu: 1e3 };
    let x0 = Vector2::new(2.0, 0.0);
    let t1 = 3000.0; // almost two relaxation periods (≈ 1614 each)
    let reference = Rodas4::new(1e-11, 1e-11)
        .integrate_with_jacobian(&vdp, 0.0, x0, t1)
        .unwrap();
    for rtol in [1e-4, 1e-6, 1e-8] {
        let mut ros = Rodas4::new(rtol, rtol);
        let fd = ros.integrate(&vdp, 0.0, x0, t1).unwrap();
        let an = ros.integrate_with_jacobian(&vdp, 0.0, x0, t1).unwrap();
        let err_fd = (fd.x[0] - reference.x[0]).abs();
        let err_an = (an.x[0] - reference.x[0]).abs();
        println!(
            "vdp rtol {rtol:e}: |Δx1| fd {err_fd:.2e} analytic {err_an:.2e}, steps {} / {}, rejected {} / {}, {:?}",
            fd.stats.steps, an.stats.steps, fd.stats.rejected, an.stats.rejected, an.stats
        );
        // The position x1 is O(1) on the slow manifold at t1.
        assert!(err_fd < 1e3 * rtol, "fd err {err_fd:e} at rtol {rtol:e}");
        assert!(
            err_an < 1e3 * rtol,
            "analytic err {err_an:e} at rtol {rtol:e}"
        );
        assert!(an.stats.steps < 5000);
        // One Jacobian per accepted step plus the initial one.
        assert_eq!(an.stats.jacobian_evals, an.stats.steps);
        assert_eq!(
            an.stats.lu_decompositions,
            an.stats.steps + an.stats.rejected
        );
    }
}

#[test]
fn robertson_chemical_kinetics() {
    let y0 = Vector3::new(1.0, 0.0, 0.0);
    let expected = Vector3::from(common::ROBER_AT_40);
    let mut ros = Rodas4::new(1e-8, 1e-12);
    let fd = ros.integrate(&Robertson, 0.0, y0, 40.0).unwrap();
    let an = ros
        .integrate_with_jacobian(&Robertson, 0.0, y0, 40.0)
        .unwrap();
    for (name, out) in [("fd", fd), ("analytic", an)] {
        println!("robertson {name}: {:?} {:?}", out.x.as_slice(), out.stats);
        let rel = (out.x - expected).component_div(&expected).amax();
        assert!(rel < 1e-6, "{name}: relative error {rel:e}");
        // Mass conservation y1 + y2 + y3 = 1 (linear invariant, preserved
        // by Rosenbrock methods up to round-off and the Jacobian error).
        assert!((out.x.sum() - 1.0).abs() < 1e-12);
        assert!(out.stats.steps < 300, "{name}: {} steps", out.stats.steps);
    }
    // Far into the transient-free regime: still cheap.
    let out = Rodas4::new(1e-6, 1e-12)
        .integrate_with_jacobian(&Robertson, 0.0, y0, 4e10)
        .unwrap();
    println!("robertson to 4e10: {:?} {:?}", out.x.as_slice(), out.stats);
    assert!(out.stats.steps < 1000);
    assert!(out.x[0] < 1e-4 && out.x[2] > 0.9999);
}

#[test]
fn stiff_linear_problem_rosenbrock_vs_dopri() {
    let x0 = Vector1::new(1.0);
    let t1 = 3.0;
    let mut ros = Rodas4::new(1e-6, 1e-9);
    let out = ros.integrate(&prothero_robinson, 0.0, x0, t1).unwrap();
    let err = (out.x[0] - t1.cos()).abs();
    println!("rodas4: err {err:.2e}, {:?}", out.stats);
    assert!(err < 1e-6);
    assert!(out.stats.steps <= 100, "{} steps", out.stats.steps);

    // Dormand–Prince is stability-limited to |h| ≈ 3.3e-6: about 1e6 steps
    // for [0, 3]. Give it 20 000 and extrapolate from how far it got.
    let budget = 20_000;
    let mut dp = Dopri5::new(1e-6, 1e-9).with_max_steps(budget);
    let e = dp.integrate(&prothero_robinson, 0.0, x0, t1).unwrap_err();
    let SimError::MaxSteps { t, .. } = e else {
        panic!("{e:?}")
    };
    let needed = budget as f64 * t1 / t;
    println!("dopri5: reached t = {t:.4} in {budget} attempts: ≈ {needed:.2e} steps needed");
    assert!(needed > 5e5, "{needed:e}");
    assert!(dp.last_stats().stiffness_detected);
}

#[test]
fn singular_iteration_matrix() {
    // f(t, x) = x / (hγ) is impossible to know in advance, but a Jacobian
    // that is NaN makes every factorisation fail: NonFinite at once.
    struct NanJacobian;
    impl OdeSystem<f64, 1> for NanJacobian {
        fn rhs(&self, _t: f64, x: &Vector1<f64>) -> Vector1<f64> {
            -x
        }
    }
    impl OdeJacobian<f64, 1> for NanJacobian {
        fn jacobian(&self, _t: f64, _x: &Vector1<f64>) -> nalgebra::Matrix1<f64> {
            nalgebra::Matrix1::new(f64::NAN)
        }
    }
    let e = Rodas4::new(1e-6, 1e-9)
        .integrate_with_jacobian(&NanJacobian, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    assert!(matches!(e, SimError::NonFinite { t: 0.0, .. }), "{e:?}");

    // A Jacobian that claims J = 1/(hγ) for the fixed step h makes the
    // iteration matrix exactly singular: Singular with the start state.
    struct Resonant;
    impl OdeSystem<f64, 1> for Resonant {
        fn rhs(&self, _t: f64, x: &Vector1<f64>) -> Vector1<f64> {
            x * 40.0
        }
    }
    impl OdeJacobian<f64, 1> for Resonant {
        fn jacobian(&self, _t: f64, _x: &Vector1<f64>) -> nalgebra::Matrix1<f64> {
            nalgebra::Matrix1::new(40.0)
        }
    }
    // h = 0.1, γ = 1/4: 1/(hγ) = 40.
    let e = Rodas4::new(1e-6, 1e-9)
        .with_fixed_step(0.1)
        .integrate_with_jacobian(&Resonant, 0.0, Vector1::new(1.0), 1.0)
        .unwrap_err();
    assert_eq!(
        e,
        SimError::Singular {
            t: 0.0,
            x: Vector1::new(1.0),
            cause: Singularity::IterationMatrix,
        }
    );
    // Adaptively, the step is halved and the integration proceeds.
    let out = Rodas4::new(1e-6, 1e-9)
        .with_initial_step(0.1)
        .integrate_with_jacobian(&Resonant, 0.0, Vector1::new(1.0), 0.5)
        .unwrap();
    assert!((out.x[0] / 20.0f64.exp() - 1.0).abs() < 1e-4);
    let _ = SVector::<f64, 1>::zeros();
}
