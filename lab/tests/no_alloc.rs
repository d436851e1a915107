//! Zero heap allocations inside `integrate` for generated systems, with every
//! integrator (the Rodas4, BDF and Gauss methods with the generated Jacobian
//! and with finite differences), and inside the generated methods themselves.
//! The one exception is `GaussLegendre4`, which allocates its Newton
//! workspace once per call: its allocations must not depend on the number
//! of steps.
use nh_lab::systems::{RollingDisc, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;
#[path = "../../tests/common/counting_alloc.rs"]
mod counting_alloc;

use counting_alloc::allocations_during;

fn x0() -> SVector<f64, 8> {
    SVector::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5])
}

#[test]
fn integrators_allocate_nothing_on_a_generated_system() {
    let disc: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let checks: Vec<(&str, usize, usize)> = vec![
        {
            let (n, r) = allocations_during(|| Rk4::new(1e-3).integrate(&disc, 0.0, x0(), 1.0));
            ("Rk4", n, r.expect("Rk4").stats.steps)
        },
        {
            let (n, r) =
                allocations_during(|| Dopri5::new(1e-8, 1e-10).integrate(&disc, 0.0, x0(), 1.0));
            ("Dopri5", n, r.expect("Dopri5").stats.steps)
        },
        {
            let (n, r) =
                allocations_during(|| Dop853::new(1e-8, 1e-10).integrate(&disc, 0.0, x0(), 1.0));
            ("Dop853", n, r.expect("Dop853").stats.steps)
        },
        {
            let (n, r) = allocations_during(|| {
                Rodas4::new(1e-6, 1e-8).integrate_with_jacobian(&disc, 0.0, x0(), 1.0)
            });
            (
                "Rodas4, generated Jacobian",
                n,
                r.expect("Rodas4").stats.steps,
            )
        },
        {
            let (n, r) =
                allocations_during(|| Rodas4::new(1e-6, 1e-8).integrate(&disc, 0.0, x0(), 1.0));
            (
                "Rodas4, finite differences",
                n,
                r.expect("Rodas4 FD").stats.steps,
            )
        },
        {
            let (n, r) = allocations_during(|| {
                Bdf::new(1e-6, 1e-8).integrate_with_jacobian(&disc, 0.0, x0(), 1.0)
            });
            ("Bdf, generated Jacobian", n, r.expect("Bdf").stats.steps)
        },
        {
            let (n, r) =
                allocations_during(|| Bdf::new(1e-6, 1e-8).integrate(&disc, 0.0, x0(), 1.0));
            ("Bdf, finite differences", n, r.expect("Bdf FD").stats.steps)
        },
        {
            let times = [0.1, 0.2, 0.5, 0.9];
            let mut sum = 0.0;
            let (n, r) = allocations_during(|| {
                Dop853::new(1e-8, 1e-10).integrate_with_outputs(
                    &disc,
                    0.0,
                    x0(),
                    1.0,
                    &times,
                    |_, x| sum += x[2],
                )
            });
            (
                "Dop853 with output times",
                n,
                r.expect("Dop853 outputs").stats.steps,
            )
        },
    ];
    for (name, allocations, steps) in checks {
        println!("{name}: {steps} steps, {allocations} allocations");
        assert!(steps > 10, "{name} did too little work to prove anything");
        assert_eq!(allocations, 0, "{name} allocated");
    }

    // GaussLegendre4: one workspace per call, independent of the steps.
    let gauss = |t1: f64| {
        allocations_during(|| {
            GaussLegendre4::new(1e-3).integrate_with_jacobian(&disc, 0.0, x0(), t1)
        })
    };
    let (short, r_short) = gauss(0.01);
    let (long, r_long) = gauss(1.0);
    let (short_steps, long_steps) = (
        r_short.expect("Gauss").stats.steps,
        r_long.expect("Gauss").stats.steps,
    );
    println!(
        "GaussLegendre4, generated Jacobian: {short_steps} steps, {short} allocations; {long_steps} steps, {long} allocations"
    );
    assert_eq!((short_steps, long_steps), (10, 1000));
    assert_eq!(short, long, "GaussLegendre4 allocated per step");
    assert!(long <= 3, "GaussLegendre4: {long} allocations");
}

#[test]
fn generated_methods_allocate_nothing() {
    let disc: RollingDisc = RollingDisc::new(1.7, 0.35, 9.81);
    let stiff: StiffDisc = StiffDisc::new(1.7, 0.35, 9.81, 1e6, 1e3, 0.2);
    let q = SVector::<f64, 5>::from([0.1, 0.2, 0.3, 0.4, 0.5]);
    let rdot = SVector::<f64, 3>::from([6.0, 2.0, 0.5]);
    let (n, sum) = allocations_during(|| {
        let mut s = 0.0;
        for _ in 0..100 {
            s += disc.accelerations(0.0, &q, &rdot)[0]
                + disc.multipliers(0.0, &q, &rdot)[0]
                + disc.energy(&q, &rdot)
                + disc.curvature(&q)[0][(0, 1)]
                + disc.jacobian(0.0, &x0())[(5, 2)]
                + stiff.rhs(0.0, &x0())[7];
        }
        s
    });
    assert!(sum.is_finite());
    assert_eq!(n, 0);
}
