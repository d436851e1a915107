//! The two routes to r̈ (DESIGN §9): their graphs built and compared, the
//! cheaper chosen, and the figures of the expansion (`Stats`).

use super::curvature::curvature_nodes;
use super::graph::{Args, bound_dag};
use super::multipliers::multiplier_nodes;
use super::nodes::exprs;
use crate::api::GeneratedMethod;
use crate::emit::{Dag, Node, ZERO_NODE};
use crate::mechanics::Derivation;
use crate::mechanics::Formulation;
use crate::mechanics::Scene;
use crate::model::Output;

/// Operations of r̈ beyond which other methods call `accelerations` (and
/// `reduced_system`) instead of repeating their code.
pub(crate) const LARGE_OPS: usize = 400;

/// Largest number of independent coordinates k for which the curvature
/// route is derived to compete with the multiplier route (always, with
/// `outputs { routes }`). Beyond it the curvature route's right side,
/// symbolic in all k velocities, costs more to derive than it can save.
pub(crate) const CURVATURE_ROUTE_MAX_K: usize = 6;

/// Which derivation `accelerations` uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Lagrange multipliers eliminated by projection, (5.9)/(5.10).
    Multiplier,
    /// The constrained Lagrangian with the curvature term, (5.20)/(5.21).
    Curvature,
}

/// Figures about one expansion, for statistics and tests.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// The struct's name.
    pub name: String,
    /// Operations of `accelerations` by the multiplier route, after CSE.
    pub ops_multiplier: usize,
    /// Operations of `accelerations` by the curvature route, after CSE.
    pub ops_curvature: usize,
    /// Of the multiplier route's operations, those of Cᵀ M C and the right
    /// side of (5.9), before the k × k factorisation and solve (whose
    /// k³/3 operations are the rest, with the dependent velocities); of the
    /// right side alone where the articulated-body recursion solves it
    /// (`articulated`), which does not form Cᵀ M C.
    pub ops_projection: usize,
    /// Whether the multiplier route solves (5.9) by the articulated-body
    /// recursion on a tree of composite inertias (DESIGN §10) instead of
    /// the LDLᵀ factorisation of Cᵀ M C.
    pub articulated: bool,
    /// Of the operations of the route `accelerations` uses, those on the
    /// parameters alone: computed once per parameter set into a cache, not
    /// per call.
    pub ops_on_parameters: usize,
    /// Estimated cost (in additions) of the multiplier route.
    pub cost_multiplier: usize,
    /// Estimated cost (in additions) of the curvature route.
    pub cost_curvature: usize,
    /// The route `accelerations` uses.
    pub route: Option<Route>,
    /// Distinct expressions in the engine's graph at the end.
    pub graph_size: usize,
    /// Derivatives computed (memo misses).
    pub derivatives: usize,
    /// Whether every curvature entry is identically zero.
    pub integrable: bool,
    /// Whether that was proved symbolically (otherwise numerically).
    pub integrable_proved: bool,
    /// Which outputs were derived.
    pub derived: Vec<&'static str>,
    /// Lines of generated code (one statement or item per line, as `cargo expand` prints it).
    pub lines: usize,
    /// The formulation that gives `accelerations`: the route chosen, or
    /// Maggi's equations for a system in generalized speeds (whose figures
    /// are in the curvature route's slots: Maggi's reduced system is solved
    /// as the curvature route's is).
    pub formulation: Option<Formulation>,
    /// The other charts of the atlas (DESIGN §9.3): per chart, its name and
    /// the operations of its `accelerations`; empty with one chart.
    pub charts: Vec<(String, usize)>,
    /// Operations of `jacobian` after CSE (its part on the parameters alone
    /// included), when the system derives it.
    pub jacobian_ops: Option<usize>,
}

impl Stats {
    /// Operations of r̈ by `route`, after CSE.
    pub(crate) fn ops(&self, route: Route) -> usize {
        match route {
            Route::Multiplier => self.ops_multiplier,
            Route::Curvature => self.ops_curvature,
        }
    }

    /// Whether r̈ by `route`, the route `accelerations` uses, is large enough
    /// that methods needing it call `accelerations` instead of repeating its
    /// code.
    pub(crate) fn is_large(&self, route: Route) -> bool {
        self.ops(route) > LARGE_OPS
    }

