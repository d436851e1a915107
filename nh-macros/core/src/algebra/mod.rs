//! The linear algebra of the derivation, written once over a [`Carrier`]
//! of values: the symbolic engine ([`Engine`], values [`ExprId`]: canonical
//! forms) and the code graph ([`Dag`], values [`Node`]: the straight-line
//! code emitted). [`vector`] holds the products of 3-vectors and 3 × 3
//! matrices, [`ldlt`] the symmetric solves, [`lu`] elimination with pivots
//! given or chosen as it goes, Laplace determinants and Cramer's rule.
//!
//! Which carrier a quantity is built on follows from what is done with it
//! next: what is differentiated, tested for zero or simplified by exact
//! cancellation is derived symbolically; what is only evaluated is built on
//! the graph, which shares every subexpression and prunes structural zeros
//! where expanded forms would swell.
//!
//! * Symbolically (the engine, DESIGN §4, §9, §10): the Lagrangian's
//!   derivatives, M = ∂²L/∂q̇² and the Euler–Lagrange terms, when an output
//!   or the route needs them; the block of implicit and holonomic rows solved
//!   for A and β (`lower/linear.rs`: Cramer up to three rows, else
//!   elimination with Markowitz pivots and the right sides carried along),
//!   its determinant (the singularity test, `chart_regularity`) and the
//!   Newton step of `project`; the curvature B, whose zero test decides
//!   integrability; the curvature route's reduced mass matrix and right side
//!   (5.12)–(5.20), and their LDLᵀ solve when k ≤ 3, the entries are small
//!   and it is cheaper (a pivot cos² ψ/4 or a factor m R² cancels); the
//!   derivatives of the reduced system's entries (or of a closed-form r̈)
//!   for `jacobian` and `linearization`; the values, vectors, rotations, ω
//!   and kinetic energies the user writes. A canonical zero is exact, so the
//!   zeros found here are structural zeros of the graph.
//! * On the graph (DESIGN §9, §10): the accelerations' solves (the LDLᵀ of
//!   Cᵀ M C, or of the reduced mass matrix, unrolled with the structural
//!   zeros pruned, and reused for the Jacobian's columns; its pivots give
//!   `chart_regularity` in speeds); Kane's sums body by body; the rates along
//!   the motion (J̇ q̇, Ẇ q̇ by forward differentiation of the nodes); the
//!   frames' ω and α step by step, chains of rates and screws with their
//!   cross products; and a block of more than three homogeneous,
//!   time-independent implicit or holonomic rows, solved by LU with the
//!   pivots chosen at expansion (`generate/contacts.rs`): differentiating the
//!   symbolic elimination's quotients swells, and a contact's expanded rows
//!   carry 1/|e_z × n| into every term.
//!
//! The order of the operations of every function here is part of its
//! contract: the engine interns in call order (and its sums are ordered by
//! the ids of their monomials), the graph emits in call order, so the
//! generated code depends on it. Where the two carriers' algorithms differ,
//! the difference is a parameter of the one function ([`Carrier::plus`] for
//! sums, [`ldlt::Updates`], [`lu::Order`], the pivot rule of [`lu::factor`]),
//! never a second copy.

pub mod ldlt;
pub mod lu;
pub mod vector;

#[cfg(test)]
mod tests;

pub use vector::dot_from;
pub use vector::{
    Mat3, Vec3, add3, cross, cross_component, dot, dot3, mat_mat, mat_t_vec, mat_vec, scale3, sub3,
    transpose,
};

use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::sym::{Engine, ExprId, ONE, Rational, ZERO};

/// The arithmetic the algebra needs from a carrier of values.
pub trait Carrier {
    /// A value: an expression of the engine, a node of the graph.
    type Value: Copy + Eq + std::fmt::Debug;
    /// A sum being formed (see [`Carrier::plus`]).
    type Sum;
    /// 0 (every zero the carrier finds is this value).
    const ZERO: Self::Value;
    /// 1.
    const ONE: Self::Value;

