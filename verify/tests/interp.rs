//! The interpreter against the compiled code. Every system is written once,
//! in a `system!` invocation that both compiles it with
//! `nonholonomic_system!` and keeps its text, which `nh_core::expand`
//! expands for the interpreter. At random states the interpreter's `f64`
//! results must be the compiled methods' bit for bit, and its double-double
//! results must agree with them to about 1e-13 of the largest entry.
//! `cargo test --release -p nh-verify --test interp -- --nocapture` prints
//! the figures (states, comparisons, worst double-double difference, the
//! time per call of the bicycle's accelerations).

use nh_core::sym::dd::Dd;
use nh_verify::interp::{Arg, Expansion, Shape};
use nonholonomic::prelude::*;
use std::time::Instant;

/// Compiles a system and keeps its text in `$src`.
macro_rules! system {
    ($src:ident, { $($body:tt)* }) => {
        nonholonomic_system! { $($body)* }
        const $src: &str = stringify!($($body)*);
    };
}

/// Random states per system.
const STATES: usize = 100;

/// The largest difference allowed between the double-double and the `f64`
/// evaluation, relative to the result's largest entry.
const DD_TOLERANCE: f64 = 1e-12;

// ---------------------------------------------------------------- the harness

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    /// Uniform in [-1, 1).
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// A vector with entries uniform in [-scale, scale).
    fn vec<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::from_fn(|_, _| scale * self.next())
    }

    /// Parameter values uniform in [0.5, 1.5).
    fn params(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| 1.0 + 0.5 * self.next()).collect()
    }
}

fn vector<const N: usize>(v: &SVector<f64, N>) -> Arg<f64> {
    Arg::Vector(v.as_slice().to_vec())
}

/// x = [q, v].
fn state<const N: usize, const K: usize, const D: usize>(
    q: &SVector<f64, N>,
    v: &SVector<f64, K>,
) -> SVector<f64, D> {
    SVector::from_fn(|i, _| if i < N { q[i] } else { v[i - N] })
}

fn to_dd(a: &Arg<f64>) -> Arg<Dd> {
    match a {
        Arg::Scalar(x) => Arg::Scalar(Dd::from_f64(*x)),
        Arg::Vector(v) => Arg::Vector(v.iter().map(|&x| Dd::from_f64(x)).collect()),
    }
}

/// The interpreter of one system and what it has compared.
struct Checker {
    exp: Expansion,
    calls: usize,
    entries: usize,
    /// The largest relative double-double difference, and in which method.
    worst_dd: (f64, String),
}

impl Checker {
    fn new(src: &str) -> Checker {
        Checker::of(src.parse().expect("a system's text is tokens"))
    }

    fn of(body: proc_macro2::TokenStream) -> Checker {
        let exp = Expansion::new(&nh_core::expand(body)).unwrap_or_else(|e| panic!("{e}"));
        Checker {
            exp,
            calls: 0,
            entries: 0,
            worst_dd: (0.0, String::new()),
        }
    }

    /// Method `method` interpreted in `f64` is `compiled` bit for bit, and in
    /// double-double close to it (relative to its largest entry).
    fn check(&mut self, method: &str, params: &[f64], args: &[(&str, Arg<f64>)], compiled: &[f64]) {
        self.check_scaled(method, params, args, compiled, Some(0.0));
    }

