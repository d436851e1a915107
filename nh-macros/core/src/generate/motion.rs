//! Rates along the motion at q̈ = 0 (J̇ q̇, Ẇ q̇ of bodies and contacts)
//! computed on the graph from the velocities' own nodes, instead of from
//! symbolic derivatives Σ_i ∂(J q̇)/∂q_i q̇_i: a rate then shares every
//! subexpression with the Jacobian it comes from.

use crate::algebra;
use crate::emit::{Dag, Node};
use crate::mechanics::Scene;
use crate::sym::ExprId;
use rustc_hash::FxHashMap as HashMap;

/// How the graph's nodes move: each coordinate at its velocity's node, the
/// velocities (and parameters, time, inputs) held.
pub(crate) struct Motion {
    pub(crate) seeds: HashMap<Node, Node>,
    pub(crate) held: Vec<Node>,
    /// ψ̇, when vectors are given in the heading's frame R = R_z(−ψ).
    pub(crate) heading_rate: Option<Node>,
}

impl Motion {
    /// The motion of a graph made by `bound_dag`, where every coordinate
    /// and velocity is bound (an unbound one would be an undefined name in
    /// the generated code, never a wrong rate).
    pub(crate) fn of(d: &mut Dag, m: &Scene<'_>, heading_rate: Option<ExprId>) -> Motion {
        let mut seeds = HashMap::default();
        let mut held = Vec::with_capacity(m.n());
        for c in &m.coordinates {
            let v = d
                .bound(c.velocity)
                .unwrap_or_else(|| d.leaf(quote::quote!(__nh_unbound_velocity)));
            if let Some(q) = d.bound(c.position) {
                seeds.insert(q, v);
            }
            held.push(v);
        }
        let heading_rate = heading_rate.map(|h| d.expr(m.engine, h));
        Motion {
            seeds,
            held,
            heading_rate,
        }
    }

    /// The rate of the vector `u`; for a world vector given in the
    /// heading's frame (`in_heading_frame`), the world rate turned into it:
    /// R ȧ = (R a)˙ + ψ̇ e_z × R a.
    pub(crate) fn rate(&self, d: &mut Dag, u: [Node; 3], in_heading_frame: bool) -> [Node; 3] {
        let r = d.rates(&u, &self.seeds, &self.held);
        let mut r = [r[0], r[1], r[2]];
        if let (true, Some(w)) = (in_heading_frame, self.heading_rate) {
            let wy = d.mul(w, u[1]);
            let wx = d.mul(w, u[0]);
            r[0] = d.sub(r[0], wy);
            r[1] = d.add(r[1], wx);
        }
        r
    }

    /// The rate of a scalar.
    pub(crate) fn rate_of(&self, d: &mut Dag, x: Node) -> Node {
        d.rates(&[x], &self.seeds, &self.held)[0]
    }

    /// The rate of J q̇ for a 3 × n Jacobian J of positions (see [`Motion::rate`]).
    pub(crate) fn rate_of_jacobian(
        &self,
        d: &mut Dag,
        j: &[Vec<Node>],
        in_heading_frame: bool,
    ) -> [Node; 3] {
        let u = [0, 1, 2].map(|x| {
            let pairs = j[x].iter().copied().zip(self.held.iter().copied());
            algebra::dot(d, pairs)
        });
        self.rate(d, u, in_heading_frame)
    }
}
