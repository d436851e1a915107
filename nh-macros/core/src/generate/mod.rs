//! Assembly of the generated struct, its inherent methods and its runtime
//! trait implementation (DESIGN §3), from the derived mechanics.

use crate::check;
use crate::ctxt::{Ctxt, Site, SpanRange};
use crate::mechanics::Derivation;
use crate::mechanics::Formulation;
use crate::mechanics::Scene;
use crate::model::{Model, Output};
use crate::parse::SystemDef;
use crate::sym::Engine;
use proc_macro2::TokenStream;

mod articulated;
pub mod atlas;
mod bodies;
mod chains;
mod composite_inertia;
pub use composite_inertia::{Taken, with_composite_inertias};
mod contacts;
mod curvature;
mod derivatives;
mod frames;
mod graph;
mod kane;
mod maggi;
mod manifold;
mod methods;
mod motion;
mod multipliers;
mod nodes;
mod poles;
mod routes;
mod screws;

mod stand_in;

use curvature::curvature_nodes;
use graph::{Args, bound_dag};
use methods::Derived;
use routes::{CURVATURE_ROUTE_MAX_K, RouteGraphs, compare_routes, solved_if_cheaper};
pub use routes::{Route, Stats};
pub use stand_in::{shape_of, stand_in_shape};

/// Builds the whole expansion for a lowered model: derives the mechanics,
/// checks them, builds each route's graph of r̈ to choose one, and emits
/// the API from the derivation and those graphs.
pub fn generate(
    def: &SystemDef,
    model: &Model,
    engine: &mut Engine,
    cx: &mut Ctxt,
    atlas: Vec<crate::api::ChartShape>,
) -> (TokenStream, Stats) {
    let mut stats = Stats {
        name: def.name.to_string(),
        ..Stats::default()
    };
    let _ = crate::emit::take_unrepresentable();
    let mut m = Scene::new(model, engine);
    if m.speeds.is_some() {
        return generate_speeds(def, m, cx, stats);
    }
    // the curvature route pays for small systems (its closed forms); beyond
    // CURVATURE_ROUTE_MAX_K independent coordinates it is derived only when
    // `routes` asks for it, and `accelerations` takes the multiplier route
    // (only for homogeneous, time-independent velocity constraints: DESIGN §9)
    // (and not for another chart whose system's own took the multiplier
    // route decisively: `atlas::Charts::generate`)
    let small = m.k() <= CURVATURE_ROUTE_MAX_K && !atlas::multiplier_only();
    let both_routes = m.homogeneous && (m.outputs.contains(Output::Routes) || small);
    let mut dv = crate::mechanics::derive(&mut m, both_routes);
    stats.derived.extend([
        if both_routes {
            "accelerations (both routes)"
        } else {
            "accelerations (multiplier route)"
        },
        "curvature terms",
    ]);
    // (5.21) decides integrability of the homogeneous part only: with affine
    // or time-dependent terms the constraints are not called integrable
    dv.integrable &= !m.affine;
    stats.integrable = dv.integrable;
    stats.integrable_proved = dv.integrable_proved;
    if !derivation_checked(def, &mut m, &mut dv, cx) {
        return (TokenStream::new(), stats);
    }
    // the rest of the expansion, whose symbolic work (the outputs'
    // derivatives, a small reduced system solved) is at the outputs
    m.engine.enter(generation_site(def));
    let compared = compare_routes(&mut m, &mut dv, both_routes);
    if !check::within_limits(def, m.engine, cx) || !check::regular(def, &compared.pivots, cx) {
        return (TokenStream::new(), stats);
    }
    let route = compared.choose(&mut stats);
    let formulation = match route {
        Route::Multiplier => Formulation::Multipliers,
        Route::Curvature => Formulation::Curvature,
    };
    stats.formulation = Some(formulation);
    let graphs = compared.keep(route, &m, &dv, &stats);
    let (integrable, proved) = (dv.integrable, dv.integrable_proved);
    let mut shape = shape_of(def);
    shape.integrable = integrable;
    shape.outputs = m.outputs;
    shape.independent = m.independent().to_vec();
    shape.dependent = m.dependent().to_vec();
    shape.dependent_doc = dependent_doc(&m);
    shape.affine = m.affine;
    shape.rheonomic = m.rheonomic();
    shape.atlas = atlas;
    shape.momenta = momentum_shapes(&m, dv.momenta.as_ref());
    shape.symmetry_momenta = symmetry_shapes(&m, &dv.symmetries);
    shape.declared_momenta = (dv.declared_momenta.iter())
        .map(|d| verdict_words(&m, &d.verdict))
        .collect();
    let mut bodies = Derived {
        m: &mut m,
        dv,
        formulation,
        stats: &mut stats,
        hoist_blocks: Vec::new(),
        hoist_len: 0,
        hoist_seen: rustc_hash::FxHashMap::default(),
        graphs,
        maggi: None,
        sensitivity_params: shape.sensitivity_params.clone(),
    };
    let mut tokens = crate::api::expand(&shape, &mut bodies);
    let velocity_constraints = m.constraints.iter().any(|c| c.holonomic.is_none());
    if integrable && velocity_constraints {
        tokens.extend(integrability_warning(
            def,
            m.constraints_span.unwrap_or(def.name.span()),
            proved,
        ));
    }
    finish(def, &m, cx, tokens, stats)
}

