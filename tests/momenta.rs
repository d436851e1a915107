//! What is conserved (§5.5): the momenta of the cyclic coordinates and the
//! rates (5.36) the constraints give them, against the thesis's closed forms
//! (6.63)–(6.64) and the closed forms of the vertical disc, the Chaplygin
//! sleigh and a pendulum on a cart, at random states and along
//! integrations.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The thesis's disc, whose constrained Lagrangian is (6.41).
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { momenta }
    }
}

nonholonomic_system! {
    /// A disc rolling upright: rolling angle θ, heading φ.
    pub struct VerticalDisc {
        parameters { m, R, I, J }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + I/2*dot(theta)^2 + J/2*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { momenta }
    }
}

nonholonomic_system! {
    /// The Chaplygin sleigh with its contact point at the centre of mass.
    pub struct Sleigh {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { momenta }
    }
}

nonholonomic_system! {
    /// A pendulum on a cart: no constraints.
    pub struct PendulumCart {
        parameters { M, m, l, g }
        coordinates { x, theta }
        lagrangian = (M + m)/2*dot(x)^2 + m*l*cos(theta)*dot(x)*dot(theta)
                   + m*l^2/2*dot(theta)^2 + m*g*l*cos(theta);
        outputs { momenta }
    }
}

/// A few states from a fixed sequence.
fn states<const N: usize>(count: usize) -> Vec<[f64; N]> {
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    (0..count)
        .map(|_| {
            std::array::from_fn(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            })
        })
        .collect()
}

#[test]
fn the_thesis_disc_gives_its_closed_forms() {
    // (6.63) ṗ_θ = mR² cos ψ φ̇ ψ̇, (6.64) ṗ_φ = −mR² cos ψ θ̇ ψ̇;
    // p_θ = ∂Lc/∂θ̇ = mR²(3/2 θ̇ − sin ψ φ̇), p_φ = mR²((1/4 + sin²ψ) φ̇ − sin ψ θ̇)
    let (m, r) = (1.3, 0.4);
    let disc = ThesisDisc::new(m, r, 9.81);
    assert_eq!(ThesisDisc::CYCLIC, [0, 1]);
    assert_eq!(
        ThesisDisc::CONSERVED,
        [Conservation::NotConserved, Conservation::NotConserved]
    );
    let mr2 = m * r * r;
    let mut worst = 0.0f64;
    for s in states::<8>(20) {
        let q = SVector::<f64, 5>::from([s[0], s[1], s[2], s[3], s[4]]);
        let v = SVector::<f64, 3>::from([s[5], s[6], s[7]]);
        let (psi, td, pd, sd) = (q[2], v[0], v[1], v[2]);
        let p = disc.momenta(0.0, &q, &v);
        let rate = disc.momentum_rates(0.0, &q, &v);
        let want_p = [
            mr2 * (1.5 * td - psi.sin() * pd),
            mr2 * ((0.25 + psi.sin().powi(2)) * pd - psi.sin() * td),
        ];
        let want_rate = [mr2 * psi.cos() * pd * sd, -mr2 * psi.cos() * td * sd];
        for i in 0..2 {
            worst = worst
                .max((p[i] - want_p[i]).abs())
                .max((rate[i] - want_rate[i]).abs());
        }
    }
    println!("thesis disc: momenta and rates against (6.41), (6.63), (6.64): {worst:.1e}");
    assert!(worst < 1e-14, "{worst:e}");
}

#[test]
fn the_vertical_disc_conserves_both_momenta() {
    assert_eq!(VerticalDisc::CYCLIC, [0, 1]);
    assert_eq!(VerticalDisc::CONSERVED, [Conservation::Conserved; 2]);
    let disc = VerticalDisc::new(1.0, 0.3, 0.05, 0.02);
    for s in states::<6>(10) {
        let q = SVector::<f64, 4>::from([s[0], s[1], s[2], s[3]]);
        let v = SVector::<f64, 2>::from([s[4], s[5]]);
        let p = disc.momenta(0.0, &q, &v);
        // (m R² + I) θ̇ and J φ̇
        assert!((p[0] - (0.09 + 0.05) * v[0]).abs() < 1e-15);
        assert!((p[1] - 0.02 * v[1]).abs() < 1e-15);
        assert_eq!(disc.momentum_rates(0.0, &q, &v), SVector::<f64, 2>::zeros());
    }
}

