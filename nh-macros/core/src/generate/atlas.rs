//! The other charts of a system's atlas (DESIGN §9.3): each is the same
//! definition with its implicit and holonomic rows solved for other
//! coordinates, expanded as a hidden system of its own.

use crate::api::{ChartShape, EulerShape};
use crate::lower::atlas::Chart;
use crate::model::{Model, Output};
use crate::parse::SystemDef;
use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

std::thread_local! {
    /// Whether the charts being generated take the multiplier route
    /// without deriving the curvature route ([`Charts::generate`]).
    static MULTIPLIER_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the system being generated is another chart of one whose own
/// chart chose the multiplier route decisively ([`Charts::generate`]).
pub(crate) fn multiplier_only() -> bool {
    MULTIPLIER_ONLY.with(std::cell::Cell::get)
}

/// The other charts of a system, lowered: each its hidden definition, its
/// model and engine, and its shape for the API.
pub struct Charts {
    own: Option<ChartShape>,
    others: Vec<(SystemDef, Model, crate::sym::Engine, ChartShape)>,
}

impl Charts {
    /// The other charts of `model`'s atlas lowered (a chart that does not
    /// lower is left out); none for a system with one chart.
    pub fn lower(def: &SystemDef, model: &Model, engine: &crate::sym::Engine) -> Charts {
        let mut charts = Charts {
            own: None,
            others: Vec::new(),
        };
        if model.atlas.len() < 2 {
            return charts;
        }
        let jacobian = model.outputs.contains(Output::Jacobian);
        let own = &model.atlas[0];
        charts.own = Some(ChartShape {
            system: None,
            name: chart_name(model, own),
            singular: own.singular.clone(),
            independent: model.independent().to_vec(),
            dependent: model.dependent().to_vec(),
            rheonomic: rheonomic_of(model, engine),
            jacobian,
            euler: euler_shape(own),
        });
        for (c, chart) in model.atlas.iter().enumerate().skip(1) {
            let hidden = hidden_def(def, model, c, chart);
            let mut cx = crate::ctxt::Ctxt::new();
            let Some((hmodel, engine)) = crate::lower::lower(&hidden, &mut cx) else {
                let _ = cx.finish();
                continue;
            };
            let shape = ChartShape {
                system: Some(hidden.name.clone()),
                name: chart_name(model, chart),
                singular: chart.singular.clone(),
                independent: hmodel.independent().to_vec(),
                dependent: hmodel.dependent().to_vec(),
                rheonomic: rheonomic_of(&hmodel, &engine),
                jacobian,
                euler: euler_shape(chart),
            };
            let _ = cx.finish();
            charts.others.push((hidden, hmodel, engine, shape));
        }
        charts
    }

    /// The charts as the API sees them, the system's own first, if every
    /// other chart lowered here expands; none with fewer than two.
    pub fn shapes(&self) -> Vec<ChartShape> {
        if self.others.is_empty() {
            return Vec::new();
        }
        let others = self.others.iter().map(|x| x.3.clone());
        self.own.iter().cloned().chain(others).collect()
    }

    /// Expands the other charts: the charts that expanded as the API sees
    /// them (as [`Charts::shapes`], a chart whose expansion fails left
    /// out), their hidden systems and each one's operations. With
    /// `multiplier_only` (the system's own chart chose the multiplier
    /// route at under half the curvature route's estimated cost) they take
    /// the multiplier route without deriving the other: the same mechanics
    /// in other coordinates, where the curvature route took about 40% of
    /// the hand-written rattleback's expansion in its three other charts.
    pub fn generate(
        self,
        multiplier_only: bool,
    ) -> (Vec<ChartShape>, TokenStream, Vec<(String, usize)>) {
        let before = MULTIPLIER_ONLY.with(|c| c.replace(multiplier_only));
        let mut figures = Vec::new();
        let mut shapes: Vec<ChartShape> = self.own.into_iter().collect();
        let mut tokens = TokenStream::new();
        for (hidden, hmodel, mut engine, shape) in self.others {
            let mut cx = crate::ctxt::Ctxt::new();
            let (code, stats) = super::generate(&hidden, &hmodel, &mut engine, &mut cx, Vec::new());
            if cx.finish().is_err() || code.is_empty() {
                continue;
            }
            let ops = stats.route.map_or(0, |r| stats.ops(r));
            figures.push((shape.name.clone(), ops));
            tokens.extend(code);
            shapes.push(shape);
        }
        MULTIPLIER_ONLY.with(|c| c.set(before));
        if shapes.len() < 2 {
            return (Vec::new(), TokenStream::new(), Vec::new());
        }
        (shapes, tokens, figures)
    }
}

/// "solved for `x`, `y`", or for a chart of a free rotation "the angles
/// of `rot_z(phi)*rot_x(theta)*rot_y(psi)`".
fn chart_name(model: &Model, chart: &Chart) -> String {
    if let Some(e) = &chart.euler {
        let names: Vec<String> = model
            .coordinates
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        return e.name(&names);
    }
    let names: Vec<String> = chart
        .dependent
        .iter()
        .map(|&i| format!("`{}`", model.coordinates[i].name))
        .collect();
    format!("solved for {}", names.join(", "))
}

/// The sequence of `chart`'s free rotation, for the API.
fn euler_shape(chart: &Chart) -> Option<EulerShape> {
    chart.euler.as_ref().map(|e| EulerShape {
        sequence: e.sequence(),
        angles: e.angles,
        world: e.world,
    })
}

/// Whether some dependent velocity of `model` depends on t (then its
/// `dependent_velocities` takes `t`).
fn rheonomic_of(model: &Model, engine: &crate::sym::Engine) -> bool {
    model
        .constraints
        .iter()
        .any(|c| engine.depends_on(c.velocity, model.time))
}

/// The definition of chart `c`: hidden, named `__nh_{Name}_chart{c}`, its
/// rows solved for the chart's coordinates (or its free rotation written
/// in the chart's sequence), with one chart and only the outputs the
/// runtime takes from it.
fn hidden_def(def: &SystemDef, model: &Model, c: usize, chart: &Chart) -> SystemDef {
    let span = def.name.span();
    let mut hidden = def.clone();
    let name = syn::ext::IdentExt::unraw(&def.name);
    hidden.name = format_ident!("__nh_{}_chart{}", name, c, span = span);
    // private, undocumented, and quiet about the API it does not use
    hidden.vis = syn::Visibility::Inherited;
    hidden.attrs = vec![
        quote!(#[doc(hidden)]),
        quote!(#[allow(dead_code, unused_imports, missing_docs, non_camel_case_types)]),
    ];
    hidden.attrs.extend(crate::attrs::inherited(&def.attrs));
    if let Some(euler) = &chart.euler {
        euler.rewrite(&mut hidden);
        hidden.euler_chart = true;
    } else {
        hidden.dependent = Some((
            Ident::new("dependent", span),
            (chart.dependent.iter())
                .map(|&i| model.coordinates[i].name.clone())
                .collect(),
        ));
    }
    hidden.one_chart = true;
    // the Jacobian, when the system has one (asked for, or implied by
    // `sensitivities` or `linearization`), and nothing else
    hidden.outputs = model.outputs.contains(Output::Jacobian).then(|| {
        let jacobian = crate::words::Spelled {
            ident: Ident::new("jacobian", span),
            word: Some(Output::Jacobian),
        };
        (Ident::new("outputs", span), vec![jacobian])
    });
    hidden.output_arguments = Vec::new();
    hidden
}
