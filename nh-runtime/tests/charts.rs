//! Switching charts at run time (DESIGN §6.7), on the knife edge: a sleigh
//! whose centre of mass is at the blade, q = (x, y, θ), constraint
//! sin θ ẋ − cos θ ẏ = 0, L = ½m(ẋ² + ẏ²) + ½Iθ̇². Its motion is known in
//! closed form: θ = θ0 + ω t at constant speed v along the heading.
use nalgebra::{Matrix5, SVector, Vector1, Vector5};
use nh_runtime::{
    AutoSwitch, Bdf, Dop853, Dopri5, Events, GaussLegendre4, Integrator, OdeJacobian, OdeSystem,
    Rk4, Rodas4, Rodas5P, SimError, Singularity, Stats,
};

type V5 = Vector5<f64>;

/// The knife edge in chart 0 alone (solved for ẏ): x = [x, y, θ, ẋ, θ̇],
/// ẏ = tan θ ẋ, ẍ = −ẋ tan θ θ̇, θ̈ = 0; regularity cos θ.
struct KnifeChart0;

fn rhs_solved_for_y(x: &V5) -> V5 {
    let tan = x[2].tan();
    V5::new(x[3], tan * x[3], x[4], -x[3] * tan * x[4], 0.0)
}

fn jacobian_solved_for_y(x: &V5) -> Matrix5<f64> {
    let (tan, sec2) = (x[2].tan(), 1.0 / x[2].cos().powi(2));
    let (u, w) = (x[3], x[4]);
    let mut j = Matrix5::zeros();
    j[(0, 3)] = 1.0;
    j[(1, 2)] = sec2 * u;
    j[(1, 3)] = tan;
    j[(2, 4)] = 1.0;
    j[(3, 2)] = -u * sec2 * w;
    j[(3, 3)] = -tan * w;
    j[(3, 4)] = -u * tan;
    j
}

impl OdeSystem<f64, 5> for KnifeChart0 {
    fn rhs(&self, _t: f64, x: &V5) -> V5 {
        rhs_solved_for_y(x)
    }

    fn chart_regularity(&self, _t: f64, x: &V5) -> Option<f64> {
        Some(x[2].cos())
    }

    fn is_autonomous(&self) -> bool {
        true
    }
}

impl OdeJacobian<f64, 5> for KnifeChart0 {
    fn jacobian(&self, _t: f64, x: &V5) -> Matrix5<f64> {
        jacobian_solved_for_y(x)
    }
}

const THETA0: f64 = 0.3;

/// The start: at the origin, heading θ0, speed 1, turning at 1 rad/s.
fn start() -> V5 {
    V5::new(0.0, 0.0, THETA0, THETA0.cos(), 1.0)
}

/// FNV-1a over 64-bit words.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn float(&mut self, v: f64) {
        self.word(v.to_bits());
    }
    fn state(&mut self, x: &SVector<f64, 5>) {
        x.iter().for_each(|&v| self.float(v));
    }
    fn stats(&mut self, s: &Stats) {
        for w in [
            s.steps,
            s.rejected,
            s.rhs_evals,
            s.jacobian_evals,
            s.newton_iterations,
            s.lu_decompositions,
            s.event_evals,
            s.switches_to_stiff,
            s.switches_to_nonstiff,
            s.stiff_steps,
            usize::from(s.stiffness_detected),
        ] {
            self.word(w as u64);
        }
    }
}

/// The bits of the runs every entry point makes of the one-chart knife
/// edge: plain to t = 0.9 (θ = 1.2), into the singularity (t = 3, ending
/// in `Singular { cause: Chart }`), output times every 0.05, every step's
/// ends and midpoint, an observer, and a terminal event (x = 0.5).
fn fingerprint<I: Integrator<f64>>(i: &mut I) -> u64 {
    let mut h = Fnv::new();
    let sys = KnifeChart0;
    let out = i.integrate(&sys, 0.0, start(), 0.9).unwrap();
    h.state(&out.x);
    h.stats(&out.stats);
    match i.integrate(&sys, 0.0, start(), 3.0) {
        Err(SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        }) => {
            h.float(t);
            h.state(&x);
        }
        other => panic!("{other:?}"),
    }
    let times: Vec<f64> = (0..=18).map(|k| 0.05 * k as f64).collect();
    let out = i
        .integrate_with_outputs(&sys, 0.0, start(), 0.9, &times, |t, x| {
            h.float(t);
            h.state(x);
        })
        .unwrap();
    h.stats(&out.stats);
    i.integrate_with_steps(&sys, 0.0, start(), 0.9, |s| {
        h.float(s.t());
        h.state(s.x());
        h.state(&s.interpolate(0.5 * (s.t_prev() + s.t())));
    })
    .unwrap();
    i.integrate_with_observer(&sys, 0.0, start(), 0.9, |t, x| {
        h.float(t);
        h.state(x);
    })
    .unwrap();
    let events = Events::new(|_t: f64, x: &V5| Vector1::new(x[0] - 0.5)).terminal([true]);
    let out = i
        .integrate_with_events(&sys, 0.0, start(), 0.9, &events, |hit| {
            h.float(hit.t);
            h.state(&hit.x);
        })
        .unwrap();
    h.float(out.t);
    h.stats(&out.stats);
    h.0
}

