//! An ellipsoid rolling on the plane z = 0, `rolls(BODY, semi_axes: [a, b,
//! c])` (DESIGN §10): the rattleback (Kane and Levinson's ellipsoid, its
//! inertia turned by δ about the vertical body axis) against the same body
//! with its contact written by hand as implicit rows, and with the centre's
//! height left to the contact's holonomic row.
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The rattleback by `rolls`, its centre's height written.
    pub struct ByRolls {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let gam = transpose(R)*[0, 0, 1];
        let s = sqrt(a1^2*gam.x^2 + a2^2*gam.y^2 + a3^2*gam.z^2);
        let Cg = [x, y, s];
        let G = Cg + R*[0, 0, -h];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, semi_axes: [a1, a2, a3], centre: Cg); }
    }
}

nonholonomic_system! {
    /// The rattleback with its contact written by hand: the lowest point
    /// P − C = −R D² γ / s, and no slip of the material point there.
    pub struct ByHand {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let gam = transpose(R)*[0, 0, 1];
        let s = sqrt(a1^2*gam.x^2 + a2^2*gam.y^2 + a3^2*gam.z^2);
        let Cg = [x, y, s];
        let G = Cg + R*[0, 0, -h];
        let w = omega(R);
        let o = -(R*[a1^2*gam.x, a2^2*gam.y, a3^2*gam.z])/s;
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints {
            dot(x) + cross(w, o).x = 0;
            dot(y) + cross(w, o).y = 0;
        }
    }
}

nonholonomic_system! {
    /// The rattleback by `rolls` with the centre's height a coordinate:
    /// the contact's height row holds it.
    pub struct FreeHeight {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let Cg = [x, y, z];
        let G = Cg + R*[0, 0, -h];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, semi_axes: [a1, a2, a3], centre: Cg); }
        outputs { contact_points }
    }
}

/// Kane and Levinson's (1982) ellipsoid and moments (SI units), its inertia
/// turned by δ = 0.1.
const P: [f64; 10] = [
    0.2, 0.03, 0.02, 0.01, 1.0, 2.0e-4, 1.6e-3, 1.7e-3, 0.1, 9.81,
];

fn rng(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// The height of the ellipsoid's centre, √(γᵀ D² γ), γ = Rᵀ e_z.
fn height(psi: f64, theta: f64, phi: f64) -> f64 {
    let _ = psi;
    let gam = [
        -theta.sin(),
        theta.cos() * phi.sin(),
        theta.cos() * phi.cos(),
    ];
    (0..3).map(|i| (P[i] * gam[i]).powi(2)).sum::<f64>().sqrt()
}

#[test]
fn rolls_agrees_with_the_contact_written_by_hand() {
    let [a1, a2, a3, h, m, a, b, c, d, g] = P;
    let rolls = ByRolls::new(a1, a2, a3, h, m, a, b, c, d, g);
    let hand = ByHand::new(a1, a2, a3, h, m, a, b, c, d, g);
    let free = FreeHeight::new(a1, a2, a3, h, m, a, b, c, d, g);
    assert_eq!(ByRolls::<f64>::DEPENDENT, [3, 4]);
    assert_eq!(FreeHeight::<f64>::DEPENDENT, [3, 4, 5]);
    let (mut seed, mut worst, mut worst_free) = (7u64, 0.0f64, 0.0f64);
    for _ in 0..50 {
        let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng(&mut seed);
        let (psi, theta, phi) = (u(-3.0, 3.0), u(-0.6, 0.6), u(-0.6, 0.6));
        let (x, y) = (u(-1.0, 1.0), u(-1.0, 1.0));
        let v = SVector::<f64, 3>::from([u(-5.0, 5.0), u(-2.0, 2.0), u(-2.0, 2.0)]);
        let q = SVector::<f64, 5>::from([psi, theta, phi, x, y]);
        let (acc, want) = (
            rolls.accelerations(0.0, &q, &v),
            hand.accelerations(0.0, &q, &v),
        );
        let scale = want.amax().max(1.0);
        worst = worst.max((acc - want).amax() / scale);
        let sdot = rolls.dependent_velocities(&q, &v) - hand.dependent_velocities(&q, &v);
        worst = worst.max(sdot.amax() / scale);
        let q6 = SVector::<f64, 6>::from([psi, theta, phi, x, y, height(psi, theta, phi)]);
        let got = free.accelerations(0.0, &q6, &v);
        worst_free = worst_free.max((got - want).amax() / scale);
        // the contact point is on the plane, below the centre's footprint
        let p = free.contact_points(&q6);
        assert!(p[(2, 0)].abs() < 1e-15, "{}", p[(2, 0)]);
    }
    println!(
        "rattleback by rolls against by hand: {worst:.1e}; the height a coordinate: {worst_free:.1e}"
    );
    assert!(worst < 1e-13, "{worst:e}");
    assert!(worst_free < 1e-13, "{worst_free:e}");
}
