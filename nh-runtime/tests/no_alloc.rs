//! Proves that integration performs no heap allocation per step: the
//! allocations of a call do not depend on its number of steps, and are zero
//! for every integrator but `GaussLegendre4` (whose Newton workspace is
//! allocated once per call).
//!
//! A counting global allocator counts allocations made by the current thread
//! while a thread-local flag is set, so the test harness's own threads do not
//! interfere.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use common::Oscillators3;
use nalgebra::{SVector, Vector1};
use nh_runtime::OdeSystem as _;
use nh_runtime::{
    AutoSwitch, Dop853, Dopri5, Events, GaussLegendre4, Integrator, Rk4, Rodas4, Rodas5P,
};

struct Counting;

thread_local! {
    static ACTIVE: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    if ACTIVE.try_with(Cell::get).unwrap_or(false) {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
    }
}

// SAFETY: forwards to the system allocator unchanged; only counts calls.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f` on this thread.
fn allocations_during<R>(f: impl FnOnce() -> R) -> (usize, R) {
    COUNT.with(|c| c.set(0));
    ACTIVE.with(|a| a.set(true));
    let r = f();
    ACTIVE.with(|a| a.set(false));
    (COUNT.with(Cell::get), r)
}

#[test]
fn counter_sees_allocations() {
    let (n, v) = allocations_during(|| vec![1u8; 16]);
    assert_eq!(v.len(), 16);
    assert!(n >= 1);
}

#[test]
fn integrate_does_not_allocate() {
    let x0 = SVector::<f64, 6>::from([1.0, 0.0, 0.5, 0.0, 0.0, 1.0]);

    let mut rk4 = Rk4::new(1e-3);
    let (n, out) = allocations_during(|| rk4.integrate(&Oscillators3, 0.0, x0, 5.0));
    let out = out.unwrap();
    assert!(out.stats.steps >= 5000);
    assert_eq!(n, 0, "Rk4 allocated {n} times");

    let mut dp = Dopri5::new(1e-9, 1e-11);
    let (n, out) = allocations_during(|| dp.integrate(&Oscillators3, 0.0, x0, 5.0));
    let out = out.unwrap();
    assert!(out.stats.steps > 50);
    assert_eq!(n, 0, "Dopri5 allocated {n} times");

    // Error paths and the observer variant do not allocate either.
    let mut dp = Dopri5::new(1e-9, 1e-11).with_max_steps(10);
    let mut seen = 0usize;
    let (n, out) = allocations_during(|| {
        dp.integrate_with_observer(&Oscillators3, 0.0, x0, 5.0, |_, _| seen += 1)
    });
    assert!(out.is_err());
    assert!(seen > 1);
    assert_eq!(n, 0, "Dopri5 error path allocated {n} times");
}

/// Allocations of `run(t1)` for a short and a long span: they must not
/// depend on the number of steps, and must be zero unless the integrator
/// has a per-call workspace.
fn per_step<R>(name: &str, workspace: bool, mut run: impl FnMut(f64) -> R) -> (R, R) {
    let (short, r_short) = allocations_during(|| run(0.05));
    let (long, r_long) = allocations_during(|| run(5.0));
    assert_eq!(short, long, "{name}: allocations grow with the steps");
    if !workspace {
        assert_eq!(long, 0, "{name}: allocated {long} times");
    }
    (r_short, r_long)
}

/// `integrate`, `integrate_with_outputs` (dense output) and the error path
/// of one integrator allocate nothing per step.
fn check_no_alloc<I: Integrator<f64>>(
    name: &str,
    mut make: impl FnMut() -> I,
    min_steps: usize,
    workspace: bool,
) {
    let x0 = SVector::<f64, 6>::from([1.0, 0.0, 0.5, 0.0, 0.0, 1.0]);
    let times: [f64; 64] = core::array::from_fn(|i| i as f64 * 5.0 / 63.0);

    let (_, out) = per_step(name, workspace, |t1| {
        make().integrate(&Oscillators3, 0.0, x0, t1)
    });
    let out = out.unwrap();
    assert!(out.stats.steps >= min_steps, "{name}: {:?}", out.stats);

    let mut seen = 0usize;
    let mut sum = 0.0;
    let (_, out) = per_step(name, workspace, |t1| {
        seen = 0;
        make().integrate_with_outputs(&Oscillators3, 0.0, x0, t1, &times, |_, x| {
            seen += 1;
            sum += x[0];
        })
    });
    out.unwrap();
    assert_eq!(seen, 64);
    assert!(sum.is_finite());

    let mut seen = 0usize;
    let (_, out) = per_step(name, workspace, |t1| {
        seen = 0;
        make().integrate_with_steps(&Oscillators3, 0.0, x0, t1, |s| {
            seen += 1;
            let _ = s.interpolate(0.5 * (s.t_prev() + s.t()));
        })
    });
    out.unwrap();
    assert!(seen >= min_steps);

    // Events: the zeros of x[0] (two in the long span), located on the
    // dense output of the steps across them.
    let zeros = Events::new(|_t: f64, x: &SVector<f64, 6>| Vector1::new(x[0]));
    let mut hits = 0usize;
    let (_, out) = per_step(name, workspace, |t1| {
        hits = 0;
        make().integrate_with_events(&Oscillators3, 0.0, x0, t1, &zeros, |_| hits += 1)
    });
    assert!(out.unwrap().stats.event_evals > 0);
    assert_eq!(hits, 2, "{name}");

    // An error path: a right-hand side that turns NaN after a fifth of
    // the span.
    let (short, long) = per_step(name, workspace, |t1| {
        let nan_late = |t: f64, x: &SVector<f64, 6>| {
            if t > 0.2 * t1 {
                SVector::<f64, 6>::repeat(f64::NAN)
            } else {
                Oscillators3.rhs(t, x)
            }
        };
        make().integrate(&nan_late, 0.0, x0, t1)
    });
    assert!(short.is_err() && long.is_err(), "{name}");
}

