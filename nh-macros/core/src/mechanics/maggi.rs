//! Maggi's equations for a system in generalized speeds (DESIGN §9): with
//! q̇ = S(q, t) u + σ(q, t) and the Euler–Lagrange terms
//! E = M q̈ + h (3.9), forces included in h, the motion satisfies
//! Sᵀ E = 0 with q̈ = S u̇ + a, a = Ṡ u + σ̇ (total time derivatives along
//! the motion at fixed u), so that
//!
//! (Sᵀ M S) u̇ = −Sᵀ (h + M a),
//!
//! everything evaluated at q̇ = S u + σ. The reduced system has the shape of
//! the curvature route's (a k × k symmetric matrix and a right side), so the
//! generation solves it, differentiates it and checks it the same way.

use super::multipliers::MultiplierRoute;
use super::reduced::Reduced;
use super::scene::Scene;
use crate::sym::{ExprId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// The pieces of Maggi's equations beyond the reduced system, for the
/// reaction forces.
pub struct MaggiTerms {
    /// M at q̇ = S u + σ, n × n.
    pub mass: Vec<Vec<ExprId>>,
    /// h at q̇ = S u + σ.
    pub bias: Vec<ExprId>,
    /// S = ∂q̇/∂u, n × k.
    pub s: Vec<Vec<ExprId>>,
    /// a = Ṡ u + σ̇: the part of q̇'s time derivative at fixed u.
    pub acc_bias: Vec<ExprId>,
}

impl Scene<'_> {
    /// Maggi's equations of a system in generalized speeds: the multiplier
    /// route's M and h, the reduced system (Sᵀ M S) u̇ = −Sᵀ (h + M a) and
    /// the terms of the reaction forces.
    pub fn maggi_equations(&mut self) -> (MultiplierRoute, Reduced, MaggiTerms) {
        let (multiplier_route, _) = self.multiplier_route();
        let (n, k) = (self.model.n(), self.model.k());
        let map = self.constrained_velocities();
        let w = self.constrained_qdot();
        let speeds = self.model.independent_velocities();
        let positions: Vec<_> = self.model.positions().collect();
        let time = self.model.time;
        let e = &mut *self.engine;
        let mut memo = HashMap::default();
        let mass: Vec<Vec<ExprId>> = multiplier_route
            .mass
            .iter()
            .map(|row| row.iter().map(|&x| e.subst(x, &map, &mut memo)).collect())
            .collect();
        let bias: Vec<ExprId> = multiplier_route
            .bias
            .iter()
            .map(|&x| e.subst(x, &map, &mut memo))
            .collect();
        let s: Vec<Vec<ExprId>> = w
            .iter()
            .map(|&wi| speeds.iter().map(|&u| e.diff(wi, u)).collect())
            .collect();
        let acc_bias: Vec<ExprId> = w
            .iter()
            .map(|&wi| {
                let mut parts = vec![e.diff(wi, time)];
                for (j, &q) in positions.iter().enumerate() {
                    let d = e.diff(wi, q);
                    if d != ZERO {
                        parts.push(e.mul(d, w[j]));
                    }
                }
                e.sum(&parts)
            })
            .collect();
        // M S and h + M a
        let ms: Vec<Vec<ExprId>> = (0..n)
            .map(|i| {
                (0..k)
                    .map(|b| {
                        let parts: Vec<ExprId> =
                            (0..n).map(|j| e.mul(mass[i][j], s[j][b])).collect();
                        e.sum(&parts)
                    })
                    .collect()
            })
            .collect();
        let g: Vec<ExprId> = (0..n)
            .map(|i| {
                let mut parts = vec![bias[i]];
                parts.extend((0..n).map(|j| e.mul(mass[i][j], acc_bias[j])));
                e.sum(&parts)
            })
            .collect();
        let mut reduced = vec![vec![ZERO; k]; k];
        for a in 0..k {
            for b in a..k {
                let parts: Vec<ExprId> = (0..n).map(|i| e.mul(s[i][a], ms[i][b])).collect();
                let x = e.sum(&parts);
                reduced[a][b] = x;
                reduced[b][a] = x;
            }
        }
        let rhs: Vec<ExprId> = (0..k)
            .map(|a| {
                let parts: Vec<ExprId> = (0..n).map(|i| e.mul(s[i][a], g[i])).collect();
                let x = e.sum(&parts);
                e.neg(x)
            })
            .collect();
        let reduced = Reduced {
            mass: reduced,
            rhs,
            solution: None,
        };
        let terms = MaggiTerms {
            mass,
            bias,
            s,
            acc_bias,
        };
        (multiplier_route, reduced, terms)
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use crate::testing::{SLED_SPEEDS, close, lowered, value};

    /// The sled in speeds (ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω): Maggi's
    /// equations are m v̇ = 0, J ω̇ = 0, with S = ∂q̇/∂u.
    #[test]
    fn the_sled_in_speeds_has_maggis_diagonal_equations() {
        let (model, mut engine) = lowered(SLED_SPEEDS);
        let mut scene = Scene::new(&model, &mut engine);
        let (_, reduced, terms) = scene.maggi_equations();
        let at = [
            ("theta", 0.3),
            ("v", 0.7),
            ("omega", -1.1),
            ("m", 2.0),
            ("J", 0.5),
        ];
        let v = |e| value(&model, scene.engine, e, &at);
        let mass = [[2.0, 0.0], [0.0, 0.5]];
        for (row, want) in reduced.mass.iter().zip(mass) {
            for (&e, w) in row.iter().zip(want) {
                assert!(close(v(e), w));
            }
        }
        assert!(reduced.rhs.iter().all(|&f| close(v(f), 0.0)));
        assert!(close(v(terms.s[0][0]), 0.3f64.cos()));
        assert!(close(v(terms.s[2][0]), 0.3f64.sin()));
        assert_eq!(v(terms.s[1][1]), 1.0);
    }
}
