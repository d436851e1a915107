//! The constraint forms of DESIGN §9 against independent references:
//!
//! * the Chaplygin sled written implicitly (`cos(theta)*dot(y) - sin(theta)*dot(x) = 0`)
//!   agrees with the explicit sled and with its closed form, and a run that
//!   reaches the chart's singularity θ = π/2 ends in `SimError::Singular` with
//!   the last good state in every integrator;
//! * the ball on a turntable (affine constraints, explicit and implicit with
//!   `dependent { .. }`): its centre moves on a circle at 2Ω/7 of the table's
//!   rate;
//! * a pendulum in Cartesian coordinates (a holonomic constraint): the rod
//!   tension from the multiplier, and the residual with and without projection;
//! * the thesis disc with Z as a coordinate and `Z = R*cos(psi)`, equal to the
//!   original;
//! * a knife edge whose heading turns with time (`dot(y) = k*t*dot(x)`), against
//!   its closed form.
// Reference values are copied digit for digit from the JSON.
#![allow(clippy::excessive_precision)]

use nonholonomic::prelude::*;
use serde_json::Value;

#[path = "common/refdata_json.rs"]
mod refdata_json;
// the quaternion ball there is for tests/euler_charts.rs
#[allow(dead_code)]
#[path = "common/turntable.rs"]
mod turntable;
use refdata_json::{arr, load, num, vector};
use turntable::{TurntableBall, ball_centre};

nonholonomic_system! {
    /// Chaplygin sled, the knife edge as written (explicit, singular at θ = π/2).
    pub struct ExplicitSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { multipliers, jacobian }
    }
}

nonholonomic_system! {
    /// Chaplygin sled, the knife edge written implicitly: solved for `y` by
    /// the rule (no constant coefficient: the last declared coordinate).
    pub struct ImplicitSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; }
        outputs { multipliers, jacobian }
    }
}

nonholonomic_system! {
    /// The same ball with implicit rows and named dependent coordinates.
    pub struct TurntableBallImplicit {
        parameters { m, R, Omega }
        coordinates { x, y, phix, phiy, phiz }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + m*R^2/5*(dot(phix)^2 + dot(phiy)^2 + dot(phiz)^2);
        constraints {
            dot(x) - R*dot(phiy) + Omega*y = 0;
            dot(y) + R*dot(phix) = Omega*x;
        }
        dependent { x, y }
    }
}

nonholonomic_system! {
    /// A planar pendulum in Cartesian coordinates (y up): solved for `y`.
    pub struct CartesianPendulum {
        parameters { m, l, g }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - m*g*y;
        constraints { x^2 + y^2 = l^2; }
        outputs { multipliers, jacobian }
    }
}

nonholonomic_system! {
    /// The rolling disc of the thesis (its simplified rotational energy).
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
        outputs { multipliers }
    }
}

nonholonomic_system! {
    /// The same disc with the height Z of its centre a coordinate, held by a
    /// holonomic constraint.
    pub struct ThesisDiscZ {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y, Z }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
            Z = R*cos(psi);
        }
        outputs { multipliers }
    }
}

nonholonomic_system! {
    /// A particle on a knife edge whose heading turns with time: tan of the
    /// heading is k t (a rheonomic constraint).
    pub struct TurningBlade {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2;
        constraints { dot(y) = k*t*dot(x); }
        outputs { jacobian }
    }
}

/// A deterministic uniform sample in [lo, hi).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// The largest difference between a generated Jacobian and central
/// differences of `rhs`, relative to max(1, |entry|).
fn jacobian_error<S: OdeJacobian<f64, D>, const D: usize>(
    s: &S,
    t: f64,
    x: &SVector<f64, D>,
) -> f64 {
    let j = s.jacobian(t, x);
    let mut worst = 0.0f64;
    for i in 0..D {
        let h = 1e-6 * x[i].abs().max(1.0);
        let (mut a, mut b) = (*x, *x);
        a[i] += h;
        b[i] -= h;
        let col = (s.rhs(t, &a) - s.rhs(t, &b)) / (2.0 * h);
        for r in 0..D {
            worst = worst.max((j[(r, i)] - col[r]).abs() / col[r].abs().max(1.0));
        }
    }
    worst
}

