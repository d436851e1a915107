//! The system's knowledge of its derivatives, from the macro: ∂f/∂t for the
//! implicit methods (`outputs { jacobian }` of a system that depends on t),
//! ∂f/∂p and the forward sensitivities (`outputs { sensitivities }`),
//! against central differences, closed forms and an independent
//! integration of the variational equations (tests/data/sensitivities_sympy.py).

use nonholonomic::prelude::*;
use serde_json::Value;

nonholonomic_system! {
    /// A stiff oscillator driven by a force that varies in time.
    pub struct Forced {
        parameters { m, k, c }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        forces { x: sin(t) - c*dot(x); }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// A stiff oscillator pushed by a force that grows linearly in time
    /// (whose difference in t is exact up to rounding).
    pub struct Ramped {
        parameters { m, k, c, a }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        forces { x: a*t - c*dot(x); }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// A particle on a knife edge whose heading turns with time (tan of the
    /// heading is k t): a rheonomic constraint.
    pub struct TurningBlade {
        parameters { m, k }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2;
        constraints { dot(y) = k*t*dot(x); }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// A cart pushed by an input that is modulated in time.
    pub struct ModulatedCart {
        parameters { m, c }
        coordinates { x }
        inputs { u }
        lagrangian = m*dot(x)^2/2;
        forces { x: u*cos(2*t) - c*dot(x); }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// The damped oscillator m ẍ + c ẋ + k x = 0.
    pub struct Oscillator {
        parameters { m, c, k }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        forces { x: -c*dot(x); }
        outputs { sensitivities }
    }
}

nonholonomic_system! {
    /// Rolling disc of the thesis, section 6.
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4) - m*g*Z;
        constraints { dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }
        outputs { sensitivities }
    }
}

nonholonomic_system! {
    /// The same disc, sensitive to g and R only (in that order).
    pub struct ThesisDiscGR {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4) - m*g*Z;
        constraints { dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }
        outputs { sensitivities(g, R) }
    }
}

nonholonomic_system! {
    /// The Chaplygin sled in generalized speeds, with a time-dependent push
    /// along the blade (Maggi's equations).
    pub struct PushedSled {
        parameters { m, J, a, F }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta);
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        forces { x: F*cos(t)*cos(theta); y: F*cos(t)*sin(theta); }
        outputs { sensitivities }
    }
}

/// The largest of |a − b| / max(floor, |b|) over the entries.
fn rel_dev<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    floor: f64,
) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs() / y.abs().max(floor))
        .fold(0.0, f64::max)
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

    fn vector<const D: usize>(&mut self, lo: f64, hi: f64) -> SVector<f64, D> {
        SVector::from_fn(|_, _| self.uniform(lo, hi))
    }
}

/// ∂f/∂t by central differences.
fn central_in_t<S: OdeSystem<f64, D>, const D: usize>(
    s: &S,
    t: f64,
    x: &SVector<f64, D>,
) -> SVector<f64, D> {
    let h = 1e-5 * t.abs().max(1.0);
    (s.rhs(t + h, x) - s.rhs(t - h, x)) / (2.0 * h)
}

#[test]
fn the_forced_oscillator_has_dfdt_cos_t_over_m() {
    let sys = Forced::new(1.3, 1e4, 50.0);
    assert!(!sys.is_autonomous());
    let mut rng = Rng(0x5eed_0001);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let t = rng.uniform(-5.0, 5.0);
        let x = rng.vector::<2>(-1.0, 1.0);
        let ft = sys.time_derivative(t, &x);
        assert_eq!(ft, OdeJacobian::time_derivative(&sys, t, &x).unwrap());
        let exact = SVector::from([0.0, t.cos() / 1.3]);
        assert!((ft - exact).amax() <= 1e-15, "{ft} vs {exact}");
        worst = worst.max(rel_dev(&ft, &central_in_t(&sys, t, &x), 1e-3));
    }
    assert!(worst <= 1e-7, "against central differences: {worst:e}");
}

