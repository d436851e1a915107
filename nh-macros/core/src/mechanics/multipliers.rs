//! The multiplier route (5.9)/(5.10): the Euler–Lagrange terms E = M q̈ + h
//! of the whole Lagrangian (or Kane's form of them for bodies) and the
//! part of the dependent accelerations that does not depend on r̈.

use super::kane::BodyTerms;
use super::scene::Scene;
use crate::model::Output;
use crate::sym::{Atom, Engine, ExprId, SymId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// The pieces of the multiplier route, with the full velocity vector q̇
/// symbolic (dependent velocities are evaluated numerically first).
pub struct MultiplierRoute {
    /// M_ij = ∂²L/∂q̇_i∂q̇_j, n × n, symmetric.
    pub mass: Vec<Vec<ExprId>>,
    /// h_j = Σ_i ∂²L/∂q̇_j∂q_i q̇_i + ∂²L/∂q̇_j∂t − ∂L/∂q_j − Q_j, so that E_j = Σ_i M_ji q̈_i + h_j (3.9).
    pub bias: Vec<ExprId>,
    /// −(Ȧ ṙ)_a − β̇_a: the part of s̈_a that does not depend on r̈ (from
    /// differentiating (5.3), with ∂/∂t for time-dependent constraints).
    pub dependent_bias: Vec<ExprId>,
}

/// A Lagrangian of bodies with at most this many terms also has its
/// expanded M and h derived, and the cheaper of the two forms is emitted;
/// beyond it Kane's form is taken without the comparison. Measured: Kane's
/// form was the cheaper for every Lagrangian of bodies with more than 12
/// terms (57 terms: 307 operations against 737; the bicycle's 203: 1,350
/// against 5,857), the expanded form for the rolling disc (9 terms: 135
/// against 196) and the differential drive (12 terms: 96 against 174).
pub const LAGRANGIAN_TERMS_COMPARED: usize = 32;

/// The degree of `e` as a polynomial in the symbols `velocities` (powers of
/// sums kept unexpanded count their base's degree times the exponent), or
/// `None` if one of them appears inside a function or under a power that is
/// not a natural number.
pub(crate) fn velocity_degree(
    e: &Engine,
    x: ExprId,
    velocities: &[SymId],
    memo: &mut HashMap<ExprId, Option<i64>>,
) -> Option<i64> {
    if let Some(&d) = memo.get(&x) {
        return d;
    }
    let mut degree = Some(0);
    for &(m, _) in e.terms(x) {
        let mut term = Some(0);
        for &(a, ex) in e.factors(m) {
            if !e.atom_symbols(a).iter().any(|s| velocities.contains(s)) {
                continue;
            }
            let k = ex.to_integer().filter(|&k| k >= 0);
            let factor = match e.atom(a) {
                Atom::Sym(_) => k,
                Atom::Base(b) => velocity_degree(e, *b, velocities, memo)
                    .zip(k)
                    .map(|(d, k)| d * k),
                Atom::Func(..) | Atom::Atan2(..) => None,
            };
            term = term.zip(factor).map(|(t, f)| t + f);
        }
        degree = degree.zip(term).map(|(d, t)| d.max(t));
    }
    memo.insert(x, degree);
    degree
}

impl Scene<'_> {
    /// The multiplier route's symbolic pieces, and Kane's form of the
    /// bodies' terms (`kane.rs`) when the Lagrangian is made of bodies: with
    /// it, M and h of the whole Lagrangian are derived only when an output
    /// uses them or they are small (`needs_lagrangian_terms`).
    pub fn multiplier_route(&mut self) -> (MultiplierRoute, Option<BodyTerms>) {
        let n = self.model.n();
        let places = self.model.places;
        let kane = "deriving Kane's terms of the bodies (the Lagrangian's kinetic energies)";
        let bodies = self.at(places.lagrangian, kane, |m| m.body_terms());
        let (mass, bias) = if self.needs_lagrangian_terms(bodies.is_some()) {
            let task = "differentiating the Lagrangian (its mass matrix and Euler–Lagrange terms)";
            self.at(places.lagrangian, task, |m| {
                let l = m.lagrangian();
                m.euler_lagrange_terms(l, true)
            })
        } else {
            (Vec::new(), Vec::new())
        };
        // with a block solved numerically, the accelerations take its rates
        // on the graph, and their derivatives are the rates of those nodes
        // (`generate/derivatives.rs`): the symbolic −Ȧṙ serves nothing
        let task = "differentiating the constraints along the motion";
        let dependent_bias = self.at(places.constraints, task, |m| {
            if m.block.is_some() {
                Vec::new()
            } else if m.model.velocity_rows.is_empty() {
                m.dependent_bias_from_solutions()
            } else {
                m.dependent_bias_from_rows()
            }
        });
        debug_assert!(mass.len() == n || (mass.is_empty() && bodies.is_some()));
        let route = MultiplierRoute {
            mass,
            bias,
            dependent_bias,
        };
        (route, bodies)
    }

    /// Whether the expanded Lagrangian's M and h are derived. Always without
    /// Kane's form of the bodies; with it, when an output uses them (the
    /// multipliers, the mass matrix, the reaction forces, both routes; the
    /// derivatives of the equations are taken on the graph), when the Lagrangian is small enough
    /// that its expanded form may be the cheaper
    /// ([`LAGRANGIAN_TERMS_COMPARED`]), or when it is not quadratic in the
    /// velocities ([`velocity_degree`]: the reduced mass matrix cannot be
    /// sampled from it for [`Model::silent_velocities`]).
    pub(crate) fn needs_lagrangian_terms(&self, kane: bool) -> bool {
        let l = self.model.lagrangian_folded;
        let used = [
            Output::Multipliers,
            Output::MassMatrix,
            Output::ReactionForces,
            Output::Routes,
        ];
        !kane
            || used.into_iter().any(|o| self.model.outputs.contains(o))
            || (!self.folds() && self.engine.num_terms(l) <= LAGRANGIAN_TERMS_COMPARED)
            || !self.quadratic_in_velocities(l)
    }

    /// Whether a body's kinetic energy is folded into a symbol in
    /// [`Model::lagrangian_folded`](crate::model::Model): the Lagrangian is
    /// then large, and its folded form is quadratic in the velocities
    /// exactly when L is (a folded kinetic energy is a quadratic form in
    /// them).
    pub(crate) fn folds(&self) -> bool {
        let bodies = self.model.kinetic.iter().flat_map(|k| &k.bodies);
        bodies.into_iter().any(|b| b.folded.is_some())
    }

    /// Whether `l` is a polynomial of degree at most two in the velocities,
    /// so that vᵀ M v = l(q, v) + l(q, −v) − 2 l(q, 0) exactly.
    pub(crate) fn quadratic_in_velocities(&self, l: ExprId) -> bool {
        let velocities: Vec<SymId> = self.model.coordinates.iter().map(|c| c.velocity).collect();
        velocity_degree(self.engine, l, &velocities, &mut HashMap::default())
            .is_some_and(|d| d <= 2)
    }

    /// M_ij = ∂²l/∂q̇_i∂q̇_j and h_j = Σ_i ∂²l/∂q̇_j∂q_i q̇_i + ∂²l/∂q̇_j∂t
    /// − ∂l/∂q_j (− Q_j `with_forces`) of a Lagrangian (or part of one) l.
    pub(crate) fn euler_lagrange_terms(
        &mut self,
        l: ExprId,
        with_forces: bool,
    ) -> (Vec<Vec<ExprId>>, Vec<ExprId>) {
        let n = self.model.n();
        let momenta: Vec<ExprId> = (0..n)
            .map(|j| self.engine.diff(l, self.model.coordinates[j].velocity))
            .collect();
        let mut mass = vec![vec![ZERO; n]; n];
        for i in 0..n {
            for j in i..n {
                let m = self
                    .engine
                    .diff(momenta[i], self.model.coordinates[j].velocity);
                mass[i][j] = m;
                mass[j][i] = m;
            }
        }
        let mut bias = Vec::with_capacity(n);
        for (j, &p) in momenta.iter().enumerate() {
            let mut parts = vec![self.along_motion(p)];
            let e = &mut *self.engine;
            let q = &self.model.coordinates[j];
            parts.push(e.diff(p, self.model.time));
            let dl = e.diff(l, q.position);
            parts.push(e.neg(dl));
            if with_forces {
                parts.push(e.neg(q.force));
            }
            bias.push(e.sum(&parts));
        }
        (mass, bias)
    }

    /// −(Ȧ ṙ)_a − β̇_a from the solved velocities ṡ_a(q, ṙ, t).
    pub(crate) fn dependent_bias_from_solutions(&mut self) -> Vec<ExprId> {
        let sdots: Vec<ExprId> = self.model.constraints.iter().map(|c| c.velocity).collect();
        sdots
            .into_iter()
            .map(|sdot| {
                let along = self.along_motion(sdot);
                let dt = self.engine.diff(sdot, self.model.time);
                self.engine.add(along, dt)
            })
            .collect()
    }

    /// The part of s̈ that does not depend on r̈, from the velocity rows:
    /// differentiating g(q, q̇, t) = 0 along the motion, c_s s̈ + c_r r̈ + d = 0
    /// with d = Σ_j ∂g/∂q_j q̇_j + ∂g/∂t, so it is −c_s⁻¹ d, the block solved
    /// as for the velocities (its pivots shared with them). The rows are
    /// compact where the eliminated solutions are not.
    pub(crate) fn dependent_bias_from_rows(&mut self) -> Vec<ExprId> {
        let rows = self.model.velocity_rows.clone();
        let e = &mut *self.engine;
        let q = &self.model.coordinates;
        let mut block = Vec::with_capacity(rows.len());
        let mut minus_d = Vec::with_capacity(rows.len());
        for &g in &rows {
            block.push(
                self.model
                    .constraints
                    .iter()
                    .map(|c| e.diff(g, q[c.dependent].velocity))
                    .collect::<Vec<_>>(),
            );
            let mut parts = Vec::new();
            for c in q {
                let dg = e.diff(g, c.position);
                if dg != ZERO {
                    let v = e.sym(c.velocity);
                    parts.push(e.mul(dg, v));
                }
            }
            parts.push(e.diff(g, self.model.time));
            let d = e.sum(&parts);
            minus_d.push(e.neg(d));
        }
        crate::lower::linear::solve(e, &block, &[minus_d])
            .x
            .remove(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sym::{Fun, Rational};

    /// Degrees in the velocity `v` (with `y` another symbol), including a
    /// power of a long sum the engine keeps unexpanded.
    #[test]
    fn velocity_degree_counts_powers_and_refuses_functions() {
        let mut e = Engine::new();
        let (v, y) = (e.symbol("v"), e.symbol("y"));
        let (vs, ys) = (e.sym(v), e.sym(y));
        let degree = |e: &Engine, x| velocity_degree(e, x, &[v], &mut HashMap::default());
        let sin_y = e.func(Fun::Sin, ys);
        let v2 = e.mul(vs, vs);
        let x = e.mul(v2, sin_y);
        assert_eq!(degree(&e, x), Some(2));
        let v3 = e.mul(x, vs);
        assert_eq!(degree(&e, v3), Some(3));
        assert_eq!(degree(&e, sin_y), Some(0));
        let sin_v = e.func(Fun::Sin, vs);
        assert_eq!(degree(&e, sin_v), None);
        let root = e.pow(vs, Rational::new(1, 2).unwrap());
        assert_eq!(degree(&e, root), None);
        // (v + y + y² + … + y⁹)³, kept as a power of its base
        let mut parts = vec![vs];
        for k in 1..10 {
            parts.push(e.pow_int(ys, k));
        }
        let long = e.sum(&parts);
        let cube = e.pow_int(long, 3);
        assert_eq!(degree(&e, cube), Some(3));
    }
}

#[cfg(test)]
mod sled_tests {
    use super::super::scene::Scene;
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled's multiplier route: M = diag(m, J, m) in coordinate order,
    /// no bias (L depends on no coordinate), and the dependent bias
    /// s̈ − A r̈ = sec²θ θ̇ ẋ of ẏ = tan θ ẋ differentiated.
    #[test]
    fn the_sleds_euler_lagrange_terms_and_dependent_bias() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let (route, kane) = scene.multiplier_route();
        let at = sled_at();
        let v = |e| value(&model, scene.engine, e, &at);
        let expected = [[2.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 2.0]];
        for (row, want) in route.mass.iter().zip(expected) {
            for (&e, w) in row.iter().zip(want) {
                assert!(close(v(e), w), "{} against {w}", v(e));
            }
        }
        assert!(route.bias.iter().all(|&h| v(h) == 0.0));
        let sec2 = 1.0 / 0.3f64.cos().powi(2);
        assert!(close(v(route.dependent_bias[0]), sec2 * -1.1 * 0.7));
        assert!(kane.is_none());
    }
}
