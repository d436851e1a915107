//! Rolling on a fixed surface given as the graph of its height,
//! `rolls(BODY, .., on: z = h(x, y), contact: [u, v])` (DESIGN §10).
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A homogeneous ball in a spherical bowl written as the graph of its
    /// lower half, the contact point at (u, v).
    pub struct GraphBowlBall {
        parameters { m, r, Rb, g }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: z = Rb - sqrt(Rb^2 - x^2 - y^2), contact: [u, v]); }
    }
}

nonholonomic_system! {
    /// The same ball in the bowl as a sphere.
    pub struct BowlBall {
        parameters { m, r, Rb, g }
        coordinates { x, y, z, yaw, pitch, roll }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, inside: sphere(Rb, [0, 0, Rb])); }
        dependent { z, x, y }
    }
}

/// A small deterministic generator of numbers in [−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[test]
fn a_ball_in_a_bowl_written_as_a_graph_moves_as_in_the_sphere() {
    let (m, r, big, g) = (0.3, 0.05, 0.8, 9.81);
    let graph = GraphBowlBall::new(m, r, big, g);
    let sphere = BowlBall::new(m, r, big, g);
    assert_eq!(GraphBowlBall::<f64>::INDEPENDENT, [3, 4, 5]);
    assert_eq!(BowlBall::<f64>::INDEPENDENT, [3, 4, 5]);
    assert_eq!(GraphBowlBall::<f64>::DEPENDENT, [0, 1, 2, 6, 7]);
    assert_eq!(BowlBall::<f64>::DEPENDENT, [0, 1, 2]);
    let mut rng = Lcg(7);
    let mut worst = 0.0f64;
    for _ in 0..24 {
        // the direction from the bowl's centre to the contact, below it
        let (a, b) = (0.9 * rng.next(), 0.9 * rng.next());
        let d = [a.sin() * b.cos(), b.sin(), -a.cos() * b.cos()];
        let c = [0, 1, 2].map(|k| [0.0, 0.0, big][k] + (big - r) * d[k]);
        let angles = [rng.next() * 3.0, rng.next(), rng.next() * 3.0];
        let rates = SVector::<f64, 3>::from_fn(|_, _| 4.0 * rng.next());
        let q6 = SVector::<f64, 6>::from_column_slice(&[
            c[0], c[1], c[2], angles[0], angles[1], angles[2],
        ]);
        let mut q8 = SVector::<f64, 8>::zeros();
        q8.fixed_rows_mut::<6>(0).copy_from(&q6);
        q8[6] = big * d[0];
        q8[7] = big * d[1];
        let acc_s = sphere.accelerations(0.0, &q6, &rates);
        let acc_g = graph.accelerations(0.0, &q8, &rates);
        let sdot_s = sphere.dependent_velocities(&q6, &rates);
        let sdot_g = graph.dependent_velocities(&q8, &rates);
        let scale = acc_s.amax().max(1.0);
        worst = worst.max((acc_s - acc_g).amax() / scale);
        for k in 0..3 {
            worst = worst.max((sdot_s[k] - sdot_g[k]).abs() / scale);
        }
        // the contact moves with the centre, scaled by R0/(R0 − r)
        for k in 0..2 {
            let want = big / (big - r) * sdot_s[k];
            worst = worst.max((sdot_g[3 + k] - want).abs() / scale);
        }
    }
    println!("graph of a bowl against the sphere at 24 states: {worst:.1e}");
    assert!(worst < 1e-12, "{worst:e}");
}

nonholonomic_system! {
    /// A homogeneous ball on the slope z = s x, the engine choosing the
    /// dependent coordinates.
    pub struct SlopeBall {
        parameters { m, r, g, s }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: z = s*x, contact: [u, v]); }
    }
}

