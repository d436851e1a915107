//! The engine behind `nonholonomic_system!`, in stages that each build
//! their result once: `parse` (the surface syntax) → `lower` (names
//! resolved, the typed `model`) → `mechanics` (the symbolic derivation) →
//! `generate` (each route's graph, the method bodies) with `api` (the
//! generated API, from one table of methods) → `emit` (straight-line code).
//! `check` holds the consistency checks each stage calls on what it built;
//! `sym` is the symbolic algebra.
//!
//! [`expand`] is the whole macro: it never panics, collects every error it
//! finds and reports them together, pointing at the tokens at fault.
#![forbid(unsafe_code)]
// Index loops over matrices read like the formulas they implement.
#![allow(clippy::needless_range_loop)]

mod algebra;
mod api;
mod attrs;
mod check;
mod ctxt;
mod emit;
mod errors;
mod generate;
mod lower;

mod mechanics;
mod model;
mod names;
mod parse;

pub mod sym;
#[cfg(test)]
mod testing;
#[cfg(test)]
mod tests;
mod words;

pub use emit::with_text_parser;
pub use errors::{ReportedError, reported_errors};
pub use generate::{Route, Stats};
#[doc(hidden)]
pub use generate::{Taken, with_composite_inertias};
#[doc(hidden)]
pub use lower::bodies::with_fold_terms;
pub use mechanics::Formulation;

use proc_macro2::TokenStream;
use quote::quote;

/// Expands a `nonholonomic_system!` invocation.
pub fn expand(input: TokenStream) -> TokenStream {
    expand_derivation(input).0
}

/// Expands and reports figures about the expansion (operation counts, the
/// route chosen, what was derived, the lines generated).
pub fn expand_with_stats(input: TokenStream) -> (TokenStream, Stats) {
    let (out, mut stats) = expand_derivation(input);
    stats.lines = generate::count_lines(&out);
    (out, stats)
}

fn expand_derivation(input: TokenStream) -> (TokenStream, Stats) {
    expand_in(input, sym::Engine::new)
}

/// The expansion, with the system derived in a fresh engine from `engine`
/// (with its limits set).
fn expand_in(input: TokenStream, engine: impl Fn() -> sym::Engine) -> (TokenStream, Stats) {
    let mut cx = ctxt::Ctxt::new();
    let def = parse::parse_system(input, &mut cx);
    let mut out = TokenStream::new();
    let mut stats = Stats::default();
    if let Some(def) = &def
        && let Some((model, mut main)) = lower::lower_in(def, &mut cx, engine())
    {
        // the system's own chart first: its choice of route spares the
        // other charts the curvature route when it was decisive
        let charts = generate::atlas::Charts::lower(def, &model, &main);
        let assumed = charts.shapes();
        let (mut tokens, mut s) =
            generate::generate(def, &model, &mut main, &mut cx, assumed.clone());
        let decisive = s.route == Some(generate::Route::Multiplier)
            && s.cost_curvature >= 2 * s.cost_multiplier;
        let (atlas, code, figures) = charts.generate(decisive);
        if atlas.len() != assumed.len() {
            // a chart did not expand: the own chart again, with the others
            cx = ctxt::Ctxt::new();
            if let Some((model, mut fresh)) = lower::lower_in(def, &mut cx, engine()) {
                (tokens, s) = generate::generate(def, &model, &mut fresh, &mut cx, atlas);
            }
        }
        out = quote!(#tokens #code);
        stats = s;
        stats.charts = figures;
    }
    let rows = cx.constraint_rows;
    match cx.finish() {
        Ok(()) => (out, stats),
        Err(e) => {
            let errors = e.to_compile_error();
            let fallback = def.as_ref().map(|d| fallback(d, rows)).unwrap_or_default();
            (quote!(#fallback #errors), stats)
        }
    }
}

/// The stand-in emitted next to the errors: the full API with diverging
/// bodies, so that the user's other code that uses the system still
/// type-checks and no follow-up errors bury the real ones (as thiserror does).
/// `rows`: the number of constraint rows, if lowering found it.
fn fallback(def: &parse::SystemDef, rows: Option<usize>) -> TokenStream {
    api::expand(&generate::stand_in_shape(def, rows), &mut api::StandIn)
}