#[test]
fn the_turning_blade_has_dfdt_in_closed_form() {
    // f = [ẋ, k t ẋ, −k² t ẋ/(1 + k²t²)], so
    // ∂f/∂t = [0, k ẋ, −k² ẋ (1 − k²t²)/(1 + k²t²)²]
    let (m, k) = (0.8, 1.7);
    let sys = TurningBlade::new(m, k);
    assert!(!sys.is_autonomous());
    let mut rng = Rng(0x5eed_0002);
    let (mut worst_closed, mut worst_central) = (0.0f64, 0.0f64);
    for _ in 0..20 {
        let t = rng.uniform(-2.0, 2.0);
        let x = rng.vector::<3>(-1.0, 1.0);
        let ft = sys.time_derivative(t, &x);
        let kt2 = (k * t).powi(2);
        let exact = SVector::from([
            0.0,
            k * x[2],
            -k * k * x[2] * (1.0 - kt2) / (1.0 + kt2).powi(2),
        ]);
        worst_closed = worst_closed.max(rel_dev(&ft, &exact, 1.0));
        worst_central = worst_central.max(rel_dev(&ft, &central_in_t(&sys, t, &x), 1e-3));
    }
    assert!(
        worst_closed <= 1e-14,
        "against the closed form: {worst_closed:e}"
    );
    assert!(
        worst_central <= 1e-7,
        "against central differences: {worst_central:e}"
    );
}

#[test]
fn a_held_input_forwards_the_time_derivative() {
    let cart = ModulatedCart::new(2.0, 0.5);
    let u = SVector::<f64, 1>::from([3.0]);
    let driven = Driven::new(&cart, u);
    let (t, x) = (0.7, SVector::from([0.1, -0.4]));
    let ft = driven.time_derivative(t, &x).unwrap();
    // ∂/∂t of (u cos 2t − c ẋ)/m
    let exact = SVector::from([0.0, -2.0 * 3.0 * (2.0 * t).sin() / 2.0]);
    assert!((ft - exact).amax() <= 1e-15, "{ft} vs {exact}");
}

#[test]
fn an_autonomous_system_has_a_zero_time_derivative() {
    let disc = ThesisDisc::new(1.7, 0.35, 9.81);
    assert!(disc.is_autonomous());
    let x = SVector::from([0.1, 0.2, 0.3, 0.4, 0.5, 6.0, 20.0, 0.5]);
    assert_eq!(disc.time_derivative(2.0, &x), SVector::<f64, 8>::zeros());
}

/// The same system without its own ∂f/∂t: the implicit methods difference
/// f in t.
struct Differenced<'a>(&'a Ramped);

impl OdeSystem<f64, 2> for Differenced<'_> {
    fn rhs(&self, t: f64, x: &SVector<f64, 2>) -> SVector<f64, 2> {
        self.0.rhs(t, x)
    }
}

impl OdeJacobian<f64, 2> for Differenced<'_> {
    fn jacobian(&self, t: f64, x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        self.0.jacobian(t, x)
    }
}

#[test]
fn rosenbrock_takes_the_analytic_time_derivative() {
    let sys = Ramped::new(1.0, 1e4, 50.0, 3.0);
    assert_eq!(
        sys.time_derivative(0.5, &SVector::zeros()),
        SVector::from([0.0, 3.0])
    );
    let x0 = SVector::from([0.1, 0.0]);
    let mut rodas = Rodas4::new(1e-8, 1e-10);
    let own = rodas.integrate_with_jacobian(&sys, 0.0, x0, 3.0).unwrap();
    let differenced = rodas
        .integrate_with_jacobian(&Differenced(&sys), 0.0, x0, 3.0)
        .unwrap();
    eprintln!(
        "ramped oscillator, Rodas4 rtol 1e-8: {} steps; {} right-hand sides with the analytic ∂f/∂t, {} with the difference ({} Jacobians)",
        own.stats.steps, own.stats.rhs_evals, differenced.stats.rhs_evals, own.stats.jacobian_evals
    );
    // the difference of a linear function is exact up to rounding: the same steps
    assert_eq!(own.stats.steps, differenced.stats.steps);
    assert_eq!(own.stats.rejected, differenced.stats.rejected);
    assert_eq!(own.stats.jacobian_evals, differenced.stats.jacobian_evals);
    assert!(own.stats.jacobian_evals >= own.stats.steps);
    assert_eq!(
        differenced.stats.rhs_evals - own.stats.rhs_evals,
        own.stats.jacobian_evals,
        "one right-hand side fewer per Jacobian"
    );
    // the two ∂f/∂t differ by the difference's rounding (about √ε of f):
    // the runs agree to the tolerance asked for (measured difference
    // 2.7e-12)
    let scale = own.x.amax();
    assert!((own.x - differenced.x).amax() <= 1e-8 * scale);
}