#[test]
fn a_ball_on_a_slope_rolls_down_at_five_sevenths_of_g_sin_alpha() {
    let (m, r, g, slope): (f64, f64, f64, f64) = (0.7, 0.1, 9.81, 0.4);
    let sys = SlopeBall::new(m, r, g, slope);
    println!("slope: DEPENDENT {:?}", SlopeBall::<f64>::DEPENDENT);
    let alpha = slope.atan();
    // at rest touching the slope at the origin: G = r N, N = (−sin α, 0, cos α)
    let ind = SlopeBall::<f64>::INDEPENDENT;
    let mut q = [0.0; 8];
    q[0] = -r * alpha.sin();
    q[2] = r * alpha.cos();
    let mut x0 = SVector::<f64, 11>::zeros();
    x0.fixed_rows_mut::<8>(0).copy_from_slice(&q);
    let t1 = 1.0;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, t1)
        .expect("runs");
    // down the slope, along −(cos α, 0, sin α)
    let d = 0.5 * 5.0 / 7.0 * g * alpha.sin() * t1 * t1;
    let want = [q[0] - d * alpha.cos(), 0.0, q[2] - d * alpha.sin()];
    let err = (0..3)
        .map(|i| (out.x[i] - want[i]).abs())
        .fold(0.0, f64::max);
    // the contact point is the centre's foot on the slope: G − r N
    let foot = [out.x[0] + r * alpha.sin(), out.x[1]];
    let off = (out.x[6] - foot[0]).abs().max((out.x[7] - foot[1]).abs());
    println!(
        "slope: centre after 1 s {:?}, closed form {want:?}: {err:.1e}; contact point {off:.1e} from the centre's foot; independent {ind:?}",
        &out.x.as_slice()[..3]
    );
    assert!(err < 1e-10 && off < 1e-10, "{err:e} {off:e}");
}

nonholonomic_system! {
    /// A ball with an anisotropic inertia on the wavy terrain
    /// z = a cos(k x) cos(k y) + b x.
    pub struct WavyBall {
        parameters { m, r, g, a, k, b, A, B, C }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(A, B, C) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: z = a*cos(k*x)*cos(k*y) + b*x, contact: [u, v]); }
    }
}

nonholonomic_system! {
    /// A thin uniform disc (a wheel) on the same terrain.
    pub struct WavyDisc {
        parameters { m, r, g, a, k, b }
        coordinates { x, y, z, yaw, roll, spin, u, v }
        let R = rot_z(yaw)*rot_x(roll)*rot_y(spin);
        body disc { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m*r^2/4, m*r^2/2, m*r^2/4) }
        lagrangian = kinetic_energy(disc) - m*g*z;
        constraints { rolls(disc, radius: r, axle: [0, 1, 0], on: z = a*cos(k*x)*cos(k*y) + b*x, contact: [u, v]); }
        dependent { x, y, z, u, v }
    }
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_str().expect("a string").parse().expect("a number")
}

/// The largest difference, relative to the largest acceleration, between
/// the generated accelerations and dependent velocities and the
/// reference's at its states (independent: the three angles).
fn against_reference(
    cases: &serde_json::Value,
    f: impl Fn(&SVector<f64, 8>, &SVector<f64, 3>) -> (SVector<f64, 3>, SVector<f64, 5>),
) -> (usize, f64) {
    let mut worst = 0.0f64;
    let mut count = 0;
    for s in cases.as_array().expect("cases") {
        let vec = |k: &str| -> Vec<f64> { s[k].as_array().expect(k).iter().map(num).collect() };
        let (q, qdot, qddot) = (vec("q"), vec("qdot"), vec("qddot"));
        let q = SVector::<f64, 8>::from_column_slice(&q);
        let rdot = SVector::<f64, 3>::from_column_slice(&qdot[3..6]);
        let (acc, sdot) = f(&q, &rdot);
        let scale = qddot.iter().fold(1.0f64, |m, a| m.max(a.abs()));
        for k in 0..3 {
            worst = worst.max((acc[k] - qddot[3 + k]).abs() / scale);
        }
        for (k, i) in [0, 1, 2, 6, 7].into_iter().enumerate() {
            worst = worst.max((sdot[k] - qdot[i]).abs() / scale);
        }
        count += 1;
    }
    (count, worst)
}

