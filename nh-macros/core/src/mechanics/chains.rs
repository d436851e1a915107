//! Kinematic chains and body frames (DESIGN §10): how a point's
//! acceleration follows a root point's through the bodies' frames, and a
//! frame as a product of elementary rotations.

use crate::sym::ExprId;

/// How a point's acceleration at q̈ = 0 follows from a root point's
/// (DESIGN §10): a = J̇_root q̇ + Σ_links R(α_b × r + ω_b × (ω_b × r)),
/// each link a body frame in which the next point is fixed at offset r
/// from the last.
#[derive(Clone)]
pub struct Chain {
    /// J of the root point, 3 × n, in the frame of the bodies' J.
    pub root: [Vec<ExprId>; 3],
    /// The links, from the root on.
    pub links: Vec<Link>,
}

/// One link of a [`Chain`].
#[derive(Clone)]
pub struct Link {
    /// ω_b of the frame's body (body axes).
    pub omega: [ExprId; 3],
    /// r, body axes, constant.
    pub offset: [ExprId; 3],
    /// The frame's orientation R (body → world), turned into the frame of J.
    pub turn: [[ExprId; 3]; 3],
    /// The same frame as its elementary rotations, when it is one.
    pub frame: Option<Frame>,
}

/// The product T of a rotation's trailing constant factors.
pub type Tail = [[ExprId; 3]; 3];

/// A body frame as the product of elementary rotations R_k(θ), from which
/// its orientation R, ω_b and α_b follow step by step (DESIGN §10):
/// ω' = R_kᵀ ω + θ̇ e_k, α' = R_kᵀ α + (R_kᵀ ω) × θ̇ e_k + θ̈ e_k.
#[derive(Clone)]
pub struct Frame {
    /// The steps, left to right.
    pub steps: Vec<FrameStep>,
    /// Whether the first step is the heading R_z(ψ) that the frame of the
    /// bodies' J turns back (R = the product of the others there).
    pub heading_out: bool,
}

/// One elementary rotation of a [`Frame`].
#[derive(Clone)]
pub struct FrameStep {
    /// k.
    pub axis: usize,
    /// R_k(θ).
    pub turn: [[ExprId; 3]; 3],
    /// θ̇.
    pub rate: ExprId,
    /// ∂θ̇/∂q̇, 1 × n.
    pub rate_jacobian: Vec<ExprId>,
}
