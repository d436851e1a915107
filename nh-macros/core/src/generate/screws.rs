//! A point's Jacobian as screws (DESIGN §10): a point carried along a chain
//! of frames, p = root + Σ_l R_l r_l, moves with ṗ = J_root q̇ +
//! Σ_l ω_l × R_l r_l, and each frame's ω = Σ_s θ̇_s a_s sums its elementary
//! rotations' rates along their axes. So J = J_root + Σ_s a_s × L_s ∂θ̇_s/∂q̇
//! over the steps, each step once, with the lever L_s summing the offsets
//! of every frame that turns with it: a few cross products where the
//! expanded ∂p/∂q repeats every product of sines and cosines.

use super::nodes::planar_columns;
use super::nodes::{exprs, matrix};
use crate::algebra;
use crate::emit::{Dag, Node, ZERO_NODE};
use crate::mechanics::Scene;
use crate::mechanics::{Frame, FrameStep, Link};
use crate::sym::{ExprId, ZERO};

/// J = J_root + Σ_s arm_s ∂θ̇_s/∂q̇ (frame of the bodies' J).
pub(crate) struct Screws {
    /// J_root, 3 × n.
    pub(crate) root: Vec<Vec<Node>>,
    /// Per step that turns: a_s × L_s and ∂θ̇_s/∂q̇ (n).
    pub(crate) arms: Vec<([Node; 3], Vec<Node>)>,
}

/// The offsets R_l r_l of a chain's links with their frames; `None` if a
/// link has no frame of elementary rotations.
pub(crate) fn link_pieces<'a>(
    d: &mut Dag,
    m: &Scene<'_>,
    links: &'a [Link],
) -> Option<Vec<(&'a Frame, [Node; 3])>> {
    let mut pieces = Vec::with_capacity(links.len() + 1);
    for link in links {
        let frame = link.frame.as_ref()?;
        let turn = super::frames::orientation(d, m, frame);
        let r = exprs(d, m, &link.offset);
        let off = algebra::mat_vec(d, &turn, &r);
        pieces.push((frame, off));
    }
    Some(pieces)
}

impl Screws {
    /// The screws of a point at root + Σ offsets of `pieces` (with a planar
    /// pair's columns e_x, e_y: see [`planar_columns`]).
    pub(crate) fn of(
        d: &mut Dag,
        m: &Scene<'_>,
        root: &[Vec<ExprId>; 3],
        pieces: &[(&Frame, [Node; 3])],
        planar: Option<[usize; 2]>,
    ) -> Screws {
        let mut steps: Vec<(&[FrameStep], [Node; 3], [Node; 3])> = Vec::new();
        for &(frame, off) in pieces {
            let axes = super::frames::world_axes(d, m, frame);
            for (j, axis) in axes.into_iter().enumerate() {
                let prefix = &frame.steps[..=j];
                match steps.iter_mut().find(|(s, _, _)| same_steps(s, prefix)) {
                    Some((_, _, lever)) => *lever = algebra::add3(d, *lever, off),
                    None => steps.push((prefix, axis, off)),
                }
            }
        }
        let arms = steps
            .into_iter()
            .filter_map(|(prefix, axis, lever)| {
                let step = &prefix[prefix.len() - 1];
                if step.rate_jacobian.iter().all(|&x| x == ZERO) {
                    return None;
                }
                let arm = algebra::cross(d, axis, lever);
                Some(([arm[0], arm[1], arm[2]], exprs(d, m, &step.rate_jacobian)))
            })
            .collect();
        let mut root = matrix(d, m, root);
        planar_columns(&mut root, planar, true);
        Screws { root, arms }
    }

    /// The columns ∂ṗ/∂q̇_i.
    pub(crate) fn columns(&self, d: &mut Dag) -> Vec<[Node; 3]> {
        let n = self.root.first().map_or(0, Vec::len);
        (0..n)
            .map(|i| {
                [0, 1, 2].map(|x| {
                    let pairs = self.arms.iter().map(|(arm, rates)| (rates[i], arm[x]));
                    algebra::dot_from(d, self.root[x][i], pairs)
                })
            })
            .collect()
    }

    /// J v for a vector v of velocities (n).
    pub(crate) fn times(&self, d: &mut Dag, v: &[Node]) -> [Node; 3] {
        let along: Vec<Node> = self
            .arms
            .iter()
            .map(|(_, rates)| algebra::dot(d, rates.iter().copied().zip(v.iter().copied())))
            .collect();
        [0, 1, 2].map(|x| {
            let root = algebra::dot_from(
                d,
                ZERO_NODE,
                self.root[x].iter().copied().zip(v.iter().copied()),
            );
            let pairs = self
                .arms
                .iter()
                .zip(&along)
                .map(|((arm, _), &t)| (t, arm[x]));
            algebra::dot_from(d, root, pairs)
        })
    }
}

/// Whether two runs of steps are the same rotations.
fn same_steps(a: &[FrameStep], b: &[FrameStep]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.axis == y.axis && x.turn == y.turn)
}
