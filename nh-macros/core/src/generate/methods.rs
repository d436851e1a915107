//! The generated methods' bodies: the derivation and the routes' graphs
//! (`Derived`), hoisting of parameter-only values, and the table of
//! methods the API asks for (`Bodies`).

use super::curvature::curvature_nodes;
use super::graph::{Args, bound_dag, velocity_arg};
use super::multipliers::multiplier_nodes;
use super::nodes::vector_expr;
use super::routes::{Route, RouteGraphs, Stats};
use crate::api::{Bodies, GeneratedMethod, Method};
use crate::emit::{Dag, Node};
use crate::mechanics::Derivation;
use crate::mechanics::Formulation;
use crate::mechanics::Scene;
use crate::model::Output;
use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// Method bodies computed from the derivation, on demand: a method that is
/// not requested is never emitted.
pub(crate) struct Derived<'a, 'b> {
    pub(crate) m: &'a mut Scene<'b>,
    pub(crate) dv: Derivation,
    pub(crate) formulation: Formulation,
    pub(crate) stats: &'a mut Stats,
    /// Parameter-only values hoisted out of the methods: the code computing
    /// each method's share of the cache, and the cache length so far.
    pub(crate) hoist_blocks: Vec<TokenStream>,
    pub(crate) hoist_len: usize,
    pub(crate) hoist_seen: rustc_hash::FxHashMap<String, usize>,
    /// The graphs of r̈ built when the routes were compared.
    pub(crate) graphs: RouteGraphs,
    /// Maggi's terms, for a system in generalized speeds.
    pub(crate) maggi: Option<crate::mechanics::MaggiTerms>,
    /// The parameters of `sensitivities`, in order.
    pub(crate) sensitivity_params: Vec<Ident>,
}