#[test]
fn the_sleighs_momentum_changes_at_its_rate() {
    // p_x = m ẋ sec²θ; along the motion ẍ = −tan θ θ̇ ẋ, so ṗ_x = m ẋ sec²θ tan θ θ̇
    assert_eq!(Sleigh::CYCLIC, [0]);
    assert_eq!(Sleigh::CONSERVED, [Conservation::NotConserved]);
    let sleigh = Sleigh::new(2.0, 0.3);
    let (q, v) = (
        SVector::<f64, 3>::from([0.1, 0.2, 0.4]),
        SVector::<f64, 2>::from([0.7, 1.3]),
    );
    let sec2 = 1.0 / 0.4f64.cos().powi(2);
    let p = sleigh.momenta(0.0, &q, &v)[0];
    let rate = sleigh.momentum_rates(0.0, &q, &v)[0];
    assert!((p - 2.0 * 0.7 * sec2).abs() < 1e-15);
    assert!((rate - 2.0 * 0.7 * sec2 * 0.4f64.tan() * 1.3).abs() < 1e-14);
    // along an integration, θ from 0.4 to 1.44 (short of π/2, where p_x
    // = m ẋ sec²θ is not defined): p(t1) − p(t0) = ∫ ṗ dt (trapezoid on
    // outputs every millisecond, Simpson's rule)
    let x0 = SVector::<f64, 5>::from([0.1, 0.2, 0.4, 0.7, 1.3]);
    let times: Vec<f64> = (1..=800).map(|i| 1e-3 * i as f64).collect();
    let split = |x: &SVector<f64, 5>| {
        (
            SVector::<f64, 3>::from([x[0], x[1], x[2]]),
            SVector::<f64, 2>::from([x[3], x[4]]),
        )
    };
    let mut rates = vec![sleigh.momentum_rates(0.0, &q, &v)[0]];
    let mut end = x0;
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&sleigh, 0.0, x0, 0.8, &times, |_, x| {
            let (q, v) = split(x);
            rates.push(sleigh.momentum_rates(0.0, &q, &v)[0]);
            end = *x;
        })
        .unwrap();
    // Simpson's rule over the 800 intervals
    let weight = |i: usize| match i {
        0 | 800 => 1.0,
        i if i % 2 == 1 => 4.0,
        _ => 2.0,
    };
    let integral: f64 = rates
        .iter()
        .enumerate()
        .map(|(i, r)| weight(i) * r)
        .sum::<f64>()
        * 1e-3
        / 3.0;
    let (q1, v1) = split(&end);
    let change = sleigh.momenta(0.0, &q1, &v1)[0] - p;
    println!("sleigh: p changed by {change:.12}, ∫ṗ dt = {integral:.12}");
    assert!(
        (change - integral).abs() < 1e-8 * change.abs(),
        "{change} {integral}"
    );
}

#[test]
fn the_cart_conserves_its_momentum() {
    assert_eq!(PendulumCart::CYCLIC, [0]);
    assert_eq!(PendulumCart::CONSERVED, [Conservation::Conserved]);
    let cart = PendulumCart::new(2.0, 0.5, 0.7, 9.81);
    let x0 = SVector::<f64, 4>::from([0.0, 1.2, 0.3, -0.4]);
    let p = |x: &SVector<f64, 4>| {
        let q = SVector::<f64, 2>::from([x[0], x[1]]);
        let v = SVector::<f64, 2>::from([x[2], x[3]]);
        cart.momenta(0.0, &q, &v)[0]
    };
    // (M + m) ẋ + m l cos θ θ̇
    assert!((p(&x0) - (2.5 * 0.3 + 0.5 * 0.7 * 1.2f64.cos() * -0.4)).abs() < 1e-15);
    let mut drift = 0.0f64;
    let times: Vec<f64> = (1..=100).map(|i| 0.1 * i as f64).collect();
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&cart, 0.0, x0, 10.0, &times, |_, x| {
            drift = drift.max((p(x) - p(&x0)).abs());
        })
        .unwrap();
    println!("pendulum on a cart: momentum drift {drift:.1e} over 10 s");
    assert!(drift < 1e-11, "{drift:e}");
}