#[test]
fn no_integrator_allocates_per_step() {
    check_no_alloc("rk4", || Rk4::new(1e-2), 500, false);
    check_no_alloc("dopri5", || Dopri5::new(1e-9, 1e-11), 50, false);
    check_no_alloc("dop853", || Dop853::new(1e-9, 1e-11), 20, false);
    check_no_alloc("rodas4", || Rodas4::new(1e-6, 1e-8), 20, false);
    check_no_alloc("rodas5p", || Rodas5P::new(1e-6, 1e-8), 20, false);
    check_no_alloc("gauss4", || GaussLegendre4::new(1e-2), 500, true);
    check_no_alloc("auto", || AutoSwitch::new(1e-9, 1e-11), 50, false);
}

#[test]
fn switching_does_not_allocate() {
    // Stiff (λ up to 1e5) around t = 3 only: two switches on [0, 6].
    let bump = |t: f64, x: &nalgebra::Vector1<f64>| {
        let lambda = 1.0 + 1e5 * (-((t - 3.0) / 0.8).powi(8)).exp();
        nalgebra::Vector1::new(-lambda * (x[0] - t.cos()) - t.sin())
    };
    let x0 = nalgebra::Vector1::new(1.0);
    let mut auto = AutoSwitch::new(1e-6, 1e-9);
    let (n, out) = allocations_during(|| auto.integrate(&bump, 0.0, x0, 6.0));
    let out = out.unwrap();
    assert_eq!(
        out.stats.switches_to_stiff + out.stats.switches_to_nonstiff,
        2
    );
    assert_eq!(auto.last_switches().len(), 2);
    assert_eq!(n, 0, "AutoSwitch allocated {n} times");
}

#[test]
fn analytic_jacobian_paths_do_not_allocate() {
    use nalgebra::SMatrix;
    use nh_runtime::{OdeJacobian, OdeSystem};
    struct Osc3;
    impl OdeSystem<f64, 6> for Osc3 {
        fn rhs(&self, t: f64, x: &SVector<f64, 6>) -> SVector<f64, 6> {
            Oscillators3.rhs(t, x)
        }
    }
    impl OdeJacobian<f64, 6> for Osc3 {
        fn jacobian(&self, _t: f64, _x: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
            let mut j = SMatrix::<f64, 6, 6>::zeros();
            for (k, w2) in [1.0, 4.0, 9.0].iter().enumerate() {
                j[(2 * k, 2 * k + 1)] = 1.0;
                j[(2 * k + 1, 2 * k)] = -w2;
            }
            j
        }
    }
    let x0 = SVector::<f64, 6>::from([1.0, 0.0, 0.5, 0.0, 0.0, 1.0]);
    let mut ros = Rodas4::new(1e-6, 1e-8);
    let (n, out) = allocations_during(|| ros.integrate_with_jacobian(&Osc3, 0.0, x0, 5.0));
    out.unwrap();
    assert_eq!(n, 0, "Rodas4::integrate_with_jacobian allocated {n} times");
    let mut rodas5 = Rodas5P::new(1e-6, 1e-8);
    let (n, out) = allocations_during(|| rodas5.integrate_with_jacobian(&Osc3, 0.0, x0, 5.0));
    out.unwrap();
    assert_eq!(n, 0, "Rodas5P::integrate_with_jacobian allocated {n} times");
    // The Gauss method allocates its Newton workspace (Jacobian, LU,
    // permutation) once per call, whatever the number of steps.
    let (_, out) = per_step("GaussLegendre4::integrate_with_jacobian", true, |t1| {
        GaussLegendre4::new(1e-2).integrate_with_jacobian(&Osc3, 0.0, x0, t1)
    });
    assert!(out.unwrap().stats.steps >= 500);
    let (n, _) = allocations_during(|| {
        GaussLegendre4::new(1e-2).integrate_with_jacobian(&Osc3, 0.0, x0, 5.0)
    });
    assert_eq!(
        n, 3,
        "GaussLegendre4: one workspace of three buffers per call"
    );
}

