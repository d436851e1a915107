//! Whether the constraints are integrable: every curvature entry B^b_{αβ}
//! identically zero, proved symbolically or seen at random points.

use super::scene::Scene;
use crate::sym::dd::Dd;
use crate::sym::dual::Dual;
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, ZERO};

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
    /// entry, stopping at the first that does not vanish. Every entry is
    /// first looked at numerically, at one random point after another (at
    /// most four): one seen not to vanish settles it without symbolic
    /// derivatives ([`CoefficientSample::entry_seen_nonzero`]); only when
    /// none is are the entries derived and tested symbolically.
    pub(crate) fn integrability_entry_by_entry(&mut self) -> (bool, bool) {
        let (k, p) = (self.model.k(), self.model.p());
        let entries: Vec<(usize, usize, usize)> = (0..p)
            .flat_map(|bb| (0..k).flat_map(move |al| ((al + 1)..k).map(move |be| (bb, al, be))))
            .collect();
        let mut rng = crate::sym::Rng::new(0x1319_8A2E_0370_7344);
        for _ in 0..if entries.is_empty() { 0 } else { 4 } {
            let sample = CoefficientSample::new(self, &mut rng);
            if entries
                .iter()
                .any(|&(bb, al, be)| sample.entry_seen_nonzero(bb, al, be))
            {
                return (false, false);
            }
        }
        let mut proved = true;
        for (bb, al, be) in entries {
            let v = self.curvature_entry(bb, al, be);
            if v == ZERO {
                continue;
            }
            if !vanish_at_random_points(self.engine, self.model.pi, &[v]) {
                return (false, false);
            }
            proved = false;
        }
        (true, proved)
    }
}

/// The constraint coefficients A^a_x and their derivatives ∂A^a_x/∂q_j at
/// a random point, in double-double arithmetic (forward differentiation,
/// no symbolic derivative): what the numeric test of the curvature entries
/// (5.21) reads, evaluated once for all of them.
struct CoefficientSample {
    /// `[a][x]`: A^a_x.
    values: Vec<Vec<Dd>>,
    /// `[j][a][x]`: ∂A^a_x/∂q_j, j a coordinate's index.
    slopes: Vec<Vec<Vec<Dd>>>,
    /// The indices of the independent coordinates, and of each
    /// constraint's dependent one.
    independent: Vec<usize>,
    dependent: Vec<usize>,
}

impl CoefficientSample {
    fn new(scene: &Scene<'_>, rng: &mut crate::sym::Rng) -> CoefficientSample {
        let (model, e) = (scene.model, &scene.engine);
        let coefficients: Vec<&[ExprId]> = model
            .constraints
            .iter()
            .map(|c| &c.coefficients[..])
            .collect();
        let point = rng.point(e.num_symbols(), model.pi);
        let mut memo = crate::sym::EvalMemo::default();
        let mut at = |x: ExprId| e.eval_memo(x, &point, &mut memo);
        let values = coefficients
            .iter()
            .map(|row| row.iter().map(|&x| at(x)).collect())
            .collect();
        let slopes = model.coordinates.iter().map(|c| {
            let mut vals: Vec<Dual> = point.iter().map(|&v| Dual::constant(v)).collect();
            vals[c.position.index()] = Dual::variable(point[c.position.index()]);
            let mut memo = crate::sym::EvalMemo::default();
            let mut at = |x: ExprId| e.eval_memo(x, &vals, &mut memo).derivative();
            coefficients
                .iter()
                .map(|row| row.iter().map(|&x| at(x)).collect())
                .collect()
        });
        CoefficientSample {
            values,
            slopes: slopes.collect(),
            independent: model.independent().to_vec(),
            dependent: model.constraints.iter().map(|c| c.dependent).collect(),
        }
    }

    /// Whether B^b_{αβ} of (5.21) is seen not to vanish at this point:
    /// exceeding 1e-20 of the sum of its parts' sizes, far above the
    /// rounding of 32 digits (an entry that does not is left to the
    /// symbolic test).
    fn entry_seen_nonzero(&self, bb: usize, al: usize, be: usize) -> bool {
        let (a, da) = (&self.values, &self.slopes);
        let (r_al, r_be) = (self.independent[al], self.independent[be]);
        let mut parts = vec![da[r_be][bb][al], Dd::ZERO - da[r_al][bb][be]];
        for (aa, &s) in self.dependent.iter().enumerate() {
            parts.push(a[aa][al] * da[s][bb][be]);
            parts.push(Dd::ZERO - a[aa][be] * da[s][bb][al]);
        }
        let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
        for &x in &parts {
            value = value + x;
            scale = scale + x.abs();
        }
        value.is_finite() && scale.is_finite() && value.abs().to_f64() > 1e-20 * scale.to_f64()
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