nonholonomic_system! {
    /// The physically correct rolling disc (the thesis's disc with the
    /// cross terms of a tilted disc that its simplified energy omits).
    pub struct BodyDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let F = rot_z(phi) * rot_x(-psi);
        let C = [x, y, 0] + R*(F*[0, 0, 1]);
        body disc {
            mass: m, centre: C, orientation: F*rot_y(theta),
            inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4),
        }
        lagrangian = kinetic_energy(disc) - m*g*C.z;
        constraints { rolls(disc, radius: R, axle: [0, 1, 0]); }
        outputs { momenta }
    }
}

#[test]
fn the_physically_correct_disc_agrees_with_sympy() {
    // tests/data/momenta_sympy.py: the rolling constraint, Lc and the
    // momenta from scratch, their rates by the chain rule along the
    // Lagrange–d'Alembert motion (not by (5.36)), 40 digits
    assert_eq!(BodyDisc::CYCLIC, [0, 1]);
    assert_eq!(BodyDisc::CONSERVED, [Conservation::NotConserved; 2]);
    let reference: serde_json::Value =
        serde_json::from_str(include_str!("data/momenta.json")).expect("json");
    let disc = BodyDisc::new(1.3, 0.4, 9.81);
    let num = |v: &serde_json::Value| -> f64 {
        let text = v
            .as_str()
            .map(str::to_owned)
            .unwrap_or_else(|| v.to_string());
        text.parse().expect("a number")
    };
    let mut worst = 0.0f64;
    for point in reference["points"].as_array().expect("points") {
        let s: Vec<f64> = point["state"]
            .as_array()
            .expect("state")
            .iter()
            .map(num)
            .collect();
        let q = SVector::<f64, 5>::from_column_slice(&s[..5]);
        let v = SVector::<f64, 3>::from_column_slice(&s[5..]);
        let (p, rate) = (disc.momenta(0.0, &q, &v), disc.momentum_rates(0.0, &q, &v));
        for k in 0..2 {
            let (want_p, want_rate) = (num(&point["momenta"][k]), num(&point["rates"][k]));
            worst = worst
                .max((p[k] - want_p).abs() / want_p.abs().max(1.0))
                .max((rate[k] - want_rate).abs() / want_rate.abs().max(1.0));
        }
    }
    println!("physically correct disc: momenta and rates against SymPy: {worst:.1e}");
    assert!(worst < 1e-13, "{worst:e}");
}

nonholonomic_system! {
    /// A homogeneous ball rolling on the plane, its orientation in yaw,
    /// pitch and roll.
    pub struct RollingBall {
        parameters { m, R }
        coordinates { x, y, yaw, pitch, roll }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        let w = omega(Q);
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/5*(w.x^2 + w.y^2 + w.z^2);
        constraints {
            dot(x) = R*w.y;
            dot(y) = -R*w.x;
        }
        momenta {
            K_x(Q: [1, 0, 0], y: -R);
            K_y(Q: [0, 1, 0], x: R);
            K_z(Q: [0, 0, 1]);
        }
        outputs { momenta }
    }
}