#[test]
fn generated_jacobians_match_central_differences() {
    let (m, l, g) = PENDULUM;
    let p = CartesianPendulum::new(m, l, g);
    let blade = TurningBlade::new(2.0, 0.7);
    let e1 = jacobian_error(&p, 0.0, &pendulum_state(0.7, 1.2));
    let e2 = jacobian_error(&blade, 1.3, &SVector::<f64, 3>::new(0.1, 0.2, 1.3));
    println!("Jacobian vs central differences: pendulum {e1:.2e}, turning blade {e2:.2e}");
    assert!(e1 <= 1e-7 && e2 <= 1e-7, "{e1:e} {e2:e}");
}

/// max_i |a_i − b_i| / max(1, |b_i|).
fn rel_err<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>) -> f64 {
    (0..N)
        .map(|i| (a[i] - b[i]).abs() / b[i].abs().max(1.0))
        .fold(0.0, f64::max)
}

fn sled_parameters() -> (f64, f64, f64) {
    let p = &load("chaplygin_sled")["parameters"];
    (num(&p["m"]), num(&p["J"]), num(&p["a"]))
}

#[test]
fn implicit_sled_is_solved_for_y_and_agrees_with_the_explicit_sled() {
    assert_eq!(ImplicitSled::<f64>::DEPENDENT, [2]);
    const { assert!(!ImplicitSled::<f64>::INTEGRABLE) };
    let (m, j, a) = sled_parameters();
    let (exp, imp) = (ExplicitSled::new(m, j, a), ImplicitSled::new(m, j, a));
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let q = SVector::<f64, 3>::new(
            rng.uniform(-2.0, 2.0),
            rng.uniform(-1.4, 1.4),
            rng.uniform(-2.0, 2.0),
        );
        let r = SVector::<f64, 2>::new(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
        let t = rng.uniform(0.0, 1.0);
        worst = worst
            .max(rel_err(
                &imp.accelerations(t, &q, &r),
                &exp.accelerations(t, &q, &r),
            ))
            .max(rel_err(
                &imp.dependent_velocities(&q, &r),
                &exp.dependent_velocities(&q, &r),
            ))
            .max(rel_err(
                &imp.multipliers(t, &q, &r),
                &exp.multipliers(t, &q, &r),
            ));
    }
    println!("implicit vs explicit sled at 200 random states: max relative difference {worst:.2e}");
    assert!(worst <= 1e-12, "{worst:e}");
}

#[test]
fn implicit_sled_matches_the_closed_form() {
    let (m, j, a) = sled_parameters();
    let sled = ImplicitSled::new(m, j, a);
    let data = load("chaplygin_sled");
    let mut worst = 0.0f64;
    for case in arr(&data["analytic"]["cases"]) {
        let values: &[Value] = arr(&case["values"]);
        let state = |e: &Value| {
            let q: SVector<f64, 3> = vector(&e["q"]);
            let r: SVector<f64, 2> = vector(&e["rdot"]);
            SVector::<f64, 5>::new(q[0], q[1], q[2], r[0], r[1])
        };
        let mut x = state(&values[0]);
        let mut t = 0.0;
        for e in &values[1..] {
            let t1 = num(&e["t"]);
            let out = Dopri5::new(1e-10, 1e-12)
                .integrate(&sled, t, x, t1)
                .unwrap();
            (t, x) = (out.t, out.x);
            // the chart is regular along these motions (|θ| < π/2)
            assert!(sled.chart_regularity(t, &x).unwrap() > 0.0);
            worst = worst.max((x - state(e)).amax());
        }
    }
    println!("implicit sled vs closed form: max state error {worst:.2e}");
    assert!(worst <= 1e-7, "{worst:e}");
}

