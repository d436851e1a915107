//! The chains of bodies of the scaling benchmark (`examples/chains.rs`,
//! issue 34) expand without errors at small sizes: the planar chain of 4
//! links, the spatial chain of 2, the mobile manipulator with an arm of 2,
//! without outputs and with the jacobian and energy the benchmark also
//! measures. Sizes only, never times; the physics of the planar chain is
//! checked numerically in the root crate's `tests/chains.rs`.
mod synthetic;

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
