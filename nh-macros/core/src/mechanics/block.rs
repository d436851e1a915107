//! The block of velocity rows of a system solved by elimination (DESIGN
//! §9): its rows, its contacts' terms and its pivots, as the generated code
//! solves it numerically.

use super::chains::{Chain, Frame};
use crate::sym::ExprId;

/// The block of velocity rows c_s ṡ + c_r ṙ = 0 of a system solved by
/// elimination, for solving it numerically in the generated code with the
/// pivots chosen here (DESIGN §9): its rows' coefficients and rates.
pub struct BlockTerms {
    /// The elimination's steps in order: (pivot row, column), column b
    /// the dependent velocity of constraint b.
    pub pivots: Vec<(usize, usize)>,
    /// The rows, in the order of [`Model::velocity_rows`].
    pub rows: Vec<RowTerms>,
    /// The contacts the rows refer to.
    pub contacts: Vec<ContactTerms>,
    /// ψ̇ when the contacts' vectors are in the heading's frame
    /// (`heading_frame`): a world rate ȧ is then R ȧ = (R a)˙ + ψ̇ e_z × R a.
    pub heading_rate: Option<ExprId>,
    /// A planar translation (x, y) among the dependent coordinates, solved
    /// for in the heading's frame (see [`Planar`]).
    pub planar: Option<Planar>,
}

/// Dependent coordinates x, y that translate every contact (∂G/∂x = e_x,
/// ∂G/∂y = e_y), with the rows in the heading's frame R_z(−ψ): their
/// columns there turn with ψ (static pivots would fail at some heading), so
/// the block is solved for u = R_z(−ψ)(ẋ, ẏ), whose columns are e_x and e_y
/// (DESIGN §9), and (ẋ, ẏ) = R_z(ψ) u.
#[derive(Clone, Copy)]
pub struct Planar {
    /// The constraints (block columns) of x and y.
    pub columns: [usize; 2],
    /// R_z(ψ) restricted to the plane, by rows.
    pub turn: [[ExprId; 2]; 2],
}

/// One velocity row g(q, q̇) = 0 of a [`BlockTerms`].
pub enum RowTerms {
    /// A row as written: ∂g/∂q̇_i for every coordinate, and Σ ∂g/∂q_i q̇_i.
    Written {
        /// ∂g/∂q̇_i.
        coefficients: Vec<ExprId>,
        /// Σ_i ∂g/∂q_i q̇_i.
        along: ExprId,
    },
    /// Component `component` of contact `contact`'s material velocity.
    Contact {
        /// Index into [`BlockTerms::contacts`].
        contact: usize,
        /// 0, 1, 2: x, y, z.
        component: usize,
    },
}

/// A contact's terms: v = J_G q̇ + (W q̇) × o, its rate at q̈ = 0
/// J̇_G q̇ + (Ẇ q̇) × o + ω × ȯ, with o = −r w − ρ e_z (DESIGN §10).
pub struct ContactTerms {
    /// J_G = ∂G/∂q, 3 × n.
    pub centre_jacobian: [Vec<ExprId>; 3],
    /// ω (world components).
    pub omega: [ExprId; 3],
    /// W = ∂ω/∂q̇, 3 × n.
    pub omega_jacobian: [Vec<ExprId>; 3],
    /// The chain its centre's acceleration follows, if any.
    pub chain: Option<Chain>,
    /// The world axle n and s = |e_z × n|, for a disc or torus.
    pub axle: Option<([ExprId; 3], ExprId)>,
    /// w = (e_z − n_z n)/s as an expression, when s has no root (a wheel
    /// upright in the reference configuration: s = √c cos u): the division
    /// then cancels, and ẇ is w's rate along the motion.
    pub rim: Option<[ExprId; 3]>,
    /// r.
    pub radius: ExprId,
    /// ρ.
    pub tube: ExprId,
    /// The body's frame as elementary rotations, when it is one.
    pub frame: Option<Frame>,
}
