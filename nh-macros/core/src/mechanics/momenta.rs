//! What is conserved (§5.5, `outputs { momenta }`): the cyclic
//! coordinates, the momenta p_k = ∂Lc/∂ṙ_k conjugate to them (5.35), the
//! rates (5.36) the constraints give them, and a verdict on each.

use super::scene::Scene;
use crate::sym::{ExprId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// Whether a momentum is conserved.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// Its rate is identically zero: the engine's canonical form is 0.
    Conserved,
    /// Its rate is `rate` at the point `at`, the values of every symbol
    /// (indexed by symbol) at which it was found nonzero.
    NotConserved {
        /// The point.
        at: Vec<f64>,
        /// The rate there.
        rate: f64,
    },
    /// Its rate vanishes at every sampled point, but the engine did not
    /// reduce it to zero.
    Undecided,
}

/// The momenta conjugate to the cyclic coordinates and their rates.
pub struct Momenta {
    /// The cyclic coordinates: positions α in the independent coordinates,
    /// and whether each is cyclic in the strict sense of §5.5
    /// ([`Scene::cyclic`]).
    pub cyclic: Vec<(usize, bool)>,
    /// p_α = ∂Lc/∂ṙ_α (5.35), per cyclic coordinate.
    pub momenta: Vec<ExprId>,
    /// ṗ_α of (5.36) with the projected forces, per cyclic coordinate.
    pub rates: Vec<ExprId>,
    /// The verdict on each.
    pub verdicts: Vec<Verdict>,
}