/// The sled's closed form (refdata `chaplygin_sled.json`, `analytic`) with
/// u0 = 0: θ(t) = θ0 + ω0/k gd(k t), k = m a u∞/(J + m a²),
/// u∞ = ω0 sqrt((J + m a²)/m); and the time θ reaches π/2.
fn sled_heading(theta0: f64, omega0: f64, t: f64) -> (f64, f64) {
    let (m, j, a) = sled_parameters();
    let u_inf = omega0 * ((j + m * a * a) / m).sqrt();
    let k = m * a * u_inf / (j + m * a * a);
    let gd = |s: f64| s.sinh().atan();
    let theta = theta0 + omega0 / k * gd(k * t);
    let t_star = ((std::f64::consts::FRAC_PI_2 - theta0) * k / omega0)
        .tan()
        .asinh()
        / k;
    (theta, t_star)
}

fn assert_chart_end(name: &str, result: Result<Outcome<f64, 5>, SimError<f64, 5>>) -> f64 {
    let (theta0, omega0) = (1.0, 1.0);
    let (_, t_star) = sled_heading(theta0, omega0, 0.0);
    match result {
        Err(SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        }) => {
            assert!(x.iter().all(|v| v.is_finite()), "{name}: {x:?}");
            let (theta, _) = sled_heading(theta0, omega0, t);
            println!(
                "{name}: Singular(Chart) at t = {t:.6} (θ reaches π/2 at {t_star:.6}); θ = {:.6}, closed form {theta:.6}",
                x[1]
            );
            assert!(t <= t_star && t > t_star - 0.1, "{name}: t = {t}");
            assert!(x[1] < std::f64::consts::FRAC_PI_2);
            assert!((x[1] - theta).abs() <= 1e-5, "{name}: θ = {}", x[1]);
            t
        }
        other => panic!("{name}: expected Singular(Chart), got {other:?}"),
    }
}

#[test]
fn implicit_sled_in_one_chart_ends_in_a_singular_chart_at_a_right_angle() {
    let (m, j, a) = sled_parameters();
    let sled = ImplicitSled::new(m, j, a);
    // θ0 = 1, u0 = 0, ω0 = 1: θ reaches π/2 at t ≈ 0.59 and tends to 1 + 1.26 π/2
    let x0 = SVector::<f64, 5>::new(0.0, 1.0, 0.0, 0.0, 1.0);
    let t1 = 2.0;
    // kept in its own chart (the atlas's switching off), the run ends there
    assert_chart_end(
        "Rk4",
        Rk4::new(0.01)
            .with_chart_switching(false)
            .integrate(&sled, 0.0, x0, t1),
    );
    assert_chart_end(
        "Dopri5",
        Dopri5::new(1e-8, 1e-10)
            .with_chart_switching(false)
            .integrate(&sled, 0.0, x0, t1),
    );
    assert_chart_end(
        "Dop853",
        Dop853::new(1e-10, 1e-12)
            .with_chart_switching(false)
            .integrate(&sled, 0.0, x0, t1),
    );
    assert_chart_end(
        "Rodas4",
        Rodas4::new(1e-6, 1e-8)
            .with_chart_switching(false)
            .integrate(&sled, 0.0, x0, t1),
    );
    assert_chart_end(
        "GaussLegendre4",
        GaussLegendre4::new(0.01)
            .with_chart_switching(false)
            .integrate(&sled, 0.0, x0, t1),
    );
    // with its atlas it goes on in the chart solved for x, past π/2
    let out = Dopri5::new(1e-8, 1e-10)
        .integrate(&sled, 0.0, x0, t1)
        .expect("the chart solved for x is regular at θ = π/2");
    assert_eq!(out.stats.chart_switches, 1);
    assert!(
        out.x[1] > std::f64::consts::FRAC_PI_2 + 0.1,
        "θ = {}",
        out.x[1]
    );
}

fn ball_run<S: OdeSystem<f64, 8>>(ball: &S, name: &str) {
    let (r, omega) = (0.1, 2.0 * std::f64::consts::PI);
    let (x0, y0, wx, wy, wz) = (0.3, -0.1, 0.7, -0.4, 1.1);
    let v0 = (r * wy - omega * y0, -r * wx + omega * x0);
    let nu = 2.0 * omega / 7.0;
    let mut x = SVector::<f64, 8>::from([x0, y0, 0.0, 0.0, 0.0, wx, wy, wz]);
    let mut t = 0.0;
    let mut worst = 0.0f64;
    for turn in 1..=20 {
        let out = Dop853::new(1e-13, 1e-15)
            .integrate(ball, t, x, turn as f64)
            .unwrap();
        (t, x) = (out.t, out.x);
        let (cx, cy) = ball_centre((x0, y0), v0, nu, t);
        worst = worst.max((x[0] - cx).abs()).max((x[1] - cy).abs());
    }
    println!("{name}: centre vs closed form over 20 table turns: max error {worst:.2e}");
    assert!(worst <= 1e-9, "{name}: {worst:e}");
}

