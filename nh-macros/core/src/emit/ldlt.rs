//! Symmetric linear systems solved in the graph by an LDLᵀ factorisation, so
//! that structural zeros of the matrix cost no operations: the graph's entry
//! points to [`crate::algebra::ldlt`], with the product L·D kept
//! ([`Updates::Kept`]: one multiplication per update).

use super::{Dag, Node};
use crate::algebra::ldlt::{self, Updates};

/// An LDLᵀ factorisation held as graph nodes.
pub type Ldlt = ldlt::Ldlt<Node>;

impl Dag {
    /// Solves the symmetric system `m x = f` by an LDLᵀ factorisation without
    /// pivoting, built in the graph so structural zeros cost nothing. Returns
    /// x and the pivots D (for singularity checks: a constant-zero pivot means
    /// the matrix is structurally singular).
    pub fn solve_symmetric(&mut self, m: &[Vec<Node>], f: &[Node]) -> (Vec<Node>, Vec<Node>) {
        ldlt::solve_symmetric(self, m, f, Updates::Kept)
    }

    /// The LDLᵀ factorisation of a symmetric matrix, in the graph.
    pub fn factor_symmetric(&mut self, m: &[Vec<Node>]) -> Ldlt {
        ldlt::factor(self, m, Updates::Kept)
    }

    /// Solves with a factorisation from [`Dag::factor_symmetric`] (one more
    /// right side costs only the substitutions).
    pub fn solve_factored(&mut self, fac: &Ldlt, f: &[Node]) -> Vec<Node> {
        ldlt::solve(self, fac, f)
    }
}
