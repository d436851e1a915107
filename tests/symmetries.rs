//! Declared symmetries (DESIGN §4.1): one-parameter groups by their
//! generators, checked to leave the Lagrangian, the forces and the
//! constraints invariant; the momenta along the directions the constraints
//! allow and their rates by the nonholonomic momentum equation, against
//! closed forms and along integrations.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A disc rolling upright, with the plane's rotations and translations
    /// and its own spin about its axle.
    pub struct VerticalDisc {
        parameters { m, R, I, J }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + I/2*dot(theta)^2 + J/2*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        symmetries {
            turn(x: -y, y: x, phi: 1);
            spin(theta: 1);
            slide_x(x: 1);
            slide_y(y: 1);
        }
    }
}

nonholonomic_system! {
    /// The Chaplygin sleigh (contact point at the centre of mass), with the
    /// plane's rotations and translations.
    pub struct Sleigh {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        symmetries {
            turn(x: -y, y: x, theta: 1);
            slide_x(x: 1);
            slide_y(y: 1);
        }
    }
}

nonholonomic_system! {
    /// The same sleigh with its heading a rotation, the turn of the plane
    /// written as the heading's turn about z: one angle, so the rate of
    /// `theta` comes from a single row of ω(H) = [0, 0, 1].
    pub struct SleighByHeading {
        parameters { m, J }
        coordinates { x, y, theta }
        let H = rot_z(theta);
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        symmetries {
            turn(x: -y, y: x, H: [0, 0, 1]);
            slide_x(x: 1);
            slide_y(y: 1);
        }
    }
}

#[test]
fn a_turn_of_one_angle_is_its_rate() {
    // `H: [0, 0, 1]` with H = rot_z(theta) is `theta: 1`: the same
    // momenta, rates and verdicts as the sleigh written with the rate
    assert_eq!(
        SleighByHeading::SYMMETRY_CONSERVED,
        Sleigh::SYMMETRY_CONSERVED
    );
    let (a, b) = (Sleigh::new(2.0, 0.3), SleighByHeading::new(2.0, 0.3));
    for (q, v) in [
        ([0.1, 0.2, 0.4], [0.7, 1.3]),
        ([-0.5, 1.1, -1.2], [0.3, -0.8]),
    ] {
        let (q, v) = (SVector::<f64, 3>::from(q), SVector::<f64, 2>::from(v));
        let p = (a.symmetry_momenta(0.0, &q, &v) - b.symmetry_momenta(0.0, &q, &v)).amax();
        let r = (a.symmetry_momentum_rates(0.0, &q, &v) - b.symmetry_momentum_rates(0.0, &q, &v))
            .amax();
        assert!(p < 1e-14 && r < 1e-14, "{p:e} {r:e}");
    }
}

#[test]
fn the_vertical_disc_conserves_its_heading_and_rolling_momenta() {
    // turn + y·slide_x − x·slide_y is the pure turn ∂/∂φ: J φ̇;
    // spin + R cos φ·slide_x + R sin φ·slide_y rolls it: (I + m R²) θ̇
    assert_eq!(
        VerticalDisc::SYMMETRIES,
        ["turn", "spin", "slide_x", "slide_y"]
    );
    assert_eq!(
        VerticalDisc::SYMMETRY_CONSERVED,
        [Conservation::Conserved; 2]
    );
    let (m, r, i, j) = (1.0, 0.3, 0.05, 0.02);
    let disc = VerticalDisc::new(m, r, i, j);
    let q = SVector::<f64, 4>::from([0.4, 1.1, -0.3, 0.7]);
    let v = SVector::<f64, 2>::from([2.0, -0.6]);
    let p = disc.symmetry_momenta(0.0, &q, &v);
    println!("vertical disc: momenta {p:?}");
    assert!((p[0] - j * v[1]).abs() < 1e-15, "{p}");
    assert!((p[1] - (i + m * r * r) * v[0]).abs() < 1e-15, "{p}");
    assert_eq!(
        disc.symmetry_momentum_rates(0.0, &q, &v),
        SVector::<f64, 2>::zeros()
    );
}

/// The sleigh's state split into q and ṙ.
fn split(x: &SVector<f64, 5>) -> (SVector<f64, 3>, SVector<f64, 2>) {
    (
        SVector::<f64, 3>::from([x[0], x[1], x[2]]),
        SVector::<f64, 2>::from([x[3], x[4]]),
    )
}

