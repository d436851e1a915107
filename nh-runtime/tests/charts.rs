//! Switching charts at run time (DESIGN §6.7), on the knife edge: a sleigh
//! whose centre of mass is at the blade, q = (x, y, θ), constraint
//! sin θ ẋ − cos θ ẏ = 0, L = ½m(ẋ² + ẏ²) + ½Iθ̇². Its motion is known in
//! closed form: θ = θ0 + ω t at constant speed v along the heading.
use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Matrix5, SVector, Vector1, Vector5};
use nh_runtime::{
    AutoSwitch, Bdf, ControlledSystem, Direction, Dop853, Dopri5, Driven, Ensemble, Events,
    GaussLegendre4, Integrator, OdeJacobian, OdeSystem, Rk4, Rodas4, Rodas5P, SimError,
    Singularity, Stats,
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

/// The knife edge with its atlas of two charts: chart 0 solved for y
/// ([`KnifeChart0`], regularity cos θ), chart 1 solved for x: x = [x, y, θ,
/// ẏ, θ̇], ẋ = ẏ cot θ, ÿ = ẏ cot θ θ̇, regularity sin θ. With `stiff = k`
/// the turning rate relaxes onto 1 as θ̈ = −k (θ̇ − 1) (the same motion from
/// θ̇ = 1, but stiff for an explicit method when k is large).
struct Knife {
    stiff: f64,
}

const KNIFE: Knife = Knife { stiff: 0.0 };

/// (ẋ, ẏ) of the state `x` of chart `chart`.
fn velocity(chart: usize, x: &V5) -> (f64, f64) {
    if chart == 0 {
        (x[3], x[2].tan() * x[3])
    } else {
        (x[3] / x[2].tan(), x[3])
    }
}

fn rhs_solved_for_x(x: &V5) -> V5 {
    let cot = 1.0 / x[2].tan();
    V5::new(cot * x[3], x[3], x[4], x[3] * cot * x[4], 0.0)
}

fn jacobian_solved_for_x(x: &V5) -> Matrix5<f64> {
    let (cot, csc2) = (1.0 / x[2].tan(), 1.0 / x[2].sin().powi(2));
    let (v, w) = (x[3], x[4]);
    let mut j = Matrix5::zeros();
    j[(0, 2)] = -csc2 * v;
    j[(0, 3)] = cot;
    j[(1, 3)] = 1.0;
    j[(2, 4)] = 1.0;
    j[(3, 2)] = -v * csc2 * w;
    j[(3, 3)] = cot * w;
    j[(3, 4)] = v * cot;
    j
}

impl OdeSystem<f64, 5> for Knife {
    fn rhs(&self, t: f64, x: &V5) -> V5 {
        self.rhs_in_chart(0, t, x)
    }

    fn chart_regularity(&self, t: f64, x: &V5) -> Option<f64> {
        self.chart_regularity_in(0, t, x)
    }

    fn is_autonomous(&self) -> bool {
        true
    }

    fn charts(&self) -> usize {
        2
    }

    fn chart_name(&self, chart: usize) -> &'static str {
        ["solved for y", "solved for x"][chart]
    }

    fn rhs_in_chart(&self, chart: usize, _t: f64, x: &V5) -> V5 {
        let mut f = if chart == 0 {
            rhs_solved_for_y(x)
        } else {
            rhs_solved_for_x(x)
        };
        f[4] = -self.stiff * (x[4] - 1.0);
        f
    }

    fn chart_regularity_in(&self, chart: usize, _t: f64, x: &V5) -> Option<f64> {
        Some(if chart == 0 { x[2].cos() } else { x[2].sin() })
    }

    fn change_chart(&self, from: usize, to: usize, _t: f64, x: &V5) -> V5 {
        let (vx, vy) = velocity(from, x);
        V5::new(x[0], x[1], x[2], if to == 0 { vx } else { vy }, x[4])
    }
}

impl OdeJacobian<f64, 5> for Knife {
    fn jacobian(&self, t: f64, x: &V5) -> Matrix5<f64> {
        self.jacobian_in_chart(0, t, x).unwrap()
    }

    fn jacobian_in_chart(&self, chart: usize, _t: f64, x: &V5) -> Option<Matrix5<f64>> {
        let mut j = if chart == 0 {
            jacobian_solved_for_y(x)
        } else {
            jacobian_solved_for_x(x)
        };
        j[(4, 4)] = -self.stiff;
        Some(j)
    }
}