/// A point running round the unit circle (`x ẋ + y ẏ = 0`) with an atlas
/// of two charts: chart 0 keeps ẋ (`[x, y, ẋ]`, singular where y = 0),
/// chart 1 keeps ẏ (`[x, y, ẏ]`, singular where x = 0).
struct Circle;

impl Circle {
    fn velocity(chart: usize, s: &nalgebra::Vector3<f64>) -> (f64, f64) {
        let (x, y) = (s[0], s[1]);
        if chart == 0 {
            (s[2], -x * s[2] / y)
        } else {
            (-y * s[2] / x, s[2])
        }
    }
}

impl nh_runtime::OdeSystem<f64, 3> for Circle {
    fn rhs(&self, t: f64, s: &nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
        self.rhs_in_chart(0, t, s)
    }
    fn charts(&self) -> usize {
        2
    }
    fn rhs_in_chart(
        &self,
        chart: usize,
        _t: f64,
        s: &nalgebra::Vector3<f64>,
    ) -> nalgebra::Vector3<f64> {
        let (vx, vy) = Self::velocity(chart, s);
        let w2 = (vx * vx + vy * vy) / (s[0] * s[0] + s[1] * s[1]);
        let a = if chart == 0 { -w2 * s[0] } else { -w2 * s[1] };
        nalgebra::Vector3::new(vx, vy, a)
    }
    fn chart_regularity_in(
        &self,
        chart: usize,
        _t: f64,
        s: &nalgebra::Vector3<f64>,
    ) -> Option<f64> {
        let r = (s[0] * s[0] + s[1] * s[1]).sqrt();
        Some(if chart == 0 { s[1] / r } else { s[0] / r })
    }
    fn change_chart(
        &self,
        from: usize,
        to: usize,
        _t: f64,
        s: &nalgebra::Vector3<f64>,
    ) -> nalgebra::Vector3<f64> {
        let (vx, vy) = Self::velocity(from, s);
        nalgebra::Vector3::new(s[0], s[1], if to == 0 { vx } else { vy })
    }
}

/// Switching charts allocates nothing either: every integrator round the
/// circle five times (19 switches: from the angle 0.5 the first is at π),
/// with events and output times; the
/// implicit Gauss–Legendre method allocates its workspace once per chart
/// segment.
#[test]
fn switching_charts_does_not_allocate() {
    let x0 = nalgebra::Vector3::new(0.5f64.cos(), 0.5f64.sin(), -0.5f64.sin());
    let t1 = 10.0 * std::f64::consts::PI;
    let times: [f64; 64] = core::array::from_fn(|i| i as f64 * t1 / 63.0);
    let crossings = Events::new(|_t: f64, s: &nalgebra::Vector3<f64>| Vector1::new(s[0] - 0.3));
    fn check<I: Integrator<f64>>(
        name: &str,
        mut i: I,
        x0: nalgebra::Vector3<f64>,
        t1: f64,
        times: &[f64],
        crossings: &Events<f64, impl Fn(f64, &nalgebra::Vector3<f64>) -> Vector1<f64>, 1>,
        workspace: bool,
    ) {
        let (n, out) = allocations_during(|| i.integrate(&Circle, 0.0, x0, t1));
        let out = out.unwrap();
        assert_eq!(out.switches.total(), 19, "{name}");
        let segments = out.switches.total() + 1;
        // (GaussLegendre4: its three work vectors, once per segment.)
        let expected = if workspace { 3 * segments } else { 0 };
        assert_eq!(n, expected, "{name}: integrate allocated {n} times");
        let mut seen = 0;
        let (n, out) = allocations_during(|| {
            i.integrate_with_outputs(&Circle, 0.0, x0, t1, times, |_, _| seen += 1)
        });
        out.unwrap();
        assert_eq!((n, seen), (expected, 64), "{name}: outputs");
        let mut hits = 0;
        let (n, out) = allocations_during(|| {
            i.integrate_with_events(&Circle, 0.0, x0, t1, crossings, |_| hits += 1)
        });
        out.unwrap();
        assert_eq!((n, hits), (expected, 10), "{name}: events");
    }
    check("rk4", Rk4::new(1e-3), x0, t1, &times, &crossings, false);
    check(
        "dopri5",
        Dopri5::new(1e-9, 1e-11),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "dop853",
        Dop853::new(1e-9, 1e-11),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "rodas4",
        Rodas4::new(1e-6, 1e-8),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "rodas5p",
        Rodas5P::new(1e-6, 1e-8),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "bdf",
        nh_runtime::Bdf::new(1e-6, 1e-8),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "auto",
        AutoSwitch::new(1e-9, 1e-11),
        x0,
        t1,
        &times,
        &crossings,
        false,
    );
    check(
        "gauss4",
        GaussLegendre4::new(1e-3),
        x0,
        t1,
        &times,
        &crossings,
        true,
    );
}