    /// [`Checker::check`] with the double-double difference relative to at
    /// least `floor` (a residual that cancels to nothing is compared with the
    /// size of its terms), or not compared (`None`: at a kink of `abs`, where
    /// the two evaluations may take different sides).
    fn check_scaled(
        &mut self,
        method: &str,
        params: &[f64],
        args: &[(&str, Arg<f64>)],
        compiled: &[f64],
        floor: Option<f64>,
    ) {
        let name = format!("{}::{method}", self.exp.name());
        let got = (self.exp.call(method, params, args)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(got.len(), compiled.len(), "{name}: the number of entries");
        for (i, (g, c)) in got.iter().zip(compiled).enumerate() {
            let same = g.to_bits() == c.to_bits() || g.is_nan() && c.is_nan();
            assert!(
                same,
                "{name}[{i}]: interpreted {g:e}, compiled {c:e} at {args:?}"
            );
        }
        self.calls += 1;
        self.entries += compiled.len();
        let Some(floor) = floor else {
            return;
        };
        let dd_params: Vec<Dd> = params.iter().map(|&p| Dd::from_f64(p)).collect();
        let dd_args: Vec<(&str, Arg<Dd>)> = args.iter().map(|(n, a)| (*n, to_dd(a))).collect();
        let dd =
            (self.exp.call(method, &dd_params, &dd_args)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let scale = compiled.iter().fold(floor, |m, x| m.max(x.abs()));
        if scale.is_finite() && scale > 0.0 {
            for (i, (d, c)) in dd.iter().zip(compiled).enumerate() {
                let rel = (d.to_f64() - c).abs() / scale;
                assert!(
                    rel <= DD_TOLERANCE,
                    "{name}[{i}]: double-double {d:?}, f64 {c:e}: {rel:e}"
                );
                if rel > self.worst_dd.0 {
                    self.worst_dd = (rel, method.to_string());
                }
            }
        }
    }

    fn report(&self) {
        println!(
            "{}: {} calls, {} entries equal bit for bit; double-double within {:.1e} (worst in {})",
            self.exp.name(),
            self.calls,
            self.entries,
            self.worst_dd.0,
            self.worst_dd.1
        );
    }
}

/// ("t", t), ("q", q), (name, v) and any further vectors.
fn args3<const N: usize, const K: usize>(
    t: f64,
    q: &SVector<f64, N>,
    name: &'static str,
    v: &SVector<f64, K>,
) -> Vec<(&'static str, Arg<f64>)> {
    vec![("t", Arg::Scalar(t)), ("q", vector(q)), (name, vector(v))]
}

// ---------------------------------------------------------------- the systems

system!(TAN_SLED, {
    pub struct TanSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { multipliers }
    }
});

#[test]
fn tan_sled() {
    let mut c = Checker::new(TAN_SLED);
    let mut rng = Rng(1);
    for _ in 0..STATES {
        let p = rng.params(3);
        let s = TanSled::new(p[0], p[1], p[2]);
        let (t, q, r) = (rng.next(), rng.vec::<3>(1.0), rng.vec::<2>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check("multipliers", &p, &a, s.multipliers(t, &q, &r).as_slice());
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
        let x = state::<3, 2, 5>(&q, &r);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x))];
        c.check("rhs", &p, &xa, s.rhs(t, &x).as_slice());
    }
    c.report();
}

system!(THESIS_DISC, {
    /// Rolling disc of the thesis, section 6.
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
        outputs { energy, multipliers, curvature, constraint_matrix, mass_matrix, routes }
    }
});

#[test]
fn thesis_disc() {
    let mut c = Checker::new(THESIS_DISC);
    let mut rng = Rng(2);
    for _ in 0..STATES {
        let p = rng.params(3);
        let s = ThesisDisc::new(p[0], p[1], p[2]);
        let (t, q, r) = (rng.next(), rng.vec::<5>(1.0), rng.vec::<3>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        let routes = s.accelerations_multiplier_route(t, &q, &r);
        c.check("accelerations_multiplier_route", &p, &a, routes.as_slice());
        let routes = s.accelerations_curvature_route(t, &q, &r);
        c.check("accelerations_curvature_route", &p, &a, routes.as_slice());
        let (m, f) = s.reduced_system(t, &q, &r);
        let both: Vec<f64> = m.iter().chain(f.iter()).copied().collect();
        c.check("reduced_system", &p, &a, &both);
        c.check("multipliers", &p, &a, s.multipliers(t, &q, &r).as_slice());
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
        c.check("energy", &p, &a[1..], &[s.energy(&q, &r)]);
        let b: Vec<f64> = s
            .curvature(&q)
            .iter()
            .flat_map(|m| m.iter().copied())
            .collect();
        c.check("curvature", &p, &a[1..2], &b);
        c.check(
            "constraint_matrix",
            &p,
            &a[1..2],
            s.constraint_matrix(&q).as_slice(),
        );
        c.check("mass_matrix", &p, &a[1..2], s.mass_matrix(&q).as_slice());
    }
    c.report();
}

system!(PUSHED_SLED, {
    pub struct PushedSled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer; }
        outputs { energy, multipliers, constraint_matrix, mass_matrix, jacobian, linearization }
    }
});

