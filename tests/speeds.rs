//! Systems in generalized speeds (`speeds` and `kinematics`, DESIGN §9)
//! against independent references:
//!
//! * the Chaplygin sled in the speeds (v, ω) against its closed-form
//!   solution, integrated through θ = π/2 (where the explicit form's
//!   `tan(theta)` is singular), and against the explicit sled away from it;
//! * the vertical rolling disc, whose speeds are constant and whose contact
//!   point moves on a circle;
//! * a chart that loses rank, which the runtime ends as a singular chart;
//! * the snakeboard with inputs against Maggi's equations derived
//!   independently in SymPy (`tests/data/snakeboard_speeds_sympy.py`).
use nonholonomic::prelude::*;
use serde_json::Value;

nonholonomic_system! {
    /// Chaplygin sled in generalized speeds: v the speed of the blade along
    /// the body axis, omega the yaw rate.
    pub struct SledSpeeds {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        outputs { energy, mass_matrix, reaction_forces, jacobian }
    }
}

nonholonomic_system! {
    /// The same sled with the explicit constraint (singular at θ = π/2).
    pub struct SledExplicit {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
    }
}

nonholonomic_system! {
    /// Vertical rolling disc: contact point (x, y), rolling angle theta,
    /// heading phi; speeds w (rolling rate) and s (turning rate).
    pub struct VerticalDiscSpeeds {
        parameters { m, R, I, J }
        coordinates { x, y, theta, phi }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + I*dot(theta)^2/2 + J*dot(phi)^2/2;
        speeds { w, s }
        kinematics {
            dot(x) = R*cos(phi)*w;
            dot(y) = R*sin(phi)*w;
            dot(theta) = w;
            dot(phi) = s;
        }
        outputs { energy, reaction_forces }
    }
}

nonholonomic_system! {
    /// A free particle in a chart that loses rank at x = 0:
    /// ẋ = w1 + w2, ẏ = x w2 (det SᵀS = x²).
    pub struct DegenerateChart {
        parameters { m }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2;
        speeds { w1, w2 }
        kinematics {
            dot(x) = w1 + w2;
            dot(y) = x*w2;
        }
    }
}

nonholonomic_system! {
    /// The snakeboard on a belt moving along x at velocity b t (see
    /// tests/data/snakeboard_speeds_sympy.py): xi is the forward speed
    /// relative to the belt, the rotor and the wheels are driven.
    pub struct SnakeboardSpeeds {
        parameters { m, J, Jr, Jw, l, c, b }
        coordinates { x, y, theta, psi, phi }
        inputs { tau_psi, tau_phi }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2 + Jr*(dot(theta) + dot(psi))^2/2
            + Jw*(dot(theta) + dot(phi))^2/2 + Jw*(dot(theta) - dot(phi))^2/2;
        forces { x: -c*dot(x); psi: tau_psi; phi: tau_phi; }
        speeds { xi, w_psi, w_phi }
        kinematics {
            dot(x) = xi*cos(theta) + b*t;
            dot(y) = xi*sin(theta);
            dot(theta) = xi*tan(phi)/l;
            dot(psi) = w_psi;
            dot(phi) = w_phi;
        }
        outputs { reaction_forces, linearization }
    }
}

const M: f64 = 2.0;
const J_SLED: f64 = 0.3;
const A: f64 = 0.5;

#[path = "common/sleigh.rs"]
mod sleigh;

/// The closed form of the sleigh of these tests.
fn sled_closed_form(theta0: f64, v0: f64, omega0: f64, t: f64) -> (f64, f64, f64) {
    sleigh::sleigh_closed_form((M, J_SLED, A), (theta0, v0, omega0), t)
}