/// The checks of a derivation within the engine's limits, with the energy
/// derived in between if asked for (once the rest is known to be within
/// them). False after an error.
fn derivation_checked(
    def: &SystemDef,
    m: &mut Scene<'_>,
    dv: &mut Derivation,
    cx: &mut Ctxt,
) -> bool {
    if !check::within_limits(def, m.engine, cx) {
        return false;
    }
    if m.outputs.contains(Output::Energy) {
        let site = output_site(def, Output::Energy);
        dv.energy = Some(m.at(site, "deriving the energy", |m| m.energy()));
    }
    if let Some(cyclic) = check::momenta(def, m, cx) {
        let site = output_site(def, Output::Momenta);
        dv.momenta = Some(m.at(site, "deriving the momenta", |m| m.momenta(cyclic)));
    }
    if !check::within_limits(def, m.engine, cx) {
        return false;
    }
    if check::symmetries(def, m, cx) {
        let site = def.keyword_range(def.symmetries.as_ref());
        let task = "deriving the momenta of the symmetries";
        dv.symmetries = m.at(site, task, |m| m.symmetry_momenta());
    }
    if check::declared_momenta(def, m, cx) {
        let site = def.keyword_range(def.momenta.as_ref());
        let task = "deriving the declared momenta";
        dv.declared_momenta = m.at(site, task, |m| m.declared_momenta());
    }
    check::within_limits(def, m.engine, cx)
        && check::derivation(def, m, dv, cx)
        && check::forms(def, m, cx)
}

/// Where an output is asked for: its word in `outputs { .. }`, or the
/// `outputs` keyword if another output implies it, or the system's name.
fn output_site(def: &SystemDef, output: Output) -> SpanRange {
    let Some((kw, list)) = &def.outputs else {
        return SpanRange::single(def.name.span());
    };
    let word = list.iter().find(|o| o.word == Some(output));
    SpanRange::single(word.map_or(kw.span(), |o| o.ident.span()))
}

/// The site of the methods' generation once the derivation is checked
/// (the outputs' derivatives, the symbolic solve of a small reduced
/// system): the `outputs` keyword, or the system's name without one.
fn generation_site(def: &SystemDef) -> Site {
    let site = def.keyword_range(def.outputs.as_ref());
    Site::new(site, "generating the methods and the outputs")
}

/// The expansion once every method is emitted: empty if a constant of the
/// generated code is beyond `f64`, with the engine's figures.
fn finish(
    def: &SystemDef,
    m: &Scene<'_>,
    cx: &mut Ctxt,
    tokens: TokenStream,
    mut stats: Stats,
) -> (TokenStream, Stats) {
    if !check::within_limits(def, m.engine, cx) || !check::representable(def, m, cx) {
        return (TokenStream::new(), stats);
    }
    stats.graph_size = m.engine.num_exprs();
    stats.derivatives = m.engine.counters.derivatives;
    (tokens, stats)
}

