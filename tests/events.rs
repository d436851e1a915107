//! Events at the facade: a rolling disc that falls flat and a slow bicycle
//! that falls over end their runs at a terminal event, with the state
//! there, instead of at the typed failure of a singular chart.
#[path = "../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)] // the linearisation helpers serve tests/whipple.rs
mod model;

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The rolling disc written with a body and a rolling contact.
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
    }
}

/// The disc's state `[θ, φ, ψ, x, y, θ̇, φ̇, ψ̇]`: at rest, leaning 1.2 rad.
fn leaning_at_rest() -> SVector<f64, 8> {
    SVector::from([0.0, 0.0, 1.2, 0.0, 0.0, 0.0, 0.0, 0.0])
}

/// Flat: the lean ψ reaches π/2 (terminal).
fn flat() -> Events<f64, impl Fn(f64, &SVector<f64, 8>) -> Vector1<f64>, 1> {
    Events::new(|_t: f64, x: &SVector<f64, 8>| Vector1::new(std::f64::consts::FRAC_PI_2 - x[2]))
        .direction([Direction::Falling])
        .terminal([true])
}

/// Released at rest, the disc pivots about its fixed contact point (θ̇
/// and φ̇ stay 0): a pendulum with moment 5mR²/4 about the contact, so
/// ψ̇² = 8g/(5R)·(cos ψ0 − cos ψ). It lies flat at
/// t* = ∫ dψ/ψ̇ from ψ0 = 1.2 to π/2 (mpmath, 40 digits, with
/// cos ψ0 − cos ψ = u²) with ψ̇ = √(8g/(5R)·cos ψ0) there.
const FLAT_TIME: f64 = 0.186_594_100_746_641_68;
const FLAT_RATE: f64 = 4.031_152_729_241_837;