    /// One line: operation counts, route, graph size.
    pub fn summary(&self) -> String {
        if self.formulation == Some(Formulation::Maggi) {
            return format!(
                "accelerations: Maggi's equations (generalized speeds) {} ops (cost {}) after CSE; {} generated lines; graph {} expressions, {} derivatives",
                self.ops_curvature,
                self.cost_curvature,
                self.lines,
                self.graph_size,
                self.derivatives
            );
        }
        let curvature = if self.ops_curvature == 0 {
            "not derived (k > 6, or constraints that are not homogeneous)".to_string()
        } else {
            format!("{} ops (cost {})", self.ops_curvature, self.cost_curvature)
        };
        let atlas = if self.charts.is_empty() {
            String::new()
        } else {
            let each: Vec<String> = (self.charts.iter())
                .map(|(name, ops)| format!("{name}: {ops} ops"))
                .collect();
            format!(
                "; atlas of {} charts, the others {}",
                self.charts.len() + 1,
                each.join(", ")
            )
        };
        format!(
            "accelerations: multiplier route {} ops (cost {}), curvature route {curvature} after CSE, using the {} route ({} ops of it on the parameters alone, cached); {} generated lines; graph {} expressions, {} derivatives; integrable: {}{atlas}",
            self.ops_multiplier,
            self.cost_multiplier,
            match self.route {
                Some(Route::Multiplier) => "multiplier",
                Some(Route::Curvature) => "curvature",
                None => "(none)",
            },
            self.ops_on_parameters,
            self.lines,
            self.graph_size,
            self.derivatives,
            self.integrable
        )
    }
}

impl Route {
    /// The method computing r̈ by this route alone.
    pub(crate) fn method(self) -> GeneratedMethod {
        match self {
            Route::Multiplier => GeneratedMethod::AccelerationsMultiplierRoute,
            Route::Curvature => GeneratedMethod::AccelerationsCurvatureRoute,
        }
    }

    /// The route's description in the generated docs.
    pub(crate) fn doc(self) -> &'static str {
        self.method().spec().doc
    }

    /// The other route.
    pub(crate) fn other(self) -> Route {
        match self {
            Route::Multiplier => Route::Curvature,
            Route::Curvature => Route::Multiplier,
        }
    }
}

/// The graph of r̈ by each route, from the comparison of the routes, until
/// a method emits it: the chosen route's for `accelerations`, the other's
/// for its own method with `outputs { routes }`.
#[derive(Default)]
pub(crate) struct RouteGraphs {
    pub(crate) multiplier: Option<(Dag, Vec<Node>)>,
    pub(crate) curvature: Option<(Dag, Vec<Node>)>,
}

impl RouteGraphs {
    pub(crate) fn slot(&mut self, route: Route) -> &mut Option<(Dag, Vec<Node>)> {
        match route {
            Route::Multiplier => &mut self.multiplier,
            Route::Curvature => &mut self.curvature,
        }
    }
}

/// The reduced system of `dv.reduced` (graph `reduced`, solved
/// numerically, with pivots `pivots`) solved symbolically instead, if that
/// is cheaper; the solution is then kept in the derivation.
pub(crate) fn solved_if_cheaper(
    m: &mut Scene<'_>,
    dv: &mut Derivation,
    reduced: (Dag, Vec<Node>),
    pivots: &[Node],
) -> (Dag, Vec<Node>) {
    let (cmass, crhs) = (dv.reduced.mass.clone(), dv.reduced.rhs.clone());
    if pivots.iter().all(|&p| p != ZERO_NODE)
        && let Some(sol) = m.solve_symbolic(&cmass, &crhs)
    {
        let mut d3 = bound_dag(m, &Args::vectors(m));
        let x3 = exprs(&mut d3, m, &sol);
        if d3.cost_estimate(&x3) < reduced.0.cost_estimate(&reduced.1) {
            dv.reduced.solution = Some(sol);
            return (d3, x3);
        }
    }
    reduced
}

/// The graphs of r̈ by both routes, built to compare their costs.
pub(crate) struct ComparedRoutes {
    pub(crate) multiplier: (Dag, Vec<Node>),
    /// Empty when the curvature route is not derived.
    pub(crate) curvature: (Dag, Vec<Node>),
    pub(crate) both_routes: bool,
    /// The pivots of both routes' factorisations of the reduced mass matrix.
    pub(crate) pivots: Vec<Node>,
    /// Operations of the multiplier route's Cᵀ M C and right side of (5.9),
    /// before their factorisation and solve.
    pub(crate) projection_ops: usize,
    /// Whether the multiplier route's r̈ is the articulated-body solve.
    pub(crate) articulated: bool,
}