/// The expansion of a system in generalized speeds (DESIGN §9): Maggi's
/// equations, solved like the curvature route's reduced system.
fn generate_speeds(
    def: &SystemDef,
    mut m: Scene<'_>,
    cx: &mut Ctxt,
    mut stats: Stats,
) -> (TokenStream, Stats) {
    let (mut dv, terms) = crate::mechanics::derive_maggi(&mut m);
    stats.derived.push("accelerations (Maggi's equations)");
    if !derivation_checked(def, &mut m, &mut dv, cx) {
        return (TokenStream::new(), stats);
    }
    // the rest of the expansion (see `generate`)
    m.engine.enter(generation_site(def));
    let mut d = bound_dag(&m, &Args::vectors(&m));
    let (udot, pivots) = curvature_nodes(&mut d, &m, &dv.reduced);
    if !check::regular(def, &pivots, cx) {
        return (TokenStream::new(), stats);
    }
    let (d, udot) = solved_if_cheaper(&mut m, &mut dv, (d, udot), &pivots);
    stats.ops_curvature = d.op_count(&udot);
    stats.cost_curvature = d.cost_estimate(&udot);
    stats.route = Some(Route::Curvature);
    stats.formulation = Some(Formulation::Maggi);
    let mut shape = shape_of(def);
    shape.outputs = m.outputs;
    let mut bodies = Derived {
        m: &mut m,
        dv,
        formulation: Formulation::Maggi,
        stats: &mut stats,
        hoist_blocks: Vec::new(),
        hoist_len: 0,
        hoist_seen: rustc_hash::FxHashMap::default(),
        graphs: RouteGraphs {
            multiplier: None,
            curvature: Some((d, udot)),
        },
        maggi: Some(terms),
        sensitivity_params: shape.sensitivity_params.clone(),
    };
    let tokens = crate::api::expand(&shape, &mut bodies);
    finish(def, &m, cx, tokens, stats)
}

/// The documentation of `DEPENDENT` when some constraint is implicit or
/// holonomic: which coordinate each constraint is solved for.
fn dependent_doc(m: &Scene<'_>) -> Option<String> {
    m.chart?;
    let mut doc = String::from(
        " Indices in `q` of the dependent coordinates s (one per constraint), ascending. Each constraint is solved for one of them (DESIGN §9):\n",
    );
    for c in &m.constraints {
        doc.push_str(&format!(
            "\n - `{}` ({}): solved for `{}`",
            c.source,
            c.kind.describe(),
            m.coordinates[c.dependent].name
        ));
    }
    doc.push_str("\n\n`dependent_velocities` and `multipliers` follow this order; the multiplier λ_a belongs to the constraint solved for s_a, normalised as ṡ_a + Σ A^a_α ṙ_α + β_a = 0.");
    Some(doc)
}

/// A compile-time warning on stable Rust, which has no warning a
/// procedural macro can emit: the use of a deprecated item, whose note is
/// the message. rustc words it "use of deprecated {kind} `{path}`: {note}";
/// the item is a `macro_rules!` macro local to an anonymous constant,
/// whose path is its bare name, so the warning's first words say what it is:
/// "use of deprecated macro `LineWheel_has_integrable_constraints`: a
/// warning, not a deprecation: ..." (a constant's path would read
/// `_::name`). Its invocation carries the span of the `constraints`
/// keyword, where the warning points; it is the lint `deprecated`, so
/// `#[allow(deprecated)]` on the system silences it.
fn integrability_warning(def: &SystemDef, span: proc_macro2::Span, proved: bool) -> TokenStream {
    let how = if proved {
        "every curvature coefficient B^b_αβ of (5.21) vanishes identically"
    } else {
        "every curvature coefficient B^b_αβ of (5.21) evaluates to zero (to 1e-24 of its terms, in 32-digit arithmetic) at 16 random points, though the simplifier could not prove it"
    };
    let name = syn::ext::IdentExt::unraw(&def.name);
    let note = format!(
        "a warning, not a deprecation: {how}, so the constraints of `{name}` are holonomic in disguise. Integrate them and eliminate the dependent coordinates (a smaller system with no constraints), or keep them: the equations of motion are still correct. `{name}::INTEGRABLE` is `true`; `#[allow(deprecated)]` on the struct silences this warning."
    );
    let item = proc_macro2::Ident::new(&format!("{name}_has_integrable_constraints"), span);
    let inherited = crate::attrs::inherited(&def.attrs);
    quote::quote_spanned! {span=>
        #(#inherited)*
        const _: () = {
            #[deprecated(note = #note)]
            macro_rules! #item {
                () => {};
            }
            #item!();
        };
    }
}