/// The knife edge whose Jacobian is chart 0's only (the default
/// `jacobian_in_chart`): the implicit methods difference chart 1.
struct KnifeChart0Jacobian;

impl OdeSystem<f64, 5> for KnifeChart0Jacobian {
    fn rhs(&self, t: f64, x: &V5) -> V5 {
        KNIFE.rhs(t, x)
    }
    fn chart_regularity(&self, t: f64, x: &V5) -> Option<f64> {
        KNIFE.chart_regularity(t, x)
    }
    fn is_autonomous(&self) -> bool {
        true
    }
    fn charts(&self) -> usize {
        2
    }
    fn rhs_in_chart(&self, chart: usize, t: f64, x: &V5) -> V5 {
        KNIFE.rhs_in_chart(chart, t, x)
    }
    fn chart_regularity_in(&self, chart: usize, t: f64, x: &V5) -> Option<f64> {
        KNIFE.chart_regularity_in(chart, t, x)
    }
    fn change_chart(&self, from: usize, to: usize, t: f64, x: &V5) -> V5 {
        KNIFE.change_chart(from, to, t, x)
    }
}

impl OdeJacobian<f64, 5> for KnifeChart0Jacobian {
    fn jacobian(&self, t: f64, x: &V5) -> Matrix5<f64> {
        KNIFE.jacobian(t, x)
    }
}

/// The knife edge in a chart without singularities: the speed along the
/// heading as state, x = [x, y, θ, v, θ̇], ẋ = v cos θ, ẏ = v sin θ,
/// v̇ = θ̈ = 0 (the reference for the cost of switching).
struct KnifeSpeed;

impl OdeSystem<f64, 5> for KnifeSpeed {
    fn rhs(&self, _t: f64, x: &V5) -> V5 {
        let (s, c) = x[2].sin_cos();
        V5::new(x[3] * c, x[3] * s, x[4], 0.0, 0.0)
    }
}

/// The closed form in chart 0's layout at `t` (from [`start`]).
fn exact(t: f64) -> V5 {
    let theta = THETA0 + t;
    V5::new(
        theta.sin() - THETA0.sin(),
        THETA0.cos() - theta.cos(),
        theta,
        theta.cos(),
        1.0,
    )
}

/// Ten turns: θ from 0.3 to 0.3 + 20π.
const TEN_TURNS: f64 = 20.0 * PI;

/// `$body` once for each integrator, `$i` the integrator (adaptive ones
/// at rtol 1e-9, the fixed-step ones at h = 0.01), `$name` its name and
/// `$tol` the error on the closed form it meets through ten turns.
macro_rules! each_integrator {
    (|$name:ident, $i:ident, $tol:ident| $body:block) => {{
        macro_rules! one {
            ($n:expr, $make:expr, $t:expr) => {{
                let $name: &str = $n;
                #[allow(unused_mut)]
                let mut $i = $make;
                let $tol: f64 = $t;
                $body
            }};
        }
        one!("Dopri5", Dopri5::new(1e-9, 1e-12), 1e-6);
        one!("Dop853", Dop853::new(1e-9, 1e-12), 1e-6);
        one!("Rodas4", Rodas4::new(1e-9, 1e-12), 1e-6);
        one!("Rodas5P", Rodas5P::new(1e-9, 1e-12), 1e-6);
        one!("Bdf", Bdf::new(1e-9, 1e-12), 1e-6);
        one!("AutoSwitch", AutoSwitch::new(1e-9, 1e-12), 1e-6);
        one!("Rk4", Rk4::new(0.01), 1e-6);
        one!("GaussLegendre4", GaussLegendre4::new(0.01), 1e-6);
    }};
}

/// The largest error of a state in chart 0's layout on the closed form.
fn error_at(t: f64, x: &V5) -> f64 {
    (x - exact(t)).amax()
}