#[test]
fn sled_in_speeds_has_maggis_equations_in_closed_form() {
    let sled = SledSpeeds::new(M, J_SLED, A);
    assert_eq!(SledSpeeds::<f64>::SPEEDS, ["v", "omega"]);
    assert_eq!((SledSpeeds::<f64>::N, SledSpeeds::<f64>::K), (3, 2));
    assert_eq!(SledSpeeds::<f64>::STATE_DIM, 5);
    let inertia = J_SLED + M * A * A;
    let q = SVector::<f64, 3>::new(0.3, 1.2, -0.4);
    let u = SVector::<f64, 2>::new(0.7, -1.3);
    let udot = sled.accelerations(0.0, &q, &u);
    // v̇ = a ω², (J + m a²) ω̇ = −m a v ω
    assert!((udot[0] - A * u[1] * u[1]).abs() < 1e-15);
    assert!((udot[1] + M * A * u[0] * u[1] / inertia).abs() < 1e-15);
    let qdot = sled.velocities(0.0, &q, &u);
    assert!((qdot[0] - u[0] * q[1].cos()).abs() < 1e-15);
    assert!((qdot[1] - u[1]).abs() < 1e-15);
    assert!((qdot[2] - u[0] * q[1].sin()).abs() < 1e-15);
    // the mass matrix in the speeds: Sᵀ M S = diag(m, J + m a²)
    let mu = sled.mass_matrix(&q);
    assert!((mu[(0, 0)] - M).abs() < 1e-15 && mu[(0, 1)].abs() < 1e-15);
    assert!((mu[(1, 1)] - inertia).abs() < 1e-15);
    // E = (m v² + (J + m a²) ω²) / 2
    let e = sled.energy(&q, &u);
    assert!((e - 0.5 * (M * u[0] * u[0] + inertia * u[1] * u[1])).abs() < 1e-14);
    // the reaction force is orthogonal to the columns of S, and is the
    // sideways force on the blade: m (v ω + a ω̇) along (−sin θ, cos θ)
    let r = sled.reaction_forces(0.0, &q, &u);
    let (s, c) = q[1].sin_cos();
    let s_cols = [[c, 0.0, s], [0.0, 1.0, 0.0]];
    for col in s_cols {
        let p: f64 = (0..3).map(|i| col[i] * r[i]).sum();
        assert!(p.abs() < 1e-14, "Sᵀ(E − Q) = {p}");
    }
    let lateral = M * (u[0] * u[1] + A * udot[1]);
    assert!((r[0] + lateral * s).abs() < 1e-14, "{r}");
    assert!((r[2] - lateral * c).abs() < 1e-14, "{r}");
    // the chart is regular everywhere: S has orthogonal columns in M
    let x = SVector::<f64, 5>::new(q[0], q[1], q[2], u[0], u[1]);
    let reg = sled.chart_regularity(0.0, &x).expect("a regularity");
    assert!((reg - 1.0).abs() < 1e-15);
}

#[test]
fn sled_in_speeds_crosses_a_quarter_turn_on_its_closed_form() {
    let sled = SledSpeeds::new(M, J_SLED, A);
    let (theta0, v0, omega0) = (1.0, 0.1, 2.0);
    let mut x = SVector::<f64, 5>::new(0.1, theta0, -0.2, v0, omega0);
    let mut dp = Dopri5::new(1e-12, 1e-14);
    let mut t = 0.0;
    let mut worst: f64 = 0.0;
    let mut crossed = false;
    for i in 1..=20 {
        let t1 = 0.5 * f64::from(i);
        let out = dp
            .integrate(&sled, t, x, t1)
            .expect("no singularity in the speeds");
        (t, x) = (out.t, out.x);
        let (theta, v, omega) = sled_closed_form(theta0, v0, omega0, t);
        worst = worst
            .max((x[1] - theta).abs())
            .max((x[3] - v).abs())
            .max((x[4] - omega).abs());
        crossed |= x[1] > std::f64::consts::FRAC_PI_2 + 0.5;
        dp = Dopri5::new(1e-12, 1e-14);
    }
    eprintln!("sled in speeds vs closed form through θ = π/2: {worst:.1e}");
    assert!(crossed, "θ(10) = {} should be well past π/2", x[1]);
    assert!(worst < 1e-9, "max error against the closed form {worst:e}");
}

