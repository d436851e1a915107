//! The one result shape of the formulations that reduce symbolically
//! (in the spirit of SymPy's `_Methods`): a k × k symmetric mass matrix and
//! a right side, M ẍ = f for the independent accelerations r̈ (the curvature
//! route, 5.20) or the speeds' rates u̇ (Maggi's equations). The multiplier
//! route returns the unreduced M and h of E = M q̈ + h instead: its
//! reduction Cᵀ M C is formed on the graph, where it does not swell.

use crate::sym::ExprId;

/// Reduced equations of motion M ẍ = f in closed form.
pub struct Reduced {
    /// The reduced mass matrix, k × k, symmetric: ∂²Lc/∂ṙ_α∂ṙ_β for the
    /// curvature route, Sᵀ M S for Maggi's equations.
    pub mass: Vec<Vec<ExprId>>,
    /// The right side f: from (5.20) with the forces projected, or
    /// −Sᵀ (h + M a).
    pub rhs: Vec<ExprId>,
    /// ẍ solved symbolically, when that is cheaper than solving numerically.
    pub solution: Option<Vec<ExprId>>,
}