#[test]
fn pushed_sled_with_inputs_and_forces() {
    let mut c = Checker::new(PUSHED_SLED);
    assert_eq!(c.exp.inputs(), ["push", "steer"]);
    let mut rng = Rng(3);
    for _ in 0..STATES {
        let p = rng.params(4);
        let s = PushedSled::new(p[0], p[1], p[2], p[3]);
        let (t, q, r, u) = (
            rng.next(),
            rng.vec::<3>(1.0),
            rng.vec::<2>(1.0),
            rng.vec::<2>(1.0),
        );
        let mut a = args3(t, &q, "rdot", &r);
        a.push(("u", vector(&u)));
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r, &u).as_slice(),
        );
        c.check(
            "multipliers",
            &p,
            &a,
            s.multipliers(t, &q, &r, &u).as_slice(),
        );
        let x = state::<3, 2, 5>(&q, &r);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x)), ("u", vector(&u))];
        c.check("jacobian", &p, &xa, s.jacobian(t, &x, &u).as_slice());
        let (fa, fb) = s.linearization(t, &x, &u);
        let both: Vec<f64> = fa.iter().chain(fb.iter()).copied().collect();
        c.check("linearization", &p, &xa, &both);
        c.check(
            "rhs_with_input",
            &p,
            &xa,
            s.rhs_with_input(t, &x, &u).as_slice(),
        );
        let ja = ControlledJacobian::jacobian_with_input(&s, t, &x, &u);
        c.check("jacobian_with_input", &p, &xa, ja.as_slice());
    }
    c.report();
}

system!(SHAKEN, {
    struct Shaken {
        parameters { m, k, c, A, omega }
        coordinates { x }
        inputs { F }
        let X = x + A*sin(omega*t);
        lagrangian = m/2*dot(X)^2 - k/2*x^2 + exp(x/3) - ln(2 + x^2) + sqrt(1 + x^2) + pi*x^(3/2);
        forces { x: -c*dot(x) + F*cos(pi*t); }
        outputs { jacobian }
    }
});

#[test]
fn shaken_time_dependent() {
    let mut c = Checker::new(SHAKEN);
    let mut rng = Rng(4);
    for _ in 0..STATES {
        let p = rng.params(5);
        let s = Shaken::new(p[0], p[1], p[2], p[3], p[4]);
        // x > 0 for x^(3/2)
        let (t, q, r, u) = (
            rng.next(),
            rng.vec::<1>(0.5).add_scalar(1.0),
            rng.vec::<1>(1.0),
            rng.vec::<1>(1.0),
        );
        let mut a = args3(t, &q, "rdot", &r);
        a.push(("u", vector(&u)));
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r, &u).as_slice(),
        );
        let x = state::<1, 1, 2>(&q, &r);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x)), ("u", vector(&u))];
        c.check("jacobian", &p, &xa, s.jacobian(t, &x, &u).as_slice());
        c.check(
            "time_derivative",
            &p,
            &xa,
            s.time_derivative(t, &x, &u).as_slice(),
        );
    }
    c.report();
}

system!(TURNING_DISC, {
    pub struct TurningDisc {
        parameters { m, R, w }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(w*t)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { multipliers }
    }
});