#[test]
fn every_integrator_turns_ten_times_switching_charts_40_times() {
    each_integrator!(|name, i, tol| {
        let out = i.integrate(&KNIFE, 0.0, start(), TEN_TURNS).unwrap();
        let err = error_at(out.t, &out.x);
        let switches = out.switches;
        println!(
            "{name:>15}: error {err:.1e}, {} switches, {} steps + {} rejected, {} rhs, {} jacobians",
            switches.total(),
            out.stats.steps,
            out.stats.rejected,
            out.stats.rhs_evals,
            out.stats.jacobian_evals,
        );
        assert!(err < tol, "{name}: error {err:e}");
        assert_eq!(switches.total(), 40, "{name}");
        assert_eq!(out.stats.chart_switches, 40, "{name}");
        assert_eq!(switches.len(), 32, "{name}: the first 32 are recorded");
        let mut chart = 0;
        for s in &switches {
            assert_eq!((s.from, s.to), (chart, 1 - chart), "{name}: {s:?}");
            chart = s.to;
            // Where the chart left had become poor: |cos θ| (chart 0) or
            // |sin θ| (chart 1) above the threshold 0.1, within a step.
            let theta = THETA0 + s.t;
            let rho = if s.from == 0 {
                theta.cos()
            } else {
                theta.sin()
            };
            assert!(
                rho.abs() > 0.1 && rho.abs() < 0.2,
                "{name}: {s:?}, ρ = {rho}"
            );
        }
        assert_eq!(i.last_stats(), out.stats, "{name}");
        assert_eq!(i.last_chart_switches(), out.switches, "{name}");
    });
}

#[test]
fn held_in_chart_0_every_integrator_ends_at_the_singularity() {
    each_integrator!(|name, i, _tol| {
        let mut i = i.with_chart_switching(false);
        let err = i.integrate(&KNIFE, 0.0, start(), TEN_TURNS).unwrap_err();
        let SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        } = err
        else {
            panic!("{name}: {err:?}")
        };
        // The last good state, before θ = π/2.
        assert!(
            x[2] < FRAC_PI_2 && x[2] > FRAC_PI_2 - 0.05,
            "{name}: θ = {}",
            x[2]
        );
        assert!(error_at(t, &x) < 1e-6, "{name}");
        assert_eq!(i.last_stats().chart_switches, 0, "{name}");
        assert!(i.last_chart_switches().is_empty(), "{name}");
    });
}

/// A run that needs no switch takes the steps of the one-chart system,
/// bit for bit (the segment's threshold 0.1 is never reached).
#[test]
fn without_a_switch_the_atlas_changes_nothing() {
    each_integrator!(|name, i, _tol| {
        let one = i.integrate(&KnifeChart0, 0.0, start(), 0.9).unwrap();
        let atlas = i.integrate(&KNIFE, 0.0, start(), 0.9).unwrap();
        assert_eq!(one, atlas, "{name}");
        assert!(atlas.switches.is_empty(), "{name}");
    });
}

#[test]
fn output_times_see_one_continuous_solution_in_chart_0() {
    let times: Vec<f64> = (0..=628).map(|k| 0.1 * k as f64).collect();
    each_integrator!(|name, i, tol| {
        let mut worst: f64 = 0.0;
        let mut n = 0;
        let out = i
            .integrate_with_outputs(&KNIFE, 0.0, start(), TEN_TURNS, &times, |t, x| {
                // The 4th entry is ẋ = cos θ, in every chart's stretch.
                worst = worst.max((x[3] - (THETA0 + t).cos()).abs());
                worst = worst.max(error_at(t, x));
                n += 1;
            })
            .unwrap();
        assert_eq!(n, times.len(), "{name}");
        assert!(worst < tol, "{name}: {worst:e}");
        assert_eq!(out.switches.total(), 40, "{name}");
    });
}

#[test]
fn observers_and_steps_see_chart_0_and_a_continuous_solution() {
    each_integrator!(|name, i, tol| {
        let mut last: Option<(f64, V5)> = None;
        i.integrate_with_observer(&KNIFE, 0.0, start(), TEN_TURNS, |t, x| {
            if let Some((tp, _)) = last {
                assert!(t > tp, "{name}: {t} after {tp}");
            }
            // ẋ = cos θ: chart 0's layout also where the run is in chart 1.
            assert!((x[3] - x[2].cos()).abs() < tol, "{name} at {t}: {x}");
            last = Some((t, *x));
        })
        .unwrap();
        let mut prev: Option<V5> = None;
        let (mut jump, mut worst): (f64, f64) = (0.0, 0.0);
        i.integrate_with_steps(&KNIFE, 0.0, start(), TEN_TURNS, |s| {
            if let Some(p) = prev {
                // Each step starts where the last ended (up to the rounding
                // of the round trip through the other chart at a switch).
                jump = jump.max((s.x_prev() - p).amax());
            }
            prev = Some(*s.x());
            let tm = 0.5 * (s.t_prev() + s.t());
            worst = worst.max(error_at(tm, &s.interpolate(tm)));
            assert_eq!(s.interpolate(s.t()), *s.x());
        })
        .unwrap();
        assert!(jump < 1e-13, "{name}: {jump:e}");
        assert!(worst < 10.0 * tol, "{name}: dense output {worst:e}");
    });
}

