//! The rest of the input language: inputs and forces, explicit time, `pi`,
//! `dot` of a time-dependent `let`, `sqrt`/`exp`/`ln`, systems without
//! constraints, private visibility; and the runtime adapter for inputs.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A forced, damped oscillator on a shaken support: X = x + A sin(ω t).
    pub struct ShakenOscillator {
        parameters { m, k, c, A, omega }
        coordinates { x }
        inputs { F }
        let X = x + A*sin(omega*t);
        lagrangian = m/2*dot(X)^2 - k/2*x^2;
        forces { x: -c*dot(x) + F*cos(pi*t); }
    }
}

#[test]
fn time_inputs_forces_and_dot_of_a_time_dependent_let() {
    let s: ShakenOscillator = ShakenOscillator::new(2.0, 3.0, 0.4, 0.25, 1.7);
    for &(t, x, v, f) in &[
        (0.3, 0.2, -1.0, 0.5),
        (1.1, -0.7, 0.4, -2.0),
        (2.9, 1.3, 2.2, 0.0),
    ] {
        let a = s.accelerations(
            t,
            &SVector::from([x]),
            &SVector::from([v]),
            &SVector::from([f]),
        )[0];
        // m (ẍ − A ω² sin ω t) + k x = −c ẋ + F cos π t
        let expect = s.A * s.omega.powi(2) * (s.omega * t).sin()
            + (-s.k * x - s.c * v + f * (std::f64::consts::PI * t).cos()) / s.m;
        assert!(
            (a - expect).abs() <= 1e-14 * expect.abs().max(1.0),
            "{a} vs {expect}"
        );
    }
    assert_eq!(ShakenOscillator::<f64>::INPUTS, ["F"]);
    assert_eq!(ShakenOscillator::<f64>::P, 0);
    const { assert!(ShakenOscillator::<f64>::INTEGRABLE) };
}

#[test]
fn inputs_drive_the_runtime_through_the_driven_adapter() {
    let s = ShakenOscillator::new(1.0, 4.0, 0.0, 0.0, 1.0);
    // constant force F: equilibrium x = F/k; starting there it stays there
    let u = SVector::<f64, 1>::from([2.0]);
    let sys = Driven::new(&s, u);
    // cos(π t) modulates F; integrate over a short span and compare with a
    // hand-written right side integrated the same way
    let x0 = SVector::<f64, 2>::from([0.1, 0.0]);
    let a = Dopri5::new(1e-10, 1e-12)
        .integrate(&sys, 0.0, x0, 2.0)
        .expect("driven system integrates");
    let hand = |t: f64, x: &SVector<f64, 2>| {
        SVector::<f64, 2>::from([x[1], -4.0 * x[0] + 2.0 * (std::f64::consts::PI * t).cos()])
    };
    let b = Dopri5::new(1e-10, 1e-12)
        .integrate(&hand, 0.0, x0, 2.0)
        .expect("hand system integrates");
    assert!((a.x - b.x).amax() <= 1e-9, "{} vs {}", a.x, b.x);
}

nonholonomic_system! {
    /// A particle in a potential written with sqrt, exp and ln.
    pub struct Potentials {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) - k*(sqrt(1 + x^2) + exp(y/3) + ln(2 + x^2*y^2));
    }
}

#[test]
fn elementary_functions_differentiate_correctly() {
    let p: Potentials = Potentials::new(1.5, 0.7);
    let (x, y) = (0.4, -1.2);
    let a = p.accelerations(0.0, &SVector::from([x, y]), &SVector::from([0.3, 0.1]));
    let dvdx = p.k * (x / (1.0 + x * x).sqrt() + 2.0 * x * y * y / (2.0 + x * x * y * y));
    let dvdy = p.k * ((y / 3.0).exp() / 3.0 + 2.0 * x * x * y / (2.0 + x * x * y * y));
    assert!((a[0] + dvdx / p.m).abs() <= 1e-14);
    assert!((a[1] + dvdy / p.m).abs() <= 1e-14);
}

nonholonomic_system! {
    /// The Chaplygin sled pushed and steered: forces on every coordinate,
    /// including the dependent one.
    pub struct PushedSled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces {
            x: push*cos(theta) - c*dot(x);
            y: push*sin(theta) - c*dot(y);
            theta: steer;
        }
        outputs { routes, energy, multipliers }
    }
}

#[test]
fn forces_project_the_same_way_on_both_routes_and_do_the_work() {
    let s = PushedSled::new(2.0, 0.3, 0.5, 0.2);
    let u = SVector::<f64, 2>::from([0.8, -0.3]);
    for i in 0..50 {
        let f = i as f64 * 0.37;
        let q = SVector::<f64, 3>::from([f.sin(), 0.9 * (1.3 * f).cos(), (0.7 * f).sin()]);
        let rdot = SVector::<f64, 2>::from([1.0 + 0.5 * f.cos(), 0.8 * (2.1 * f).sin()]);
        let a = s.accelerations_multiplier_route(0.0, &q, &rdot, &u);
        let b = s.accelerations_curvature_route(0.0, &q, &rdot, &u);
        assert!((a - b).amax() <= 1e-12 * a.amax().max(1.0), "{a} vs {b}");
        // dE/dt = Σ Q_j q̇_j: the constraint forces do no work
        let sdot = s.dependent_velocities(&q, &rdot);
        let qdot = SVector::<f64, 3>::from([rdot[0], rdot[1], sdot[0]]);
        let h = 1e-6;
        let e = |sign: f64| s.energy(&(q + sign * h * qdot), &(rdot + sign * h * a));
        let de_dt = (e(1.0) - e(-1.0)) / (2.0 * h);
        let power = (u[0] * q[1].cos() - s.c * qdot[0]) * qdot[0]
            + u[1] * qdot[1]
            + (u[0] * q[1].sin() - s.c * qdot[2]) * qdot[2];
        assert!(
            (de_dt - power).abs() <= 1e-7 * power.abs().max(1.0),
            "{de_dt} vs {power}"
        );
    }
}

mod private_system {
    use nonholonomic::prelude::*;
    nonholonomic_system! {
        struct Hidden {
            parameters { m }
            coordinates { x }
            lagrangian = m*dot(x)^2/2;
        }
    }
    pub fn free_particle_does_not_accelerate() -> f64 {
        Hidden::new(1.0).accelerations(0.0, &SVector::from([0.0]), &SVector::from([1.0]))[0]
    }
}

#[test]
fn private_visibility_is_kept() {
    assert_eq!(private_system::free_particle_does_not_accelerate(), 0.0);
}

nonholonomic_system! {
    /// A pendulum written with the constant `pi` and a rational power.
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { th }
        lagrangian = m*l^2*dot(th)^2/2 + m*g*l*cos(th - pi/2 + pi/2) + 0*(l^(3/2));
    }
}

#[test]
fn pi_and_rational_exponents() {
    let p = Pendulum::new(1.0, 2.0, 9.81);
    let a = p.accelerations(0.0, &SVector::from([0.5]), &SVector::from([0.0]))[0];
    assert!((a + 9.81 / 2.0 * 0.5f64.sin()).abs() <= 1e-14);
}
