//! Declared momenta (`momenta { K_x(Q: [1, 0, 0], y: -R); }`, DESIGN
//! §4.1): the momentum J = ⟨∂L/∂q̇, X⟩ along a direction X(q) the
//! constraints allow, whether or not a symmetry's. The multipliers' forces
//! do no work along X ∈ D, so by Lagrange–d'Alembert dJ/dt = ⟨∂L/∂q, X⟩ +
//! ⟨∂L/∂q̇, Ẋ⟩ + ⟨Q, X⟩ with Ẋ = (∂X/∂q) q̇, with no accelerations.

use super::scene::Scene;
use super::symmetries::SymmetryMomentum;
use crate::sym::ExprId;

impl Scene<'_> {
    /// The first constraint row that the direction `x` leaves, ω^a(X) ≠ 0:
    /// a momentum's direction must be a motion the constraints allow.
    pub fn leaves_distribution(&mut self, x: &[ExprId]) -> Option<usize> {
        (0..self.model.constraints.len()).find(|&a| {
            let omega = self.row(a);
            let parts: Vec<ExprId> = (omega.iter().zip(x))
                .map(|(&w, &xj)| self.engine.mul(w, xj))
                .collect();
            let value = self.engine.sum(&parts);
            !self.vanishes(value)
        })
    }

    /// The declared momenta (`momenta { .. }`): along each direction X(q)
    /// in the distribution, J = ⟨∂L/∂q̇, X⟩ and, by Lagrange–d'Alembert
    /// (the constraint forces do no work along X), dJ/dt = ⟨∂L/∂q, X⟩ +
    /// ⟨∂L/∂q̇, Ẋ⟩ + ⟨Q, X⟩ with Ẋ = (∂X/∂q) q̇: the derivative of L along
    /// the motion's prolongation, zero when X's flow leaves L invariant.
    pub fn declared_momenta(&mut self) -> Vec<SymmetryMomentum> {
        let directions: Vec<Vec<ExprId>> = (self.model.momentum_directions.iter())
            .map(|d| d.generator.clone())
            .collect();
        directions
            .iter()
            .map(|x| {
                let xdot: Vec<ExprId> = x.iter().map(|&v| self.along(v)).collect();
                let l = self.lagrangian();
                let dl = self.lie_derivative(l, x, &xdot);
                self.momentum_with(x, vec![dl])
            })
            .collect()
    }
}