/// x = sin θ − sin θ0 falls through 0.6138 at θ = 2 (t = 1.7), where the
/// run is in chart 1 (from θ ≈ π/2 − 0.1 to π − 0.1).
#[test]
fn a_terminal_event_in_chart_1_is_located_and_reported_in_chart_0() {
    let x_at = 2.0f64.sin() - THETA0.sin();
    let events = Events::new(move |_t: f64, x: &V5| Vector1::new(x[0] - x_at))
        .direction([Direction::Falling])
        .terminal([true]);
    each_integrator!(|name, i, tol| {
        let mut seen = Vec::new();
        let out = i
            .integrate_with_events(&KNIFE, 0.0, start(), TEN_TURNS, &events, |hit| {
                seen.push(*hit);
            })
            .unwrap();
        let hit = out.event.expect("the event ends the run");
        assert_eq!(seen, [hit], "{name}");
        assert_eq!((out.t, out.x), (hit.t, hit.x), "{name}: not mapped twice");
        println!(
            "{name:>15}: event at t - 1.7 = {:.1e}, state error {:.1e}",
            hit.t - 1.7,
            error_at(hit.t, &hit.x)
        );
        // Measured: 1.7e-10 (Dopri5) to 1.5e-8 (Bdf) off t = 1.7.
        assert!((hit.t - 1.7).abs() < 0.1 * tol, "{name}: t = {}", hit.t);
        assert!(error_at(hit.t, &hit.x) < 0.1 * tol, "{name}: {}", hit.x);
        assert!(
            (hit.x[3] - 2.0f64.cos()).abs() < tol,
            "{name}: ẋ = {}",
            hit.x[3]
        );
        assert_eq!(out.switches.total(), 1, "{name}");
        assert!(out.stats.event_evals > 0);
    });
}

/// Every segment's counters go into the run's: Dormand–Prince spends 6
/// right-hand sides per attempt, 2 at the start (the derivative and the
/// initial-step heuristic) and 1 at the start of each later segment (the
/// derivative there; its first step is the last one); each segment ends
/// with the trial whose end fell below the threshold, counted in `steps`.
#[test]
fn statistics_add_up_across_segments() {
    let mut dopri = Dopri5::new(1e-9, 1e-12);
    let mut reported = 0;
    let out = dopri
        .integrate_with_steps(&KNIFE, 0.0, start(), TEN_TURNS, |_| reported += 1)
        .unwrap();
    let s = out.stats;
    let switches = out.switches.total();
    assert_eq!(switches, 40);
    assert_eq!(s.rhs_evals, 6 * (s.steps + s.rejected) + 2 + switches);
    assert_eq!(s.steps, reported + switches);
    // The same for a fixed step: 4 per step, no heuristic.
    let out = Rk4::new(0.01)
        .integrate(&KNIFE, 0.0, start(), TEN_TURNS)
        .unwrap();
    assert_eq!(out.stats.rhs_evals, 4 * out.stats.steps);
    // Events count their evaluations over all segments.
    let never = Events::new(|_t: f64, x: &V5| Vector1::new(x[4] - 2.0));
    let mut dopri = Dopri5::new(1e-9, 1e-12);
    let with = dopri
        .integrate_with_events(&KNIFE, 0.0, start(), TEN_TURNS, &never, |_| {})
        .unwrap();
    assert_eq!(
        with.x,
        dopri.integrate(&KNIFE, 0.0, start(), TEN_TURNS).unwrap().x
    );
    // g at t0, and at every trial end the driver shows it.
    assert!(
        with.stats.event_evals > with.stats.steps,
        "{:?}",
        with.stats
    );
}