#[test]
fn ball_on_a_turntable_circles_at_two_sevenths_of_the_table_rate() {
    assert_eq!(TurntableBall::<f64>::DEPENDENT, [0, 1]);
    assert_eq!(TurntableBallImplicit::<f64>::DEPENDENT, [0, 1]);
    const { assert!(!TurntableBall::<f64>::INTEGRABLE) };
    let (m, r, omega) = (1.0, 0.1, 2.0 * std::f64::consts::PI);
    ball_run(&TurntableBall::new(m, r, omega), "TurntableBall");
    ball_run(
        &TurntableBallImplicit::new(m, r, omega),
        "TurntableBallImplicit",
    );
}

const PENDULUM: (f64, f64, f64) = (1.5, 1.3, 9.81);

/// The pendulum's state [x, y, ẋ] at angle θ from the downward vertical.
fn pendulum_state(theta: f64, theta_dot: f64) -> SVector<f64, 3> {
    let l = PENDULUM.1;
    SVector::<f64, 3>::new(
        l * theta.sin(),
        -l * theta.cos(),
        l * theta.cos() * theta_dot,
    )
}

#[test]
fn cartesian_pendulum_tension_and_residual() {
    assert_eq!(CartesianPendulum::<f64>::DEPENDENT, [1]);
    const { assert!(CartesianPendulum::<f64>::INTEGRABLE) };
    let (m, l, g) = PENDULUM;
    let p = CartesianPendulum::new(m, l, g);
    // the rod tension: the row solved for y is ẏ + (x/y) ẋ = 0, so λ is the
    // constraint force on y, −T y/l, and T = −λ l/y; the closed form is
    // T = m (g cos θ + l θ̇²)
    let mut worst_tension = 0.0f64;
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    for _ in 0..100 {
        let (theta, theta_dot) = (rng.uniform(-1.4, 1.4), rng.uniform(-3.0, 3.0));
        let s = pendulum_state(theta, theta_dot);
        let (q, r) = (
            SVector::<f64, 2>::new(s[0], s[1]),
            SVector::<f64, 1>::new(s[2]),
        );
        let lambda = p.multipliers(0.0, &q, &r)[0];
        let tension = -lambda * l / q[1];
        let want = m * (g * theta.cos() + l * theta_dot * theta_dot);
        worst_tension = worst_tension.max((tension - want).abs() / want.abs().max(1.0));
    }
    println!(
        "pendulum: tension from λ vs m(g cos θ + l θ̇²): max relative error {worst_tension:.2e}"
    );
    assert!(worst_tension <= 1e-12, "{worst_tension:e}");

    // Newton on y cannot move a state with y = 0 (∂f/∂y = 0) onto the circle
    let mut off = SVector::<f64, 3>::new(2.0 * l, 0.0, 0.0);
    let failure = p.project(0.0, &mut off).unwrap_err();
    assert!(failure.residual.is_nan() || failure.residual > 1e-12);
    // a state near the circle is projected in a few Newton steps
    let mut near = pendulum_state(0.3, 1.0);
    near[1] *= 1.0 + 1e-6;
    assert!(p.project(0.0, &mut near).unwrap());
    assert!(p.constraint_residual(0.0, &near).unwrap() <= 1e-15);

    let x0 = pendulum_state(0.8, 0.0);
    let projected = Dopri5::new(1e-10, 1e-12)
        .integrate(&p, 0.0, x0, 100.0)
        .unwrap();
    let with = projected.max_residual.unwrap();
    let free = Dopri5::new(1e-10, 1e-12)
        .with_projection(false)
        .integrate(&p, 0.0, x0, 100.0)
        .unwrap();
    let without = free.max_residual.unwrap();
    println!(
        "pendulum over 100 s: max residual |x² + y² − l²| {with:.2e} with projection, {without:.2e} without"
    );
    assert!(with <= 1e-12, "{with:e}");
    assert!(without > with);
    // the angle against θ̈ = −(g/l) sin θ
    let f = |_t: f64, s: &SVector<f64, 2>| SVector::<f64, 2>::new(s[1], -g / l * s[0].sin());
    let reference = Dop853::new(1e-13, 1e-15)
        .integrate(&f, 0.0, SVector::<f64, 2>::new(0.8, 0.0), 100.0)
        .unwrap()
        .x[0];
    let theta = projected.x[0].atan2(-projected.x[1]);
    println!("pendulum angle at 100 s: {theta:.12} vs reference {reference:.12}");
    assert!((theta - reference).abs() <= 1e-6);
}

