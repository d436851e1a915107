//! Poles of the user's own chart (DESIGN §9.2, §9.3): the Chaplygin sled
//! written `dot(y) = tan(theta)*dot(x)` is an implicit row with its
//! denominator cleared, cos θ ẏ − sin θ ẋ = 0, solved for y in its own chart
//! and for x in the atlas's other one: driven through θ = π/2 every
//! integrator moves to the other chart and agrees with the same sled in
//! generalized speeds (no pole); held in its own chart it ends in
//! `Singular` at the last good state before the pole, never `Ok` with a
//! wrong state. A pole the charts do not remove (a force with tan θ) ends
//! every run in `Singular` with the pole named. A system without poles gets
//! no `crossed_pole` (the runtime's default).
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A point pushed along x by a force that grows as tan θ while θ turns
    /// freely: the force has a pole at θ = π/2.
    pub struct TanForce {
        parameters { m, k }
        coordinates { x, theta }
        lagrangian = m*(dot(x)^2 + dot(theta)^2)/2;
        forces { x: k*tan(theta); }
    }
}

nonholonomic_system! {
    pub struct TanSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
    }
}

nonholonomic_system! {
    pub struct SpeedSled {
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
    }
}

const PARAMS: (f64, f64, f64) = (1.0, 0.3, 0.4);

/// θ, the speed v along the blade and the yaw rate ω at t = 0.
const START: (f64, f64, f64) = (1.2, 0.5, 1.5);

/// The sled in speeds from the same start, at time t.
fn reference(t: f64) -> SVector<f64, 5> {
    let (m, j, a) = PARAMS;
    let (theta, v, omega) = START;
    let x0 = SVector::<f64, 5>::new(0.0, theta, 0.0, v, omega);
    Dopri5::new(1e-13, 1e-14)
        .integrate(&SpeedSled::new(m, j, a), 0.0, x0, t)
        .expect("no pole in speeds")
        .x
}

/// A run's outcome.
type Run = Result<Outcome<f64, 5>, SimError<f64, 5>>;

