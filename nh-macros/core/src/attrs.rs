//! The user's outer attributes on the system's struct: which of them the
//! generated items besides the struct inherit, and the derives the macro
//! makes itself.
//!
//! Everything generated for a struct must exist exactly when the struct
//! does, and obey the lint levels the user set on it: `#[cfg]`,
//! `#[cfg_attr]` and the lint attributes (`allow`, `warn`, `deny`, `forbid`)
//! go onto every generated item. Doc comments and any other attribute
//! (further derives, `repr`, serde's, ...) stay on the struct alone.

use crate::ctxt::Ctxt;
use proc_macro2::{Delimiter, TokenStream, TokenTree};
use syn::parse::Parser;
use syn::punctuated::Punctuated;

/// The traits `nonholonomic_system!` derives for every system's struct.
pub const DERIVED: [&str; 4] = ["Clone", "Copy", "Debug", "PartialEq"];

/// Derived in addition for a system without parameters (its only field is a
/// marker, so the system has an obvious default).
pub const DERIVED_WITHOUT_PARAMETERS: &str = "Default";

/// The name of an attribute `#[name ..]` and the tokens after the name.
fn split(attr: &TokenStream) -> Option<(String, TokenStream)> {
    let mut it = attr.clone().into_iter();
    let _pound = it.next()?;
    let TokenTree::Group(g) = it.next()? else {
        return None;
    };
    if g.delimiter() != Delimiter::Bracket {
        return None;
    }
    let mut inner = g.stream().into_iter();
    let TokenTree::Ident(name) = inner.next()? else {
        return None;
    };
    Some((name.to_string(), inner.collect()))
}

/// The attributes every generated item inherits from the struct.
pub fn inherited(attrs: &[TokenStream]) -> Vec<TokenStream> {
    attrs
        .iter()
        .filter(|a| applies_to_every_item(a))
        .cloned()
        .collect()
}

/// `#[cfg]` and the lint attributes; `#[cfg_attr(pred, ..)]` when every
/// attribute it adds is one of those (a `cfg_attr` that adds a derive or a
/// serde attribute stays on the struct: a `const` item would reject it).
fn applies_to_every_item(attr: &TokenStream) -> bool {
    let Some((name, rest)) = split(attr) else {
        return false;
    };
    match name.as_str() {
        "cfg" | "allow" | "warn" | "deny" | "forbid" => true,
        "cfg_attr" => {
            let Some(TokenTree::Group(args)) = rest.into_iter().next() else {
                return false;
            };
            // the predicate, then the attributes, separated by top-level commas
            let mut parts: Vec<TokenStream> = vec![TokenStream::new()];
            for tt in args.stream() {
                match &tt {
                    TokenTree::Punct(p) if p.as_char() == ',' => parts.push(TokenStream::new()),
                    _ => {
                        if let Some(last) = parts.last_mut() {
                            last.extend([tt.clone()]);
                        }
                    }
                }
            }
            parts.len() >= 2
                && parts[1..].iter().filter(|p| !p.is_empty()).all(|inner| {
                    let group = proc_macro2::Group::new(Delimiter::Bracket, inner.clone());
                    let pound = proc_macro2::Punct::new('#', proc_macro2::Spacing::Alone);
                    applies_to_every_item(&TokenStream::from_iter([
                        TokenTree::Punct(pound),
                        TokenTree::Group(group),
                    ]))
                })
        }
        _ => false,
    }
}

/// Reports every trait in the user's `#[derive(..)]`s that the macro derives
/// itself (a conflicting implementation otherwise, E0119, far from the
/// cause) at its path, and returns the attributes with those paths removed,
/// so the struct emitted next to the errors raises no follow-up error.
pub fn check_derives(
    attrs: Vec<TokenStream>,
    has_parameters: bool,
    cx: &mut Ctxt,
) -> Vec<TokenStream> {
    let mut ours: Vec<&str> = DERIVED.to_vec();
    if !has_parameters {
        ours.push(DERIVED_WITHOUT_PARAMETERS);
    }
    let mut out = Vec::with_capacity(attrs.len());
    for attr in attrs {
        let Some((name, rest)) = split(&attr) else {
            out.push(attr);
            continue;
        };
        let group = match rest.into_iter().collect::<Vec<_>>().as_slice() {
            [TokenTree::Group(g)]
                if name == "derive" && g.delimiter() == Delimiter::Parenthesis =>
            {
                g.clone()
            }
            _ => {
                out.push(attr);
                continue;
            }
        };
        // a malformed derive is rustc's to report
        let Ok(paths) =
            Punctuated::<syn::Path, syn::Token![,]>::parse_terminated.parse2(group.stream())
        else {
            out.push(attr);
            continue;
        };
        let mut kept: Vec<&syn::Path> = Vec::new();
        for path in &paths {
            let last = path.segments.last().map(|s| s.ident.to_string());
            match last.as_deref() {
                Some(t) if ours.contains(&t) => cx.error_at(
                    syn::spanned::Spanned::span(path),
                    format!(
                        "`{t}` is derived by `nonholonomic_system!` already; remove it (the macro derives `Clone`, `Copy`, `Debug` and `PartialEq` for every system, and `Default` for a system without parameters)"
                    ),
                ),
                _ => kept.push(path),
            }
        }
        if kept.len() == paths.len() {
            out.push(attr);
        } else if !kept.is_empty() {
            let mut pound = TokenStream::new();
            pound.extend(attr.clone().into_iter().take(1));
            let span = group.span();
            let mut inner = proc_macro2::Group::new(
                Delimiter::Bracket,
                quote::quote_spanned!(span=> derive(#(#kept),*)),
            );
            inner.set_span(span);
            pound.extend([TokenTree::Group(inner)]);
            out.push(pound);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    #[test]
    fn cfg_and_lints_are_inherited_docs_are_not() {
        let attrs = vec![
            quote!(#[doc = "x"]),
            quote!(#[cfg(test)]),
            quote!(#[cfg_attr(test, allow(unused))]),
            quote!(#[allow(dead_code)]),
            quote!(#[derive(Eq)]),
            quote!(#[cfg_attr(test, derive(Eq), allow(unused))]),
            quote!(#[cfg_attr(test, cfg_attr(all(), deny(unused)),)]),
        ];
        let got: Vec<String> = inherited(&attrs).iter().map(|a| a.to_string()).collect();
        assert_eq!(got.len(), 4, "{got:?}");
        assert!(!got.iter().any(|a| a.contains("Eq")), "{got:?}");
    }

    #[test]
    fn our_derives_are_errors_others_pass() {
        let mut cx = Ctxt::new();
        let out = check_derives(
            vec![
                quote!(#[derive(Clone, Eq, ::core::fmt::Debug)]),
                quote!(#[derive(Hash)]),
            ],
            true,
            &mut cx,
        );
        assert_eq!(cx.len(), 2);
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].to_string().replace(' ', ""), "#[derive(Eq)]");
        let mut cx = Ctxt::new();
        let out = check_derives(vec![quote!(#[derive(Default)])], true, &mut cx);
        assert!(cx.is_empty());
        assert_eq!(out.len(), 1);
        let out = check_derives(vec![quote!(#[derive(Default)])], false, &mut cx);
        assert_eq!(cx.len(), 1);
        assert!(out.is_empty());
    }
}