#[test]
fn time_dependent_constraint() {
    let mut c = Checker::new(TURNING_DISC);
    let mut rng = Rng(5);
    for _ in 0..STATES {
        let p = rng.params(3);
        let s = TurningDisc::new(p[0], p[1], p[2]);
        let (t, q, r) = (rng.next(), rng.vec::<4>(1.0), rng.vec::<2>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check("multipliers", &p, &a, s.multipliers(t, &q, &r).as_slice());
        c.check(
            "dependent_velocities",
            &p,
            &a,
            s.dependent_velocities(t, &q, &r).as_slice(),
        );
    }
    c.report();
}

system!(CARTESIAN_PENDULUM, {
    /// A planar pendulum in Cartesian coordinates (y up): solved for `y`.
    pub struct CartesianPendulum {
        parameters { m, l, g }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - m*g*y;
        constraints { x^2 + y^2 = l^2; }
        outputs { multipliers, jacobian }
    }
});

#[test]
fn holonomic_constraint() {
    let mut c = Checker::new(CARTESIAN_PENDULUM);
    let mut rng = Rng(6);
    for _ in 0..STATES {
        let p = rng.params(3);
        let s = CartesianPendulum::new(p[0], p[1], p[2]);
        let angle = 1.2 * rng.next();
        let q = SVector::<f64, 2>::new(p[1] * angle.sin(), -p[1] * angle.cos() + 0.01 * rng.next());
        let (t, r) = (rng.next(), rng.vec::<1>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check("multipliers", &p, &a, s.multipliers(t, &q, &r).as_slice());
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
        let x = state::<2, 1, 3>(&q, &r);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x))];
        c.check("jacobian", &p, &xa, s.jacobian(t, &x).as_slice());
        let residual = OdeSystem::constraint_residual(&s, t, &x).expect("a holonomic constraint");
        c.check_scaled("constraint_residual", &p, &xa, &[residual], Some(1.0));
        let regularity = OdeSystem::chart_regularity(&s, t, &x).expect("a chart");
        c.check("chart_regularity", &p, &xa, &[regularity]);
    }
    c.report();
}

system!(BODY_DISC, {
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
        outputs { multipliers, energy, contact_points }
    }
});

#[test]
fn body_rolling() {
    let mut c = Checker::new(BODY_DISC);
    let mut rng = Rng(7);
    for _ in 0..STATES {
        let p = rng.params(3);
        let s = BodyDisc::new(p[0], p[1], p[2]);
        let (t, q, r) = (rng.next(), rng.vec::<5>(1.0), rng.vec::<3>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check("multipliers", &p, &a, s.multipliers(t, &q, &r).as_slice());
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
        c.check("energy", &p, &a[1..], &[s.energy(&q, &r)]);
        c.check(
            "contact_points",
            &p,
            &a[1..2],
            s.contact_points(&q).as_slice(),
        );
    }
    c.report();
}

system!(SNAKEBOARD, {
    /// The snakeboard on a belt, in generalized speeds.
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
        outputs { mass_matrix, reaction_forces, jacobian, linearization }
    }
});

#[test]
fn speeds_and_kinematics() {
    let mut c = Checker::new(SNAKEBOARD);
    assert_eq!(c.exp.speeds(), ["xi", "w_psi", "w_phi"]);
    let mut rng = Rng(8);
    for _ in 0..STATES {
        let p = rng.params(7);
        let s = SnakeboardSpeeds::new(p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
        let (t, q, v, u) = (
            rng.next(),
            rng.vec::<5>(1.0),
            rng.vec::<3>(1.0),
            rng.vec::<2>(1.0),
        );
        let mut a = args3(t, &q, "speeds", &v);
        a.push(("u", vector(&u)));
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &v, &u).as_slice(),
        );
        c.check(
            "reaction_forces",
            &p,
            &a,
            s.reaction_forces(t, &q, &v, &u).as_slice(),
        );
        c.check(
            "velocities",
            &p,
            &a[..3],
            s.velocities(t, &q, &v).as_slice(),
        );
        let x = state::<5, 3, 8>(&q, &v);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x)), ("u", vector(&u))];
        let (fa, fb) = s.linearization(t, &x, &u);
        let both: Vec<f64> = fa.iter().chain(fb.iter()).copied().collect();
        c.check("linearization", &p, &xa, &both);
        c.check(
            "rhs_with_input",
            &p,
            &xa,
            s.rhs_with_input(t, &x, &u).as_slice(),
        );
    }
    c.report();
}

system!(GAUNTLET, {
    /// Every function of the language.
    pub struct Gauntlet {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + cosh(y)^2*dot(y)^2)
            - k*(atan2(y, x + 2) + abs(x*y - 1/5) + cot(x + 1) + sec(y/2) + csc(x + 2)
                 + sinh(x*y) + tanh(x - y) + asin(x/3) + acos(y/4) + atan(x*y) + x^7 + y^(1/3) + 2^x);
        outputs { jacobian, energy }
    }
});