/// Builds the graph of r̈ by each route (the curvature route's with the
/// reduced system solved symbolically, if that is cheaper).
pub(crate) fn compare_routes(
    m: &mut Scene<'_>,
    dv: &mut Derivation,
    both_routes: bool,
) -> ComparedRoutes {
    let args_v = Args::vectors(m).moving();
    let mut d1 = bound_dag(m, &args_v);
    let mn = multiplier_nodes(&mut d1, m, &dv.multiplier_route, dv.kane.as_ref());
    let mass = mn.projected_mass.iter().flatten();
    let projected: Vec<Node> = (mass.take(if mn.by_tree { 0 } else { usize::MAX }))
        .chain(&mn.projected_rhs)
        .copied()
        .collect();
    let projection_ops = d1.op_count(&projected);
    let mut d2 = bound_dag(m, &args_v);
    let (mut rdd2, piv2) = if both_routes {
        curvature_nodes(&mut d2, m, &dv.reduced)
    } else {
        (Vec::new(), Vec::new())
    };
    if both_routes {
        (d2, rdd2) = solved_if_cheaper(m, dv, (d2, rdd2), &piv2);
    }
    ComparedRoutes {
        multiplier: (d1, mn.rdd),
        curvature: (d2, rdd2),
        both_routes,
        pivots: mn.pivots.into_iter().chain(piv2).collect(),
        projection_ops,
        articulated: mn.by_tree,
    }
}

impl ComparedRoutes {
    /// Records both routes' figures and chooses the cheaper.
    pub(crate) fn choose(&self, stats: &mut Stats) -> Route {
        let ((d1, rdd1), (d2, rdd2)) = (&self.multiplier, &self.curvature);
        stats.ops_multiplier = d1.op_count(rdd1);
        stats.ops_projection = self.projection_ops;
        stats.articulated = self.articulated;
        stats.ops_curvature = d2.op_count(rdd2);
        stats.cost_multiplier = d1.cost_estimate(rdd1);
        stats.cost_curvature = d2.cost_estimate(rdd2);
        let route = if self.both_routes && stats.cost_curvature <= stats.cost_multiplier {
            Route::Curvature
        } else {
            Route::Multiplier
        };
        stats.route = Some(route);
        let (d, rdd) = match route {
            Route::Multiplier => (d1, rdd1),
            Route::Curvature => (d2, rdd2),
        };
        stats.ops_on_parameters = d.op_count(&d.hoistable(rdd));
        route
    }

    /// The graphs a method will emit: the chosen route's, and with `routes`
    /// the other's, unless its method emits another graph (the curvature
    /// route of a large system is solved from `reduced_system`; solved
    /// symbolically, it is emitted with its steps labelled).
    pub(crate) fn keep(
        self,
        route: Route,
        m: &Scene<'_>,
        dv: &Derivation,
        stats: &Stats,
    ) -> RouteGraphs {
        let other_kept = m.outputs.contains(Output::Routes)
            && (route == Route::Curvature
                || (dv.reduced.solution.is_none() && !stats.is_large(route)));
        let mut graphs = RouteGraphs::default();
        let (multiplier, curvature) = (self.multiplier, self.curvature);
        if route == Route::Multiplier || other_kept {
            graphs.multiplier = Some(multiplier);
        }
        if route == Route::Curvature || other_kept {
            graphs.curvature = Some(curvature);
        }
        graphs
    }
}

#[cfg(test)]
mod tests {
    use super::{Route, Stats, compare_routes};
    use crate::mechanics::Scene;
    use crate::testing::{SLED, close, lowered, node_value, without_ydot};

    /// Both routes' graphs of the sled give the same r̈; the cheaper is
    /// chosen and the figures recorded.
    #[test]
    fn the_routes_agree_and_the_cheaper_is_chosen() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let mut dv = crate::mechanics::derive(&mut scene, true);
        let compared = compare_routes(&mut scene, &mut dv, true);
        let at = without_ydot();
        let value = |(d, rdd): &(crate::emit::Dag, Vec<crate::emit::Node>)| {
            rdd.iter()
                .map(|&n| node_value(&model, d, n, &at))
                .collect::<Vec<f64>>()
        };
        let (a, b) = (value(&compared.multiplier), value(&compared.curvature));
        assert!(a.iter().zip(&b).all(|(x, y)| close(*x, *y)), "{a:?} {b:?}");
        let mut stats = Stats::default();
        let route = compared.choose(&mut stats);
        assert_eq!(stats.route, Some(route));
        assert!(stats.ops_multiplier > 0 && stats.ops_curvature > 0);
        let (chosen, other) = match route {
            Route::Multiplier => (stats.cost_multiplier, stats.cost_curvature),
            Route::Curvature => (stats.cost_curvature, stats.cost_multiplier),
        };
        assert!(chosen <= other);
    }
}
