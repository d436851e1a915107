//! A system pays only for what it asks for: with no `outputs`, the expansion
//! has no multiplier, curvature, energy, mass-matrix, constraint-matrix,
//! Jacobian or linearisation code and the derivation computes none of them;
//! each output adds its own method and changes nothing else.
use std::collections::BTreeMap;

fn system(outputs: &str) -> proc_macro2::TokenStream {
    let src = format!(
        r#"pub struct ThesisDisc {{
            parameters {{ m, R, g }}
            coordinates {{ theta, phi, psi, x, y }}
            inputs {{ u }}
            let X = x - R*sin(phi)*sin(psi);
            let Y = y + R*cos(phi)*sin(psi);
            let Z = R*cos(psi);
            lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                       + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4) - m*g*Z;
            forces {{ psi: u; }}
            constraints {{ dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }}
            {outputs}
        }}"#
    );
    src.parse().expect("the test system lexes")
}

/// The generated methods by name, each with its signature and body.
fn methods(out: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for (start, _) in out.match_indices("pub fn ") {
        let rest = &out[start + 7..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // the body: from the first `{` to its matching `}`
        let Some(open) = rest.find('{') else { continue };
        let mut depth = 0usize;
        let mut end = rest.len();
        for (i, ch) in rest[open..].char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + i + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        map.insert(name, rest[..end].to_string());
    }
    // the constructor fills the cache of parameter-only values, which grows
    // with the outputs' own hoisted values: not a method of the mechanics;
    // nor are the helpers that build and read the state and the parameters
    // by name, which every system has
    for helper in [
        "new",
        "state",
        "split",
        "state_from_velocities",
        "state_from_known_velocities",
        "from_parameters",
        "parameters",
    ] {
        map.remove(helper);
    }
    map
}

const ALL: [(&str, &[&str]); 8] = [
    ("multipliers", &["multipliers"]),
    ("curvature", &["curvature"]),
    ("energy", &["energy"]),
    ("constraint_matrix", &["constraint_matrix"]),
    ("mass_matrix", &["mass_matrix"]),
    ("jacobian", &["jacobian", "time_derivative"]),
    ("linearization", &["linearization"]),
    (
        "routes",
        &[
            "accelerations_multiplier_route",
            "accelerations_curvature_route",
            "reduced_system",
        ],
    ),
];
// (`sensitivities` is for systems without inputs, which this one has: it is
// rejected here and checked in tests/sensitivities.rs)

#[test]
fn no_outputs_no_output_code_and_no_output_derivation() {
    let (out, stats) = nh_core::expand_with_stats(system(""));
    let text = out.to_string();
    let names: Vec<String> = methods(&text).into_keys().collect();
    assert_eq!(
        names,
        ["accelerations", "dependent_velocities"],
        "{names:?}"
    );
    for (_, ms) in ALL {
        for m in ms {
            assert!(
                !text.contains(&format!("fn {m} ")),
                "{m} emitted without being asked for"
            );
        }
    }
    // what was derived: the two routes of `accelerations` (the chosen one is
    // emitted) and the curvature terms both the curvature route and
    // `INTEGRABLE` need — nothing for any output
    assert_eq!(
        stats.derived,
        ["accelerations (both routes)", "curvature terms"]
    );
}

#[test]
fn each_output_adds_only_its_own_code() {
    let (base, base_stats) = nh_core::expand_with_stats(system(""));
    let base = methods(&base.to_string());
    for (output, added) in ALL {
        let (out, stats) = nh_core::expand_with_stats(system(&format!("outputs {{ {output} }}")));
        let with = methods(&out.to_string());
        let new: Vec<&String> = with.keys().filter(|k| !base.contains_key(*k)).collect();
        let mut expect: Vec<String> = added.iter().map(|s| s.to_string()).collect();
        expect.sort();
        let mut got: Vec<String> = new.into_iter().cloned().collect();
        got.sort();
        assert_eq!(got, expect, "output `{output}` added {got:?}");
        for (name, body) in &base {
            let other = with
                .get(name)
                .unwrap_or_else(|| panic!("`{name}` vanished with `{output}`"));
            assert_eq!(
                body, other,
                "`{name}` changed when `{output}` was asked for"
            );
        }
        // the derivation work grows only by what the output needs
        assert!(stats.derivatives >= base_stats.derivatives);
        assert!(
            stats
                .derived
                .iter()
                .any(|d| *d != "accelerations (both routes)" && *d != "curvature terms"),
            "{output}: {:?}",
            stats.derived
        );
    }
}