#[test]
fn a_ball_and_a_wheel_on_a_wavy_terrain_agree_with_an_independent_derivation() {
    // tests/data/terrain_sympy.py: minimal coordinates (the contact point
    // and the angles), the centre from the contact geometry, the tangential
    // no-slip rows, Lagrange–d'Alembert with multipliers in SymPy,
    // cross-checked, evaluated at 50 digits at 16 random states each
    let data: serde_json::Value =
        serde_json::from_str(include_str!("data/terrain.json")).expect("json");
    let p = &data["parameters"];
    let v = |k: &str| num(&p[k]);
    assert_eq!(WavyBall::<f64>::DEPENDENT, [0, 1, 2, 6, 7]);
    assert_eq!(WavyDisc::<f64>::DEPENDENT, [0, 1, 2, 6, 7]);
    let ball = WavyBall::new(
        v("m"),
        v("r"),
        v("g"),
        v("a"),
        v("k"),
        v("b"),
        v("A"),
        v("B"),
        v("C"),
    );
    let disc = WavyDisc::new(v("m"), v("r"), v("g"), v("a"), v("k"), v("b"));
    let (nb, wb) = against_reference(&data["ball"], |q, r| {
        (
            ball.accelerations(0.0, q, r),
            ball.dependent_velocities(q, r),
        )
    });
    let (nd, wd) = against_reference(&data["disc"], |q, r| {
        (
            disc.accelerations(0.0, q, r),
            disc.dependent_velocities(q, r),
        )
    });
    println!(
        "wavy terrain against SymPy: ball at {nb} states {wb:.1e}, wheel at {nd} states {wd:.1e}"
    );
    assert!(
        nb == 16 && nd == 16 && wb < 1e-12 && wd < 1e-12,
        "{wb:e} {wd:e}"
    );
}

nonholonomic_system! {
    /// A ball in the trough z = c x², whose bottom is too sharp for it.
    pub struct TroughBall {
        parameters { m, r, g, c }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: z = c*x^2, contact: [u, v]); }
    }
}

#[test]
fn a_ball_that_no_longer_fits_the_surface_ends_the_run_singular() {
    // the trough's curvature 2c/(1 + 4c²x²)^(3/2) is 1/r at |x| = x*: a ball
    // of radius r touches it at one point only where |x| > x*, and rolling
    // down from rest it gets there
    let (m, r, g, c): (f64, f64, f64, f64) = (0.5, 0.1, 9.81, 6.0);
    let sys = TroughBall::new(m, r, g, c);
    assert_eq!(TroughBall::<f64>::DEPENDENT, [0, 1, 2, 6, 7]);
    let fits = (((2.0 * c * r).powf(2.0 / 3.0) - 1.0) / (4.0 * c * c)).sqrt();
    let u0: f64 = 0.3;
    let slope = 2.0 * c * u0;
    let n = [-slope, 0.0, 1.0].map(|k| k / (1.0 + slope * slope).sqrt());
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[0] = u0 + r * n[0];
    x0[2] = c * u0 * u0 + r * n[2];
    x0[6] = u0;
    let out = Dop853::new(1e-10, 1e-12).integrate(&sys, 0.0, x0, 2.0);
    let Err(SimError::Singular { t, x, cause }) = out else {
        panic!("the run should end singular: {out:?}");
    };
    let u = x[6];
    println!(
        "trough: the ball fits where |u| > {fits:.7}; the run ends {cause:?} at t = {t:.6} with the contact at u = {u:.7} ({:.1e} beyond)",
        u / fits - 1.0
    );
    assert!(
        cause == Singularity::Chart && u > fits && u < fits * 1.001,
        "{u}"
    );
}
