//! The physically correct rolling disc (`systems::RollingDisc`), checked
//! against an independent Newton–Euler computation of steady rolling on a
//! circle at constant lean, and against the thesis's simplified model.
use nh_lab::systems::{BodyDisc, RollingDisc, ThesisDisc};
use nonholonomic::prelude::*;

type V3 = [f64; 3];
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

/// Newton–Euler residual of steady rolling (ψ̇ = 0, θ̇, φ̇ constant) at φ = 0:
/// the rate of change of the angular momentum about the centre, which in the
/// frame turning with φ̇ z is φ̇ z × H, minus the torque of the contact force
/// F = m a_C + m g z about the centre. Zero for a steady motion.
fn newton_euler_residual(m: f64, r: f64, g: f64, psi: f64, theta_dot: f64, phi_dot: f64) -> V3 {
    let (s, c) = psi.sin_cos();
    let t = [1.0, 0.0, 0.0];
    let l = [0.0, 1.0, 0.0];
    let z = [0.0, 0.0, 1.0];
    let u = add(scale(s, l), scale(c, z)); // contact point → centre
    let n = cross(t, u); // axle
    // body angular velocity (see the RollingDisc docs for the derivation)
    let (w_u, w_n) = (phi_dot * c, phi_dot * s - theta_dot);
    let h = add(
        scale(m * r * r / 4.0 * w_u, u),
        scale(m * r * r / 2.0 * w_n, n),
    );
    let dh = cross(scale(phi_dot, z), h);
    // the contact point runs on a circle of radius R θ̇ / φ̇ about P + ρ l; the
    // centre, at P + R u, on one of radius ρ − R sin ψ about the same axis
    let rho = r * theta_dot / phi_dot;
    let a_c = scale(-phi_dot * phi_dot * (r * s - rho), l);
    let f = add(scale(m, a_c), scale(m * g, z));
    let torque = cross(scale(-r, u), f);
    [dh[0] - torque[0], dh[1] - torque[1], dh[2] - torque[2]]
}

/// The precession rates φ̇ of steady motions for given lean and spin, found
/// as sign changes of the Newton–Euler residual and refined by bisection.
fn steady_precession_rates(m: f64, r: f64, g: f64, psi: f64, theta_dot: f64) -> Vec<f64> {
    let f = |p: f64| newton_euler_residual(m, r, g, psi, theta_dot, p)[0];
    let mut roots = Vec::new();
    let grid: Vec<f64> = (1..=4000)
        .map(|i| -100.0 + 200.0 * i as f64 / 4001.0)
        .collect();
    for w in grid.windows(2) {
        let (mut a, mut b) = (w[0], w[1]);
        if a * b <= 0.0 || f(a).signum() == f(b).signum() {
            continue;
        }
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            if f(a).signum() == f(mid).signum() {
                a = mid;
            } else {
                b = mid;
            }
        }
        roots.push(0.5 * (a + b));
    }
    roots
}

#[test]
fn steady_rolling_on_a_circle_agrees_with_newton_euler() {
    let (m, r, g) = (1.7, 0.35, 9.81);
    let disc: RollingDisc = RollingDisc::new(m, r, g);
    let mut checked = 0;
    for &(psi, theta_dot) in &[
        (0.3, 8.0),
        (0.1, 20.0),
        (-0.4, 15.0),
        (0.6, -12.0),
        (0.2, 3.0),
    ] {
        let roots = steady_precession_rates(m, r, g, psi, theta_dot);
        assert!(
            !roots.is_empty(),
            "no steady motion found for ψ = {psi}, θ̇ = {theta_dot}"
        );
        for phi_dot in roots {
            let res = newton_euler_residual(m, r, g, psi, theta_dot, phi_dot);
            // the other two components of the Newton–Euler balance hold too
            assert!(res.iter().all(|x| x.abs() < 1e-9), "{res:?}");
            let q = SVector::<f64, 5>::from([0.0, 0.0, psi, 0.0, 0.0]);
            let rdot = SVector::<f64, 3>::from([theta_dot, phi_dot, 0.0]);
            let a = disc.accelerations(0.0, &q, &rdot);
            println!(
                "ψ = {psi}, θ̇ = {theta_dot}: φ̇ = {phi_dot:.12}, |r̈| = {:.2e}",
                a.amax()
            );
            assert!(a.amax() < 1e-9, "not steady: {a}");
            checked += 1;
        }
    }
    assert!(checked >= 8);
}

