//! A body frame's motion from its elementary rotations (DESIGN §10): the
//! orientation, ω_b and α_b built step by step from the previous step's
//! nodes, instead of from the expanded products the symbolic ω_b is, whose
//! rates would repeat every product.

use super::motion::Motion;
use super::nodes::matrix;
use crate::algebra;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Scene;
use crate::mechanics::{Frame, FrameStep};

/// A frame's ω_b and α_b at q̈ = 0 (body axes).
pub(crate) struct FrameMotion {
    pub(crate) omega: [Node; 3],
    pub(crate) alpha0: [Node; 3],
}

/// Fᵀ v.
fn back(d: &mut Dag, f: &[Vec<Node>], v: [Node; 3]) -> [Node; 3] {
    algebra::mat_t_vec(d, f, v)
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
    let carried = algebra::cross(d, w, spin);
    let a = back(d, f, alpha);
    let mut omega = w;
    omega[k] = d.add(w[k], rate);
    let alpha = [0, 1, 2].map(|x| {
        let t = d.add(a[x], carried[x]);
        if x == k { d.add(t, accel) } else { t }
    });
    (omega, alpha)
}

/// The frame's ω_b and α_b at q̈ = 0 (its orientation: [`orientation`]).
pub(crate) fn frame_motion(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &Motion,
    frame: &Frame,
) -> FrameMotion {
    let (mut omega, mut alpha0) = ([ZERO_NODE; 3], [ZERO_NODE; 3]);
    for step in &frame.steps {
        let f = step_turn(d, m, step);
        let rate = d.expr(m.engine, step.rate);
        let accel = motion.rate_of(d, rate);
        (omega, alpha0) = turn_rates(d, &f, (step.axis, rate, accel), omega, alpha0);
    }
    FrameMotion { omega, alpha0 }
}

/// ω and α at q̈ = 0 in the frame of the bodies' J, summed over the steps
/// in those axes: with a_i = R₁⋯R_{i−1} e_k, ω = Σ θ̇_i a_i and
/// α = Σ (ω_{<i} × θ̇_i a_i + θ̈_i a_i), ω_{<i} the sum before step i.
pub(crate) fn world_motion(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &Motion,
    frame: &Frame,
) -> ([Node; 3], [Node; 3]) {
    let mut turn = identity();
    let (mut omega, mut alpha) = ([ZERO_NODE; 3], [ZERO_NODE; 3]);
    for (i, step) in frame.steps.iter().enumerate() {
        let rate = d.expr(m.engine, step.rate);
        let accel = motion.rate_of(d, rate);
        let axis = [0, 1, 2].map(|x| turn[x][step.axis]);
        let spin = algebra::scale3(d, rate, axis);
        let carried = algebra::cross(d, omega, spin);
        for x in 0..3 {
            let t = d.mul(accel, axis[x]);
            let t = d.add(carried[x], t);
            alpha[x] = d.add(alpha[x], t);
            omega[x] = d.add(omega[x], spin[x]);
        }
        if !(i == 0 && frame.heading_out) {
            let f = step_turn(d, m, step);
            turn = turned(d, turn, &f);
        }
    }
    (omega, alpha)
}

/// The frame's orientation in the frame of the bodies' J.
pub(crate) fn orientation(d: &mut Dag, m: &Scene<'_>, frame: &Frame) -> [[Node; 3]; 3] {
    let mut turn = identity();
    for (i, step) in frame.steps.iter().enumerate() {
        if !(i == 0 && frame.heading_out) {
            let f = step_turn(d, m, step);
            turn = turned(d, turn, &f);
        }
    }
    turn
}

/// Each step's axis a_i = R₁⋯R_{i−1} e_k in the frame of the bodies' J.
pub(crate) fn world_axes(d: &mut Dag, m: &Scene<'_>, frame: &Frame) -> Vec<[Node; 3]> {
    let mut turn = identity();
    let mut axes = Vec::with_capacity(frame.steps.len());
    for (i, step) in frame.steps.iter().enumerate() {
        axes.push([0, 1, 2].map(|x| turn[x][step.axis]));
        if !(i == 0 && frame.heading_out) {
            let f = step_turn(d, m, step);
            turn = turned(d, turn, &f);
        }
    }
    axes
}

/// R F.
fn turned(d: &mut Dag, r: [[Node; 3]; 3], f: &[Vec<Node>]) -> [[Node; 3]; 3] {
    algebra::mat_mat(d, &r, f)
}

fn identity() -> [[Node; 3]; 3] {
    [0, 1, 2].map(|x| [0, 1, 2].map(|y| if x == y { ONE_NODE } else { ZERO_NODE }))
}

fn step_turn(d: &mut Dag, m: &Scene<'_>, step: &FrameStep) -> Vec<Vec<Node>> {
    matrix(d, m, &step.turn.map(|row| row.to_vec()))
}