#[test]
fn every_function() {
    let mut c = Checker::new(GAUNTLET);
    let mut rng = Rng(9);
    for i in 0..STATES {
        let p = rng.params(2);
        let s = Gauntlet::new(p[0], p[1]);
        let mut q = rng.vec::<2>(1.0);
        q[1] = q[1].abs() + 0.1; // y^(1/3)
        if i % 10 == 0 {
            q[0] = 0.2 / q[1]; // abs at its kink: the sign's zero
        }
        let dd = if i % 10 == 0 { None } else { Some(0.0) };
        let (t, r) = (rng.next(), rng.vec::<2>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check_scaled(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
            dd,
        );
        c.check_scaled("energy", &p, &a[1..], &[s.energy(&q, &r)], dd);
        let x = state::<2, 2, 4>(&q, &r);
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x))];
        c.check_scaled("jacobian", &p, &xa, s.jacobian(t, &x).as_slice(), dd);
    }
    c.report();
}

include!(concat!(env!("OUT_DIR"), "/dense20.rs"));

#[test]
fn chunked_accelerations() {
    let mut c = Checker::new(DENSE20);
    let mut rng = Rng(10);
    for _ in 0..STATES / 4 {
        let p = rng.params(1);
        let s = Synth20::new(p[0]);
        let (t, q, r) = (rng.next(), rng.vec::<20>(1.0), rng.vec::<14>(1.0));
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
    }
    c.report();
}

#[allow(dead_code)]
#[path = "../../examples/whipple_bicycle/model.rs"]
mod whipple_model;

use whipple_model::Whipple;

/// The body of the bicycle model's `nonholonomic_system!`.
fn whipple_body() -> proc_macro2::TokenStream {
    use proc_macro2::TokenTree;
    let file: proc_macro2::TokenStream = (include_str!("../../examples/whipple_bicycle/model.rs")
        .parse())
    .expect("the model is Rust");
    let tokens: Vec<TokenTree> = file.into_iter().collect();
    let at = (tokens.iter())
        .position(|t| matches!(t, TokenTree::Ident(i) if i == "nonholonomic_system"));
    match at.and_then(|i| tokens.get(i + 2)) {
        Some(TokenTree::Group(g)) => g.stream(),
        _ => panic!("no `nonholonomic_system! {{ .. }}` in the model"),
    }
}

/// The benchmark's parameters in declared order, each scaled by 1 ± 5 %.
fn whipple_params(rng: &mut Rng) -> Vec<f64> {
    let b = whipple_model::benchmark();
    let base = [
        b.w, b.c, b.lambda, b.g, b.rR, b.mR, b.IRxx, b.IRyy, b.xB, b.zB, b.mB, b.IBxx, b.IByy,
        b.IBzz, b.IBxz, b.xH, b.zH, b.mH, b.IHxx, b.IHyy, b.IHzz, b.IHxz, b.rF, b.mF, b.IFxx,
        b.IFyy,
    ];
    base.iter().map(|v| v * (1.0 + 0.05 * rng.next())).collect()
}

fn whipple(p: &[f64]) -> Whipple {
    Whipple::new(
        p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13],
        p[14], p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23], p[24], p[25],
    )
}

/// A state near upright running, its pitch put on the front wheel's
/// contact by the compiled projection.
fn whipple_state(s: &Whipple, rng: &mut Rng) -> SVector<f64, 11> {
    let mut x = SVector::<f64, 11>::from_fn(|i, _| match i {
        0 | 1 => 0.3 * rng.next(),
        4 => 0.05 * rng.next(),
        8 | 9 => rng.next(),
        10 => 15.0 + 5.0 * rng.next(),
        _ => 3.0 * rng.next(),
    });
    let _ = OdeSystem::project(s, 0.0, &mut x);
    x
}