#[test]
fn the_sleighs_momenta_change_at_their_rates() {
    // slide_x + tan θ·slide_y is the translation along the blade, whose
    // momentum m ẋ sec²θ is the cyclic x's; turn − (x + y tan θ)·slide_y
    // turns it about the origin while keeping to the blade
    assert_eq!(Sleigh::SYMMETRY_CONSERVED, [Conservation::NotConserved; 2]);
    let sleigh = Sleigh::new(2.0, 0.3);
    let x0 = SVector::<f64, 5>::from([0.1, 0.2, 0.4, 0.7, 1.3]);
    let (q, v) = split(&x0);
    let p0 = sleigh.symmetry_momenta(0.0, &q, &v);
    let sec2 = 1.0 / 0.4f64.cos().powi(2);
    assert!((p0[1] - 2.0 * 0.7 * sec2).abs() < 1e-14, "{p0}");
    // along the motion, to θ = 1.44: J(t1) − J(t0) = ∫ dJ/dt (Simpson's
    // rule on outputs every millisecond)
    let times: Vec<f64> = (1..=800).map(|i| 1e-3 * i as f64).collect();
    let mut rates = vec![sleigh.symmetry_momentum_rates(0.0, &q, &v)];
    let mut end = x0;
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&sleigh, 0.0, x0, 0.8, &times, |_, x| {
            let (q, v) = split(x);
            rates.push(sleigh.symmetry_momentum_rates(0.0, &q, &v));
            end = *x;
        })
        .unwrap();
    let weight = |i: usize| match i {
        0 | 800 => 1.0,
        i if i % 2 == 1 => 4.0,
        _ => 2.0,
    };
    let integral = rates
        .iter()
        .enumerate()
        .fold(SVector::<f64, 2>::zeros(), |s, (i, r)| s + r * weight(i))
        * (1e-3 / 3.0);
    let (q1, v1) = split(&end);
    let change = sleigh.symmetry_momenta(0.0, &q1, &v1) - p0;
    println!("sleigh: momenta changed by {change:?}, the integrated rates {integral:?}");
    for k in 0..2 {
        assert!(
            (change[k] - integral[k]).abs() < 1e-8 * change[k].abs(),
            "{change} {integral}"
        );
    }
}

nonholonomic_system! {
    /// A free rigid body (Euler's top without gravity), its orientation in
    /// yaw, pitch and roll; its symmetries are the turns of the body about
    /// the fixed world axes, declared by the axis, not by the angles' rates.
    pub struct FreeTop {
        parameters { A, B, C }
        coordinates { yaw, pitch, roll }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        let w = omega_body(Q);
        lagrangian = (A*w.x^2 + B*w.y^2 + C*w.z^2)/2;
        symmetries {
            about_x(Q: [1, 0, 0]);
            about_y(Q: [0, 1, 0]);
            about_z(Q: [0, 0, 1]);
        }
    }
}

#[test]
fn a_free_bodys_turns_about_fixed_axes_conserve_its_angular_momentum() {
    // The momentum along the turn about world axis e is e·Q I ω_body, the
    // spatial angular momentum's component: conserved, proved by the engine
    assert_eq!(FreeTop::SYMMETRY_CONSERVED, [Conservation::Conserved; 3]);
    let (a, b, c) = (1.0, 2.0, 3.5);
    let top = FreeTop::new(a, b, c);
    let seq = EulerSequence::ZYX;
    let spatial = |x: &SVector<f64, 6>| {
        let (angles, rates) = ([x[0], x[1], x[2]], [x[3], x[4], x[5]]);
        let w = seq.body_rates(&angles, &rates);
        seq.matrix(&angles) * Vector3::new(a * w.x, b * w.y, c * w.z)
    };
    let x0 = SVector::<f64, 6>::from([0.3, -0.4, 1.1, 0.8, -0.5, 1.7]);
    let split = |x: &SVector<f64, 6>| {
        (
            SVector::<f64, 3>::from([x[0], x[1], x[2]]),
            SVector::<f64, 3>::from([x[3], x[4], x[5]]),
        )
    };
    let (q0, v0) = split(&x0);
    let k0 = spatial(&x0);
    let j0 = top.symmetry_momenta(0.0, &q0, &v0);
    let at_start = (j0 - k0).amax();
    println!("free top: symmetry momenta {j0:?} against Q I ω by hand: {at_start:.1e}");
    assert!(at_start < 1e-14, "{at_start:e}");
    let (mut drift, mut turned) = (0.0f64, 0.0f64);
    let times: Vec<f64> = (1..=100).map(|i| 0.02 * i as f64).collect();
    Dop853::new(1e-12, 1e-14)
        .integrate_with_outputs(&top, 0.0, x0, 2.0, &times, |_, x| {
            let (q, v) = split(x);
            drift = drift.max((top.symmetry_momenta(0.0, &q, &v) - k0).amax());
            turned = turned.max((x[2] - x0[2]).abs());
        })
        .unwrap();
    println!("free top: drift {drift:.1e} over 2 s, roll turned by up to {turned:.2} rad");
    assert!(drift < 1e-10, "{drift:e}");
    assert!(turned > 0.5);
}
