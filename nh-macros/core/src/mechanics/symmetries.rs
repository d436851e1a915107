//! Declared symmetries and the nonholonomic momentum equation (DESIGN
//! §4.1; Bloch, Krishnaprasad, Marsden and Murray 1996): a one-parameter
//! group given by its generator ξ_Q (`symmetries { turn(x: -y, y: x, phi:
//! 1); }`) is a symmetry when the Lagrangian, the forces and the
//! constraint distribution are invariant under its flow. The momentum
//! along a direction the constraints allow, ξ(q) = Σ_i c_i(q) ξ_i with
//! ξ(q)_Q in the distribution, is J = ⟨∂L/∂q̇, ξ(q)_Q⟩, and along the motion
//! dJ/dt = ⟨∂L/∂q̇, Σ_i ċ_i ξ_i⟩ + ⟨Q, ξ(q)_Q⟩ (the constraint forces do no
//! work along ξ(q)_Q, and the invariance of L removes the rest).

use super::momenta::Verdict;
use super::scene::Scene;
use crate::algebra::lu;
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// What a declared symmetry does not leave invariant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Broken {
    /// The Lagrangian.
    Lagrangian,
    /// The force on this coordinate (the force as a 1-form).
    Force(usize),
    /// The constraint distribution, at this row of `Model::constraints`.
    Constraint(usize),
}

/// A momentum along a direction the constraints allow.
pub struct SymmetryMomentum {
    /// The direction's coefficients c_i(q), one per declared symmetry
    /// (none for a declared momentum, whose direction is written out).
    pub coefficients: Vec<ExprId>,
    /// J = ⟨∂L/∂q̇, ξ(q)_Q⟩ at the constrained velocities.
    pub momentum: ExprId,
    /// dJ/dt along the motion.
    pub rate: ExprId,
    /// The verdict on the rate.
    pub verdict: Verdict,
}