#[test]
fn whipple_bicycle() {
    let mut c = Checker::of(whipple_body());
    assert_eq!(c.exp.parameters().len(), 26);
    let mut rng = Rng(11);
    for _ in 0..STATES / 2 {
        let p = whipple_params(&mut rng);
        let s = whipple(&p);
        let x = whipple_state(&s, &mut rng);
        let (q, r) = (
            x.fixed_rows::<8>(0).into_owned(),
            x.fixed_rows::<3>(8).into_owned(),
        );
        let t = rng.next();
        let a = args3(t, &q, "rdot", &r);
        c.check(
            "accelerations",
            &p,
            &a,
            s.accelerations(t, &q, &r).as_slice(),
        );
        c.check(
            "dependent_velocities",
            &p,
            &a[1..],
            s.dependent_velocities(&q, &r).as_slice(),
        );
        c.check("energy", &p, &a[1..], &[s.energy(&q, &r)]);
        c.check("mass_matrix", &p, &a[1..2], s.mass_matrix(&q).as_slice());
        c.check(
            "constraint_matrix",
            &p,
            &a[1..2],
            s.constraint_matrix(&q).as_slice(),
        );
        c.check(
            "contact_points",
            &p,
            &a[1..2],
            s.contact_points(&q).as_slice(),
        );
        let xa = [("t", Arg::Scalar(t)), ("x", vector(&x))];
        c.check("jacobian", &p, &xa, s.jacobian(t, &x).as_slice());
        c.check("rhs", &p, &xa, s.rhs(t, &x).as_slice());
        let residual = OdeSystem::constraint_residual(&s, t, &x).expect("a holonomic constraint");
        c.check_scaled("constraint_residual", &p, &xa, &[residual], Some(1.0));
    }
    c.report();
    whipple_timing(&c.exp, &mut rng);
}

/// Prints the time to read the bicycle's expansion and per call of its
/// accelerations: interpreted in `f64` (bound to its parameters, and
/// through `Expansion::call`, which computes the cache each time) and in
/// double-double, and compiled.
fn whipple_timing(exp: &Expansion, rng: &mut Rng) {
    let tokens = nh_core::expand(whipple_body());
    let start = Instant::now();
    let again = Expansion::new(&tokens).expect("the bicycle");
    let read = start.elapsed().as_secs_f64();
    assert_eq!(again.name(), exp.name());
    let p = whipple_params(rng);
    let s = whipple(&p);
    let x = whipple_state(&s, rng);
    let (q, r) = (
        x.fixed_rows::<8>(0).into_owned(),
        x.fixed_rows::<3>(8).into_owned(),
    );
    let a = args3(0.0, &q, "rdot", &r);
    let mut bound = exp.bind(&p).expect("26 parameters");
    let per_bound = per_call(|| bound.call("accelerations", &a).expect("interpreted")[0]);
    let per_call_f64 = per_call(|| exp.call("accelerations", &p, &a).expect("interpreted")[0]);
    let pd: Vec<Dd> = p.iter().map(|&v| Dd::from_f64(v)).collect();
    let ad: Vec<(&str, Arg<Dd>)> = a.iter().map(|(n, v)| (*n, to_dd(v))).collect();
    let mut bound_dd = exp.bind(&pd).expect("26 parameters");
    let per_dd = per_call(|| bound_dd.call("accelerations", &ad).expect("interpreted")[0].hi);
    let compiled = per_call(|| std::hint::black_box(&s).accelerations(0.0, &q, &r)[0]);
    println!(
        "Whipple: expansion read in {:.1} ms; accelerations per call: interpreted f64 {:.1} µs bound, \
         {:.1} µs through `call`; double-double {:.1} µs bound; compiled {:.2} µs",
        read * 1e3,
        per_bound * 1e6,
        per_call_f64 * 1e6,
        per_dd * 1e6,
        compiled * 1e6
    );
}

/// Seconds per call of `f`, over 2000 calls.
fn per_call(mut f: impl FnMut() -> f64) -> f64 {
    let n = 2000;
    let start = Instant::now();
    for _ in 0..n {
        std::hint::black_box(f());
    }
    start.elapsed().as_secs_f64() / f64::from(n)
}

// ---------------------------------------------------------------- errors

/// The expansion of a system as text (tokens separated by spaces).
fn expansion_text(src: &str) -> String {
    nh_core::expand(src.parse().expect("tokens")).to_string()
}

fn read(text: &str) -> Result<Expansion, String> {
    let tokens: proc_macro2::TokenStream = text.parse().map_err(|e| format!("{e}"))?;
    Expansion::new(&tokens)
}

