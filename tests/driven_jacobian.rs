//! Systems with inputs on every integrator, with their generated Jacobian:
//! a system with `inputs` and `outputs { jacobian }` implements
//! `ControlledJacobian`, and `Driven` (its input held) is then an
//! `OdeJacobian` whose Jacobian is the generated ∂f/∂x at the held input.
//! Checked against central differences, and the implicit methods with the
//! analytic Jacobian against Dop853 at tight tolerances.
use nonholonomic::prelude::*;

#[path = "common/differences.rs"]
mod central;

nonholonomic_system! {
    /// A pushed and steered sled in a viscous medium: stiff for large `c`.
    pub struct PushedSled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer - c*dot(theta); }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// The sled in generalized speeds, driven by a yaw torque and damped.
    pub struct SteeredSled {
        parameters { m, J, a, c }
        coordinates { x, y, theta }
        inputs { tau }
        lagrangian = J*dot(theta)^2/2
            + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        forces { theta: tau - c*dot(theta); }
        outputs { jacobian }
    }
}

fn pushed_sled() -> (PushedSled, SVector<f64, 5>) {
    let sled = PushedSled::from_parameters(PushedSledParameters {
        m: 2.0,
        J: 0.3,
        a: 0.5,
        c: 40.0,
    });
    let x0 = PushedSled::state(
        PushedSledCoordinates {
            x: 0.0,
            theta: 0.3,
            y: 0.0,
        },
        PushedSledVelocities { x: 1.0, theta: 2.0 },
    );
    (sled, x0)
}

#[test]
fn the_held_jacobian_is_the_generated_one_and_matches_differences() {
    let (sled, _) = pushed_sled();
    let u = SVector::<f64, 2>::from([3.0, -0.4]);
    let driven = Driven::new(&sled, u);
    for (i, th) in [-1.0, -0.2, 0.4, 1.1].into_iter().enumerate() {
        let x = SVector::<f64, 5>::from([0.3 * i as f64, th, -0.2, 0.7 - 0.3 * i as f64, 1.5 * th]);
        let j = driven.jacobian(0.5, &x);
        assert_eq!(j, sled.jacobian(0.5, &x, &u));
        let worst = central::jacobian_deviation(|x| driven.rhs(0.5, x), &j, &x);
        assert!(worst < 1e-6, "{worst:e} at {x}");
    }
}

#[test]
fn rosenbrock_with_the_generated_jacobian_agrees_with_dop853() {
    let (sled, x0) = pushed_sled();
    let driven = Driven::new(&sled, SVector::from([3.0, -0.4]));
    let reference = Dop853::new(1e-12, 1e-14)
        .integrate(&driven, 0.0, x0, 2.0)
        .unwrap();
    let analytic = Rodas4::new(1e-9, 1e-11)
        .integrate_with_jacobian(&driven, 0.0, x0, 2.0)
        .unwrap();
    let differences = Rodas4::new(1e-9, 1e-11)
        .integrate(&driven, 0.0, x0, 2.0)
        .unwrap();
    let error = (analytic.x - reference.x).amax();
    assert!(error < 1e-7, "{error:e}: {} vs {}", analytic.x, reference.x);
    // the analytic Jacobian was used: no right-hand sides spent on differences
    assert!(analytic.stats.jacobian_evals > 0);
    let per_step = |o: &Outcome<f64, 5>| o.stats.rhs_evals as f64 / o.stats.jacobian_evals as f64;
    assert!(
        per_step(&differences) - per_step(&analytic) > 4.0,
        "{:?} vs {:?}",
        analytic.stats,
        differences.stats
    );
    // the constraint holds along the motion, by name
    let (q, v) = PushedSled::split(&analytic.x);
    let qdot = PushedSledCoordinates {
        x: v.x,
        theta: v.theta,
        y: q.theta.tan() * v.x,
    };
    assert_eq!(sled.state_from_velocities(q, qdot), Ok(analytic.x));
}

#[test]
fn gauss_legendre_with_the_generated_jacobian_agrees_with_dop853() {
    let (sled, x0) = pushed_sled();
    let driven = Driven::new(&sled, SVector::from([3.0, -0.4]));
    let reference = Dop853::new(1e-12, 1e-14)
        .integrate(&driven, 0.0, x0, 1.0)
        .unwrap();
    let gauss = GaussLegendre4::new(1e-3)
        .integrate_with_jacobian(&driven, 0.0, x0, 1.0)
        .unwrap();
    let error = (gauss.x - reference.x).amax();
    assert!(error < 1e-8, "{error:e}");
}

#[test]
fn a_control_loop_on_rosenbrock_in_generalized_speeds() {
    let sled: SteeredSled = SteeredSled::new(2.0, 0.3, 0.5, 30.0);
    let mut x = SteeredSled::state(
        SteeredSledCoordinates {
            x: 0.0,
            y: 0.0,
            theta: 0.0,
        },
        SteeredSledVelocities { v: 1.0, omega: 0.0 },
    );
    let mut reference = x;
    let target = 0.8;
    for k in 0..50 {
        let (t0, t1) = (0.02 * k as f64, 0.02 * (k + 1) as f64);
        // a proportional heading controller, sampled every 20 ms
        let tau = SVector::from([20.0 * (target - SteeredSled::split(&x).0.theta)]);
        let driven = Driven::new(&sled, tau);
        let j = driven.jacobian(t0, &x);
        assert!(central::jacobian_deviation(|x| driven.rhs(t0, x), &j, &x) < 1e-6);
        x = Rodas4::new(1e-9, 1e-11)
            .integrate_with_jacobian(&driven, t0, x, t1)
            .unwrap()
            .x;
        let tau_ref = SVector::from([20.0 * (target - reference[2])]);
        reference = Dop853::new(1e-12, 1e-14)
            .integrate(&Driven::new(&sled, tau_ref), t0, reference, t1)
            .unwrap()
            .x;
    }
    assert!((x - reference).amax() < 1e-7, "{x} vs {reference}");
    let (q, _) = SteeredSled::split(&x);
    assert!(
        q.theta > 0.3 && q.theta < 1.0,
        "turned towards the target: {q:?}"
    );
}
