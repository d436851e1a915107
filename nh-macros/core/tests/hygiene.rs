//! The expansion stays out of the user's way: the facade is named only
//! through the path given with `@crate(..)` (`::nonholonomic` without it),
//! and every local the generated code binds starts with `__nh_`, so no
//! constant, static or unit struct of the user's scope can match its pattern.
use proc_macro2::{TokenStream, TokenTree};

fn system(prefix: &str, extra: &str) -> TokenStream {
    format!(
        r#"{prefix} pub struct Disc {{
            parameters {{ m, R, g }}
            coordinates {{ theta, phi, psi, x, y }}
            inputs {{ u }}
            let X = x - R*sin(phi)*sin(psi);
            let Y = y + R*cos(phi)*sin(psi);
            let Z = R*cos(psi);
            lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                       + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4) - m*g*Z + {extra};
            forces {{ psi: u - dot(psi)^4; }}
            constraints {{ dot(x) = R*cos(phi)*dot(theta); dot(y) = R*sin(phi)*dot(theta); }}
            outputs {{ energy, multipliers, curvature, constraint_matrix, mass_matrix, jacobian, linearization, routes }}
        }}"#
    )
    .parse()
    .expect("the test system lexes")
}

fn idents(ts: &TokenStream, out: &mut Vec<String>) {
    for tt in ts.clone() {
        match tt {
            TokenTree::Ident(i) => out.push(i.to_string()),
            TokenTree::Group(g) => idents(&g.stream(), out),
            _ => {}
        }
    }
}

/// Every identifier bound by a `let` (in any nesting): the tokens from `let`
/// up to its `=` or `:`, or the idents of a tuple pattern.
fn let_bindings(ts: &TokenStream, out: &mut Vec<String>) {
    let tokens: Vec<TokenTree> = ts.clone().into_iter().collect();
    for (i, tt) in tokens.iter().enumerate() {
        match tt {
            TokenTree::Ident(kw) if kw == "let" => {
                for t in &tokens[i + 1..] {
                    match t {
                        TokenTree::Ident(id) if id == "mut" => {}
                        TokenTree::Ident(id) => {
                            out.push(id.to_string());
                            break;
                        }
                        TokenTree::Group(g) => {
                            idents(&g.stream(), out);
                            break;
                        }
                        _ => break,
                    }
                }
            }
            TokenTree::Group(g) => let_bindings(&g.stream(), out),
            _ => {}
        }
    }
}

#[test]
fn the_facade_is_named_only_through_the_given_path() {
    for extra in ["0", "cso(x)"] {
        // the full expansion, and the stand-in emitted next to an error
        let out = nh_core::expand(system("@crate(::renamed)", extra));
        let mut ids = Vec::new();
        idents(&out, &mut ids);
        assert!(
            !ids.iter().any(|i| i == "nonholonomic"),
            "`nonholonomic` named in the expansion ({extra})"
        );
        assert!(ids.iter().any(|i| i == "renamed"), "{extra}");
    }
    let out = nh_core::expand(system("", "0")).to_string();
    assert!(out.contains(":: nonholonomic :: __private"));
}

#[test]
fn every_generated_local_starts_with_nh() {
    let out = nh_core::expand(system("", "0"));
    let mut bound = Vec::new();
    let_bindings(&out, &mut bound);
    assert!(bound.len() > 100, "{}", bound.len());
    let strays: Vec<&String> = bound
        .iter()
        .filter(|b| !b.starts_with("__nh_") && *b != "_" && *b != "T")
        .collect();
    assert!(strays.is_empty(), "locals outside `__nh_`: {strays:?}");
}
