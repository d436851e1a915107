//! Small products on the graph shared by the routes and the bodies.

use crate::algebra;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
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
    algebra::dot_from(d, fa, (0..p.len()).map(|x| (p[x][a], force[x])))
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

/// Cᵀ M C and −Cᵀ (M acc_bias + h) of (5.9).
pub(crate) fn projection(
    d: &mut Dag,
    mass: &[Vec<Node>],
    bias: &[Node],
    c: &[Vec<Node>],
    acc_bias: &[Node],
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let (n, k) = (c.len(), c.first().map_or(0, Vec::len));
    let mut mc = vec![vec![ZERO_NODE; k]; n];
    for i in 0..n {
        for b in 0..k {
            mc[i][b] = algebra::dot(d, (0..n).map(|j| (mass[i][j], c[j][b])));
        }
    }
    let mut mr = vec![vec![ZERO_NODE; k]; k];
    for a in 0..k {
        for b in a..k {
            let acc = algebra::dot(d, (0..n).map(|i| (c[i][a], mc[i][b])));
            mr[a][b] = acc;
            mr[b][a] = acc;
        }
    }
    let g: Vec<Node> = (0..n)
        .map(|i| algebra::dot_from(d, bias[i], (0..n).map(|j| (mass[i][j], acc_bias[j]))))
        .collect();
    let f = (0..k)
        .map(|a| {
            let acc = algebra::dot(d, (0..n).map(|i| (c[i][a], g[i])));
            d.neg(acc)
        })
        .collect();
    (mr, f)
}

/// The columns of a planar pair (x, y) of a Jacobian in the heading's
/// frame: e_x and e_y where the dependent rows are u = R_z(−ψ)(ẋ, ẏ)
/// (`constant`), or zero in a rate at q̈ = 0, to which a column constant in
/// the world adds nothing.
pub(crate) fn planar_columns(j: &mut [Vec<Node>], planar: Option<[usize; 2]>, constant: bool) {
    for (axis, i) in planar.into_iter().flat_map(|p| p.into_iter().enumerate()) {
        for (x, row) in j.iter_mut().enumerate() {
            row[i] = if constant && x == axis {
                ONE_NODE
            } else {
                ZERO_NODE
            };
        }
    }
}

/// A body's inertia T (I + Σ μ(|d|² 1 − d dᵀ)) Tᵀ from its parts
/// ([`crate::mechanics::Inertia`]), symmetric.
pub(crate) fn inertia_nodes(
    d: &mut Dag,
    m: &Scene<'_>,
    inertia: &crate::mechanics::Inertia,
) -> Vec<Vec<Node>> {
    let mut sum = matrix(d, m, &inertia.own.map(|r| r.to_vec()));
    for (mu, offset) in &inertia.masses {
        let mu = d.expr(m.engine, *mu);
        let v = exprs(d, m, offset);
        for a in 0..3 {
            for b in a..3 {
                let t = point_inertia(d, &v, (a, b));
                let t = d.mul(mu, t);
                sum[a][b] = d.add(sum[a][b], t);
                sum[b][a] = sum[a][b];
            }
        }
    }
    let Some(tail) = &inertia.tail else {
        return sum;
    };
    let t = matrix(d, m, &tail.map(|r| r.to_vec()));
    let ts: Vec<Vec<Node>> = (0..3)
        .map(|a| {
            (0..3)
                .map(|b| algebra::dot(d, (0..3).map(|k| (t[a][k], sum[k][b]))))
                .collect()
        })
        .collect();
    let mut out = vec![vec![ZERO_NODE; 3]; 3];
    for a in 0..3 {
        for b in a..3 {
            out[a][b] = algebra::dot(d, (0..3).map(|k| (ts[a][k], t[b][k])));
            out[b][a] = out[a][b];
        }
    }
    out
}

/// (|r|² 1 − r rᵀ)_ab, a unit mass's inertia at r: Σ_{k≠a} r_k² on the
/// diagonal, −r_a r_b off it.
pub(crate) fn point_inertia(d: &mut Dag, r: &[Node], (a, b): (usize, usize)) -> Node {
    match a == b {
        true => (0..3).filter(|&k| k != a).fold(ZERO_NODE, |acc, k| {
            algebra::dot_from(d, acc, [(r[k], r[k])])
        }),
        false => {
            let p = d.mul(r[a], r[b]);
            d.neg(p)
        }
    }
}
