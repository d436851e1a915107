//! The scene the stages after lowering work on: the model, immutable, with
//! the engine its expressions live in and the contacts' terms derived once;
//! and the questions every formulation asks of it (the velocities at the
//! constraints, rates along the motion, Jacobians).

use super::block::BlockTerms;
use super::chains::Chain;
use crate::ctxt::{Site, SpanRange};
use crate::model::Model;
use crate::sym::{Engine, ExprId, SymId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// A lowered model with the engine its expressions live in, and the
/// contacts' terms derived from it once: the working state of the stages
/// after lowering. The model is borrowed immutably (nothing after lowering
/// writes into it); the engine grows as quantities are derived.
pub struct Scene<'a> {
    /// The model, as lowering built it.
    pub model: &'a Model,
    /// The engine holding the model's expressions and everything derived.
    pub engine: &'a mut Engine,
    /// Per contact, the chain its centre's acceleration follows (see
    /// [`Chain`]).
    pub contact_chains: Vec<Option<Chain>>,
    /// The velocity rows' terms for solving their block numerically (see
    /// [`BlockTerms`]).
    pub block: Option<BlockTerms>,
    /// The values of the expressions already evaluated at the two states
    /// of the quick tests of fixed offsets ([`Scene::two_states`]), kept
    /// for the whole derivation: a chain's points share their subterms,
    /// which a fresh evaluation of each would visit again and again.
    pub(crate) samples: Option<Box<Samples>>,
    /// L expanded ([`Scene::lagrangian`]), once something asked for it.
    lagrangian: Option<ExprId>,
}

/// The two states of the quick tests of fixed offsets and of the weight
/// (`mechanics/composite.rs`) and the values found at them so far (see
/// [`Scene::samples`]).
pub(crate) struct Samples {
    pub(crate) states: [Vec<crate::sym::dd::Dd>; 2],
    pub(crate) memos: [crate::sym::EvalMemo<crate::sym::dd::Dd>; 2],
}

impl Scene<'_> {
    /// The substitution ṡ_a ↦ −Σ_α A^a_α ṙ_α of (5.11).
    /// For a system in generalized speeds, every q̇_i ↦ (S u + σ)_i.
    pub fn constrained_velocities(&self) -> HashMap<SymId, ExprId> {
        if let Some(sp) = &self.model.speeds {
            let velocities = self.model.coordinates.iter().map(|c| c.velocity);
            return velocities.zip(sp.velocities.iter().copied()).collect();
        }
        self.model
            .constraints
            .iter()
            .map(|c| (self.model.coordinates[c.dependent].velocity, c.velocity))
            .collect()
    }

    /// q̇ at the constrained velocities, per coordinate (S u + σ, for a
    /// system in generalized speeds).
    pub fn constrained_qdot(&mut self) -> Vec<ExprId> {
        if let Some(sp) = &self.model.speeds {
            return sp.velocities.clone();
        }
        let mut out = Vec::with_capacity(self.model.n());
        for i in 0..self.model.n() {
            match self.model.constraints.iter().find(|c| c.dependent == i) {
                Some(c) => out.push(c.velocity),
                None => out.push(self.engine.sym(self.model.coordinates[i].velocity)),
            }
        }
        out
    }

    /// Σ_i ∂x/∂q_i q̇_i: the rate of x along the motion, t held fixed.
    pub fn along_motion(&mut self, x: ExprId) -> ExprId {
        let e = &mut *self.engine;
        let mut parts = Vec::new();
        for c in &self.model.coordinates {
            let d = e.diff(x, c.position);
            if d != ZERO {
                let v = e.sym(c.velocity);
                parts.push(e.mul(d, v));
            }
        }
        e.sum(&parts)
    }

    /// ∂x/∂q_i for every coordinate.
    pub(crate) fn positional_jacobian(&mut self, x: ExprId) -> Vec<ExprId> {
        let e = &mut *self.engine;
        self.model
            .coordinates
            .iter()
            .map(|c| e.diff(x, c.position))
            .collect()
    }

    /// ∂x/∂q̇_i for every coordinate.
    pub(crate) fn velocity_jacobian(&mut self, x: ExprId) -> Vec<ExprId> {
        let e = &mut *self.engine;
        self.model
            .coordinates
            .iter()
            .map(|c| e.diff(x, c.velocity))
            .collect()
    }
}
impl std::ops::Deref for Scene<'_> {
    type Target = Model;
    fn deref(&self) -> &Model {
        self.model
    }
}

