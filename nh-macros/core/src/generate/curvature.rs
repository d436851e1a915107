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