/// Calls every method the interpreter can run, with every argument 0.3:
/// whatever the results, nothing panics.
fn call_everything(exp: &Expansion) -> usize {
    let p = vec![0.7; exp.parameters().len()];
    let mut ran = 0;
    let names: Vec<String> = exp.methods().map(String::from).collect();
    for m in &names {
        let Ok(shapes) = exp.arguments(m) else {
            continue;
        };
        let args: Vec<(&str, Arg<f64>)> = (shapes.iter())
            .map(|(n, s)| match s {
                Shape::Scalar => (*n, Arg::Scalar(0.3)),
                Shape::Entries(k) => (*n, Arg::Vector(vec![0.3; *k])),
            })
            .collect();
        exp.call(m, &p, &args)
            .unwrap_or_else(|e| panic!("{m}: {e}"));
        let dd: Vec<(&str, Arg<Dd>)> = args.iter().map(|(n, a)| (*n, to_dd(a))).collect();
        let pd: Vec<Dd> = p.iter().map(|&x| Dd::from_f64(x)).collect();
        exp.call(m, &pd, &dd).unwrap_or_else(|e| panic!("{m}: {e}"));
        ran += 1;
    }
    ran
}

#[test]
fn what_is_not_a_system_is_an_error() {
    for text in [
        "",
        "fn main() {}",
        "impl X<f64> { }",
        "pub struct S { a: f64 }",
    ] {
        assert!(read(text).is_err(), "{text}");
    }
    // an expansion that reports an error in the system
    let bad = expansion_text("pub struct Bad { parameters { m } coordinates { x } }");
    let err = read(&bad).expect_err("a compile_error! is no system");
    assert!(err.contains("compile_error"), "{err}");
}

#[test]
fn unknown_syntax_is_reported_with_its_tokens() {
    let text = expansion_text(TAN_SLED);
    let exp = read(&text).expect("the sled");
    let p = [1.0, 1.0, 1.0];
    let a = args3(
        0.0,
        &SVector::<f64, 3>::zeros(),
        "rdot",
        &SVector::<f64, 2>::zeros(),
    );
    assert!(exp.call("accelerations", &p, &a).is_ok());
    let cases = [
        (". sin_cos ()", ". sin_cos_fast ()", "sin_cos_fast"),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = (| z : T | z) (q [1usize]) ;",
            "| z",
        ),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = match q { _ => q [1usize] } ;",
            "match",
        ),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = q [9usize] ;",
            "9usize",
        ),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = q [1usize] ? ;",
            "?",
        ),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = q [1usize] % q [0usize] ;",
            "Rem",
        ),
        (
            "let __nh_q_theta : T = q [1usize] ;",
            "let __nh_q_theta : T = self . unknown (q) ;",
            "unknown",
        ),
    ];
    for (from, to, quoted) in cases {
        assert!(text.contains(from), "{from}");
        let exp = read(&text.replace(from, to)).expect("still a system");
        let err = exp.call("accelerations", &p, &a).expect_err(to);
        assert!(err.contains(quoted), "{to}: {err}");
        assert!(exp.unsupported().any(|(m, _)| m == "accelerations"));
    }
    // a method's misuse: unknown method, missing or extra arguments, wrong shapes
    assert!(exp.call("nothing", &p, &a).is_err());
    assert!(exp.call("accelerations", &p, &a[..2]).is_err());
    assert!(exp.call("dependent_velocities", &p, &a).is_err());
    assert!(exp.call("accelerations", &p[..2], &a).is_err());
    let mut wrong = a.clone();
    wrong[1].1 = Arg::Vector(vec![0.0; 2]);
    assert!(exp.call("accelerations", &p, &wrong).is_err());
}