/// Each integrator's run of the tan sled across θ = π/2, with switching
/// (`true`) or held in its own chart.
fn runs(switching: bool) -> Vec<(&'static str, Run)> {
    let (m, j, a) = PARAMS;
    let sys = TanSled::new(m, j, a);
    let (theta, v, omega) = START;
    let x0 = SVector::<f64, 5>::new(0.0, theta, 0.0, v * theta.cos(), omega);
    let t1 = 2.0;
    assert!(reference(t1)[1] > 2.0, "the motion crosses θ = π/2");
    let s = switching;
    vec![
        (
            "Rk4",
            Rk4::new(0.01)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Dopri5",
            Dopri5::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Dopri5 tight",
            Dopri5::new(1e-10, 1e-12)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Dop853",
            Dop853::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Rodas4",
            Rodas4::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Rodas5P",
            Rodas5P::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "Bdf",
            Bdf::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "GaussLegendre4",
            GaussLegendre4::new(0.01)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
        (
            "AutoSwitch",
            AutoSwitch::new(1e-8, 1e-10)
                .with_chart_switching(s)
                .integrate(&sys, 0.0, x0, t1),
        ),
    ]
}

/// The largest error of x, θ, y against the sled in speeds at `t`.
fn off(t: f64, x: &SVector<f64, 5>) -> f64 {
    let r = reference(t);
    (0..3).map(|i| (x[i] - r[i]).abs()).fold(0.0, f64::max)
}

#[test]
fn the_tan_sled_goes_through_its_pole_in_the_other_chart() {
    assert_eq!(TanSled::<f64>::DEPENDENT, [2]);
    let sys = TanSled::new(PARAMS.0, PARAMS.1, PARAMS.2);
    assert_eq!(sys.charts(), 2);
    assert_eq!(sys.chart_name(1), "solved for `x`");
    for (name, run) in runs(true) {
        let out = run.unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let err = off(out.t, &out.x);
        println!(
            "{name}: θ = {:.6} at t = {}, {} switches, off by {err:.1e}",
            out.x[1], out.t, out.stats.chart_switches
        );
        assert!(out.stats.chart_switches >= 1, "{name}");
        assert!(out.x[1] > 2.0, "{name}");
        assert!(err < 1e-4, "{name}: {err}");
    }
}

#[test]
fn the_tan_chart_held_never_steps_over_its_pole() {
    for (name, run) in runs(false) {
        match run {
            Err(SimError::Singular {
                t,
                x,
                cause: Singularity::Chart,
            }) => {
                assert!(x[1] < std::f64::consts::FRAC_PI_2, "{name}: θ = {}", x[1]);
                // the last good state is the motion's, to the tolerance
                let err = off(t, &x);
                assert!(x[1] > 1.4, "{name}: stopped early, θ = {}", x[1]);
                println!(
                    "{name}: stopped at t = {t:.6}, θ = {:.6}, off by {err:.1e}",
                    x[1]
                );
                assert!(err < 1e-4, "{name}: {err}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

#[test]
fn a_pole_of_a_force_ends_every_run_with_its_name() {
    // θ turns at 1 rad/s from 1.2: the force's pole at t = π/2 − 1.2
    let sys = TanForce::new(1.0, 0.5);
    let x0 = SVector::<f64, 4>::new(0.0, 1.2, 0.0, 1.0);
    let t_pole = std::f64::consts::FRAC_PI_2 - 1.2;
    type Run4 = Result<Outcome<f64, 4>, SimError<f64, 4>>;
    let runs: Vec<(&str, Run4)> = vec![
        ("Rk4", Rk4::new(0.01).integrate(&sys, 0.0, x0, 1.0)),
        (
            "Dopri5",
            Dopri5::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 1.0),
        ),
        (
            "Dop853",
            Dop853::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 1.0),
        ),
        (
            "Rodas4",
            Rodas4::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 1.0),
        ),
        ("Bdf", Bdf::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 1.0)),
        (
            "GaussLegendre4",
            GaussLegendre4::new(0.01).integrate(&sys, 0.0, x0, 1.0),
        ),
    ];
    for (name, run) in runs {
        match run {
            Err(SimError::Singular {
                t,
                x,
                cause: Singularity::Pole(expr),
            }) => {
                assert_eq!(expr, "1/cos(theta)", "{name}");
                assert!(t < t_pole && t > t_pole - 0.05, "{name}: t = {t}");
                // θ moves freely: θ = 1.2 + t
                assert!((x[1] - 1.2 - t).abs() < 1e-9, "{name}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

#[test]
fn a_system_without_poles_has_no_pole_check() {
    // the runtime's default: no guard is evaluated
    let sys = SpeedSled::new(1.0, 0.3, 0.4);
    let x = SVector::<f64, 5>::new(0.0, 1.5, 0.0, 1.0, 0.8);
    assert_eq!(sys.crossed_pole(0.0, &x, 1.0, &(x * 2.0)), None);
}

#[test]
fn the_guard_is_the_cosine_of_the_tan() {
    let sys = TanForce::new(1.0, 0.5);
    let at = |theta: f64| SVector::<f64, 4>::new(0.0, theta, 1.0, 0.8);
    assert_eq!(sys.crossed_pole(0.0, &at(1.5), 0.1, &at(1.56)), None);
    assert_eq!(
        sys.crossed_pole(0.0, &at(1.5), 0.1, &at(1.6)),
        Some("1/cos(theta)")
    );
    assert_eq!(
        sys.crossed_pole(0.0, &at(-1.5), 0.1, &at(-1.6)),
        Some("1/cos(theta)")
    );
}

#[test]
#[ignore = "a measurement for the record: the same runs with the guard hidden"]
fn without_the_guard() {
    struct Hidden(TanSled);
    impl OdeSystem<f64, 5> for Hidden {
        fn rhs(&self, t: f64, x: &SVector<f64, 5>) -> SVector<f64, 5> {
            self.0.rhs(t, x)
        }
    }
    let (m, j, a) = PARAMS;
    let sys = Hidden(TanSled::new(m, j, a));
    let (theta, v, omega) = START;
    let x0 = SVector::<f64, 5>::new(0.0, theta, 0.0, v * theta.cos(), omega);
    let r = reference(2.0);
    let show = |name: &str, run: Run| match run {
        Ok(o) => println!(
            "{name}: Ok, y = {:.6} (reference {:.6}), θ = {:.6} ({:.6})",
            o.x[2], r[2], o.x[1], r[1]
        ),
        Err(e) => println!("{name}: {e:?}"),
    };
    show("Rk4", Rk4::new(0.01).integrate(&sys, 0.0, x0, 2.0));
    show(
        "Dopri5",
        Dopri5::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 2.0),
    );
    show(
        "Dopri5 tight",
        Dopri5::new(1e-10, 1e-12).integrate(&sys, 0.0, x0, 2.0),
    );
    show(
        "Dop853",
        Dop853::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 2.0),
    );
    show(
        "Rodas4",
        Rodas4::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 2.0),
    );
    show("Bdf", Bdf::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 2.0));
}