impl Derived<'_, '_> {
    /// Emits a method's values; those that depend on parameters alone are
    /// computed once, when the parameters are set, into a cache the method
    /// reads (see `api::expand`).
    pub(crate) fn emit_hoisted(
        &mut self,
        d: &Dag,
        outs: &[Node],
    ) -> (TokenStream, Vec<TokenStream>) {
        // `NH_HOIST=0` while compiling turns hoisting off (to measure it)
        let enabled = std::env::var_os("NH_HOIST").is_none_or(|v| v != "0");
        let hoisted = if self.m.parameters.is_empty() || !enabled {
            Vec::new()
        } else {
            d.hoistable(outs)
        };
        if hoisted.is_empty() {
            return d.emit(outs);
        }
        let (htext, houts) = d.emit_text(&hoisted, &rustc_hash::FxHashMap::default());
        // methods that hoist the same values share their cache slots
        let key = format!("{htext} => {}", houts.join(","));
        let base = match self.hoist_seen.get(&key) {
            Some(&base) => base,
            None => {
                let base = self.hoist_len;
                let mut block = htext;
                for (j, v) in houts.iter().enumerate() {
                    block.push_str(&format!("__nh_hoisted[{}] = {v};\n", base + j));
                }
                let hstmts = crate::emit::parse_text(&block);
                self.hoist_blocks.push(quote!({ #hstmts }));
                self.hoist_len += hoisted.len();
                self.hoist_seen.insert(key, base);
                base
            }
        };
        let given: rustc_hash::FxHashMap<Node, TokenStream> = hoisted
            .iter()
            .enumerate()
            .map(|(j, &h)| {
                let i = base + j;
                (h, quote!(__nh_cache[#i]))
            })
            .collect();
        let (stmts, o) = d.emit_with(outs, &given);
        // the cache read in place (no copy), or the values afresh if a
        // parameter changed since it was filled
        let read = quote! {
            let __nh_fresh;
            let __nh_cache = if self.__nh_cache_current() {
                &self.__nh_cache
            } else {
                __nh_fresh = self.__nh_compute_cache();
                &__nh_fresh
            };
        };
        (quote!(#read #stmts), o)
    }

    pub(crate) fn acc_nodes(&self, d: &mut Dag, route: Route) -> Vec<Node> {
        match route {
            Route::Multiplier => {
                multiplier_nodes(d, self.m, &self.dv.multiplier_route, self.dv.kane.as_ref()).rdd
            }
            Route::Curvature => curvature_nodes(d, self.m, &self.dv.reduced).0,
        }
    }

    /// r̈ by `route`, from the route's graph.
    pub(crate) fn accelerations(&mut self, route: Route) -> TokenStream {
        let k = self.m.k();
        // the route's graph, built once when the routes were compared
        let (d, rdd) = match self.graphs.slot(route).take() {
            Some(g) => g,
            None => {
                let mut d = bound_dag(self.m, &Args::vectors(self.m).moving());
                let rdd = self.acc_nodes(&mut d, route);
                (d, rdd)
            }
        };
        let (stmts, o) = self.emit_hoisted(&d, &rdd);
        let ret = vector_expr(k, &o);
        let vel = velocity_arg(self.m);
        quote! { let _ = (t, q, #vel); #stmts #ret }
    }

    /// Operations of r̈ by `route`, after CSE.
    pub(crate) fn ops(&self, route: Route) -> usize {
        self.stats.ops(route)
    }

    /// The documentation of `accelerations`: what it computes, and by which
    /// route at what cost.
    pub(crate) fn accelerations_doc(&self) -> String {
        let u_doc = if self.m.inputs.is_empty() {
            ""
        } else {
            "\n\n`u` holds the inputs in declared order."
        };
        let used = self.ops(self.route());
        let other = match self.ops(self.route().other()) {
            0 if !self.m.homogeneous => {
                "the curvature route needs homogeneous, time-independent velocity constraints"
                    .to_string()
            }
            0 => {
                "the curvature route is derived for k ≤ 6 or with `outputs { routes }`".to_string()
            }
            other => format!("the other route needs {other}"),
        };
        format!(
            "{}{u_doc}\n\nDerived by {}; {used} operations after common-subexpression elimination ({other}). The k × k reduced mass matrix is factorised as LDLᵀ, unrolled, with its structural zeros pruned.",
            GeneratedMethod::Accelerations.spec().doc,
            self.route().doc(),
        )
    }

    /// The documentation of the method of `route` when `accelerations` uses
    /// the other.
    pub(crate) fn other_route_doc(&self, route: Route) -> String {
        format!(
            "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
            route.doc(),
            self.ops(route)
        )
    }

    /// `jacobian` as the matrix A of `linearization` (one copy of the code),
    /// documented as `doc` describes the system.
    pub(crate) fn jacobian_from_linearization(&self, doc: &str) -> (String, TokenStream) {
        let u = self.u_forward();
        let doc = format!(
            "{doc}: the matrix A of [`Self::linearization`], derived symbolically through the reduced solve.",
        );
        (doc, quote! { self.linearization(t, x #u).0 })
    }

    /// The route `accelerations` takes (Maggi's equations are solved as
    /// the curvature route's reduced system).
    pub(crate) fn route(&self) -> Route {
        match self.formulation {
            Formulation::Multipliers => Route::Multiplier,
            Formulation::Curvature | Formulation::Maggi => Route::Curvature,
        }
    }
}

impl Bodies for Derived<'_, '_> {
    fn method(&mut self, method: GeneratedMethod) -> Method {
        let spec = method.spec();
        if let Some(output) = spec.requested_by
            && output != Output::Routes
        {
            self.stats.derived.push(spec.name);
        }
        if self.formulation == Formulation::Maggi
            && let Some((doc, body)) = self.maggi_method(method)
        {
            return Method { doc, body };
        }
        let static_doc = || spec.doc.to_string();
        let (doc, body) = match method {
            GeneratedMethod::DependentVelocities => {
                (static_doc(), self.dependent_velocities_body())
            }
            GeneratedMethod::Accelerations => {
                (self.accelerations_doc(), self.accelerations(self.route()))
            }
            GeneratedMethod::Velocities => (static_doc(), self.velocities_body()),
            GeneratedMethod::ReactionForces => (static_doc(), self.reaction_forces_body()),
            GeneratedMethod::AccelerationsMultiplierRoute
            | GeneratedMethod::AccelerationsCurvatureRoute
                if method == self.route().method() =>
            {
                let u = self.u_forward();
                let doc = format!(
                    "r̈ by {}, the route [`Self::accelerations`] uses ({} operations).",
                    self.route().doc(),
                    self.ops(self.route())
                );
                (doc, quote! { self.accelerations(t, q, rdot #u) })
            }
            GeneratedMethod::AccelerationsCurvatureRoute if self.is_large() => (
                self.other_route_doc(Route::Curvature),
                self.curvature_route_from_reduced(),
            ),
            GeneratedMethod::AccelerationsMultiplierRoute => (
                self.other_route_doc(Route::Multiplier),
                self.accelerations(Route::Multiplier),
            ),
            GeneratedMethod::AccelerationsCurvatureRoute => (
                self.other_route_doc(Route::Curvature),
                self.accelerations(Route::Curvature),
            ),
            GeneratedMethod::ReducedSystem => (static_doc(), self.reduced_system_body()),
            GeneratedMethod::Multipliers => (static_doc(), self.multipliers_body()),
            GeneratedMethod::Curvature => (static_doc(), self.curvature_body()),
            GeneratedMethod::Energy => (static_doc(), self.energy_body()),
            GeneratedMethod::Momenta => (static_doc(), self.momenta_body(false)),
            GeneratedMethod::MomentumRates => (static_doc(), self.momenta_body(true)),
            GeneratedMethod::SymmetryMomenta => (static_doc(), self.symmetry_momenta_body(false)),
            GeneratedMethod::DeclaredMomenta => (static_doc(), self.declared_momenta_body(false)),
            GeneratedMethod::DeclaredMomentumRates => {
                (static_doc(), self.declared_momenta_body(true))
            }
            GeneratedMethod::SymmetryMomentumRates => {
                (static_doc(), self.symmetry_momenta_body(true))
            }
            GeneratedMethod::ConstraintMatrix => (static_doc(), self.constraint_matrix_body()),
            GeneratedMethod::ContactPoints => (static_doc(), self.contact_points_body()),
            GeneratedMethod::MassMatrix => (static_doc(), self.mass_matrix_body()),
            GeneratedMethod::Linearization => (static_doc(), self.linearization_body()),
            GeneratedMethod::Jacobian if self.m.outputs.contains(Output::Linearization) => {
                self.jacobian_from_linearization(spec.doc)
            }
            GeneratedMethod::Jacobian => {
                let doc = format!(
                    "{}, derived symbolically through the reduced solve: ∂r̈/∂z = Mc⁻¹ (∂f/∂z − (∂Mc/∂z) r̈) with the curvature route's Mc and f (5.20), reusing one LDLᵀ factorisation for every column.",
                    spec.doc
                );
                (doc, self.jacobian_body())
            }
            GeneratedMethod::TimeDerivative => (static_doc(), self.time_derivative_body()),
            GeneratedMethod::ParameterJacobian => (static_doc(), self.parameter_jacobian_body()),
            GeneratedMethod::VariationalRhs => (static_doc(), self.variational_rhs_body()),
            GeneratedMethod::SensitivitySystem => (
                static_doc(),
                quote!(__nh_private::nh_runtime::Sensitivities::new(self)),
            ),
            // q̇ and r̈ from their methods, inlined (one copy of the code;
            // measured as fast as a fused body)
            GeneratedMethod::Rhs => (static_doc(), self.rhs_body()),
        };
        Method { doc, body }
    }

    fn runtime_hooks(&mut self, xty: &TokenStream) -> TokenStream {
        let mut hooks = if self.formulation == Formulation::Maggi {
            self.chart_regularity()
        } else {
            super::manifold::methods(self.m, xty)
        };
        hooks.extend(super::poles::method(self.m, xty));
        if !self.m.autonomous() {
            return hooks;
        }
        quote! {
            #hooks
            /// Nothing in the definition depends on `t` explicitly: ∂f/∂t = 0.
            #[inline]
            fn is_autonomous(&self) -> bool {
                true
            }
        }
    }

    fn description(&self) -> Vec<String> {
        self.m.description.clone()
    }

    fn hoisting(&mut self) -> (usize, TokenStream) {
        let blocks = &self.hoist_blocks;
        (self.hoist_len, quote!(#(#blocks)*))
    }

    fn route_consts(&mut self) -> TokenStream {
        let (om, oc) = (self.stats.ops_multiplier, self.stats.ops_curvature);
        let chosen = match self.route() {
            Route::Multiplier => "multiplier",
            Route::Curvature => "curvature",
        };
        self.stats.derived.push("routes");
        quote! {
            /// Operations (after CSE) of r̈ by the multiplier route (5.9).
            pub const OPS_MULTIPLIER_ROUTE: usize = #om;
            /// Operations (after CSE) of r̈ by the curvature route (5.20).
            pub const OPS_CURVATURE_ROUTE: usize = #oc;
            /// The route [`Self::accelerations`] uses: `"multiplier"` or `"curvature"`.
            pub const ROUTE: &'static str = #chosen;
        }
    }
}