/// Random mutations of expansions (tokens deleted, duplicated, swapped or
/// replaced) are read and run without a panic.
#[test]
fn mutated_expansions_never_panic() {
    const WORDS: &[&str] = &[
        "floor",
        "1.5",
        "x",
        "(",
        ")",
        "{",
        "}",
        ";",
        "?",
        "|",
        "match",
        "0usize",
        "99usize",
        "let",
        "=",
        "[",
        "]",
        "T",
        "self",
        ".",
        "::",
        "<",
        ">",
        "if",
        "else",
        "for",
        "in",
        "mut",
        "4294967295usize",
        "-",
        "*",
        "&",
        "SVector",
        "zeros",
        "from",
        "__nh_cache",
        "q",
        "rdot",
        "true",
        "\"s\"",
        "0.5f64",
        "powi",
        "sin_cos",
    ];
    let texts = [
        expansion_text(TAN_SLED),
        expansion_text(CARTESIAN_PENDULUM),
        expansion_text(SNAKEBOARD),
    ];
    let mut rng = Rng(12);
    let (mut read_ok, mut ran) = (0, 0);
    for i in 0..600 {
        let mut words: Vec<&str> = texts[i % texts.len()].split(' ').collect();
        for _ in 0..1 + i % 3 {
            let k = ((rng.next() + 1.0) / 2.0 * words.len() as f64) as usize % words.len();
            let w = WORDS[((rng.next() + 1.0) / 2.0 * WORDS.len() as f64) as usize % WORDS.len()];
            match i % 4 {
                0 => drop(words.remove(k)),
                1 => {
                    let w = words[k];
                    words.insert(k, w);
                }
                2 => {
                    let next = (k + 1) % words.len();
                    words.swap(k, next);
                }
                _ => words[k] = w,
            }
        }
        if let Ok(exp) = read(&words.join(" ")) {
            read_ok += 1;
            ran += call_everything(&exp);
        }
    }
    println!("mutations: {read_ok} of 600 read, {ran} methods run");
    assert!(read_ok > 100 && ran > 1000);
}

// ---------------------------------------------------------------- coverage

/// Methods that are not computations on numbers: constructors, the state
/// by name, the projection onto holonomic constraints (a loop with a
/// closure), the sensitivities' runtime object and the name of a pole a
/// step crossed.
const NOT_NUMERIC: &[&str] = &[
    "new",
    "from",
    "from_parameters",
    "parameters",
    "state",
    "split",
    "state_from_velocities",
    "state_from_known_velocities",
    "__nh_c",
    "project",
    "sensitivities",
    "crossed_pole",
    // the atlas's methods reach the other charts' hidden systems, which
    // the tests of the atlas run compiled (tests/atlas.rs)
    "charts",
    "chart_name",
    "rhs_in_chart",
    "rhs_with_input_in_chart",
    "chart_regularity_in",
    "crossed_pole_in",
    "constraint_residual_in",
    "project_in",
    "change_chart",
    "change_chart_near",
    "chart_switch_below",
    "free_rotation",
    "jacobian_in_chart",
    "jacobian_with_input_in_chart",
];

/// The bodies of the `nonholonomic_system!` invocations in a file.
fn invocations(src: &str) -> Vec<proc_macro2::TokenStream> {
    use proc_macro2::TokenTree;
    fn walk(ts: proc_macro2::TokenStream, out: &mut Vec<proc_macro2::TokenStream>) {
        let tokens: Vec<TokenTree> = ts.into_iter().collect();
        for (i, t) in tokens.iter().enumerate() {
            match (t, tokens.get(i + 2)) {
                (TokenTree::Ident(id), Some(TokenTree::Group(g)))
                    if id == "nonholonomic_system" =>
                {
                    out.push(g.stream())
                }
                (TokenTree::Group(g), _) => walk(g.stream(), out),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    if let Ok(ts) = src.parse() {
        walk(ts, &mut out);
    }
    out
}

/// Every system of the repository's tests and examples: every method that
/// computes numbers is interpreted and runs.
#[test]
fn every_system_of_the_repository() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in ["tests", "tests/pass", "examples"] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        files.extend(
            entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "rs")),
        );
    }
    files.push(root.join("examples/whipple_bicycle/model.rs"));
    files.sort();
    let (mut systems, mut methods) = (0, 0);
    for file in &files {
        let src = std::fs::read_to_string(file).expect("readable");
        for body in invocations(&src) {
            let Ok(exp) = Expansion::new(&nh_core::expand(body)) else {
                continue; // a system written to fail, or one a macro builds
            };
            for (m, e) in exp.unsupported() {
                assert!(
                    NOT_NUMERIC.contains(&m),
                    "{}: {}::{m}: {e}",
                    file.display(),
                    exp.name()
                );
            }
            methods += call_everything(&exp);
            systems += 1;
        }
    }
    println!("{systems} systems of the repository, {methods} methods run");
    assert!(systems > 80, "{systems} systems");
}