impl Scene<'_> {
    /// The time derivative along the motion, Σ_k ∂e/∂q_k q̇_k, of an
    /// expression `e` of the coordinates (q̇ as symbols).
    pub(super) fn along(&mut self, e: ExprId) -> ExprId {
        let mut parts = Vec::new();
        for c in &self.model.coordinates {
            let d = self.engine.diff(e, c.position);
            if d != ZERO {
                let v = self.engine.sym(c.velocity);
                parts.push(self.engine.mul(d, v));
            }
        }
        self.engine.sum(&parts)
    }

    /// Whether `e` vanishes: in canonical form, or at 16 random points.
    pub(super) fn vanishes(&self, e: ExprId) -> bool {
        e == ZERO || vanish_at_random_points(self.engine, self.model.pi, &[e])
    }

    /// What the declared symmetry `i` does not leave invariant, if
    /// anything: δL = ⟨∂L/∂q, ξ⟩ + ⟨∂L/∂q̇, ξ̇⟩; the Lie derivative of each
    /// force 1-form, (£_ξ Q)_j = ξ·∂Q_j/∂q + ξ̇·∂Q_j/∂q̇ + Q·∂ξ/∂q_j; and
    /// the Lie derivative of each constraint row ω^a on the constrained
    /// velocities, (£_ξ ω^a)(q̇) = Σ_j (ξ·∂ω^a_j/∂q + ω^a·∂ξ/∂q_j) q̇_j.
    pub fn broken(&mut self, i: usize) -> Option<Broken> {
        let xi = self.model.symmetries[i].generator.clone();
        let xidot: Vec<ExprId> = xi.iter().map(|&x| self.along(x)).collect();
        let q = &self.model.coordinates;
        let l = self.lagrangian();
        let dl = self.lie_derivative(l, &xi, &xidot);
        if !self.vanishes(dl) {
            return Some(Broken::Lagrangian);
        }
        for j in 0..q.len() {
            let force: Vec<ExprId> = q.iter().map(|c| c.force).collect();
            if force.iter().all(|&f| f == ZERO) {
                break;
            }
            let mut parts = vec![self.lie_derivative(force[j], &xi, &xidot)];
            for (k, &fk) in force.iter().enumerate() {
                let d = self.engine.diff(xi[k], q[j].position);
                parts.push(self.engine.mul(fk, d));
            }
            let lie = self.engine.sum(&parts);
            if !self.vanishes(lie) {
                return Some(Broken::Force(j));
            }
        }
        let map = self.constrained_velocities();
        let mut memo = HashMap::default();
        for a in 0..self.model.constraints.len() {
            let omega = self.row(a);
            let mut parts = Vec::new();
            for j in 0..q.len() {
                let mut comp = vec![self.lie_derivative(omega[j], &xi, &[])];
                for (k, &wk) in omega.iter().enumerate() {
                    let d = self.engine.diff(xi[k], q[j].position);
                    comp.push(self.engine.mul(wk, d));
                }
                let comp = self.engine.sum(&comp);
                let v = self.engine.sym(q[j].velocity);
                parts.push(self.engine.mul(comp, v));
            }
            let lie = self.engine.sum(&parts);
            let lie = self.engine.subst(lie, &map, &mut memo);
            if !self.vanishes(lie) {
                return Some(Broken::Constraint(a));
            }
        }
        None
    }

    /// ξ·∂e/∂q + ξ̇·∂e/∂q̇ (no velocity part when `xidot` is empty).
    pub(super) fn lie_derivative(&mut self, e: ExprId, xi: &[ExprId], xidot: &[ExprId]) -> ExprId {
        let q = &self.model.coordinates;
        let mut parts = Vec::new();
        for (k, c) in q.iter().enumerate() {
            if xi[k] != ZERO {
                let d = self.engine.diff(e, c.position);
                parts.push(self.engine.mul(xi[k], d));
            }
            if let Some(&xd) = xidot.get(k)
                && xd != ZERO
            {
                let d = self.engine.diff(e, c.velocity);
                parts.push(self.engine.mul(xd, d));
            }
        }
        self.engine.sum(&parts)
    }

    /// The constraint row ω^a in coordinate order: 1 at s_a, A^a_α at r_α
    /// (ṡ_a + Σ_α A^a_α ṙ_α = 0).
    pub(super) fn row(&mut self, a: usize) -> Vec<ExprId> {
        let m = self.model;
        let mut omega = vec![ZERO; m.n()];
        let c = &m.constraints[a];
        omega[c.dependent] = self.engine.int(1);
        for (al, &i) in m.independent().iter().enumerate() {
            omega[i] = c.coefficients[al];
        }
        omega
    }

    /// The momenta along the directions the constraints allow: a basis
    /// c(q) of the null space of K_{ai} = ω^a(ξ_i), chosen by the pivots of
    /// K at a random point (the free columns; the pivot columns by Cramer's
    /// rule, scaled by the pivot block's determinant so that c has no
    /// denominator), each with its momentum, rate and verdict.
    pub fn symmetry_momenta(&mut self) -> Vec<SymmetryMomentum> {
        let g = self.model.symmetries.len();
        let p = self.model.constraints.len();
        let xis: Vec<Vec<ExprId>> = (self.model.symmetries.iter())
            .map(|s| s.generator.clone())
            .collect();
        let mut k = vec![vec![ZERO; g]; p];
        for (a, row) in k.iter_mut().enumerate() {
            let omega = self.row(a);
            for (i, xi) in xis.iter().enumerate() {
                let parts: Vec<ExprId> = (omega.iter().zip(xi))
                    .map(|(&w, &x)| self.engine.mul(w, x))
                    .collect();
                row[i] = self.engine.sum(&parts);
            }
        }
        let (rows, cols) = self.pivots(&k);
        let block: Vec<Vec<ExprId>> = (rows.iter())
            .map(|&a| cols.iter().map(|&i| k[a][i]).collect())
            .collect();
        let det = lu::laplace(&mut *self.engine, &block);
        let mut out = Vec::new();
        for f in (0..g).filter(|i| !cols.contains(i)) {
            let w: Vec<ExprId> = rows.iter().map(|&a| k[a][f]).collect();
            let one = self.engine.int(1);
            let solved = lu::cramer(&mut *self.engine, &block, &w, one);
            let mut c = vec![ZERO; g];
            c[f] = det;
            for (&i, &x) in cols.iter().zip(&solved) {
                c[i] = self.engine.neg(x);
            }
            out.push(self.momentum_along(c, &xis));
        }
        out
    }

    /// The pivot rows and columns of `k` at a random point: the columns
    /// from the last declared symmetry back, each a pivot when it has an
    /// entry above 1e-20 of the largest once the pivots before are
    /// eliminated (its row the largest such entry). The symmetries declared
    /// first are then the free ones: each momentum is along one of them,
    /// corrected by those declared after it as the constraints require.
    fn pivots(&self, k: &[Vec<ExprId>]) -> (Vec<usize>, Vec<usize>) {
        let mut rng = crate::sym::Rng::new(0x082E_FA98_EC4E_6C89);
        let vals = rng.point(self.engine.num_symbols(), self.model.pi);
        let value = |e| self.engine.eval_with_scale(e, &vals).0.to_f64();
        let mut m: Vec<Vec<f64>> = (k.iter())
            .map(|row| row.iter().map(|&e| value(e)).collect())
            .collect();
        let scale = m.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
        let g = k.first().map_or(0, Vec::len);
        let (mut rows, mut cols) = (Vec::new(), Vec::new());
        for i in (0..g).rev() {
            let free_rows = (0..m.len()).filter(|a| !rows.contains(a));
            let best = free_rows.max_by(|&a, &b| m[a][i].abs().total_cmp(&m[b][i].abs()));
            let Some(a) = best.filter(|&a| m[a][i].abs() > 1e-20 * scale) else {
                continue;
            };
            let pivot = m[a][i];
            for b in (0..m.len()).filter(|&b| b != a) {
                let f = m[b][i] / pivot;
                for j in 0..g {
                    m[b][j] -= f * m[a][j];
                }
            }
            rows.push(a);
            cols.push(i);
        }
        (rows, cols)
    }

    /// The momentum along ξ(q) = Σ_i c_i ξ_i, its rate and verdict.
    fn momentum_along(&mut self, c: Vec<ExprId>, xis: &[Vec<ExprId>]) -> SymmetryMomentum {
        let q = &self.model.coordinates;
        let n = q.len();
        let mut direction = vec![ZERO; n];
        let mut turning = vec![ZERO; n];
        for (i, xi) in xis.iter().enumerate() {
            let cdot = self.along(c[i]);
            for j in 0..n {
                let t = self.engine.mul(c[i], xi[j]);
                direction[j] = self.engine.add(direction[j], t);
                let t = self.engine.mul(cdot, xi[j]);
                turning[j] = self.engine.add(turning[j], t);
            }
        }
        let mut rate_parts = Vec::new();
        for (jdx, coord) in q.iter().enumerate() {
            let l = self.lagrangian();
            let p = self.engine.diff(l, coord.velocity);
            rate_parts.push(self.engine.mul(p, turning[jdx]));
        }
        let mut out = self.momentum_with(&direction, rate_parts);
        out.coefficients = c;
        out
    }

    /// J = ⟨∂L/∂q̇, X⟩ and its rate, `rate_parts` + ⟨Q, X⟩, at the
    /// constrained velocities, with the verdict on the rate.
    pub(super) fn momentum_with(
        &mut self,
        x: &[ExprId],
        mut rate_parts: Vec<ExprId>,
    ) -> SymmetryMomentum {
        let map = self.constrained_velocities();
        let mut j_parts = Vec::new();
        for (coord, &xj) in self.model.coordinates.iter().zip(x) {
            let l = self.lagrangian();
            let p = self.engine.diff(l, coord.velocity);
            j_parts.push(self.engine.mul(p, xj));
            rate_parts.push(self.engine.mul(coord.force, xj));
        }
        let mut memo = HashMap::default();
        let momentum = self.engine.sum(&j_parts);
        let momentum = self.engine.subst(momentum, &map, &mut memo);
        let rate = self.engine.sum(&rate_parts);
        let rate = self.engine.subst(rate, &map, &mut memo);
        let verdict = self.verdict(rate);
        SymmetryMomentum {
            coefficients: Vec::new(),
            momentum,
            rate,
            verdict,
        }
    }
}