/// The analytic Jacobian of each chart, or differences where a chart
/// has none (`jacobian_in_chart` is `None`): the same motion; the
/// differences cost right-hand sides, counted.
#[test]
fn the_jacobian_entry_points_switch_too() {
    macro_rules! check {
        ($name:expr, $i:expr, $tol:expr) => {{
            let mut i = $i;
            let own = i
                .integrate_with_jacobian(&KNIFE, 0.0, start(), TEN_TURNS)
                .unwrap();
            let differenced = i
                .integrate_with_jacobian(&KnifeChart0Jacobian, 0.0, start(), TEN_TURNS)
                .unwrap();
            for out in [&own, &differenced] {
                assert!(error_at(out.t, &out.x) < $tol, "{}: {}", $name, error_at(out.t, &out.x));
                assert_eq!(out.switches.total(), 40, "{}", $name);
            }
            println!(
                "{:>15}: analytic in both charts {} rhs + {} jacobians, chart 1 differenced {} rhs + {} jacobians",
                $name,
                own.stats.rhs_evals,
                own.stats.jacobian_evals,
                differenced.stats.rhs_evals,
                differenced.stats.jacobian_evals
            );
            // (AutoSwitch never goes implicit here: no Jacobian at all.)
            if own.stats.jacobian_evals > 0 {
                assert!(differenced.stats.rhs_evals > own.stats.rhs_evals, "{}", $name);
            }
            let mut steps = 0;
            let events = Events::new(|_t: f64, x: &V5| Vector1::new(x[4] - 2.0));
            i.integrate_with_jacobian_and_steps(&KNIFE, 0.0, start(), TEN_TURNS, |_| steps += 1)
                .unwrap();
            assert_eq!(steps + 40, own.stats.steps, "{}", $name);
            let with_events = i
                .integrate_with_jacobian_and_events(&KNIFE, 0.0, start(), TEN_TURNS, &events, |_| {})
                .unwrap();
            assert_eq!(with_events.x, own.x, "{}", $name);
        }};
    }
    check!("Rodas4", Rodas4::new(1e-9, 1e-12), 1e-6);
    check!("Rodas5P", Rodas5P::new(1e-9, 1e-12), 1e-6);
    check!("Bdf", Bdf::new(1e-9, 1e-12), 1e-6);
    check!("AutoSwitch", AutoSwitch::new(1e-9, 1e-12), 1e-6);
    check!("GaussLegendre4", GaussLegendre4::new(0.01), 1e-6);
}

/// The knife edge with an input (ignored): `Driven` forwards the atlas.
struct SteeredKnife;

impl ControlledSystem<f64, 5, 1> for SteeredKnife {
    fn rhs_with_input(&self, t: f64, x: &V5, _u: &Vector1<f64>) -> V5 {
        KNIFE.rhs(t, x)
    }
    fn chart_regularity(&self, t: f64, x: &V5) -> Option<f64> {
        KNIFE.chart_regularity(t, x)
    }
    fn charts(&self) -> usize {
        2
    }
    fn chart_name(&self, chart: usize) -> &'static str {
        KNIFE.chart_name(chart)
    }
    fn rhs_with_input_in_chart(&self, chart: usize, t: f64, x: &V5, _u: &Vector1<f64>) -> V5 {
        KNIFE.rhs_in_chart(chart, t, x)
    }
    fn chart_regularity_in(&self, chart: usize, t: f64, x: &V5) -> Option<f64> {
        KNIFE.chart_regularity_in(chart, t, x)
    }
    fn change_chart(&self, from: usize, to: usize, t: f64, x: &V5) -> V5 {
        KNIFE.change_chart(from, to, t, x)
    }
}

#[test]
fn the_input_adapter_forwards_the_atlas() {
    let driven = Driven::new(&SteeredKnife, Vector1::new(0.0));
    assert_eq!(driven.charts(), 2);
    assert_eq!(driven.chart_name(1), "solved for x");
    let via = Dopri5::new(1e-9, 1e-12)
        .integrate(&driven, 0.0, start(), TEN_TURNS)
        .unwrap();
    let direct = Dopri5::new(1e-9, 1e-12)
        .integrate(&KNIFE, 0.0, start(), TEN_TURNS)
        .unwrap();
    assert_eq!(via, direct);
}

