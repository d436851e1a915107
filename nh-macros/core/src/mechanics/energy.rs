//! The energy E = Σ q̇_i ∂L/∂q̇_i − L (`outputs { energy }`).

use super::scene::Scene;
use crate::sym::ExprId;

/// How many times the terms E may keep its substituted parts may count
/// before cancellation, before the substitution is abandoned.
const SUBSTITUTION_SLACK: usize = 4;

impl Scene<'_> {
    /// E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities: substituted,
    /// or in the full q̇ whose dependent velocities the emitted code binds
    /// to their solved values.
    pub fn energy(&mut self) -> ExprId {
        let map = self.constrained_velocities();
        let l = self.lagrangian();
        let e = &mut *self.engine;
        let mut parts = Vec::new();
        for v in self.model.coordinates.iter().map(|c| c.velocity) {
            let p = e.diff(l, v);
            let vs = e.sym(v);
            parts.push(e.mul(vs, p));
        }
        parts.push(e.neg(l));
        let en = e.sum(&parts);
        // Substituting the solved velocities pays when they simplify E (the
        // closed forms of small systems). When they are large (a block of
        // implicit rows), E stays in the full q̇: the emitted code binds each
        // velocity symbol to its solved value, computed once. The
        // substitution is abandoned once its terms before cancellation pass
        // SUBSTITUTION_SLACK times what E may keep.
        let solved: usize = map.values().map(|&v| e.num_terms(v)).sum();
        let keep = e.num_terms(en) + solved;
        match e.subst_within(en, &map, SUBSTITUTION_SLACK * keep) {
            Some(substituted) if e.num_terms(substituted) <= keep => substituted,
            _ => en,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled's energy is its kinetic energy m/2 (ẋ² + ẏ²) + J/2 θ̇².
    #[test]
    fn the_sleds_energy_is_its_kinetic_energy() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let e = scene.energy();
        let ydot = 0.3f64.tan() * 0.7;
        let want = 1.0 * (0.49 + ydot * ydot) + 0.25 * 1.21;
        assert!(close(value(&model, scene.engine, e, &sled_at()), want));
    }
}