#[test]
fn the_thesis_model_is_not_the_physical_disc() {
    // the thesis's steady motion (6.67) is not steady for the physical disc
    let (m, r, g) = (1.7, 0.35, 9.81);
    let (psi, theta_dot) = (0.3f64, 8.0f64);
    let phi_dot = theta_dot / (2.0 * psi.sin())
        + (theta_dot.powi(2) / (4.0 * psi.sin().powi(2)) - g / (r * psi.cos())).sqrt();
    let q = SVector::<f64, 5>::from([0.0, 0.0, psi, 0.0, 0.0]);
    let rdot = SVector::<f64, 3>::from([theta_dot, phi_dot, 0.0]);
    let thesis: ThesisDisc = ThesisDisc::new(m, r, g);
    let physical: RollingDisc = RollingDisc::new(m, r, g);
    assert!(thesis.accelerations(0.0, &q, &rdot).amax() < 1e-12);
    assert!(physical.accelerations(0.0, &q, &rdot).amax() > 1.0);
}

#[test]
fn energy_is_conserved_along_a_rolling_motion() {
    let disc: RollingDisc = RollingDisc::new(1.7, 0.35, 9.81);
    let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.2, 0.0, 0.0, 15.0, 1.0, 0.3]);
    let e = |x: &SVector<f64, 8>| {
        disc.energy(
            &x.fixed_rows::<5>(0).into_owned(),
            &x.fixed_rows::<3>(5).into_owned(),
        )
    };
    let out = Dopri5::new(1e-12, 1e-14)
        .with_max_steps(1_000_000)
        .integrate(&disc, 0.0, x0, 5.0)
        .expect("the disc rolls for 5 s");
    let drift = (e(&out.x) - e(&x0)).abs() / e(&x0).abs();
    println!("relative energy drift over 5 s: {drift:.2e}");
    assert!(drift < 1e-9);
}

/// The reduced equations of the physical disc in closed form, derived by
/// hand from (5.20) with Lc = mR²[¾θ̇² + ⅝ψ̇² + (¾sin²ψ + ⅛cos²ψ)φ̇² − (3/2) sinψ θ̇φ̇] − mgR cosψ:
/// φ̈ = 2 ψ̇ θ̇ / cos ψ, θ̈ = sin ψ φ̈ + (5/3) cos ψ φ̇ ψ̇,
/// ψ̈ = sin ψ cos ψ φ̇² − (6/5) cos ψ θ̇ φ̇ + (4g / 5R) sin ψ.
#[test]
fn closed_form_derived_by_hand() {
    let (r, g) = (0.35, 9.81);
    let disc: RollingDisc = RollingDisc::new(1.7, r, g);
    let mut worst = 0.0f64;
    for i in 0..200 {
        let f = i as f64;
        let psi = 1.3 * (0.37 * f).sin();
        let (td, pd, sd) = (
            5.0 * (0.11 * f).cos(),
            3.0 * (0.23 * f).sin(),
            2.0 * (0.71 * f).cos(),
        );
        let q = SVector::<f64, 5>::from([0.3 * f, 0.7 * f, psi, f.sin(), f.cos()]);
        let a = disc.accelerations(0.0, &q, &SVector::from([td, pd, sd]));
        let (s, c) = psi.sin_cos();
        let phi_dd = 2.0 * sd * td / c;
        let theta_dd = s * phi_dd + 5.0 / 3.0 * c * pd * sd;
        let psi_dd = s * c * pd * pd - 6.0 / 5.0 * c * td * pd + 4.0 * g / (5.0 * r) * s;
        for (x, y) in [(a[0], theta_dd), (a[1], phi_dd), (a[2], psi_dd)] {
            worst = worst.max((x - y).abs() / y.abs().max(1.0));
        }
    }
    println!("closed form vs generated: {worst:.2e}");
    assert!(worst < 1e-12);
}