#[test]
fn a_disc_falling_flat_ends_at_its_event_with_every_integrator() {
    let disc = BodyDisc::new(1.7, 0.35, 9.81);
    let x0 = leaning_at_rest();
    let check = |name: &str, out: Result<Outcome<f64, 8>, SimError<f64, 8>>, tol: f64| {
        let out = out.unwrap_or_else(|e| panic!("{name}: {e}"));
        let hit = out.event.expect("the disc lies flat");
        assert_eq!((hit.index, hit.t, hit.x), (0, out.t, out.x));
        let (dt, drate) = ((out.t - FLAT_TIME).abs(), (out.x[7] - FLAT_RATE).abs());
        eprintln!(
            "{name}: flat at t = {:.15} (error {dt:.1e}), ψ̇ error {drate:.1e}, {} steps, {} evaluations of g",
            out.t, out.stats.steps, out.stats.event_evals
        );
        assert!(
            dt <= tol && drate <= 10.0 * tol,
            "{name}: {dt:e}, {drate:e}"
        );
        assert!(
            (out.x[2] - std::f64::consts::FRAC_PI_2).abs() <= 1e-13,
            "{name}"
        );
        // The contact point stays put and the disc does not turn.
        assert!(
            out.x.iter().skip(3).take(3).all(|v| v.abs() < 1e-12),
            "{name}: {}",
            out.x
        );
    };
    let events = flat();
    let mut dp = Dopri5::new(1e-10, 1e-12);
    let mut dop = Dop853::new(1e-10, 1e-12);
    let mut ros = Rodas4::new(1e-8, 1e-10);
    let mut rodas5 = Rodas5P::new(1e-8, 1e-10);
    let mut auto = AutoSwitch::new(1e-10, 1e-12);
    let (mut rk4, mut gauss) = (Rk4::new(1e-3), GaussLegendre4::new(1e-3));
    check(
        "Dopri5",
        dp.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-9,
    );
    check(
        "Dop853",
        dop.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-9,
    );
    check(
        "Rodas4",
        ros.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-7,
    );
    check(
        "Rodas5P",
        rodas5.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-7,
    );
    check(
        "AutoSwitch",
        auto.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-9,
    );
    check(
        "Rk4",
        rk4.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-9,
    );
    check(
        "GaussLegendre4",
        gauss.integrate_with_events(&disc, 0.0, x0, 1.0, &events, |_| {}),
        1e-9,
    );
    // Without the event the same fall ends at the chart's singularity.
    let err = Dopri5::new(1e-10, 1e-12)
        .integrate(&disc, 0.0, x0, 1.0)
        .unwrap_err();
    assert!(
        matches!(
            err,
            SimError::Singular {
                cause: Singularity::Chart,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.time().unwrap() < FLAT_TIME);
}

/// Upright and straight ahead at speed `v`, with roll rate `p`.
fn riding(b: &model::Whipple, v: f64, p: f64) -> SVector<f64, 11> {
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = p;
    x0[10] = v / b.rR;
    x0
}

/// The bicycle leans past 1 rad either way (non-terminal), then past
/// 1.4 rad (80°, where the rider is on the ground: terminal).
fn falls() -> Events<f64, impl Fn(f64, &SVector<f64, 11>) -> Vector2<f64>, 2> {
    let (warn, down) = (1.0f64.cos(), 1.4f64.cos());
    Events::new(move |_t: f64, x: &SVector<f64, 11>| {
        Vector2::new(x[0].cos() - warn, x[0].cos() - down)
    })
    .direction([Direction::Falling, Direction::Falling])
    .terminal([false, true])
}

#[test]
fn a_slow_bicycle_falling_over_ends_at_its_event() {
    // At 2 m/s, below the weave speed (4.29 m/s), a roll rate of
    // 0.05 rad/s grows until the bicycle falls over (to the left).
    let b = model::benchmark();
    let x0 = riding(&b, 2.0, 0.05);
    let mut first: Option<(f64, f64)> = None;
    for (name, tol) in [("Dop853", 1e-11), ("Dopri5", 1e-11), ("Rodas4", 1e-9)] {
        let mut hits = Vec::new();
        let on_event = |h: &EventHit<f64, 11>| hits.push((h.index, h.t));
        let events = falls();
        let out = match name {
            "Dop853" => Dop853::new(tol, tol * 1e-2)
                .integrate_with_events(&b, 0.0, x0, 10.0, &events, on_event),
            "Dopri5" => Dopri5::new(tol, tol * 1e-2)
                .integrate_with_events(&b, 0.0, x0, 10.0, &events, on_event),
            _ => Rodas4::new(tol, tol * 1e-2)
                .integrate_with_events(&b, 0.0, x0, 10.0, &events, on_event),
        };
        let out = out.unwrap_or_else(|e| panic!("{name}: {e}"));
        let hit = out.event.expect("it falls");
        assert_eq!(
            hits.iter().map(|h| h.0).collect::<Vec<_>>(),
            [0, 1],
            "{name}"
        );
        assert_eq!((hit.index, hit.t), (1, out.t));
        assert!(
            (out.x[0] + 1.4).abs() < 1e-12,
            "{name}: to the left, {}",
            out.x[0]
        );
        assert!(out.max_residual.unwrap() < 1e-11, "{name}");
        eprintln!(
            "{name} (rtol {tol:.0e}): leans 1 rad at t = {:.12}, 1.4 rad at t = {:.12} ({} steps, {} evaluations of g)",
            hits[0].1, out.t, out.stats.steps, out.stats.event_evals
        );
        let (t1, t2) = *first.get_or_insert((hits[0].1, out.t));
        assert!(
            (hits[0].1 - t1).abs() < 1e-7 && (out.t - t2).abs() < 1e-7,
            "{name}"
        );
    }
    // Without the events the run goes on until the chart of the equations
    // breaks down (the front contact at about 85° of roll), typed.
    let err = Dop853::new(1e-11, 1e-13)
        .integrate(&b, 0.0, x0, 10.0)
        .unwrap_err();
    assert!(
        matches!(
            err,
            SimError::Singular {
                cause: Singularity::Chart,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.time().unwrap() > first.unwrap().1);
}