/// Lines of code the way a pretty-printer lays them out: one per statement,
/// item, attribute and brace.
pub fn count_lines(tokens: &TokenStream) -> usize {
    let mut lines = 0;
    for tt in tokens.clone() {
        match tt {
            proc_macro2::TokenTree::Punct(p) if p.as_char() == ';' || p.as_char() == '#' => {
                lines += 1
            }
            proc_macro2::TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace => {
                lines += 2 + count_lines(&g.stream())
            }
            _ => {}
        }
    }
    lines
}

/// The cyclic coordinates and the verdicts on their momenta, for the API.
fn momentum_shapes(
    m: &Scene<'_>,
    momenta: Option<&crate::mechanics::Momenta>,
) -> Vec<crate::api::MomentumShape> {
    let Some(momenta) = momenta else {
        return Vec::new();
    };
    let model = m.model;
    let shapes = momenta.cyclic.iter().zip(&momenta.verdicts);
    shapes
        .map(|(&(al, strict), verdict)| {
            let coordinate = model.independent()[al];
            let (verdict, doc) = verdict_words(m, verdict);
            let kind = match strict {
                true => "cyclic (the Lagrangian, the forces and the constraints are free of it)",
                false => "cyclic in the constrained Lagrangian and the forces (the Lagrangian or the constraints as written are not free of it)",
            };
            let doc = format!("{kind}; {doc}");
            crate::api::MomentumShape { coordinate, verdict, doc }
        })
        .collect()
}

/// The momenta of the declared symmetries for the API: the verdict on
/// each and its direction Σ_i c_i ξ_i in words.
fn symmetry_shapes(
    m: &Scene<'_>,
    momenta: &[crate::mechanics::SymmetryMomentum],
) -> Vec<(&'static str, String)> {
    let names = &m.model.symmetries;
    momenta
        .iter()
        .map(|s| {
            let along: Vec<String> = (s.coefficients.iter().zip(names))
                .filter(|(c, _)| **c != crate::sym::ZERO)
                .map(|(&c, sym)| match m.engine.as_constant(c) {
                    Some(one) if one == crate::sym::Rational::ONE => format!("`{}`", sym.name),
                    _ => format!("({})·`{}`", m.engine.display_capped(c, 200), sym.name),
                })
                .collect();
            let (verdict, doc) = verdict_words(m, &s.verdict);
            (verdict, format!("along {}: {doc}", along.join(" + ")))
        })
        .collect()
}

/// A verdict as the runtime's variant and in words (with the state where a
/// rate is not zero).
fn verdict_words(m: &Scene<'_>, verdict: &crate::mechanics::Verdict) -> (&'static str, String) {
    use crate::mechanics::Verdict;
    let model = m.model;
    match verdict {
        Verdict::Conserved => ("Conserved", "conserved: its rate is identically zero".to_string()),
        Verdict::Undecided => ("Undecided", "undecided: its rate vanishes at 16 random points (double-double arithmetic) but the engine does not reduce it to zero".to_string()),
        Verdict::NotConserved { at, rate } => {
            let mut state: Vec<String> = (model.coordinates.iter())
                .map(|c| format!("{} = {:.4}", c.name, at[c.position.index()]))
                .collect();
            state.extend(model.independent().iter().map(|&i| {
                let c = &model.coordinates[i];
                format!("dot({}) = {:.4}", c.name, at[c.velocity.index()])
            }));
            let params: Vec<String> = (model.parameters.iter())
                .map(|p| format!("{} = {:.4}", p.name, at[p.sym.index()]))
                .collect();
            ("NotConserved", format!("not conserved: its rate is {rate:.4e} at {} (parameters {})", state.join(", "), params.join(", ")))
        }
    }
}
