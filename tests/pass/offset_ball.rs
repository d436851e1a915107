//! A ball whose centre of mass is offset from its geometric centre (a Chaplygin
//! top, "rattleback-like sphere") rolling without slipping on a horizontal plane.
//!
//! Model. World frame: z up, the plane is z = 0. The ball has radius R and mass m;
//! its centre of mass G lies at distance `a` from the geometric centre C along the
//! body's third axis, G = C − a e3 (below C when upright); the body axes are
//! principal axes of inertia at G with moments I1, I2, I3.
//!
//! Coordinates: Z-Y-X Euler angles (yaw psi about the world z axis, then pitch
//! theta about the new y axis, then roll phi about the body x axis), the rotation
//! body → world being Rz(psi) Ry(theta) Rx(phi), and the contact point (x, y),
//! which lies directly below C = (x, y, R). The angles are singular only at
//! theta = ±π/2, far from the motions near upright used here.
//!
//! Body components of the angular velocity:
//!   w1 = φ̇ − ψ̇ sin θ,  w2 = θ̇ cos φ + ψ̇ cos θ sin φ,  w3 = ψ̇ cos θ cos φ − θ̇ sin φ;
//! world components: ω_x = φ̇ cos ψ cos θ − θ̇ sin ψ, ω_y = θ̇ cos ψ + φ̇ sin ψ cos θ,
//! ω_z = ψ̇ − φ̇ sin θ. e3 in world components is
//! (cos ψ sin θ cos φ + sin ψ sin φ, sin ψ sin θ cos φ − cos ψ sin φ, cos θ cos φ).
//!
//! Rolling without slipping: the material point at the contact, C − R e_z, is at
//! rest: (ẋ, ẏ, 0) + ω × (−R e_z) = 0, i.e. ẋ = R ω_y, ẏ = −R ω_x (world
//! components); ω_z (pivoting) is free. The dependent coordinates are x and y.
//!
//! L = m/2 |Ġ|² + (I1 w1² + I2 w2² + I3 w3²)/2 − m g z_G. The constraints are
//! ideal and L does not depend on t, so the energy is conserved.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct OffsetBall {
        parameters { m, R, a, I1, I2, I3, g }
        coordinates { psi, theta, phi, x, y }

        // body components of the angular velocity (Z-Y-X Euler angles)
        let w1 = dot(phi) - dot(psi)*sin(theta);
        let w2 = dot(theta)*cos(phi) + dot(psi)*cos(theta)*sin(phi);
        let w3 = dot(psi)*cos(theta)*cos(phi) - dot(theta)*sin(phi);

        // the centre of mass G = C - a e3, C = (x, y, R)
        let X = x - a*(cos(psi)*sin(theta)*cos(phi) + sin(psi)*sin(phi));
        let Y = y - a*(sin(psi)*sin(theta)*cos(phi) - cos(psi)*sin(phi));
        let Z = R - a*cos(theta)*cos(phi);

        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + (I1*w1^2 + I2*w2^2 + I3*w3^2)/2
                   - m*g*Z;

        constraints {
            // x' = R ω_y, y' = -R ω_x (world components of ω)
            dot(x) = R*cos(psi)*dot(theta) + R*sin(psi)*cos(theta)*dot(phi);
            dot(y) = R*sin(psi)*dot(theta) - R*cos(psi)*cos(theta)*dot(phi);
        }
        outputs { energy }
    }
}

fn main() {
    // m, R, a, I1, I2, I3, g: unequal moments, so the motion is not trivial
    let ball = OffsetBall::new(1.5, 0.2, 0.05, 0.012, 0.016, 0.02, 9.81);
    assert_eq!(OffsetBall::<f64>::DEPENDENT, [3, 4]);

    // state [ψ, θ, φ, x, y, ψ̇, θ̇, φ̇]: tilted, spinning about the vertical, rocking
    let x0 = SVector::<f64, 8>::from([0.1, 0.3, -0.2, 0.0, 0.0, 5.0, 0.4, -0.7]);
    let (q0, r0) = (
        x0.fixed_rows::<5>(0).into_owned(),
        x0.fixed_rows::<3>(5).into_owned(),
    );
    let acc = ball.accelerations(0.0, &q0, &r0);
    assert!(acc.iter().all(|v| v.is_finite()), "accelerations {acc:?}");
    assert!(
        acc.amax() > 1e-3,
        "a tilted spinning ball accelerates: {acc:?}"
    );

    // r̈ from an independent SymPy derivation (tests/data/offset_ball_sympy.py: ω from
    // Qᵀ Q̇ of the rotation matrix, the multiplier method, evaluated to 50 digits)
    let reference: [([f64; 8], [f64; 3]); 3] = [
        (
            [0.1, 0.3, -0.2, 0.0, 0.0, 5.0, 0.4, -0.7],
            [1.895379655179986, -4.907014922583902, 6.378613492249760],
        ),
        (
            [1.3, -0.6, 0.9, 0.25, -1.5, -2.0, 1.7, 0.3],
            [8.876195978491404, 4.845213788271818, -16.24210732978638],
        ),
        (
            [-2.2, 0.8, 0.45, 3.0, 2.0, 0.6, -3.1, 2.4],
            [-17.04775894005309, -10.06731690341038, -18.23334251906215],
        ),
    ];
    for (s, want) in reference {
        let q = SVector::<f64, 5>::from([s[0], s[1], s[2], s[3], s[4]]);
        let got = ball.accelerations(0.0, &q, &SVector::from([s[5], s[6], s[7]]));
        let err = (got - SVector::from(want)).amax() / SVector::from(want).amax();
        assert!(err < 1e-12, "state {s:?}: {got:?} against SymPy {want:?}");
    }

    let e0 = ball.energy(&q0, &r0);
    let mut worst = 0.0_f64;
    let out = Dop853::new(1e-12, 1e-12)
        .integrate_with_observer(&ball, 0.0, x0, 2.0, |_, x| {
            let (q, r) = (
                x.fixed_rows::<5>(0).into_owned(),
                x.fixed_rows::<3>(5).into_owned(),
            );
            worst = worst.max(((ball.energy(&q, &r) - e0) / e0).abs());
        })
        .unwrap_or_else(|e| panic!("integration failed: {e}"));
    assert!(out.stats.steps > 10, "{:?}", out.stats);
    assert!(worst < 1e-8, "relative energy drift {worst:e}");
}
