//! A body frame's motion from its elementary rotations (DESIGN §10): the
//! orientation, ω_b and α_b built step by step from the previous step's
//! nodes, instead of from the expanded products the symbolic ω_b is, whose
//! rates would repeat every product.

use super::motion::Motion;
use super::{cross_nodes, matrix};
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::{Frame, FrameStep};
use crate::model::Model;

/// A frame's orientation (in the frame of the bodies' J), ω_b and α_b at
/// q̈ = 0 (body axes).
pub(crate) struct FrameMotion {
    pub(crate) turn: [[Node; 3]; 3],
    pub(crate) omega: [Node; 3],
    pub(crate) alpha0: [Node; 3],
}

/// Fᵀ v.
fn back(d: &mut Dag, f: &[Vec<Node>], v: [Node; 3]) -> [Node; 3] {
    [0, 1, 2].map(|x| super::dot(d, ZERO_NODE, (0..3).map(|y| (f[y][x], v[y]))))
}

/// ω' = Fᵀ ω + θ̇ e_k and α' = Fᵀ α + (Fᵀ ω) × θ̇ e_k + θ̈ e_k.
fn turn_rates(
    d: &mut Dag,
    f: &[Vec<Node>],
    (k, rate, accel): (usize, Node, Node),
    omega: [Node; 3],
    alpha: [Node; 3],
) -> ([Node; 3], [Node; 3]) {
    let w = back(d, f, omega);
    let mut spin = [ZERO_NODE; 3];
    spin[k] = rate;
    let carried = cross_nodes(d, &w, &spin);
    let a = back(d, f, alpha);
    let mut omega = w;
    omega[k] = d.add(w[k], rate);
    let alpha = [0, 1, 2].map(|x| {
        let t = d.add(a[x], carried[x]);
        if x == k { d.add(t, accel) } else { t }
    });
    (omega, alpha)
}

/// The frame's orientation, ω_b and α_b at q̈ = 0.
pub(crate) fn frame_motion(d: &mut Dag, m: &Model, motion: &Motion, frame: &Frame) -> FrameMotion {
    let mut turn = [[ZERO_NODE; 3]; 3];
    for (x, row) in turn.iter_mut().enumerate() {
        row[x] = ONE_NODE;
    }
    let (mut omega, mut alpha0) = ([ZERO_NODE; 3], [ZERO_NODE; 3]);
    for (i, step) in frame.steps.iter().enumerate() {
        let f = step_turn(d, m, step);
        let rate = d.expr(&m.engine, step.rate);
        let accel = motion.rate_of(d, rate);
        (omega, alpha0) = turn_rates(d, &f, (step.axis, rate, accel), omega, alpha0);
        if !(i == 0 && frame.heading_out) {
            turn = turn.map(|row| {
                [0, 1, 2].map(|y| super::dot(d, ZERO_NODE, (0..3).map(|x| (row[x], f[x][y]))))
            });
        }
    }
    FrameMotion {
        turn,
        omega,
        alpha0,
    }
}

/// ω and α at q̈ = 0 in the frame of the bodies' J: the last step's
/// rates in the axes before it (F_n e_k = e_k spares turning by F_n),
/// turned by the orientation up to there.
pub(crate) fn world_motion(
    d: &mut Dag,
    m: &Model,
    motion: &Motion,
    frame: &Frame,
) -> ([Node; 3], [Node; 3]) {
    let Some((last, rest)) = frame.steps.split_last() else {
        return ([ZERO_NODE; 3], [ZERO_NODE; 3]);
    };
    let before = Frame {
        steps: rest.to_vec(),
        heading_out: frame.heading_out,
    };
    let f = frame_motion(d, m, motion, &before);
    let rate = d.expr(&m.engine, last.rate);
    let accel = motion.rate_of(d, rate);
    let identity: Vec<Vec<Node>> = (0..3)
        .map(|x| {
            (0..3)
                .map(|y| if x == y { ONE_NODE } else { ZERO_NODE })
                .collect()
        })
        .collect();
    let (omega, alpha) = turn_rates(d, &identity, (last.axis, rate, accel), f.omega, f.alpha0);
    let out = |d: &mut Dag, v: [Node; 3]| {
        [0, 1, 2].map(|x| super::dot(d, ZERO_NODE, (0..3).map(|y| (f.turn[x][y], v[y]))))
    };
    (out(d, omega), out(d, alpha))
}

fn step_turn(d: &mut Dag, m: &Model, step: &FrameStep) -> Vec<Vec<Node>> {
    matrix(d, m, &step.turn.map(|row| row.to_vec()))
}