#[test]
fn thesis_disc_with_height_as_a_coordinate_equals_the_original() {
    assert_eq!(ThesisDiscZ::<f64>::DEPENDENT, [3, 4, 5]);
    assert_eq!(ThesisDiscZ::<f64>::INDEPENDENT, [0, 1, 2]);
    let (m, r, g) = (1.7, 0.35, 9.81);
    let (disc, disc_z) = (ThesisDisc::new(m, r, g), ThesisDiscZ::new(m, r, g));
    let mut rng = Rng(0xDEAD_BEEF_CAFE_F00D);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let q: [f64; 5] = std::array::from_fn(|_| rng.uniform(-1.5, 1.5));
        let rdot = SVector::<f64, 3>::from_fn(|_, _| rng.uniform(-3.0, 3.0));
        let q5 = SVector::<f64, 5>::from(q);
        let q6 = SVector::<f64, 6>::from([q[0], q[1], q[2], q[3], q[4], r * q[2].cos()]);
        let a = disc_z.accelerations(0.0, &q6, &rdot);
        let b = disc.accelerations(0.0, &q5, &rdot);
        let (lz, l) = (
            disc_z.multipliers(0.0, &q6, &rdot),
            disc.multipliers(0.0, &q5, &rdot),
        );
        let lxy = SVector::<f64, 2>::new(lz[0], lz[1]);
        worst = worst.max(rel_err(&a, &b)).max(rel_err(&lxy, &l));
    }
    println!(
        "disc with Z vs the original at 200 random states: max relative difference {worst:.2e}"
    );
    assert!(worst <= 1e-12, "{worst:e}");
    // the projection puts Z back on R cos ψ
    let mut x = SVector::<f64, 9>::from([0.1, 0.2, 0.3, 0.4, 0.5, 0.0, 1.0, 0.5, -0.3]);
    assert!(disc_z.project(0.0, &mut x).unwrap());
    assert!((x[5] - r * 0.3f64.cos()).abs() <= 1e-15);
    assert!(disc_z.constraint_residual(0.0, &x).unwrap() <= 1e-15);
}

#[test]
fn turning_blade_matches_its_closed_form() {
    // m ẍ + k t m ÿ = 0 with ẏ = k t ẋ: ẋ = ẋ0/√(1 + k²t²), so
    // x = x0 + ẋ0 asinh(k t)/k, y = y0 + ẋ0 (√(1 + k²t²) − 1)/k
    let (m, k) = (2.0, 0.7);
    let blade = TurningBlade::new(m, k);
    let (x0, y0, v0) = (0.1, 0.2, 1.3);
    let mut x = SVector::<f64, 3>::new(x0, y0, v0);
    let mut t = 0.0;
    let mut worst = 0.0f64;
    for step in 1..=10 {
        let out = Dop853::new(1e-12, 1e-14)
            .integrate(&blade, t, x, step as f64)
            .unwrap();
        (t, x) = (out.t, out.x);
        let s = (1.0 + k * k * t * t).sqrt();
        let want = SVector::<f64, 3>::new(
            x0 + v0 * (k * t).asinh() / k,
            y0 + v0 * (s - 1.0) / k,
            v0 / s,
        );
        worst = worst.max((x - want).amax());
    }
    println!("turning blade vs closed form over 10 s: max error {worst:.2e}");
    assert!(worst <= 1e-9, "{worst:e}");
}