#[test]
fn the_ball_keeps_its_vertical_angular_momentum_about_the_contact_point() {
    // yaw and roll are cyclic (ω in world axes is free of the last angle);
    // p_yaw = (2/5) m R² ω_z, the vertical component of the angular
    // momentum about the contact point, is conserved; p_roll is not
    assert_eq!(RollingBall::CYCLIC, [2, 4]);
    assert_eq!(
        RollingBall::CONSERVED,
        [Conservation::Conserved, Conservation::NotConserved]
    );
    let (m, r) = (1.2, 0.3);
    let ball = RollingBall::new(m, r);
    let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.5, -0.2, 0.7, -1.1, 2.0]);
    let split = |x: &SVector<f64, 8>| {
        (
            SVector::<f64, 5>::from_column_slice(&x.as_slice()[..5]),
            SVector::<f64, 3>::from_column_slice(&x.as_slice()[5..]),
        )
    };
    let omega_z = |x: &SVector<f64, 8>| {
        // ω_z of rot_z(yaw) rot_y(pitch) rot_x(roll): ẏaw − sin(pitch) ṙoll
        x[5] - x[3].sin() * x[7]
    };
    let (q0, v0) = split(&x0);
    let p0 = ball.momenta(0.0, &q0, &v0);
    assert!((p0[0] - 0.4 * m * r * r * omega_z(&x0)).abs() < 1e-15);
    let (mut drift, mut roll_change) = (0.0f64, 0.0f64);
    let times: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&ball, 0.0, x0, 10.0, &times, |_, x| {
            let (q, v) = split(x);
            let p = ball.momenta(0.0, &q, &v);
            drift = drift.max((p[0] - p0[0]).abs());
            roll_change = roll_change.max((p[1] - p0[1]).abs());
            assert_eq!(ball.momentum_rates(0.0, &q, &v)[0], 0.0);
        })
        .unwrap();
    println!(
        "rolling ball: p_yaw drift {drift:.1e} over 10 s; p_roll moves by up to {roll_change:.3}"
    );
    assert!(drift < 1e-12, "{drift:e}");
    assert!(roll_change > 1e-3);
    // the whole angular momentum about the contact point, K = I ω + m R e_z × v,
    // is conserved (the contact force acts through it); the macro's p_yaw is
    // its vertical component
    let contact_momentum = |x: &SVector<f64, 8>| ball_contact_momentum(&ball, m, r, x);
    let k0 = contact_momentum(&x0);
    assert!((k0.z - p0[0]).abs() < 1e-15);
    let mut k_drift = 0.0f64;
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&ball, 0.0, x0, 10.0, &times, |_, x| {
            k_drift = k_drift.max((contact_momentum(x) - k0).amax());
        })
        .unwrap();
    println!("rolling ball: K about the contact point {k0:?}, drift {k_drift:.1e}");
    assert!(k_drift < 1e-11, "{k_drift:e}");
}

