//! The chains of bodies of the scaling benchmark (`examples/chains.rs`,
//! issue 34) expand without errors at small sizes: the planar chain of 4
//! links, the spatial chain of 2, the mobile manipulator with an arm of 2,
//! without outputs and with the jacobian and energy the benchmark also
//! measures. Sizes only, never times; the physics of the planar chain is
//! checked numerically in the root crate's `tests/chains.rs`.
mod synthetic;
mod tokens;

/// Expands `body` on a thread with an 8 MiB stack, as inside rustc, and
/// requires success: the generated code and its statistics.
fn expand_ok(body: String) -> (String, nh_core::Stats) {
    std::thread::Builder::new()
        .stack_size(8 << 20)
        .spawn(move || {
            let (out, stats) = nh_core::expand_with_stats(body.parse().expect("the body lexes"));
            let out = out.to_string();
            assert!(!out.contains("compile_error"), "{}: {out}", stats.name);
            (out, stats)
        })
        .expect("spawn the expansion thread")
        .join()
        .expect("the expansion panicked")
}

/// The operations of `accelerations` by the formulation it uses.
fn ops(s: &nh_core::Stats) -> usize {
    match (s.route, s.formulation) {
        (Some(nh_core::Route::Curvature), _) | (_, Some(nh_core::Formulation::Maggi)) => {
            s.ops_curvature
        }
        _ => s.ops_multiplier,
    }
}

#[test]
fn the_families_expand_at_small_sizes() {
    for (body, name) in [
        (synthetic::planar(4, ""), "Planar4"),
        (synthetic::spatial(2, ""), "Spatial2"),
        (synthetic::manipulator(2, ""), "Manipulator2"),
    ] {
        let (out, stats) = expand_ok(body);
        assert_eq!(stats.name, name);
        assert!(out.contains("fn accelerations"), "{name}: no accelerations");
        assert!(ops(&stats) > 0, "{name}: no operations counted");
    }
}

#[test]
fn the_families_expand_with_the_measured_outputs() {
    for body in [
        synthetic::planar(2, "jacobian, energy"),
        synthetic::spatial(2, "jacobian"),
        synthetic::manipulator(2, "jacobian, energy"),
    ] {
        let (out, stats) = expand_ok(body);
        assert!(stats.derived.contains(&"jacobian"), "{}", stats.name);
        assert!(out.contains("fn jacobian"), "{}: no jacobian", stats.name);
    }
}

#[test]
fn the_manipulator_solves_for_its_base() {
    // the three rolling constraints make x, y, theta dependent: the wheel
    // rates and the arm's joint rates, 2 + N of the 5 + N, are independent
    let (out, _) = expand_ok(synthetic::manipulator(2, ""));
    let text: String = out.split_whitespace().collect();
    for constant in [
        "constDEPENDENT:[::core::primitive::usize;3usize]=[0usize,1usize,2usize];",
        "constINDEPENDENT:[::core::primitive::usize;4usize]=[3usize,4usize,5usize,6usize];",
    ] {
        assert!(text.contains(constant), "not in the expansion: {constant}");
    }
}

/// The chains' centres come as screws from the origin (DESIGN §10,
/// `mechanics/tree.rs`): the planar chain of 8 links took 3,807 operations
/// before, with every centre's expanded ∂C/∂q; 1,693 with them.
#[test]
fn the_planar_chain_takes_its_centres_along_the_links() {
    let (_, stats) = expand_ok(synthetic::planar(8, ""));
    assert!(ops(&stats) <= 1_800, "planar 8: {} operations", ops(&stats));
}

/// `jacobian` is differentiated forward through the accelerations' graph
/// (DESIGN §8.1): at most 10 times their operations (issue 34), for the
/// planar chain of 8 links (4.1 times) and for the Whipple bicycle as its
/// example writes it (7.1 times; 62,720 operations when the expanded
/// derivation was differentiated).
#[test]
fn the_jacobian_costs_at_most_ten_times_the_accelerations() {
    let source = include_str!("../../../examples/whipple_bicycle/model.rs");
    let mut bodies = Vec::new();
    tokens::find_invocations(source.parse().expect("the example lexes"), &mut bodies);
    let bicycle = bodies.pop().expect("the bicycle's invocation").to_string();
    for body in [synthetic::planar(8, "jacobian"), bicycle] {
        let (_, stats) = expand_ok(body);
        let jacobian = stats.jacobian_ops.expect("the jacobian is derived");
        let ratio = jacobian as f64 / ops(&stats) as f64;
        eprintln!(
            "{}: jacobian {jacobian} operations, {ratio:.1} times",
            stats.name
        );
        assert!(
            ratio <= 10.0,
            "{}: {jacobian} operations, {ratio:.1} times",
            stats.name
        );
    }
}

/// The composite inertias (DESIGN §10, `generate/composite_inertia.rs`)
/// and the articulated-body recursion on their tree (§10.5,
/// `generate/articulated.rs`) make `accelerations` grow as the links: from
/// 8 to 16 planar links 718 → 1,646 operations (2.3 times), from 8 to 16
/// spatial ones 4,775 → 10,479 (2.2 times). With Cᵀ M C formed and
/// factored by LDLᵀ, 16 links took 4,239 and 24,972: its k³/3 grew 8 times
/// per doubling.
#[test]
fn the_accelerations_grow_as_the_links() {
    for (short, long) in [
        (synthetic::planar(8, ""), synthetic::planar(16, "")),
        (synthetic::spatial(8, ""), synthetic::spatial(16, "")),
    ] {
        let (_, a) = expand_ok(short);
        let (_, b) = expand_ok(long);
        let ratio = ops(&b) as f64 / ops(&a) as f64;
        eprintln!(
            "{} → {}: {} → {} operations, {ratio:.2} times",
            a.name,
            b.name,
            ops(&a),
            ops(&b)
        );
        assert!(a.articulated && b.articulated, "not solved on the tree");
        assert!(ratio <= 2.5, "{ratio:.2} times");
    }
}
