//! Accelerations along a kinematic chain on the graph (DESIGN §10), and
//! the planar columns of a Jacobian in the heading's frame.

use super::nodes::{exprs, matrix, planar_columns};
use crate::algebra;
use crate::emit::{Dag, Node};
use crate::mechanics::Scene;

/// A point's acceleration at q̈ = 0 along its chain (DESIGN §10):
/// J̇_root q̇ + Σ R(α_b × r + ω_b × (ω_b × r)), α_b = Ẇ q̇.
pub(crate) fn chain_rate(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &super::motion::Motion,
    chain: &crate::mechanics::Chain,
    planar: Option<[usize; 2]>,
) -> [Node; 3] {
    let mut root = matrix(d, m, &chain.root);
    planar_columns(&mut root, planar, false);
    let mut a = motion.rate_of_jacobian(d, &root, true);
    if let Some(pieces) = super::screws::link_pieces(d, m, &chain.links) {
        // in the frame of J: α × R r + ω × (ω × R r) per link
        for (frame, off) in pieces {
            let (omega, alpha) = super::frames::world_motion(d, m, motion, frame);
            let tangential = algebra::cross(d, alpha, off);
            let wr = algebra::cross(d, omega, off);
            let normal = algebra::cross(d, omega, wr);
            a = [0, 1, 2].map(|x| {
                let t = d.add(tangential[x], normal[x]);
                d.add(a[x], t)
            });
        }
        return a;
    }
    for link in &chain.links {
        let (omega, alpha0, turn) = match &link.frame {
            Some(frame) => {
                let f = super::frames::frame_motion(d, m, motion, frame);
                let turn = super::frames::orientation(d, m, frame);
                (f.omega, f.alpha0, turn.map(|row| row.to_vec()).to_vec())
            }
            None => {
                let omega = exprs(d, m, &link.omega);
                let omega = [omega[0], omega[1], omega[2]];
                let alpha0 = motion.rate(d, omega, false);
                let turn = matrix(d, m, &link.turn.map(|row| row.to_vec()));
                (omega, alpha0, turn)
            }
        };
        let r = exprs(d, m, &link.offset);
        let tangential = algebra::cross(d, alpha0, &r);
        let wr = algebra::cross(d, omega, &r);
        let normal = algebra::cross(d, omega, wr);
        let body: Vec<Node> = (0..3).map(|x| d.add(tangential[x], normal[x])).collect();
        a = [0, 1, 2].map(|x| algebra::dot_from(d, a[x], (0..3).map(|y| (turn[x][y], body[y]))));
    }
    a
}