    /// The integer `n`.
    fn int(&mut self, n: i128) -> Self::Value;
    /// a + b.
    fn add(&mut self, a: Self::Value, b: Self::Value) -> Self::Value;
    /// a − b.
    fn sub(&mut self, a: Self::Value, b: Self::Value) -> Self::Value;
    /// a · b.
    fn mul(&mut self, a: Self::Value, b: Self::Value) -> Self::Value;
    /// 1/a.
    fn recip(&mut self, a: Self::Value) -> Self::Value;

    /// Whether `a` is structurally zero.
    fn is_zero(&self, a: Self::Value) -> bool {
        a == Self::ZERO
    }

    /// An empty sum.
    fn begin_sum(&mut self) -> Self::Sum;
    /// Adds a term to a sum: the engine collects the terms and forms their
    /// canonical sum at once in [`Carrier::total`]; the graph adds each
    /// term as it comes, the code's additions in the order of the terms.
    fn plus(&mut self, s: &mut Self::Sum, x: Self::Value);
    /// Subtracts a term from a sum (the engine collects −x, the graph
    /// subtracts: a − x, not a + (−x)).
    fn minus(&mut self, s: &mut Self::Sum, x: Self::Value);
    /// The value of a sum.
    fn total(&mut self, s: Self::Sum) -> Self::Value;
}

impl Carrier for Engine {
    type Value = ExprId;
    type Sum = Vec<ExprId>;
    const ZERO: ExprId = ZERO;
    const ONE: ExprId = ONE;

    fn int(&mut self, n: i128) -> ExprId {
        Engine::int(self, n)
    }
    fn add(&mut self, a: ExprId, b: ExprId) -> ExprId {
        Engine::add(self, a, b)
    }
    fn sub(&mut self, a: ExprId, b: ExprId) -> ExprId {
        Engine::sub(self, a, b)
    }
    fn mul(&mut self, a: ExprId, b: ExprId) -> ExprId {
        Engine::mul(self, a, b)
    }
    /// a^−1 (not 1 · a^−1).
    fn recip(&mut self, a: ExprId) -> ExprId {
        Engine::pow(self, a, Rational::MINUS_ONE)
    }

    fn begin_sum(&mut self) -> Vec<ExprId> {
        Vec::new()
    }
    fn plus(&mut self, s: &mut Vec<ExprId>, x: ExprId) {
        s.push(x);
    }
    fn minus(&mut self, s: &mut Vec<ExprId>, x: ExprId) {
        let n = Engine::neg(self, x);
        s.push(n);
    }
    fn total(&mut self, s: Vec<ExprId>) -> ExprId {
        Engine::sum(self, &s)
    }
}

impl Carrier for Dag {
    type Value = Node;
    type Sum = Node;
    const ZERO: Node = ZERO_NODE;
    const ONE: Node = ONE_NODE;

    fn int(&mut self, n: i128) -> Node {
        Dag::constant(self, Rational::int(n))
    }
    fn add(&mut self, a: Node, b: Node) -> Node {
        Dag::add(self, a, b)
    }
    fn sub(&mut self, a: Node, b: Node) -> Node {
        Dag::sub(self, a, b)
    }
    fn mul(&mut self, a: Node, b: Node) -> Node {
        Dag::mul(self, a, b)
    }
    /// 1/a as a division (folded: a constant's reciprocal is a constant).
    fn recip(&mut self, a: Node) -> Node {
        Dag::div(self, ONE_NODE, a)
    }

    fn begin_sum(&mut self) -> Node {
        ZERO_NODE
    }
    fn plus(&mut self, s: &mut Node, x: Node) {
        *s = Dag::add(self, *s, x);
    }
    fn minus(&mut self, s: &mut Node, x: Node) {
        *s = Dag::sub(self, *s, x);
    }
    fn total(&mut self, s: Node) -> Node {
        s
    }
}