#[test]
fn sled_in_speeds_agrees_with_the_explicit_sled_away_from_a_quarter_turn() {
    let speeds = SledSpeeds::new(M, J_SLED, A);
    let explicit = SledExplicit::new(M, J_SLED, A);
    // the vector fields, at states with |θ| < 1.2
    let mut worst: f64 = 0.0;
    for i in 0..25 {
        let f = f64::from(i);
        let theta = 1.2 * (0.37 * f).sin();
        let (v, omega) = (0.9 * (1.3 * f).cos(), 1.7 * (0.71 * f + 0.2).sin());
        let (xs, ys) = (0.3 * f.cos(), -0.2 * f);
        let xu = SVector::<f64, 5>::new(xs, theta, ys, v, omega);
        let xe = SVector::<f64, 5>::new(xs, theta, ys, v * theta.cos(), omega);
        let fu = speeds.rhs(0.0, &xu);
        let fe = explicit.rhs(0.0, &xe);
        // ẍ of the explicit sled is d/dt (v cos θ) = v̇ cos θ − v sin θ ω
        let xdd = fu[3] * theta.cos() - v * theta.sin() * omega;
        for (a, b) in [
            (fu[0], fe[0]),
            (fu[1], fe[1]),
            (fu[2], fe[2]),
            (xdd, fe[3]),
            (fu[4], fe[4]),
        ] {
            worst = worst.max((a - b).abs());
        }
    }
    assert!(worst < 1e-13, "vector fields differ by {worst:e}");
    // and one trajectory, θ from −0.6 to about 0.6
    let (theta0, v0, omega0) = (-0.6, 0.4, 0.9);
    let xu0 = SVector::<f64, 5>::new(0.1, theta0, -0.2, v0, omega0);
    let xe0 = SVector::<f64, 5>::new(0.1, theta0, -0.2, v0 * theta0.cos(), omega0);
    let ou = Dopri5::new(1e-12, 1e-14)
        .integrate(&speeds, 0.0, xu0, 5.0)
        .unwrap();
    let oe = Dopri5::new(1e-12, 1e-14)
        .integrate(&explicit, 0.0, xe0, 5.0)
        .unwrap();
    let (xu, xe) = (ou.x, oe.x);
    let diff = (xu[0] - xe[0])
        .abs()
        .max((xu[1] - xe[1]).abs())
        .max((xu[2] - xe[2]).abs())
        .max((xu[3] * xu[1].cos() - xe[3]).abs())
        .max((xu[4] - xe[4]).abs());
    eprintln!("sled in speeds vs explicit sled: fields {worst:.1e}, trajectory {diff:.1e}");
    assert!(diff < 1e-10, "the two forms differ by {diff:e} at t = 5");
}

#[test]
fn vertical_disc_in_speeds_rolls_on_a_circle() {
    let (m, r, i, j) = (1.5, 0.4, 0.12, 0.06);
    let disc = VerticalDiscSpeeds::new(m, r, i, j);
    let (x0, y0, th0, ph0, w, s) = (0.2, -0.1, 0.3, 0.7, 2.5, 0.8);
    let x_init = SVector::<f64, 6>::new(x0, y0, th0, ph0, w, s);
    let out = Dopri5::new(1e-12, 1e-14)
        .integrate(&disc, 0.0, x_init, 7.0)
        .unwrap();
    let (t, x) = (out.t, out.x);
    // closed form: constant speeds, θ and φ linear, the contact point on a
    // circle of radius R w / s
    let phi = ph0 + s * t;
    let rho = r * w / s;
    let expected = [
        x0 + rho * (phi.sin() - ph0.sin()),
        y0 - rho * (phi.cos() - ph0.cos()),
        th0 + w * t,
        phi,
        w,
        s,
    ];
    let err = (0..6)
        .map(|k| (x[k] - expected[k]).abs())
        .fold(0.0, f64::max);
    eprintln!("vertical disc in speeds vs closed form at t = 7: {err:.1e}");
    assert!(err < 1e-10, "error against the closed form {err:e}: {x}");
    let q = x.fixed_rows::<4>(0).into_owned();
    let u = x.fixed_rows::<2>(4).into_owned();
    let e = disc.energy(&q, &u);
    let e_exact = 0.5 * ((m * r * r + i) * w * w + j * s * s);
    assert!((e - e_exact).abs() < 1e-12);
    // the reaction keeps the disc from sliding sideways: m R w s along
    // the inward normal (−sin φ, cos φ) on (x, y), nothing on the angles
    let reaction = disc.reaction_forces(t, &q, &u);
    let centripetal = m * r * w * s;
    assert!(
        (reaction[0] + centripetal * phi.sin()).abs() < 1e-12,
        "{reaction}"
    );
    assert!(
        (reaction[1] - centripetal * phi.cos()).abs() < 1e-12,
        "{reaction}"
    );
    assert!(reaction[2].abs() < 1e-12 && reaction[3].abs() < 1e-12);
}

