//! Small products on the graph shared by the routes and the bodies.

use crate::emit::{Dag, Node};
use crate::mechanics::Scene;
use crate::sym::ExprId;
use proc_macro2::TokenStream;
use quote::quote;

/// fa + (Pᵀ force)_a: a force's part along the partial velocities a.
pub(crate) fn force_along(
    d: &mut Dag,
    fa: Node,
    p: &[Vec<Node>],
    force: &[Node],
    a: usize,
) -> Node {
    dot(d, fa, (0..p.len()).map(|x| (p[x][a], force[x])))
}

/// u × v.
pub(crate) fn cross_nodes(d: &mut Dag, u: &[Node], v: &[Node]) -> Vec<Node> {
    (0..3)
        .map(|x| {
            let (y, z) = ((x + 1) % 3, (x + 2) % 3);
            let a = d.mul(u[y], v[z]);
            let b = d.mul(u[z], v[y]);
            d.sub(a, b)
        })
        .collect()
}

/// `init + Σ x·y` over `pairs`, added up in order.
pub(crate) fn dot(d: &mut Dag, init: Node, pairs: impl IntoIterator<Item = (Node, Node)>) -> Node {
    let mut acc = init;
    for (x, y) in pairs {
        let t = d.mul(x, y);
        acc = d.add(acc, t);
    }
    acc
}

pub(crate) fn vector_expr(k: usize, items: &[TokenStream]) -> TokenStream {
    quote!(__nh_private::nalgebra::SVector::<T, #k>::from([#(#items),*]))
}

pub(crate) fn exprs(d: &mut Dag, m: &Scene<'_>, v: &[ExprId]) -> Vec<Node> {
    v.iter().map(|&e| d.expr(m.engine, e)).collect()
}

pub(crate) fn matrix(d: &mut Dag, m: &Scene<'_>, v: &[Vec<ExprId>]) -> Vec<Vec<Node>> {
    v.iter().map(|row| exprs(d, m, row)).collect()
}