impl<'a> Scene<'a> {
    /// The scene of `model`, with its contacts' chains and block derived
    /// (none for a system in generalized speeds, which has no constraints).
    pub fn new(model: &'a Model, engine: &'a mut Engine) -> Scene<'a> {
        let mut scene = Scene {
            model,
            engine,
            contact_chains: Vec::new(),
            block: None,
            samples: None,
            lagrangian: None,
        };
        if model.speeds.is_none() {
            let task = "deriving the rolling contacts' kinematics";
            scene.at(model.places.constraints, task, |m| {
                let frame = m.heading_frame();
                m.contact_chains = m.contact_chains(&frame);
                m.block = m.block_terms();
            });
        }
        scene
    }

    /// `work`, with the engine's site at `range` of the input, doing `task`
    /// (where an error for a limit exceeded in it points).
    pub fn at<T>(&mut self, range: SpanRange, task: &str, work: impl FnOnce(&mut Self) -> T) -> T {
        let outer = self.engine.enter(Site::new(range, task));
        let r = work(self);
        self.engine.leave(outer);
        r
    }

    /// Whether some dependent velocity depends on time explicitly.
    pub fn rheonomic(&self) -> bool {
        let m = self.model;
        m.constraints
            .iter()
            .any(|c| self.engine.depends_on(c.velocity, m.time))
    }

    /// The Lagrangian L(q, q̇, t), with the kinetic energies folded into
    /// symbols in [`Model::lagrangian_folded`] expanded (once, on the first
    /// call): for the outputs and routes that take L itself.
    pub fn lagrangian(&mut self) -> ExprId {
        if let Some(l) = self.lagrangian {
            return l;
        }
        let folded = self.model.kinetic.iter().flat_map(|k| &k.bodies);
        let folded: Vec<_> = folded.filter(|b| b.folded.is_some()).collect();
        let l = match folded.is_empty() {
            true => self.model.lagrangian_folded,
            false => {
                let state: Vec<(SymId, SymId)> = (self.model.coordinates.iter())
                    .map(|c| (c.position, c.velocity))
                    .collect();
                let t = self.model.time;
                let mut map = HashMap::default();
                for b in folded {
                    let energy = crate::lower::bodies::kinetic_energy(self.engine, (&state, t), b);
                    map.insert(b.folded.expect("folded"), energy.unwrap_or(ZERO));
                }
                let l = self.model.lagrangian_folded;
                self.engine.subst(l, &map, &mut HashMap::default())
            }
        };
        self.lagrangian = Some(l);
        l
    }

    /// Whether nothing in the definition depends on t explicitly (the
    /// Lagrangian, the forces, the constraints, the kinematics), so that the
    /// right-hand side is autonomous.
    pub fn autonomous(&self) -> bool {
        let m = self.model;
        let t = m.time;
        let forces = m.coordinates.iter().map(|c| c.force);
        let constraints = m
            .constraints
            .iter()
            .flat_map(|c| std::iter::once(c.velocity).chain(c.holonomic));
        let kinematics = m.speeds.iter().flat_map(|sp| sp.velocities.iter().copied());
        // a folded kinetic energy is free of t (`Model::lagrangian_folded`)
        !std::iter::once(m.lagrangian_folded)
            .chain(forces)
            .chain(constraints)
            .chain(kinematics)
            .any(|x| self.engine.depends_on(x, t))
    }
}

#[cfg(test)]
mod tests {
    use super::Scene;
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled is autonomous and its dependent velocity is free of time; a
    /// blade turned at a rate given in time (θ = w t) is neither. The
    /// constrained velocities map ẏ to tan θ ẋ.
    #[test]
    fn time_dependence_and_the_constrained_velocities() {
        let (model, mut engine) = lowered(SLED);
        let scene = Scene::new(&model, &mut engine);
        assert!(scene.autonomous() && !scene.rheonomic());
        let map = scene.constrained_velocities();
        let ydot = map[&model.coordinates[2].velocity];
        assert!(close(
            value(&model, scene.engine, ydot, &sled_at()),
            0.3f64.tan() * 0.7
        ));
        let turning = "pub struct Turning {
            parameters { m, w }
            coordinates { x, y }
            lagrangian = m/2*(dot(x)^2 + dot(y)^2);
            constraints { dot(y) = tan(w*t)*dot(x); }
        }";
        let (model, mut engine) = lowered(turning);
        let scene = Scene::new(&model, &mut engine);
        assert!(!scene.autonomous() && scene.rheonomic());
    }
}