/// ∂f/∂p of the thesis disc by central differences in the parameter fields.
fn disc_parameter_columns(disc: &ThesisDisc, t: f64, x: &SVector<f64, 8>) -> SMatrix<f64, 8, 3> {
    let mut cols = SMatrix::<f64, 8, 3>::zeros();
    for j in 0..3 {
        let value = [disc.m, disc.R, disc.g][j];
        let h = 1e-6 * value.abs().max(1.0);
        let with = |v: f64| {
            let mut d = *disc;
            match j {
                0 => d.m = v,
                1 => d.R = v,
                _ => d.g = v,
            }
            d.rhs(t, x)
        };
        cols.set_column(j, &((with(value + h) - with(value - h)) / (2.0 * h)));
    }
    cols
}

#[test]
fn the_parameter_jacobian_matches_central_differences() {
    let disc = ThesisDisc::new(1.7, 0.35, 9.81);
    assert_eq!(ThesisDisc::SENSITIVITY_PARAMETERS, ["m", "R", "g"]);
    assert_eq!(ThesisDisc::SENSITIVITY_DIM, 8 * (1 + 3 + 8));
    let mut rng = Rng(0x5eed_0003);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let mut x = rng.vector::<8>(-1.0, 1.0);
        x[2] = rng.uniform(-1.2, 1.2);
        let fp = disc.parameter_jacobian(0.0, &x);
        // the mass cancels from the equations of motion
        assert_eq!(fp.column(0).amax(), 0.0);
        worst = worst.max(rel_dev(&fp, &disc_parameter_columns(&disc, 0.0, &x), 1.0));
    }
    assert!(worst <= 1e-7, "{worst:e}");
}

#[test]
fn a_listed_subset_keeps_its_order() {
    let (full, subset) = (
        ThesisDisc::new(1.7, 0.35, 9.81),
        ThesisDiscGR::new(1.7, 0.35, 9.81),
    );
    assert_eq!(ThesisDiscGR::SENSITIVITY_PARAMETERS, ["g", "R"]);
    assert_eq!(ThesisDiscGR::SENSITIVITY_DIM, 8 * (1 + 2 + 8));
    let x = SVector::from([0.1, 0.2, 0.3, 0.4, 0.5, 6.0, 20.0, 0.5]);
    let (all, two) = (
        full.parameter_jacobian(0.0, &x),
        subset.parameter_jacobian(0.0, &x),
    );
    assert_eq!(two.column(0), all.column(2));
    assert_eq!(two.column(1), all.column(1));
}

#[test]
fn the_generated_variational_rhs_is_the_dense_product() {
    let disc = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(0x5eed_0004);
    for _ in 0..20 {
        let x = rng.vector::<8>(-1.0, 1.0);
        let s_p = SMatrix::<f64, 8, 3>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let s_x0 = SMatrix::<f64, 8, 8>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let (f, dsp, dsx) = disc.variational_rhs(0.0, &x, &s_p, &s_x0);
        let j = disc.jacobian(0.0, &x);
        assert!(rel_dev(&f, &disc.rhs(0.0, &x), 1.0) <= 1e-14);
        let dense_p = j * s_p + disc.parameter_jacobian(0.0, &x);
        assert!(rel_dev(&dsp, &dense_p, 1.0) <= 1e-13, "{dsp} vs {dense_p}");
        assert!(rel_dev(&dsx, &(j * s_x0), 1.0) <= 1e-13);
    }
}

