//! Whether the constraints are integrable: every curvature entry B^b_{αβ}
//! identically zero, proved symbolically or seen at random points.

use super::scene::Scene;
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, SymId, ZERO};

impl Scene<'_> {
    /// Whether the constraints are integrable (all B^b_αβ ≡ 0), and whether that
    /// was proved symbolically. An entry whose canonical form is not zero is
    /// evaluated at 16 random points in double-double arithmetic (about 32
    /// digits): any point where it exceeds 1e-24 of the sum of its terms' sizes
    /// proves it nonzero; an entry below that at every point is taken as zero (an
    /// identity the canonical form does not know, such as an angle-addition
    /// formula). A genuinely nonholonomic system would have to cancel to 24
    /// digits at 16 random points to be called integrable.
    pub(crate) fn integrability(&self, curv: &[Vec<Vec<ExprId>>]) -> (bool, bool) {
        let entries: Vec<ExprId> = curv
            .iter()
            .flatten()
            .flatten()
            .copied()
            .filter(|&b| b != ZERO)
            .collect();
        if entries.is_empty() {
            return (true, true);
        }
        (
            vanish_at_random_points(self.engine, self.model.pi, &entries),
            false,
        )
    }

    /// [`Model::integrability`] without the whole curvature: entry by
    /// entry, stopping at the first that does not vanish. An entry seen not
    /// to vanish at a random point settles it without symbolic derivatives
    /// ([`Model::curvature_entry_seen_nonzero`]).
    pub(crate) fn integrability_entry_by_entry(&mut self) -> (bool, bool) {
        let (k, p) = (self.model.k(), self.model.p());
        let mut proved = true;
        for bb in 0..p {
            for al in 0..k {
                for be in (al + 1)..k {
                    if self.curvature_entry_seen_nonzero(bb, al, be) {
                        return (false, false);
                    }
                    let v = self.curvature_entry(bb, al, be);
                    if v == ZERO {
                        continue;
                    }
                    if !vanish_at_random_points(self.engine, self.model.pi, &[v]) {
                        return (false, false);
                    }
                    proved = false;
                }
            }
        }
        (true, proved)
    }

    /// Whether B^b_{αβ} of (5.21) is seen not to vanish at one of four
    /// random points, its derivatives ∂A/∂q taken by forward
    /// differentiation in double-double arithmetic (no symbolic
    /// derivative). Not vanishing means exceeding 1e-20 of the sum of its
    /// parts' sizes, far above the rounding of 32 digits; an entry that does
    /// not is left to the symbolic test.
    pub(crate) fn curvature_entry_seen_nonzero(&self, bb: usize, al: usize, be: usize) -> bool {
        use crate::sym::dd::Dd;
        use crate::sym::dual::Dual;
        let r = self.model.of_independent(|c| c.position);
        let (e, a) = (&self.engine, |aa: usize, x: usize| {
            self.model.constraints[aa].coefficients[x]
        });
        let mut rng = crate::sym::Rng::new(0x1319_8A2E_0370_7344);
        for _ in 0..4 {
            let point = rng.point(e.num_symbols(), self.model.pi);
            // ∂A^b_x/∂(seed) at the point
            let slope = |x: usize, seed: SymId| -> Dd {
                let mut vals: Vec<Dual> = point.iter().map(|&v| Dual::constant(v)).collect();
                vals[seed.index()] = Dual::variable(point[seed.index()]);
                e.eval(a(bb, x), &vals).derivative
            };
            let mut parts = vec![slope(al, r[be]), Dd::ZERO - slope(be, r[al])];
            for (aa, c) in self.model.constraints.iter().enumerate() {
                let s = self.model.coordinates[c.dependent].position;
                parts.push(e.eval(a(aa, al), &point) * slope(be, s));
                parts.push(Dd::ZERO - e.eval(a(aa, be), &point) * slope(al, s));
            }
            let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
            for &x in &parts {
                value = value + x;
                scale = scale + x.abs();
            }
            if value.is_finite()
                && scale.is_finite()
                && value.abs().to_f64() > 1e-20 * scale.to_f64()
            {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use crate::testing::{SLED, lowered};

    /// The sled's constraint is not integrable (a nonzero entry seen, so
    /// nothing to prove); ẏ = 2 ẋ is (y = 2x + c), proved symbolically,
    /// entry by entry as with the full curvature.
    #[test]
    fn the_sled_is_nonholonomic_and_a_line_is_not() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let b = scene.curvature();
        assert_eq!(scene.integrability(&b), (false, false));
        assert!(!scene.integrability_entry_by_entry().0);
        let line = "pub struct Line {
            parameters { m }
            coordinates { x, y }
            lagrangian = m/2*(dot(x)^2 + dot(y)^2);
            constraints { dot(y) = 2*dot(x); }
        }";
        let (model, mut engine) = lowered(line);
        let mut scene = Scene::new(&model, &mut engine);
        let b = scene.curvature();
        assert_eq!(scene.integrability(&b), (true, true));
        assert_eq!(scene.integrability_entry_by_entry(), (true, true));
    }
}
