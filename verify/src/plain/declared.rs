//! A declared momentum plainly (`momenta { .. }`, DESIGN §4.1): J =
//! ⟨∂L/∂q̇, X(q)⟩ and its rate as the total derivative along the plain
//! motion, dJ/dt = Σ_i (d/dt ∂L/∂q̇_i) X_i + ∂L/∂q̇_i Ẋ_i, with d/dt taken
//! by moving (q, q̇, t) along (q̇, q̈, 1): the accelerations of the
//! Lagrange–d'Alembert solve, not the momentum equation the engine uses.

use super::{At, Motion, Plain, Point, Scalar};
use crate::jet::{Eps, Jet};
use crate::model::Ex;

impl<S: Scalar> Plain<'_, S> {
    /// (J, dJ/dt) along the direction `x` (one expression per coordinate)
    /// at the state `p` of the motion `m` (solved in coordinates).
    pub fn declared_momentum(&self, p: &Point<S>, m: &Motion<S>, x: &[Ex]) -> (S, S) {
        let along = |seed: Option<usize>| {
            let moving = |v: S, d: S| Jet::constant(v).plus_eps(Eps::Two, &Jet::constant(d));
            let mut qd: Vec<Jet<S>> = (0..self.n).map(|j| moving(m.qdot[j], m.qdd[j])).collect();
            if let Some(i) = seed {
                qd[i] = qd[i].plus_eps(Eps::One, &Jet::constant(S::one()));
            }
            At {
                q: (0..self.n).map(|j| moving(p.q[j], m.qdot[j])).collect(),
                qd,
                u: Vec::new(),
                t: moving(p.t, S::one()),
            }
        };
        let still = along(None);
        let (mut j, mut rate) = (S::zero(), S::zero());
        for (i, xi) in x.iter().enumerate() {
            let l = self.lagrangian(&along(Some(i)));
            let xi = self.eval.ex(xi, &still);
            j = j + l.part(1) * xi.value();
            rate = rate + l.part(3) * xi.value() + l.part(1) * xi.part(2);
        }
        (j, rate)
    }
}
