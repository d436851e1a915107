//! The control-loop example (`examples/control_loop.rs`, included below as a
//! module so the test runs exactly the example's loop): the loop allocates
//! nothing, and the controller meets the example's stated bound.
#[path = "common/counting_alloc.rs"]
mod counting_alloc;

#[path = "../examples/control_loop.rs"]
#[allow(dead_code)] // the example's `main` and printing helpers
mod scenario;

use scenario::{BOUND, DURATION, H, REFERENCES, Scenario};

use counting_alloc::allocations_during;

#[test]
fn the_counter_sees_allocations() {
    let (n, v) = allocations_during(|| std::hint::black_box(vec![1u8; 64]));
    assert_eq!(v.len(), 64);
    assert!(n >= 1, "the counting allocator is not live");
}

#[test]
fn the_loop_allocates_nothing_and_meets_the_bound() {
    // Gains are designed and the logs reserved here, outside the count.
    let mut s = Scenario::new(DURATION);
    let (allocations, obj) = allocations_during(|| s.run());
    println!("{obj:?}");
    assert_eq!(obj.steps, (DURATION / H).round() as usize);
    assert!(obj.steps >= 10_000, "at least 10 s at 1 kHz");
    assert_eq!(s.latencies.len(), obj.steps);
    assert_eq!(allocations, 0, "the control loop allocated");

    assert!(
        obj.heading_peak < 1.0,
        "heading near the chart's singularity"
    );
    assert!(obj.lateral < BOUND, "lateral offset {:.2e}", obj.lateral);
    assert!(obj.heading < BOUND, "heading error {:.2e}", obj.heading);
    assert!(obj.speed < BOUND, "speed error {:.2e}", obj.speed);
    // The last sample is the final state: on the last reference.
    let last = s.samples.last().expect("samples");
    let (y_ref, v_ref) = REFERENCES[REFERENCES.len() - 1];
    assert!((last.x[2] - y_ref).abs() < BOUND);
    assert!((last.x[3] / last.x[1].cos() - v_ref).abs() < BOUND);
}

#[test]
fn the_design_holds_the_steady_motion_and_stabilises_it() {
    let s = Scenario::new(1.0);
    for g in &s.gains {
        // Along x at speed v the damping c v must be pushed against; no torque.
        let c = s.sled.c;
        assert!((g.u_star[0] - c * g.v_ref).abs() < 1e-12, "{:?}", g.u_star);
        assert!(g.u_star[1].abs() < 1e-12);
        assert!(g.riccati_residual < 1e-12, "{:e}", g.riccati_residual);
        assert!(g.slowest_pole < -1.0, "{}", g.slowest_pole);
        // K is finite.
        assert!(g.k.iter().all(|k| k.is_finite()));
    }
}
