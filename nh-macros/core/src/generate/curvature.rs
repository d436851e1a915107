//! The curvature route on the graph: the reduced system Mc r̈ = f of
//! (5.20) factored by LDLᵀ (or its symbolic solution).

use super::nodes::{exprs, matrix};
use crate::algebra::ldlt::{self, Updates};
use crate::emit::{Dag, Node};
use crate::mechanics::Reduced;
use crate::mechanics::Scene;

pub(crate) fn curvature_nodes(d: &mut Dag, m: &Scene<'_>, r: &Reduced) -> (Vec<Node>, Vec<Node>) {
    let mass = matrix(d, m, &r.mass);
    for (a, row) in mass.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("reduced mass matrix ∂²Lc/∂ṙ{a}∂ṙ{b} of the constrained Lagrangian (5.12)"),
            );
        }
    }
    if let Some(sol) = &r.solution {
        let x = exprs(d, m, sol);
        for (a, &v) in x.iter().enumerate() {
            d.label(
                v,
                format!("r̈{a}: (5.20) with the reduced mass matrix inverted symbolically (LDLᵀ)"),
            );
        }
        return (x, Vec::new());
    }
    let rhs = exprs(d, m, &r.rhs);
    for (a, &x) in rhs.iter().enumerate() {
        d.label(x, format!("right side {a} of (5.20): projected forces minus the velocity terms and the curvature term Σ B ṙ ∂L/∂ṡ (5.21)"));
    }
    let (x, piv) = ldlt::solve_symmetric(d, &mass, &rhs, Updates::Kept);
    for (a, &v) in x.iter().enumerate() {
        d.label(v, format!("r̈{a}: the reduced mass matrix solved by LDLᵀ"));
    }
    (x, piv)
}

#[cfg(test)]
mod tests {
    use super::curvature_nodes;
    use crate::generate::graph::{Args, bound_dag};
    use crate::mechanics::Scene;
    use crate::testing::{SLED, close, lowered, node_value, without_ydot};

    /// The curvature route on the graph: Mc = diag(m sec²θ, J) factored
    /// (both pivots nonzero) and the sled's closed form.
    #[test]
    fn the_sleds_accelerations_by_the_curvature_route() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let dv = crate::mechanics::derive(&mut scene, true);
        let mut d = bound_dag(&scene, &Args::vectors(&scene));
        let (rdd, pivots) = curvature_nodes(&mut d, &scene, &dv.reduced);
        let at = without_ydot();
        let sec2 = 1.0 / 0.3f64.cos().powi(2);
        assert!(close(node_value(&model, &d, pivots[0], &at), 2.0 * sec2));
        assert!(close(node_value(&model, &d, pivots[1], &at), 0.5));
        let xdd = node_value(&model, &d, rdd[0], &at);
        assert!(close(xdd, -(0.3f64.tan()) * -1.1 * 0.7), "{xdd}");
    }
}
