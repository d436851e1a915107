//! Every method of the side-by-side, ours and the peers', on a problem with
//! a closed form: the adapters hand the right state, time and Jacobian
//! through, and the counts are the runs' own.
use nh_peers::measure::Counted;
use nh_peers::methods::{self, Method, Setting, Start, Suite, diffsol_peer};
use nonholonomic::prelude::*;

/// The harmonic oscillator q̈ = −q as (q, p): q = cos t, p = −sin t.
struct Oscillator;

impl OdeSystem<f64, 2> for Oscillator {
    fn rhs(&self, _t: f64, x: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(x[1], -x[0])
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

impl OdeJacobian<f64, 2> for Oscillator {
    fn jacobian(&self, _t: f64, _x: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -1.0, 0.0)
    }
}

fn all() -> Vec<Method<Oscillator, 2>> {
    methods::our_methods()
        .into_iter()
        .chain(methods::peer_methods())
        .collect()
}

#[test]
fn every_method_integrates_the_oscillator_to_its_closed_form() {
    let start = Start {
        x0: SVector::<f64, 2>::new(1.0, 0.0),
        t1: 2.0,
        max_steps: 1_000_000,
    };
    let exact = SVector::<f64, 2>::new(2f64.cos(), -(2f64.sin()));
    let sys = Oscillator;
    let counted = Counted::new(&sys);
    let methods = all();
    assert_eq!(methods.iter().filter(|m| m.suite == Suite::Ours).count(), 5);
    assert_eq!(methods.len(), 15);
    for m in &methods {
        let setting = match m.setting {
            Setting::Tolerance => 1e-8,
            Setting::StepSize => 1e-3,
        };
        let (out, calls) = counted.count(|| (m.run)(&counted, &start, setting));
        let out = out.unwrap_or_else(|e| panic!("{}: {e}", m.name));
        let error = (out.x - exact).amax();
        // tr_bdf2 is of order 2; every other method is far more accurate
        let bound = if m.name.contains("tr_bdf2") {
            1e-5
        } else {
            1e-6
        };
        assert!(error < bound, "{}: error {error:e}", m.name);
        assert!(
            out.steps > 0 && calls.rhs >= out.steps,
            "{}: {} steps, {calls:?}",
            m.name,
            out.steps
        );
        if m.setting == Setting::StepSize {
            assert_eq!(out.steps, 2000, "{}", m.name);
        }
    }
}

#[test]
fn the_counts_are_the_runs_own() {
    let sys = Oscillator;
    let counted = Counted::new(&sys);
    let (out, calls) = counted.count(|| {
        Dopri5::new(1e-8, 1e-10)
            .integrate(&counted, 0.0, SVector::<f64, 2>::new(1.0, 0.0), 2.0)
            .unwrap()
    });
    assert_eq!(calls.rhs, out.stats.rhs_evals);
    assert_eq!(calls.jacobian, 0);
    // the wrapper counts nothing outside `count`
    let _ = sys_rhs(&counted);
    let ((), after) = counted.count(|| ());
    assert_eq!(after.rhs, 0);
}

fn sys_rhs(s: &Counted<'_, Oscillator>) -> SVector<f64, 2> {
    s.rhs(0.0, &SVector::<f64, 2>::new(1.0, 0.0))
}

#[test]
fn diffsol_assembles_each_jacobian_from_one_generated_jacobian() {
    // diffsol builds its Jacobian matrix from products J·eᵢ (two per
    // assembly here); the adapter answers them from one generated Jacobian.
    let sys = Oscillator;
    let counted = Counted::new(&sys);
    let start = Start {
        x0: SVector::<f64, 2>::new(1.0, 0.0),
        t1: 2.0,
        max_steps: 1_000_000,
    };
    let bdf = methods::peer_methods::<Oscillator, 2>()
        .into_iter()
        .find(|m| m.name == "diffsol bdf")
        .unwrap();
    let (out, calls) = counted.count(|| (bdf.run)(&counted, &start, 1e-8));
    let out = out.unwrap();
    assert!(calls.jacobian >= 1, "{calls:?}");
    assert!(
        calls.jacobian < out.steps / 4,
        "{calls:?} for {} steps",
        out.steps
    );
}

#[test]
fn the_jacobian_cache_evaluates_once_per_state() {
    let sys = Oscillator;
    let counted = Counted::new(&sys);
    let cache = diffsol_peer::JacobianCache::<_, 2>::new(&counted);
    let mut y = [0.0; 2];
    let ((), calls) = counted.count(|| {
        cache.product(0.5, &[1.0, 2.0], &[1.0, 0.0], &mut y);
        assert_eq!(y, [0.0, -1.0]);
        cache.product(0.5, &[1.0, 2.0], &[0.0, 1.0], &mut y);
        assert_eq!(y, [1.0, 0.0]);
    });
    assert_eq!(calls.jacobian, 1);
    let ((), calls) = counted.count(|| {
        cache.product(0.5, &[1.0, 2.5], &[0.0, 1.0], &mut y); // a new state
        cache.product(0.6, &[1.0, 2.5], &[0.0, 1.0], &mut y); // a new time
    });
    assert_eq!(calls.jacobian, 2);
}