/// A stiff turning rate (θ̈ = −10⁵ (θ̇ − 1), from θ̇ = 1.001, which moves θ
/// by 1e-8): AutoSwitch goes implicit once and stays so across the 40
/// chart switches (each segment starts in the regime of the last),
/// RODAS4's steps and switches logged over all. Measured: 2,055 steps,
/// 2,034 implicit, error 3.5e-7; each segment restarting explicit took
/// 1,027 steps, 47 implicit, error 7.4e-7, since this stiff mode is at rest
/// after its transient (the carry is for stiffness that lasts).
#[test]
fn auto_switch_keeps_its_regime_across_chart_switches() {
    let stiff = Knife { stiff: 1e5 };
    let mut auto = AutoSwitch::new(1e-8, 1e-11);
    let mut x0 = start();
    x0[4] = 1.001;
    let out = auto
        .integrate_with_jacobian(&stiff, 0.0, x0, TEN_TURNS)
        .unwrap();
    println!("{:?}, error {:.1e}", out.stats, error_at(out.t, &out.x));
    assert!(
        error_at(out.t, &out.x) < 1e-5,
        "{}",
        error_at(out.t, &out.x)
    );
    assert_eq!(out.switches.total(), 40);
    assert_eq!(out.stats.switches_to_stiff, 1, "{:?}", out.stats);
    assert_eq!(out.stats.switches_to_nonstiff, 0);
    assert_eq!(auto.last_switches().len(), 1);
    assert!(
        out.stats.stiff_steps > out.stats.steps / 2,
        "{:?}",
        out.stats
    );
}

/// Started where chart 0 is singular (θ0 = π/2, ẋ = cos θ0 ≈ 6e-17, which
/// chart 0 holds as ẏ = tan θ0 ẋ = 1), the run starts in chart 1.
#[test]
fn a_run_that_starts_on_chart_0s_singularity_starts_in_chart_1() {
    let x0 = V5::new(0.0, 0.0, FRAC_PI_2, FRAC_PI_2.cos(), 1.0);
    let out = Dopri5::new(1e-9, 1e-12)
        .integrate(&KNIFE, 0.0, x0, 1.0)
        .unwrap();
    let first = out.switches.iter().next().copied().unwrap();
    assert_eq!((first.t, first.from, first.to), (0.0, 0, 1));
    assert_eq!(out.switches.total(), 1);
    let theta = FRAC_PI_2 + 1.0;
    let exact = V5::new(theta.sin() - 1.0, -theta.cos(), theta, theta.cos(), 1.0);
    assert!((out.x - exact).amax() < 1e-7, "{}", out.x - exact);
    let held = Dopri5::new(1e-9, 1e-12)
        .with_chart_switching(false)
        .integrate(&KNIFE, 0.0, x0, 1.0);
    assert!(
        matches!(
            held,
            Err(SimError::Singular {
                t: 0.0,
                cause: Singularity::Chart,
                ..
            })
        ),
        "{held:?}"
    );
}

/// The step budget is the run's, not a segment's, and a failure's state is
/// in chart 0's layout also when the run was in chart 1.
#[test]
fn the_budget_is_the_runs_and_failures_are_in_chart_0() {
    let mut in_chart_1 = 0;
    for budget in (50..250).step_by(10) {
        let mut dopri = Dopri5::new(1e-9, 1e-12).with_max_steps(budget);
        let err = dopri
            .integrate(&KNIFE, 0.0, start(), TEN_TURNS)
            .unwrap_err();
        let SimError::MaxSteps { t, x, steps } = err else {
            panic!("{err:?}")
        };
        assert_eq!(steps, budget);
        let stats = dopri.last_stats();
        assert_eq!(stats.steps + stats.rejected, budget);
        let switches = dopri.last_chart_switches();
        assert_eq!(switches.total(), stats.chart_switches);
        assert!(switches.total() >= 1, "{stats:?}");
        if switches.iter().last().unwrap().to == 1 {
            in_chart_1 += 1;
        }
        assert!(error_at(t, &x) < 1e-6, "{x}");
        assert!((x[3] - x[2].cos()).abs() < 1e-6, "ẋ in the 4th entry: {x}");
    }
    assert!(in_chart_1 >= 5, "{in_chart_1} runs stopped in chart 1");
}

#[test]
fn backwards_through_ten_turns() {
    each_integrator!(|name, i, tol| {
        let out = i
            .integrate(&KNIFE, TEN_TURNS, exact(TEN_TURNS), 0.0)
            .unwrap();
        assert!(
            (out.x - start()).amax() < tol,
            "{name}: {}",
            out.x - start()
        );
        // Downwards from θ = 0.3 + 20π in chart 0, the first singularity is
        // chart 1's (θ = 20π): 39 switches.
        assert_eq!(out.switches.total(), 39, "{name}");
    });
}