#[test]
fn a_system_in_speeds_has_its_parameter_jacobian() {
    let sled = PushedSled::new(2.0, 0.3, 0.5, 1.5);
    let mut rng = Rng(0x5eed_0005);
    let mut worst = 0.0f64;
    for _ in 0..20 {
        let t = rng.uniform(0.0, 3.0);
        let x = rng.vector::<5>(-1.0, 1.0);
        let fp = sled.parameter_jacobian(t, &x);
        let p0 = [sled.m, sled.J, sled.a, sled.F];
        for j in 0..4 {
            let h = 1e-6 * p0[j].abs().max(1.0);
            let with = |v: f64| {
                let mut p = p0;
                p[j] = v;
                PushedSled::new(p[0], p[1], p[2], p[3]).rhs(t, &x)
            };
            let col = (with(p0[j] + h) - with(p0[j] - h)) / (2.0 * h);
            for i in 0..5 {
                worst = worst.max((fp[(i, j)] - col[i]).abs() / col[i].abs().max(1.0));
            }
        }
        worst = worst.max(rel_dev(
            &sled.time_derivative(t, &x),
            &central_in_t(&sled, t, &x),
            1.0,
        ));
    }
    assert!(worst <= 1e-7, "{worst:e}");
}

/// The independent references of tests/data/sensitivities_sympy.py.
fn reference(name: &str) -> Value {
    let path = format!(
        "{}/tests/data/sensitivities.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let all: Value = serde_json::from_str(&text).unwrap();
    all[name].clone()
}

fn num(v: &Value) -> f64 {
    v.as_str().unwrap().parse().unwrap()
}

fn matrix<const R: usize, const C: usize>(v: &Value) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|i, j| num(&v[i][j]))
}

fn vector<const D: usize>(v: &Value) -> SVector<f64, D> {
    SVector::from_fn(|i, _| num(&v[i]))
}

/// x, ∂x/∂p and ∂x/∂x0 at t1 by `sens` under Dop853 at `rtol`.
#[allow(clippy::type_complexity)]
fn run<S, const D: usize, const P: usize, const A: usize>(
    sens: &Sensitivities<'_, S, D, P, A>,
    x0: SVector<f64, D>,
    t1: f64,
    rtol: f64,
) -> (
    SVector<f64, D>,
    SMatrix<f64, D, P>,
    SMatrix<f64, D, D>,
    Stats,
)
where
    S: ParameterJacobian<f64, D, P>,
{
    let out = Dop853::new(rtol, rtol * 1e-2)
        .integrate(sens, 0.0, sens.initial_state(&x0), t1)
        .unwrap();
    let (x, dp, dx0) = sens.split(&out.x);
    (x, dp, dx0, out.stats)
}

/// The relative deviations of x, ∂x/∂p and ∂x/∂x0 from the stored
/// reference `name` (its x0 and t1), integrated by Dop853 at rtol 1e-13,
/// printed with `what`.
fn deviations_from_reference<S, const D: usize, const P: usize, const A: usize>(
    name: &str,
    what: &str,
    sens: &Sensitivities<'_, S, D, P, A>,
) -> [f64; 3]
where
    S: ParameterJacobian<f64, D, P>,
{
    let r = reference(name);
    let x0 = vector::<D>(&r["x0"]);
    let (x, dp, dx0, stats) = run(sens, x0, num(&r["t1"]), 1e-13);
    let devs = [
        rel_dev(&x, &vector::<D>(&r["x"]), 1e-3),
        rel_dev(&dp, &matrix::<D, P>(&r["dx_dp"]), 1e-3),
        rel_dev(&dx0, &matrix::<D, D>(&r["dx_dx0"]), 1e-3),
    ];
    eprintln!("{what}: {devs:?} ({} steps)", stats.steps);
    devs
}

