//! Events whose function is not finite somewhere: a sign change across
//! NaN values of `g` is found (at the end of the NaN window), a pole of `g`
//! (a sign change through ±∞) is not an event, and a root next to a pole
//! still is; with every integrator.
use std::f64::consts::PI;

use nalgebra::Vector1;
use nh_runtime::{
    AutoSwitch, Bdf, Direction, Dop853, Dopri5, EventHit, Events, GaussLegendre4, Integrator,
    Outcome, Rk4, Rodas4, Rodas5P, SimError,
};

/// x' = 1 from 0: the state is the clock, so `g` may be written in `t`.
fn clock(_t: f64, _x: &Vector1<f64>) -> Vector1<f64> {
    Vector1::new(1.0)
}

type Run = Result<Outcome<f64, 1>, SimError<f64, 1>>;
type Hits = Vec<EventHit<f64, 1>>;

/// `events` with every integrator over `[0, t1]`: name, result, hits.
fn with_every_integrator<G>(
    events: &Events<f64, G, 1>,
    t1: f64,
    max_step: f64,
) -> Vec<(&'static str, Run, Hits)>
where
    G: Fn(f64, &Vector1<f64>) -> Vector1<f64>,
{
    let x0 = Vector1::new(0.0);
    let mut out = Vec::new();
    macro_rules! run {
        ($name:expr, $integrator:expr) => {{
            let mut seen = Vec::new();
            let r =
                $integrator.integrate_with_events(&clock, 0.0, x0, t1, events, |h| seen.push(*h));
            out.push(($name, r, seen));
        }};
    }
    run!("Rk4", Rk4::new(0.1));
    run!("GaussLegendre4", GaussLegendre4::new(0.1));
    run!("Dopri5", Dopri5::new(1e-8, 1e-10).with_max_step(max_step));
    run!("Dop853", Dop853::new(1e-8, 1e-10).with_max_step(max_step));
    run!("Rodas4", Rodas4::new(1e-8, 1e-10).with_max_step(max_step));
    run!("Rodas5P", Rodas5P::new(1e-8, 1e-10).with_max_step(max_step));
    run!("Bdf", Bdf::new(1e-8, 1e-10).with_max_step(max_step));
    run!(
        "AutoSwitch",
        AutoSwitch::new(1e-8, 1e-10).with_max_step(max_step)
    );
    out
}

#[test]
fn a_nan_at_the_step_end_where_the_sign_changes_does_not_lose_the_event() {
    // g = sign(t − 1/2)·sqrt|t − 1/2| is NaN (0/0) exactly at its root,
    // which is the end of the fifth Rk4 step (5·0.1 = 0.5): the values
    // with a sign on either side are −0.32 at 0.4 and 0.32 at 0.6. The
    // run used to end Ok at t1 without an event.
    let g = |t: f64, _x: &Vector1<f64>| Vector1::new((t - 0.5) / (t - 0.5).abs().sqrt());
    assert!(g(0.5, &Vector1::zeros())[0].is_nan());
    let events = Events::new(g).terminal([true]);
    for (name, r, seen) in with_every_integrator(&events, 1.0, 1.0) {
        let out = r.unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let hit = out
            .event
            .unwrap_or_else(|| panic!("{name}: the event is lost"));
        assert_eq!(seen, [hit], "{name}");
        assert_eq!(hit.direction, Direction::Rising, "{name}");
        assert!((hit.t - 0.5).abs() <= 1e-15, "{name}: {}", hit.t);
        assert_eq!((out.t, out.x), (hit.t, hit.x), "{name}");
    }
}

#[test]
fn a_sign_change_across_a_nan_window_is_reported_where_g_has_a_sign_again() {
    // g = t − 1/2, but NaN for |t − 1/2| < 0.15: the Rk4 step ends 0.4,
    // 0.5 and 0.6 all give NaN, and the sign changes between 0.3 (−0.2)
    // and 0.7 (+0.2). The event is placed where g is first seen on the far
    // side: the end of the window, t = 0.65. It used to be lost (Rk4,
    // GaussLegendre4, Bdf) or reported at a time where nothing happens
    // (Dopri5 at t1 = 1, Dop853 at 0.933: the root finder stopped
    // at the first NaN).
    let g = |t: f64, _x: &Vector1<f64>| {
        Vector1::new(if (t - 0.5).abs() < 0.15 {
            f64::NAN
        } else {
            t - 0.5
        })
    };
    let events = Events::new(g).terminal([true]);
    for max_step in [1.0, 0.05] {
        for (name, r, seen) in with_every_integrator(&events, 1.0, max_step) {
            let out = r.unwrap_or_else(|e| panic!("{name}: {e:?}"));
            let hit = out
                .event
                .unwrap_or_else(|| panic!("{name}: the event is lost"));
            assert_eq!(seen.len(), 1, "{name}");
            assert_eq!(hit.direction, Direction::Rising, "{name}");
            assert!(
                (hit.t - 0.65).abs() <= 1e-15,
                "{name}, {max_step}: {}",
                hit.t
            );
            assert!(g(hit.t, &hit.x)[0] >= 0.15, "{name}: g has crossed there");
        }
    }
    // Not terminal, and with a second sign change in the window's far
    // side: both are reported, in order.
    let twice = |t: f64, _x: &Vector1<f64>| {
        Vector1::new(if (t - 0.5).abs() < 0.15 {
            f64::NAN
        } else {
            (t - 0.5) * (0.8 - t)
        })
    };
    let events = Events::new(twice);
    for (name, r, seen) in with_every_integrator(&events, 1.0, 0.05) {
        assert_eq!(r.unwrap().t, 1.0, "{name}");
        let times: Vec<f64> = seen.iter().map(|h| h.t).collect();
        assert_eq!(seen.len(), 2, "{name}: {times:?}");
        assert!((times[0] - 0.65).abs() <= 1e-15, "{name}: {times:?}");
        assert!((times[1] - 0.8).abs() <= 1e-14, "{name}: {times:?}");
        assert_eq!(seen[1].direction, Direction::Falling);
    }
}

#[test]
fn nan_from_the_start_is_no_sign_to_change_from() {
    // g is NaN until 0.3, then t − 0.2 > 0 and later t − 0.2 stays
    // positive: no value with a sign ever changes sign.
    let g = |t: f64, _x: &Vector1<f64>| Vector1::new(if t < 0.3 { f64::NAN } else { t - 0.2 });
    let events = Events::new(g).terminal([true]);
    for (name, r, seen) in with_every_integrator(&events, 1.0, 0.05) {
        assert!(seen.is_empty(), "{name}: {seen:?}");
        assert_eq!(r.unwrap().t, 1.0, "{name}");
    }
}

#[test]
fn a_pole_of_g_is_not_an_event() {
    // g = 1/(t − 1/2) changes sign at 1/2 through ±∞, without a zero. It
    // used to be reported (Rising, at 0.5) by every integrator.
    let g = |t: f64, _x: &Vector1<f64>| Vector1::new(1.0 / (t - 0.5));
    let events = Events::new(g).terminal([true]);
    for max_step in [1.0, 0.03] {
        for (name, r, seen) in with_every_integrator(&events, 1.0, max_step) {
            let out = r.unwrap_or_else(|e| panic!("{name}: {e:?}"));
            assert!(seen.is_empty(), "{name}: {seen:?}");
            assert_eq!((out.t, out.event), (1.0, None), "{name}");
        }
    }
    // A jump from +∞ to −∞ is no event either (it used to be one, Falling,
    // reported anywhere in the step of the jump).
    let jump = |t: f64, _x: &Vector1<f64>| {
        Vector1::new(if t < 0.5 {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        })
    };
    let events = Events::new(jump).terminal([true]);
    for (name, r, seen) in with_every_integrator(&events, 1.0, 0.03) {
        assert!(seen.is_empty(), "{name}: {seen:?}");
        assert_eq!(r.unwrap().t, 1.0, "{name}");
    }
}

#[test]
fn tan_has_its_roots_found_and_its_poles_skipped() {
    // tan t over [0, 4]: a pole at π/2 (+ to −), a root at π (− to +).
    // Steps of at most 0.1 keep the two apart; before, the pole was
    // reported as a Falling event at π/2 too.
    let events = Events::new(|t: f64, _x: &Vector1<f64>| Vector1::new(t.tan()));
    for (name, r, seen) in with_every_integrator(&events, 4.0, 0.1) {
        assert_eq!(r.unwrap().t, 4.0, "{name}");
        let times: Vec<f64> = seen.iter().map(|h| h.t).collect();
        assert_eq!(seen.len(), 1, "{name}: {times:?}");
        assert!((seen[0].t - PI).abs() <= 1e-14, "{name}: {times:?}");
        assert_eq!(seen[0].direction, Direction::Rising);
    }
}

#[test]
fn a_root_next_to_a_pole_is_found() {
    // g = (t − 0.52)/(t − 0.5): + before the pole at 0.5, − between it and
    // the root at 0.52, + after. Rk4's step end 0.5 falls on the pole
    // (g = −∞ there): the step [0.4, 0.5] ends in a pole (+1.2 to −∞, no
    // event), the step [0.5, 0.6] holds the root (−∞ to 0.8). Before, the
    // pole was reported (Falling at 0.5) and the root 0.5207, the root
    // finder having started from −∞.
    let g = |t: f64, _x: &Vector1<f64>| Vector1::new((t - 0.52) / (t - 0.5));
    assert_eq!(g(0.5, &Vector1::zeros())[0], f64::NEG_INFINITY);
    let events = Events::new(g);
    // Steps of at most 0.004 for the adaptive ones: the pole and the root
    // fall in different steps.
    for (name, r, seen) in with_every_integrator(&events, 1.0, 0.004) {
        assert_eq!(r.unwrap().t, 1.0, "{name}");
        let times: Vec<f64> = seen.iter().map(|h| h.t).collect();
        assert_eq!(seen.len(), 1, "{name}: {times:?}");
        assert!((seen[0].t - 0.52).abs() <= 1e-15, "{name}: {times:?}");
        assert_eq!(seen[0].direction, Direction::Rising, "{name}");
    }
}