impl Scene<'_> {
    /// The independent coordinates r_α (positions in
    /// [`crate::model::Model::independent`]) that are cyclic: the
    /// constrained Lagrangian Lc (5.12) and every generalized force at the
    /// constrained velocities are free of r_α, so that p_α = ∂Lc/∂ṙ_α is
    /// the momentum a holonomic system would conserve. With each, whether
    /// it is cyclic in the strict sense of §5.5 as well: the Lagrangian,
    /// every force and every constraint (its solved row ṡ_a, which holds
    /// the row A^a of the constraint matrix, and a holonomic constraint's f)
    /// free of r_α. The thesis's disc has both kinds: its rolling angle θ
    /// is strictly cyclic, its heading φ only in Lc (ẋ = R cos φ θ̇).
    pub fn cyclic(&mut self) -> Vec<(usize, bool)> {
        let map = self.constrained_velocities();
        let l = self.lagrangian();
        let m = self.model;
        let mut memo = HashMap::default();
        let mut constrained = vec![self.engine.subst(l, &map, &mut memo)];
        for c in &m.coordinates {
            constrained.push(self.engine.subst(c.force, &map, &mut memo));
        }
        let mut written = vec![l];
        written.extend(m.coordinates.iter().map(|c| c.force));
        for c in &m.constraints {
            written.push(c.velocity);
            written.extend(c.coefficients.iter().copied());
            written.extend(c.holonomic);
        }
        let free = |exprs: &[ExprId], r| exprs.iter().all(|&e| !self.engine.depends_on(e, r));
        (0..m.k())
            .filter_map(|al| {
                let r = m.coordinates[m.independent()[al]].position;
                free(&constrained, r).then(|| (al, free(&written, r)))
            })
            .collect()
    }

    /// The momenta of the cyclic coordinates `cyclic`, their rates by
    /// (5.36) with the projected forces — ṗ_α = ∂Lc/∂r_α + Q_α − Σ_b Σ_β
    /// B^b_{αβ} ṙ_β ∂L/∂ṡ_b − Σ_a A^a_α (∂Lc/∂s_a + Q_{s_a}), at the
    /// constrained velocities —
    /// and the verdicts. For homogeneous, time-independent constraints.
    pub fn momenta(&mut self, cyclic: Vec<(usize, bool)>) -> Momenta {
        let map = self.constrained_velocities();
        let l = self.lagrangian();
        let q = &self.model.coordinates;
        let r_vel = self.model.independent_velocities();
        let mut memo = HashMap::default();
        let lc = self.engine.subst(l, &map, &mut memo); // (5.12)
        // ∂L/∂ṡ_b at the constrained velocities
        let p_dep: Vec<ExprId> = (self.model.constraints.iter())
            .map(|c| {
                let d = self.engine.diff(l, q[c.dependent].velocity);
                self.engine.subst(d, &map, &mut memo)
            })
            .collect();
        let (mut momenta, mut rates) = (Vec::new(), Vec::new());
        for &(al, _) in &cyclic {
            momenta.push(self.engine.diff(lc, r_vel[al]));
            let rate = self.momentum_rate(al, lc, &p_dep);
            let rate = self.engine.subst(rate, &map, &mut memo);
            rates.push(rate);
        }
        let verdicts = rates.iter().map(|&r| self.verdict(r)).collect();
        Momenta {
            cyclic,
            momenta,
            rates,
            verdicts,
        }
    }

    /// ṗ_α of (5.36) with the projected forces, before the constrained
    /// velocities are substituted into the forces.
    fn momentum_rate(&mut self, al: usize, lc: ExprId, p_dep: &[ExprId]) -> ExprId {
        let m = self.model;
        let q = &m.coordinates;
        let r = q[m.independent()[al]].position;
        let r_vel = m.independent_velocities();
        let mut parts = vec![self.engine.diff(lc, r), q[m.independent()[al]].force];
        for (b, &pb) in p_dep.iter().enumerate() {
            for (be, &v) in r_vel.iter().enumerate() {
                let bab = match al.cmp(&be) {
                    std::cmp::Ordering::Less => self.curvature_entry(b, al, be),
                    std::cmp::Ordering::Greater => {
                        let x = self.curvature_entry(b, be, al);
                        self.engine.neg(x)
                    }
                    std::cmp::Ordering::Equal => ZERO,
                };
                if bab != ZERO {
                    let e = &mut *self.engine;
                    let vs = e.sym(v);
                    let t = e.mul(bab, vs);
                    let t = e.mul(t, pb);
                    parts.push(e.neg(t));
                }
            }
        }
        for c in &m.constraints {
            let s = &q[c.dependent];
            let e = &mut *self.engine;
            let d = e.diff(lc, s.position);
            let generalized = e.add(d, s.force);
            let t = e.mul(c.coefficients[al], generalized);
            parts.push(e.neg(t));
        }
        self.engine.sum(&parts)
    }

    /// The verdict on a rate: zero in canonical form, or the first of 16
    /// random points (double-double, as [`crate::sym::vanish_at_random_points`])
    /// where it exceeds 1e-24 of the sum of its terms' sizes.
    pub(super) fn verdict(&self, rate: ExprId) -> Verdict {
        if rate == ZERO {
            return Verdict::Conserved;
        }
        let mut rng = crate::sym::Rng::new(0x13198A2E_03707344);
        let mut points = 0;
        for _ in 0..64 {
            if points == 16 {
                break;
            }
            let vals = rng.point(self.engine.num_symbols(), self.model.pi);
            let (v, scale) = self.engine.eval_with_scale(rate, &vals);
            if !v.is_finite() || !scale.is_finite() {
                continue;
            }
            points += 1;
            if v.abs().to_f64() > 1e-24 * scale.to_f64() {
                let at = vals.iter().map(|v| v.to_f64()).collect();
                let rate = v.to_f64();
                return Verdict::NotConserved { at, rate };
            }
        }
        Verdict::Undecided
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use super::Verdict;
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled's x is strictly cyclic; p_x = m ẋ sec²θ and, by (5.36),
    /// ṗ_x = −B^y_{xθ} θ̇ ∂L/∂ẏ = m ẋ sec²θ tan θ θ̇ (B^y_{xθ} = −sec²θ):
    /// not conserved.
    #[test]
    fn the_sleds_momentum_and_its_rate() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let cyclic = scene.cyclic();
        assert_eq!(cyclic, [(0, true)]);
        let momenta = scene.momenta(cyclic);
        let at = sled_at();
        let v = |e| value(&model, scene.engine, e, &at);
        let (m, th, xd, thd) = (2.0, 0.3f64, 0.7, -1.1);
        let sec2 = 1.0 / th.cos().powi(2);
        assert!(close(v(momenta.momenta[0]), m * xd * sec2));
        assert!(close(v(momenta.rates[0]), m * xd * sec2 * th.tan() * thd));
        assert!(matches!(momenta.verdicts[0], Verdict::NotConserved { .. }));
    }
}