#[test]
fn oscillator_sensitivities_match_the_closed_form() {
    let osc = Oscillator::new(1.3, 0.4, 3.5);
    let what = "oscillator against the closed form";
    let devs = deviations_from_reference("oscillator", what, &osc.sensitivities());
    assert!(devs.iter().all(|&d| d <= 1e-8), "{devs:?}");
}

#[test]
fn thesis_disc_sensitivities_match_an_independent_integration() {
    let disc = ThesisDisc::new(1.7, 0.35, 9.81);
    let what = "thesis disc against an independent integration of the variational equations";
    let devs = deviations_from_reference("thesis_disc", what, &disc.sensitivities());
    assert!(devs.iter().all(|&d| d <= 1e-8), "{devs:?}");
}

#[test]
fn thesis_disc_sensitivities_match_differences_of_whole_runs() {
    let disc = ThesisDisc::new(1.7, 0.35, 9.81);
    let x0 = SVector::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5]);
    let t1 = 1.0;
    let (_, dp, dx0, _) = run(&disc.sensitivities(), x0, t1, 1e-12);
    let plain = |d: &ThesisDisc, x0: SVector<f64, 8>| {
        Dop853::new(1e-14, 1e-16)
            .integrate(d, 0.0, x0, t1)
            .unwrap()
            .x
    };
    let mut fd_p = SMatrix::<f64, 8, 3>::zeros();
    for j in 0..3 {
        let p0 = [disc.m, disc.R, disc.g];
        let h = 1e-5 * p0[j];
        let with = |v: f64| {
            let mut p = p0;
            p[j] = v;
            plain(&ThesisDisc::new(p[0], p[1], p[2]), x0)
        };
        fd_p.set_column(j, &((with(p0[j] + h) - with(p0[j] - h)) / (2.0 * h)));
    }
    let mut fd_x0 = SMatrix::<f64, 8, 8>::zeros();
    for j in 0..8 {
        let h = 1e-5 * x0[j].abs().max(1.0);
        let (mut xp, mut xm) = (x0, x0);
        xp[j] += h;
        xm[j] -= h;
        fd_x0.set_column(j, &((plain(&disc, xp) - plain(&disc, xm)) / (2.0 * h)));
    }
    // relative to the column's scale: a difference resolves an entry only
    // down to (error of the runs)/h of its column's largest
    let scaled = |a: &SMatrix<f64, 8, 3>, b: &SMatrix<f64, 8, 3>| {
        (0..3)
            .map(|j| (a.column(j) - b.column(j)).amax() / b.column(j).amax().max(1e-300))
            .fold(0.0, f64::max)
    };
    let dev_p = scaled(&dp, &fd_p);
    let dev_x0 = (0..8)
        .map(|j| (dx0.column(j) - fd_x0.column(j)).amax() / fd_x0.column(j).amax())
        .fold(0.0, f64::max);
    eprintln!(
        "thesis disc against central differences of whole runs: ∂x/∂p {dev_p:e}, ∂x/∂x0 {dev_x0:e}"
    );
    assert_eq!(fd_p.column(0).amax(), 0.0, "the mass cancels");
    assert!(dev_p <= 1e-6 && dev_x0 <= 1e-6, "{dev_p:e} {dev_x0:e}");
}

#[test]
fn any_integrator_integrates_the_sensitivities() {
    let r = reference("oscillator");
    let osc = Oscillator::new(1.3, 0.4, 3.5);
    let sens = osc.sensitivities();
    let x0 = sens.initial_state(&vector::<2>(&r["x0"]));
    let t1 = num(&r["t1"]);
    let expected = matrix::<2, 3>(&r["dx_dp"]);
    let by_rk4 = Rk4::new(1e-3).integrate(&sens, 0.0, x0, t1).unwrap();
    let by_rodas = Rodas4::new(1e-10, 1e-12)
        .integrate(&sens, 0.0, x0, t1)
        .unwrap();
    for (name, out) in [("Rk4", by_rk4), ("Rodas4", by_rodas)] {
        let (_, dp, _) = sens.split(&out.x);
        let dev = rel_dev(&dp, &expected, 1e-3);
        assert!(dev <= 1e-8, "{name}: {dev:e}");
    }
}
