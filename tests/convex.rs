//! A strictly convex body given by its support function, `rolls(BODY,
//! support_function: h(x, y, z))` (DESIGN §10): the rattleback's ellipsoid
//! rounded by a ball of radius ρ (a Minkowski sum, whose surface has no
//! implicit equation in closed form, h = √(a²x² + b²y² + c²z²) + ρ|d|)
//! against the same body with its contact written by hand as implicit rows,
//! and the plain ellipsoid's support function against `semi_axes`.
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The rounded rattleback by its support function, the centre's height
    /// a coordinate held by the contact's height row.
    pub struct RoundedBySupport {
        parameters { a1, a2, a3, rho, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let Cg = [x, y, z];
        let G = Cg + R*[0, 0, -h];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, support_function: sqrt(a1^2*x^2 + a2^2*y^2 + a3^2*z^2) + rho*sqrt(x^2 + y^2 + z^2), centre: Cg); }
        outputs { contact_points }
    }
}

nonholonomic_system! {
    /// The rounded rattleback with its contact written by hand: the lowest
    /// point P − C = −R D² γ / s − ρ e_z, the centre at height s + ρ, and
    /// no slip of the material point there.
    pub struct RoundedByHand {
        parameters { a1, a2, a3, rho, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let gam = transpose(R)*[0, 0, 1];
        let s = sqrt(a1^2*gam.x^2 + a2^2*gam.y^2 + a3^2*gam.z^2);
        let Cg = [x, y, s + rho];
        let G = Cg + R*[0, 0, -h];
        let w = omega(R);
        let o = -(R*[a1^2*gam.x, a2^2*gam.y, a3^2*gam.z])/s - [0, 0, rho];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints {
            dot(x) + cross(w, o).x = 0;
            dot(y) + cross(w, o).y = 0;
        }
    }
}

nonholonomic_system! {
    /// The plain rattleback by its support function.
    pub struct EllipsoidBySupport {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let Cg = [x, y, z];
        let G = Cg + R*[0, 0, -h];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, support_function: sqrt(a1^2*x^2 + a2^2*y^2 + a3^2*z^2), centre: Cg); }
    }
}

nonholonomic_system! {
    /// The plain rattleback by its semi-axes.
    pub struct EllipsoidBySemiAxes {
        parameters { a1, a2, a3, h, m, A, B, C, delta, g }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let Cg = [x, y, z];
        let G = Cg + R*[0, 0, -h];
        body shell { mass: m, centre: G, orientation: R, inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)) }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, semi_axes: [a1, a2, a3], centre: Cg); }
    }
}

/// Kane and Levinson's (1982) ellipsoid and moments (SI units), its inertia
/// turned by δ = 0.1.
const P: [f64; 10] = [
    0.2, 0.03, 0.02, 0.01, 1.0, 2.0e-4, 1.6e-3, 1.7e-3, 0.1, 9.81,
];
/// The rounding radius.
const RHO: f64 = 0.015;

fn rng(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// The height of the ellipsoid's centre, √(γᵀ D² γ), γ = Rᵀ e_z.
fn height(theta: f64, phi: f64) -> f64 {
    let gam = [
        -theta.sin(),
        theta.cos() * phi.sin(),
        theta.cos() * phi.cos(),
    ];
    (0..3).map(|i| (P[i] * gam[i]).powi(2)).sum::<f64>().sqrt()
}

#[test]
fn a_body_by_its_support_function_agrees_with_its_contact_written_by_hand() {
    let [a1, a2, a3, h, m, a, b, c, d, g] = P;
    let support = RoundedBySupport::new(a1, a2, a3, RHO, h, m, a, b, c, d, g);
    let hand = RoundedByHand::new(a1, a2, a3, RHO, h, m, a, b, c, d, g);
    let by_h = EllipsoidBySupport::new(a1, a2, a3, h, m, a, b, c, d, g);
    let by_axes = EllipsoidBySemiAxes::new(a1, a2, a3, h, m, a, b, c, d, g);
    assert_eq!(RoundedBySupport::<f64>::DEPENDENT, [3, 4, 5]);
    assert_eq!(RoundedByHand::<f64>::DEPENDENT, [3, 4]);
    let (mut seed, mut worst, mut worst_axes) = (11u64, 0.0f64, 0.0f64);
    for _ in 0..50 {
        let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng(&mut seed);
        let (psi, theta, phi) = (u(-3.0, 3.0), u(-0.6, 0.6), u(-0.6, 0.6));
        let (x, y) = (u(-1.0, 1.0), u(-1.0, 1.0));
        let v = SVector::<f64, 3>::from([u(-5.0, 5.0), u(-2.0, 2.0), u(-2.0, 2.0)]);
        let q5 = SVector::<f64, 5>::from([psi, theta, phi, x, y]);
        let want = hand.accelerations(0.0, &q5, &v);
        let z = height(theta, phi);
        let q6 = SVector::<f64, 6>::from([psi, theta, phi, x, y, z + RHO]);
        let got = support.accelerations(0.0, &q6, &v);
        let scale = want.amax().max(1.0);
        worst = worst.max((got - want).amax() / scale);
        let sdot = support.dependent_velocities(&q6, &v);
        let sdot_hand = hand.dependent_velocities(&q5, &v);
        worst = worst.max(
            (sdot[0] - sdot_hand[0])
                .abs()
                .max((sdot[1] - sdot_hand[1]).abs())
                / scale,
        );
        // the contact point is on the plane
        let p = support.contact_points(&q6);
        assert!(p[(2, 0)].abs() < 1e-15, "{}", p[(2, 0)]);
        let e6 = SVector::<f64, 6>::from([psi, theta, phi, x, y, z]);
        let (e1, e2) = (
            by_h.accelerations(0.0, &e6, &v),
            by_axes.accelerations(0.0, &e6, &v),
        );
        worst_axes = worst_axes.max((e1 - e2).amax() / e2.amax().max(1.0));
    }
    println!(
        "rounded rattleback by its support function against by hand: {worst:.1e}; the ellipsoid's support function against semi_axes: {worst_axes:.1e}"
    );
    assert!(worst < 1e-13, "{worst:e}");
    assert!(worst_axes < 1e-13, "{worst_axes:e}");
}