/// The disc written as a body with a rolling contact (`systems::BodyDisc`) is
/// the hand-expanded [`RollingDisc`]: the same accelerations, multipliers,
/// dependent velocities and energy at random states, to rounding.
#[test]
fn the_disc_as_a_body_is_the_hand_expanded_disc() {
    let (m, r, g) = (1.7, 0.35, 9.81);
    let hand: RollingDisc = RollingDisc::new(m, r, g);
    let body: BodyDisc = BodyDisc::new(m, r, g);
    assert_eq!(BodyDisc::<f64>::DEPENDENT, RollingDisc::<f64>::DEPENDENT);
    let mut seed = 0x2545_F491_4F6C_DD1D_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let rel = |a: SVector<f64, 3>, b: SVector<f64, 3>| (a - b).amax() / b.amax().max(1e-300);
    let mut worst = [0.0_f64; 4];
    for _ in 0..50 {
        let q = SVector::<f64, 5>::from_fn(|i, _| if i == 2 { 1.4 * next() } else { 3.0 * next() });
        let rdot = SVector::<f64, 3>::from_fn(|_, _| 10.0 * next());
        let a = rel(
            body.accelerations(0.0, &q, &rdot),
            hand.accelerations(0.0, &q, &rdot),
        );
        let (lb, lh) = (
            body.multipliers(0.0, &q, &rdot),
            hand.multipliers(0.0, &q, &rdot),
        );
        let l = (lb - lh).amax() / lh.amax();
        let (sb, sh) = (
            body.dependent_velocities(&q, &rdot),
            hand.dependent_velocities(&q, &rdot),
        );
        let s = (sb - sh).amax() / sh.amax().max(1e-300);
        // (x, y) is the contact point
        let p = body.contact_points(&q);
        assert!((p[(0, 0)] - q[3]).abs() + (p[(1, 0)] - q[4]).abs() + p[(2, 0)].abs() < 1e-15);
        let e =
            (body.energy(&q, &rdot) - hand.energy(&q, &rdot)).abs() / hand.energy(&q, &rdot).abs();
        for (w, v) in worst.iter_mut().zip([a, l, s, e]) {
            *w = w.max(v);
        }
    }
    eprintln!(
        "body disc vs hand-expanded disc (relative): accelerations {:.1e}, multipliers {:.1e}, dependent velocities {:.1e}, energy {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|&w| w < 1e-14), "{worst:?}");
}

nonholonomic_system! {
    /// The disc with its centre's height z as a coordinate and a torus for
    /// a rim (tube radius ρ): `rolls` adds the contact's height
    /// z − R cos ψ − ρ = 0 as a holonomic constraint.
    pub struct TorusDiscZ {
        parameters { m, R, g, rho }
        coordinates { theta, phi, psi, x, y, z }
        let F = rot_z(phi) * rot_x(-psi);
        let C = [x, y, z];
        body disc {
            mass: m, centre: C, orientation: F*rot_y(theta),
            inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4),
        }
        lagrangian = kinetic_energy(disc) - m*g*C.z;
        constraints { rolls(disc, radius: R, axle: [0, 1, 0], tube: rho); }
    }
}

/// With a holonomic contact height (the centre's z a coordinate, z =
/// R cos ψ + ρ for a torus rim of tube radius ρ), the disc is the same: at
/// ρ = 0 its lean, heading and spin accelerate as [`RollingDisc`]'s at the
/// same (θ, φ, ψ) and rates; with a tube, the holonomic residual vanishes
/// at z = R cos ψ + ρ.
#[test]
fn a_holonomic_contact_height_gives_the_same_disc() {
    let (m, r, g) = (1.7, 0.35, 9.81);
    let hand: RollingDisc = RollingDisc::new(m, r, g);
    let torus = TorusDiscZ::new(m, r, g, 0.0);
    assert_eq!(TorusDiscZ::<f64>::INDEPENDENT, [0, 1, 2]);
    let mut worst = 0.0_f64;
    for (k, psi) in [0.1_f64, 0.4, -0.7, 1.1].into_iter().enumerate() {
        let rdot = SVector::<f64, 3>::from([3.0 + k as f64, -1.5, 0.4 * k as f64]);
        let q5 = SVector::<f64, 5>::from([0.2, 0.9, psi, 0.3, -0.1]);
        let q6 = SVector::<f64, 6>::from([0.2, 0.9, psi, 0.3, -0.1, r * psi.cos()]);
        let (a, b) = (
            torus.accelerations(0.0, &q6, &rdot),
            hand.accelerations(0.0, &q5, &rdot),
        );
        worst = worst.max((a - b).amax() / b.amax());
    }
    assert!(worst < 1e-13, "{worst:e}");
    // with a tube, the contact height carries ρ: z = R cos ψ + ρ on the manifold
    let tyre = TorusDiscZ::new(m, r, g, 0.05);
    let q = SVector::<f64, 6>::from([0.0, 0.0, 0.3, 0.0, 0.0, r * 0.3_f64.cos() + 0.05]);
    let x = SVector::<f64, 9>::from_fn(|i, _| if i < 6 { q[i] } else { 1.0 });
    let residual = tyre.constraint_residual(0.0, &x).expect("a holonomic row");
    assert!(residual.abs() < 1e-15, "{residual:e}");
}