nonholonomic_system! {
    /// McLachlan and Perlmutter's contact oscillator (their §5.2): the
    /// constraint dx + y dz, a quartic coupling ε x² z².
    pub struct ContactOscillator {
        parameters { eps }
        coordinates { x, y, z }
        lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2 - (x^2 + y^2 + z^2 + eps*x^2*z^2)/2;
        constraints { dot(x) = -y*dot(z); }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// Modin and Verdier's non-reversible member of the family: the
    /// Hamiltonian ½(|q|² + |p + ∇S|²) with S = cos z, whose Lagrangian is
    /// the oscillator's minus ⟨∇S, q̇⟩ = −d S/dt: a null Lagrangian.
    pub struct ShiftedOscillator {
        parameters { eps }
        coordinates { x, y, z }
        lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2 - (x^2 + y^2 + z^2 + eps*x^2*z^2)/2
                   + sin(z)*dot(z);
        constraints { dot(x) = -y*dot(z); }
        outputs { energy }
    }
}

#[test]
fn the_non_reversible_family_adds_a_null_lagrangian() {
    // In the velocities the perturbation dS/dt leaves the equations of
    // Lagrange–d'Alembert as they were: the same accelerations and energy
    let (a, b) = (ContactOscillator::new(0.1), ShiftedOscillator::new(0.1));
    let mut worst = 0.0f64;
    for s in states::<5>(20) {
        let q = SVector::<f64, 3>::from([s[0], s[1], s[2]]);
        let v = SVector::<f64, 2>::from([s[3], s[4]]);
        let gap = (a.accelerations(0.0, &q, &v) - b.accelerations(0.0, &q, &v)).amax();
        worst = worst
            .max(gap)
            .max((a.energy(&q, &v) - b.energy(&q, &v)).abs());
    }
    println!("contact oscillator with and without Modin and Verdier's dS/dt: {worst:.1e}");
    assert!(worst < 1e-14, "{worst:e}");
}

/// K = I ω + m R e_z × v, the ball's angular momentum about its contact
/// point, from the state [q, ṙ] by hand: ω in world axes from the ZYX
/// angles' rates, v from the rolling constraint.
fn ball_contact_momentum(
    ball: &RollingBall<f64>,
    m: f64,
    r: f64,
    x: &SVector<f64, 8>,
) -> Vector3<f64> {
    let seq = EulerSequence::ZYX;
    let (a, rates) = ([x[2], x[3], x[4]], [x[5], x[6], x[7]]);
    let w = seq.matrix(&a) * seq.body_rates(&a, &rates);
    let q = SVector::<f64, 5>::from_column_slice(&x.as_slice()[..5]);
    let v = SVector::<f64, 3>::from_column_slice(&x.as_slice()[5..]);
    let vel = ball.dependent_velocities(&q, &v);
    let inertia = 0.4 * m * r * r;
    Vector3::new(
        inertia * w.x - m * r * vel[1],
        inertia * w.y + m * r * vel[0],
        inertia * w.z,
    )
}

#[test]
fn the_balls_declared_momenta_are_its_angular_momentum_about_the_contact_point() {
    // K_x, K_y, K_z along the turns about the world axes through the
    // contact point (the centre moving as rolling requires): the engine
    // proves each rate zero, and each is the component of K by hand
    assert_eq!(RollingBall::MOMENTA, ["K_x", "K_y", "K_z"]);
    assert_eq!(
        RollingBall::MOMENTUM_CONSERVED,
        [Conservation::Conserved; 3]
    );
    let (m, r) = (1.2, 0.3);
    let ball = RollingBall::new(m, r);
    let mut worst = 0.0f64;
    for s in states::<8>(20) {
        let s = SVector::<f64, 8>::from(s);
        let q = SVector::<f64, 5>::from_column_slice(&s.as_slice()[..5]);
        let v = SVector::<f64, 3>::from_column_slice(&s.as_slice()[5..]);
        let k = ball_contact_momentum(&ball, m, r, &s);
        let j = ball.declared_momenta(0.0, &q, &v);
        worst = worst.max((j - k).amax() / k.amax().max(1.0));
        assert_eq!(
            ball.declared_momentum_rates(0.0, &q, &v),
            SVector::<f64, 3>::zeros()
        );
    }
    println!("rolling ball: declared momenta against K by hand at 20 states: {worst:.1e}");
    assert!(worst < 1e-14, "{worst:e}");
    let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.5, -0.2, 0.7, -1.1, 2.0]);
    let split = |x: &SVector<f64, 8>| {
        (
            SVector::<f64, 5>::from_column_slice(&x.as_slice()[..5]),
            SVector::<f64, 3>::from_column_slice(&x.as_slice()[5..]),
        )
    };
    let (q0, v0) = split(&x0);
    let j0 = ball.declared_momenta(0.0, &q0, &v0);
    let mut drift = 0.0f64;
    let times: Vec<f64> = (1..=200).map(|i| 0.05 * i as f64).collect();
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&ball, 0.0, x0, 10.0, &times, |_, x| {
            let (q, v) = split(x);
            let j = ball.declared_momenta(0.0, &q, &v);
            drift = drift.max((j - j0).amax());
        })
        .unwrap();
    println!("rolling ball: declared momenta drift {drift:.1e} over 10 s");
    assert!(drift < 1e-11, "{drift:e}");
}