/// The same with the analytic Jacobian (the implicit methods).
macro_rules! jacobian_fingerprint {
    ($i:expr) => {{
        let mut h = Fnv::new();
        let mut i = $i;
        let out = i
            .integrate_with_jacobian(&KnifeChart0, 0.0, start(), 0.9)
            .unwrap();
        h.state(&out.x);
        h.stats(&out.stats);
        i.integrate_with_jacobian_and_steps(&KnifeChart0, 0.0, start(), 0.9, |s| {
            h.state(&s.interpolate(0.5 * (s.t_prev() + s.t())));
        })
        .unwrap();
        let events = Events::new(|_t: f64, x: &V5| Vector1::new(x[0] - 0.5)).terminal([true]);
        let out = i
            .integrate_with_jacobian_and_events(&KnifeChart0, 0.0, start(), 0.9, &events, |_| {})
            .unwrap();
        h.float(out.t);
        h.state(&out.x);
        h.0
    }};
}

/// A system with one chart runs exactly as before chart switching
/// existed: the fingerprints were measured at 47d096f (before the
/// atlas), every integrator, every entry point. (The bits depend on the
/// platform's `tan` and `cos`: measured on x86_64 Linux, glibc.)
#[test]
#[cfg(all(target_arch = "x86_64", target_os = "linux"))]
fn one_chart_runs_are_bit_identical_to_before_the_atlas() {
    let measured = [
        ("Dopri5", fingerprint(&mut Dopri5::new(1e-9, 1e-12))),
        ("Dop853", fingerprint(&mut Dop853::new(1e-9, 1e-12))),
        ("Rodas4", fingerprint(&mut Rodas4::new(1e-9, 1e-12))),
        ("Rodas5P", fingerprint(&mut Rodas5P::new(1e-9, 1e-12))),
        ("Bdf", fingerprint(&mut Bdf::new(1e-9, 1e-12))),
        ("AutoSwitch", fingerprint(&mut AutoSwitch::new(1e-9, 1e-12))),
        ("Rk4", fingerprint(&mut Rk4::new(0.01))),
        (
            "GaussLegendre4",
            fingerprint(&mut GaussLegendre4::new(0.01)),
        ),
        ("Rodas4 J", jacobian_fingerprint!(Rodas4::new(1e-9, 1e-12))),
        (
            "Rodas5P J",
            jacobian_fingerprint!(Rodas5P::new(1e-9, 1e-12)),
        ),
        ("Bdf J", jacobian_fingerprint!(Bdf::new(1e-9, 1e-12))),
        (
            "AutoSwitch J",
            jacobian_fingerprint!(AutoSwitch::new(1e-9, 1e-12)),
        ),
        (
            "GaussLegendre4 J",
            jacobian_fingerprint!(GaussLegendre4::new(0.01)),
        ),
    ];
    let expected = [
        ("Dopri5", 0x41dcfa90d14b4f9c),
        ("Dop853", 0x42e9f5a2f2c120d4),
        ("Rodas4", 0xdacc9a20be1f006c),
        ("Rodas5P", 0x6ee64874ead5cd06),
        ("Bdf", 0x1ef610bcc18945e2),
        ("AutoSwitch", 0x41dcfa90d14b4f9c),
        ("Rk4", 0x69e9adaf08a77fd3),
        ("GaussLegendre4", 0x19a71658fb853ba1),
        ("Rodas4 J", 0xd051e4140ba4ed3e),
        ("Rodas5P J", 0xe41d866cf3274ab5),
        ("Bdf J", 0xe265dade9f3d23b4),
        ("AutoSwitch J", 0x52774c9167054b05),
        ("GaussLegendre4 J", 0x31398feacf1de698),
    ];
    for ((name, f), (expected_name, e)) in measured.iter().zip(expected) {
        assert_eq!(*name, expected_name);
        assert_eq!(*f, e, "{name}: {f:#018x}");
    }
}