#[test]
fn a_chart_that_loses_rank_ends_the_run_as_singular() {
    let sys = DegenerateChart::new(1.0);
    // x from −1 towards 0 at unit speed, ẏ = 0.1: w2 = ẏ/x, w1 = ẋ − w2
    let (x0, yd) = (-1.0, 0.1);
    let w2 = yd / x0;
    let x_init = SVector::<f64, 4>::new(x0, 0.0, 1.0 - w2, w2);
    let reg = sys.chart_regularity(0.0, &x_init).unwrap();
    assert!((reg - 0.5).abs() < 1e-15, "x²/(1 + x²) at x = −1: {reg}");
    match Dopri5::new(1e-10, 1e-12).integrate(&sys, 0.0, x_init, 2.0) {
        Err(SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        }) => {
            assert!(x.iter().all(|v| v.is_finite()), "{x}");
            assert!(
                t < 1.0 && t > 0.9,
                "the chart fails near x = 0 (t = 1): t = {t}"
            );
        }
        other => panic!("expected a singular chart, got {other:?}"),
    }
}

fn numbers<const L: usize>(v: &Value) -> SVector<f64, L> {
    let a = v.as_array().expect("an array");
    assert_eq!(a.len(), L);
    SVector::from_fn(|i, _| a[i].as_f64().expect("a number"))
}

#[test]
fn snakeboard_in_speeds_agrees_with_sympy() {
    let text = include_str!("data/snakeboard_speeds.json");
    let data: Value = serde_json::from_str(text).expect("valid JSON");
    let p = &data["parameters"];
    let par = |k: &str| p[k].as_f64().expect("a parameter");
    let sb = SnakeboardSpeeds::new(
        par("m"),
        par("J"),
        par("Jr"),
        par("Jw"),
        par("l"),
        par("c"),
        par("b"),
    );
    let cases = data["cases"].as_array().expect("cases");
    assert!(cases.len() >= 20);
    let (mut worst_udot, mut worst_reaction): (f64, f64) = (0.0, 0.0);
    for case in cases {
        let t = case["t"].as_f64().unwrap();
        let q: SVector<f64, 5> = numbers(&case["q"]);
        let u: SVector<f64, 3> = numbers(&case["u"]);
        let inputs: SVector<f64, 2> = numbers(&case["inputs"]);
        let udot_ref: SVector<f64, 3> = numbers(&case["udot"]);
        let reaction_ref: SVector<f64, 5> = numbers(&case["reaction_forces"]);
        let udot = sb.accelerations(t, &q, &u, &inputs);
        let reaction = sb.reaction_forces(t, &q, &u, &inputs);
        let rel = |a: f64, b: f64| (a - b).abs() / (1.0 + b.abs());
        for i in 0..3 {
            worst_udot = worst_udot.max(rel(udot[i], udot_ref[i]));
        }
        for i in 0..5 {
            worst_reaction = worst_reaction.max(rel(reaction[i], reaction_ref[i]));
        }
    }
    eprintln!(
        "snakeboard vs SymPy: u̇ {worst_udot:.1e}, reaction forces {worst_reaction:.1e} (relative)"
    );
    assert!(worst_udot < 1e-12, "u̇ differs from SymPy by {worst_udot:e}");
    assert!(
        worst_reaction < 1e-12,
        "reaction forces differ by {worst_reaction:e}"
    );
}

#[test]
fn snakeboard_linearization_matches_finite_differences() {
    let sb = SnakeboardSpeeds::new(1.5, 0.2, 0.15, 0.04, 0.4, 0.1, 0.3);
    let x = SVector::<f64, 8>::from([0.3, -0.4, 0.9, 1.1, 0.5, 0.8, -1.2, 0.6]);
    let u = SVector::<f64, 2>::new(0.3, -0.7);
    let t = 1.3;
    let (a, bm) = sb.linearization(t, &x, &u);
    let f = |x: &SVector<f64, 8>, u: &SVector<f64, 2>| sb.rhs_with_input(t, x, u);
    let h = 1e-6;
    let mut worst: f64 = 0.0;
    for j in 0..8 {
        let (mut xp, mut xm) = (x, x);
        xp[j] += h;
        xm[j] -= h;
        let col = (f(&xp, &u) - f(&xm, &u)) / (2.0 * h);
        for i in 0..8 {
            worst = worst.max((a[(i, j)] - col[i]).abs());
        }
    }
    for j in 0..2 {
        let (mut up, mut um) = (u, u);
        up[j] += h;
        um[j] -= h;
        let col = (f(&x, &up) - f(&x, &um)) / (2.0 * h);
        for i in 0..8 {
            worst = worst.max((bm[(i, j)] - col[i]).abs());
        }
    }
    assert!(
        worst < 1e-7,
        "linearization vs central differences: {worst:e}"
    );
}
