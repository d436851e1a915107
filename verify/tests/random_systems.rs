//! Differential verification of every route the engine takes (DESIGN §11):
//! thousands of random systems (Lagrangians written out, trees of rigid
//! bodies and point masses, rolling discs, spheres, tori, axles and carts,
//! systems in generalized speeds; explicit, implicit, affine,
//! time-dependent and holonomic constraints; inputs and forces), each
//! expanded by the engine, its generated accelerations, dependent
//! velocities and requested outputs interpreted in `f64` and compared at
//! three random states with the plain derivation in double-double. A
//! system some of whose coordinates the plain derivation finds cyclic is
//! expanded again with `outputs { momenta }` and its momenta, their rates
//! and its verdicts checked the same way; a system in coordinates whose
//! rows are explicit and homogeneous is expanded again with a `momenta`
//! block along the directions its rows allow, and its declared momenta,
//! their rates and verdicts checked against the plain J = ⟨∂L/∂q̇, X⟩ and
//! its total derivative along the plain motion. A system with bodies is
//! checked a second time with every kinetic energy folded into a symbol of
//! the Lagrangian (the path a chain's far links take, DESIGN §12.6) and
//! every group of bodies on chains of frames summed as composite inertias
//! (DESIGN §10) and, where they carry all of Cᵀ M C as a tree, solved by
//! the articulated-body recursion (§10).
//!
//! Reproducible from a seed; more systems for a nightly run:
//!
//! ```text
//! NH_VERIFY_SYSTEMS=100000 NH_VERIFY_SEED=12345 cargo test --release -p nh-verify --test random_systems -- --nocapture
//! ```
use nh_verify::run;

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The engine's rejections a random system may meet: its constraints
/// cannot be solved for distinct velocities or cancel to 0 = 0, or some
/// velocity carries no kinetic energy once they are substituted.
const EXPECTED_REJECTIONS: [&str; 4] = [
    "this constraint cannot be solved for any velocity not already dependent",
    "involves no velocity and no coordinate",
    "appears nowhere in the Lagrangian",
    "the reduced mass matrix is structurally singular",
];

#[test]
fn generated_code_agrees_with_the_plain_derivation() {
    let systems = env("NH_VERIFY_SYSTEMS", 3000);
    let first = env("NH_VERIFY_SEED", 0);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let s = run::run(first..first + systems, threads);
    println!("{}", s.describe());
    assert!(s.failures.is_empty(), "{} disagreements", s.failures.len());
    for why in s.rejected.keys() {
        assert!(
            EXPECTED_REJECTIONS.iter().any(|e| why.contains(e)),
            "an unexpected rejection: {why}"
        );
    }
    let n = s.systems as f64;
    let rejected = s.rejected.values().map(Vec::len).sum::<usize>() as f64;
    let no_state = s.no_state.values().map(Vec::len).sum::<usize>() as f64;
    assert!(rejected <= 0.03 * n, "{rejected} rejections");
    assert!(
        no_state <= 0.02 * n,
        "{no_state} systems without a usable state"
    );
    assert!(s.agreed as f64 >= 0.95 * n, "{} agreed", s.agreed);
    // outputs { momenta } on the systems with cyclic coordinates: compared
    // on at least a tenth of all systems, the engine proving at least 95 %
    // of the coordinates the plain derivation finds cyclic there
    let m = &s.momenta;
    assert!(
        m.compared as f64 >= 0.1 * n,
        "momenta compared on {}",
        m.compared
    );
    assert!(
        m.listed as f64 >= 0.95 * m.found as f64,
        "{} of {} cyclic coordinates listed",
        m.listed,
        m.found
    );
    // momenta { .. } along the directions the rows allow: compared on at
    // least a fifth of all systems (the comparison itself fails the run)
    assert!(
        s.declared.0 as f64 >= 0.2 * n,
        "declared momenta compared on {} systems",
        s.declared.0
    );
    // every kinetic energy folded: checked again on at least a third of
    // all systems (a disagreement there fails the run above)
    assert!(
        s.folded as f64 >= 0.3 * n,
        "checked with folded kinetic energies on {} systems",
        s.folded
    );
    // and with every group of bodies on chains of frames summed as
    // composite inertias: on at least a tenth (139 of the first 600)
    assert!(
        s.composite as f64 >= 0.1 * n,
        "checked with composite inertias on {} systems",
        s.composite
    );
    // of them, solved by the articulated-body recursion on their tree: on
    // at least one in sixty (21 of the first 600)
    assert!(
        s.articulated as f64 >= n / 60.0,
        "solved by the articulated-body recursion on {} systems",
        s.articulated
    );
    // the generator still reaches every kind of system
    for (feature, share) in [
        ("rigid bodies", 0.3),
        ("point masses", 0.05),
        ("inertia with products", 0.1),
        ("rolling contacts", 0.15),
        ("explicit constraints", 0.15),
        ("implicit constraints", 0.1),
        ("holonomic constraints", 0.05),
        ("time-dependent constraints or kinematics", 0.05),
        ("speeds", 0.08),
        ("inputs", 0.15),
        ("output multipliers", 0.1),
    ] {
        let count = s.features.get(feature).copied().unwrap_or(0) as f64;
        assert!(count >= share * n, "{feature}: {count} of {n}");
    }
}