/// An atlas whose two charts are singular together (both claim cos θ):
/// no switch helps; the run ends in `Singular` next to θ = π/2 after a few
/// restarts with lower thresholds, its state in chart 0's layout.
struct BothSingular;

impl OdeSystem<f64, 5> for BothSingular {
    fn rhs(&self, t: f64, x: &V5) -> V5 {
        KNIFE.rhs(t, x)
    }
    fn chart_regularity(&self, t: f64, x: &V5) -> Option<f64> {
        KNIFE.chart_regularity(t, x)
    }
    fn charts(&self) -> usize {
        2
    }
    fn rhs_in_chart(&self, chart: usize, t: f64, x: &V5) -> V5 {
        KNIFE.rhs_in_chart(chart, t, x)
    }
    fn chart_regularity_in(&self, _chart: usize, _t: f64, x: &V5) -> Option<f64> {
        Some(x[2].cos())
    }
    fn change_chart(&self, from: usize, to: usize, t: f64, x: &V5) -> V5 {
        KNIFE.change_chart(from, to, t, x)
    }
}

#[test]
fn where_every_chart_is_singular_the_run_ends_there() {
    each_integrator!(|name, i, _tol| {
        let err = i
            .integrate(&BothSingular, 0.0, start(), TEN_TURNS)
            .unwrap_err();
        let SimError::Singular {
            t,
            x,
            cause: Singularity::Chart,
        } = err
        else {
            panic!("{name}: {err:?}")
        };
        assert!(
            x[2] < FRAC_PI_2 && x[2] > FRAC_PI_2 - 1e-3,
            "{name}: θ = {}",
            x[2]
        );
        assert!((x[3] - x[2].cos()).abs() < 1e-6, "{name}: {x}");
        assert!(t < FRAC_PI_2 - THETA0, "{name}");
        assert!(i.last_chart_switches().is_empty(), "{name}");
    });
}

#[test]
fn ensembles_switch_in_every_run() {
    let results = Ensemble::new(8).run(|k| {
        let theta0 = THETA0 + 0.1 * k as f64;
        let x0 = V5::new(0.0, 0.0, theta0, theta0.cos(), 1.0);
        Dopri5::new(1e-9, 1e-12).integrate(&KNIFE, 0.0, x0, 2.0 * PI)
    });
    for (k, r) in results.iter().enumerate() {
        let out = r.as_ref().unwrap();
        assert_eq!(out.switches.total(), 4, "run {k}");
        let theta = THETA0 + 0.1 * k as f64 + 2.0 * PI;
        assert!((out.x[3] - theta.cos()).abs() < 1e-7, "run {k}");
    }
}

/// What switching costs: the knife edge over its atlas against the same
/// motion in a chart without singularities ([`KnifeSpeed`]), same
/// integrator and tolerance. Measured (f64, rtol 1e-9, atol 1e-12; h =
/// 0.01), steps + rejected, atlas / speed: Dopri5 1532+49 / 480+22,
/// Dop853 324+210 / 113+19, Rodas4 4028+158 / 4937+2, Rodas5P 2608+3 /
/// 925+7, Bdf 3528+198 / 2399+47, Rk4 and GaussLegendre4 6324 / 6284
/// (the 40 trial steps whose ends fell below the threshold).
#[test]
fn switching_costs_against_a_chart_without_singularities() {
    each_integrator!(|name, i, _tol| {
        let out = i.integrate(&KNIFE, 0.0, start(), TEN_TURNS).unwrap();
        let x0 = V5::new(0.0, 0.0, THETA0, 1.0, 1.0);
        let speed = i.integrate(&KnifeSpeed, 0.0, x0, TEN_TURNS).unwrap();
        let (a, b) = (out.stats, speed.stats);
        println!(
            "{name:>15}: atlas {}+{} steps, {} rhs, {} jacobians | speed {}+{} steps, {} rhs, {} jacobians",
            a.steps,
            a.rejected,
            a.rhs_evals,
            a.jacobian_evals,
            b.steps,
            b.rejected,
            b.rhs_evals,
            b.jacobian_evals
        );
        let (atlas, plain) = (a.steps + a.rejected, b.steps + b.rejected);
        assert!(atlas < 5 * plain, "{name}: {atlas} against {plain}");
    });
}
