//! The mechanics of DESIGN §4, derived symbolically: the mass matrix and
//! Euler–Lagrange terms, the constraint matrix, the multiplier route (5.9)/(5.10),
//! the constrained Lagrangian and the curvature route (5.12)–(5.21), and the
//! energy. Every function derives only what it is asked for.

use crate::model::Model;
use crate::sym::{Engine, ExprId, SymId, ZERO};
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

/// Whether every expression of `entries` vanishes at 16 random points in
/// double-double arithmetic (about 32 digits): any point where one exceeds
/// 1e-24 of the sum of its terms' sizes proves it nonzero; entries below that
/// at every point are taken as zero (an identity the canonical form does not
/// know, such as an angle-addition formula). Every symbol but π takes values
/// in [0.3, 1.4], the same points every build.
pub fn vanish_at_random_points(engine: &Engine, pi: SymId, entries: &[ExprId]) -> bool {
    use crate::sym::dd::Dd;
    let mut rng = crate::sym::Rng::new(0x243F_6A88_85A3_08D3);
    let mut vals = vec![Dd::ZERO; engine.num_symbols()];
    let mut points = 0;
    for _ in 0..64 {
        if points == 16 {
            break;
        }
        for v in vals.iter_mut() {
            *v = Dd::from_f64(0.3 + 1.1 * rng.next_f64()); // positive: keeps sqrt and ln arguments valid
        }
        vals[pi.index()] = Dd::PI;
        let mut usable = true;
        for &b in entries {
            let (v, scale) = engine.eval_with_scale(b, &vals);
            if !v.is_finite() || !scale.is_finite() {
                usable = false;
                break;
            }
            if v.abs().to_f64() > 1e-24 * scale.to_f64() {
                return false;
            }
        }
        if usable {
            points += 1;
        }
    }
    points == 16
}

/// Everything derived symbolically for one system, each piece once.
pub struct Derivation {
    /// The multiplier route's pieces.
    pub multiplier_route: MultiplierRoute,
    /// B^b_{αβ} of (5.21), p × k × k.
    pub curvature: Vec<Vec<Vec<ExprId>>>,
    /// The curvature route (its reduced mass matrix alone when only the
    /// multiplier route is derived).
    pub curvature_route: CurvatureRoute,
    /// The energy, when `outputs { energy }` asks for it (derived once the
    /// rest is known to be within the engine's limits).
    pub energy: Option<ExprId>,
    /// Whether every curvature entry is identically zero.
    pub integrable: bool,
    /// Whether that was proved symbolically (otherwise numerically).
    pub integrable_proved: bool,
}

/// The curvature route: the reduced equations Mc r̈ = f in closed form.
pub struct CurvatureRoute {
    /// ∂²Lc/∂ṙ_α∂ṙ_β, k × k.
    pub mass: Vec<Vec<ExprId>>,
    /// Right side f of Mc r̈ = f, from (5.20) with the forces projected.
    pub rhs: Vec<ExprId>,
    /// r̈ solved symbolically, when that is cheaper than solving numerically.
    pub solution: Option<Vec<ExprId>>,
}

impl Model {
    /// The multiplier route, the curvature and the curvature route (only its
    /// reduced mass matrix unless `both_routes`), and whether the
    /// constraints are integrable.
    pub fn derive(&mut self, both_routes: bool) -> Derivation {
        let multiplier_route = self.multiplier_route();
        let curvature = self.curvature();
        let curvature_route = if both_routes {
            self.curvature_route(&curvature)
        } else {
            self.reduced_mass_only(&curvature)
        };
        let (integrable, integrable_proved) = self.integrability(&curvature);
        Derivation {
            multiplier_route,
            curvature,
            curvature_route,
            energy: None,
            integrable,
            integrable_proved,
        }
    }

    /// Whether the constraints are integrable (all B^b_αβ ≡ 0), and whether that
    /// was proved symbolically. An entry whose canonical form is not zero is
    /// evaluated at 16 random points in double-double arithmetic (about 32
    /// digits): any point where it exceeds 1e-24 of the sum of its terms' sizes
    /// proves it nonzero; an entry below that at every point is taken as zero (an
    /// identity the canonical form does not know, such as an angle-addition
    /// formula). A genuinely nonholonomic system would have to cancel to 24
    /// digits at 16 random points to be called integrable.
    fn integrability(&self, curv: &[Vec<Vec<ExprId>>]) -> (bool, bool) {
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
            vanish_at_random_points(&self.engine, self.pi, &entries),
            false,
        )
    }

    /// The substitution ṡ_a ↦ −Σ_α A^a_α ṙ_α of (5.11).
    /// For a system in generalized speeds, every q̇_i ↦ (S u + σ)_i.
    pub fn constrained_velocities(&self) -> HashMap<SymId, ExprId> {
        if let Some(sp) = &self.speeds {
            let velocities = self.coordinates.iter().map(|c| c.velocity);
            return velocities.zip(sp.velocities.iter().copied()).collect();
        }
        self.constraints
            .iter()
            .map(|c| (self.coordinates[c.dependent].velocity, c.velocity))
            .collect()
    }

    /// q̇ at the constrained velocities, per coordinate (S u + σ, for a
    /// system in generalized speeds).
    pub fn constrained_qdot(&mut self) -> Vec<ExprId> {
        if let Some(sp) = &self.speeds {
            return sp.velocities.clone();
        }
        let mut out = Vec::with_capacity(self.n());
        for i in 0..self.n() {
            match self.constraints.iter().find(|c| c.dependent == i) {
                Some(c) => out.push(c.velocity),
                None => out.push(self.engine.sym(self.coordinates[i].velocity)),
            }
        }
        out
    }

    /// The multiplier route's symbolic pieces.
    pub fn multiplier_route(&mut self) -> MultiplierRoute {
        let n = self.n();
        let l = self.lagrangian;
        let e = &mut self.engine;
        let q = &self.coordinates;
        let momenta: Vec<ExprId> = (0..n).map(|j| e.diff(l, q[j].velocity)).collect();
        let mut mass = vec![vec![ZERO; n]; n];
        for i in 0..n {
            for j in i..n {
                let m = e.diff(momenta[i], q[j].velocity);
                mass[i][j] = m;
                mass[j][i] = m;
            }
        }
        let mut bias = Vec::with_capacity(n);
        for j in 0..n {
            let mut parts = Vec::new();
            for i in 0..n {
                let d = e.diff(momenta[j], q[i].position);
                if d != ZERO {
                    let v = e.sym(q[i].velocity);
                    parts.push(e.mul(d, v));
                }
            }
            parts.push(e.diff(momenta[j], self.time));
            let dl = e.diff(l, q[j].position);
            parts.push(e.neg(dl));
            parts.push(e.neg(q[j].force));
            bias.push(e.sum(&parts));
        }
        if !self.velocity_rows.is_empty() {
            let dependent_bias = self.dependent_bias_from_rows();
            return MultiplierRoute {
                mass,
                bias,
                dependent_bias,
            };
        }
        let e = &mut self.engine;
        let q = &self.coordinates;
        let mut dependent_bias = Vec::with_capacity(self.constraints.len());
        for c in &self.constraints {
            let sdot = c.velocity;
            let mut parts = Vec::new();
            for i in 0..n {
                let d = e.diff(sdot, q[i].position);
                if d != ZERO {
                    let v = e.sym(q[i].velocity);
                    parts.push(e.mul(d, v));
                }
            }
            let dt = e.diff(sdot, self.time);
            if dt != ZERO {
                parts.push(dt);
            }
            dependent_bias.push(e.sum(&parts));
        }
        MultiplierRoute {
            mass,
            bias,
            dependent_bias,
        }
    }

    /// The part of s̈ that does not depend on r̈, from the velocity rows:
    /// differentiating g(q, q̇, t) = 0 along the motion, c_s s̈ + c_r r̈ + d = 0
    /// with d = Σ_j ∂g/∂q_j q̇_j + ∂g/∂t, so it is −c_s⁻¹ d, the block solved
    /// as for the velocities (its pivots shared with them). The rows are
    /// compact where the eliminated solutions are not.
    fn dependent_bias_from_rows(&mut self) -> Vec<ExprId> {
        let rows = self.velocity_rows.clone();
        let e = &mut self.engine;
        let q = &self.coordinates;
        let mut block = Vec::with_capacity(rows.len());
        let mut minus_d = Vec::with_capacity(rows.len());
        for &g in &rows {
            block.push(
                self.constraints
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
            parts.push(e.diff(g, self.time));
            let d = e.sum(&parts);
            minus_d.push(e.neg(d));
        }
        crate::lower::linear::solve(e, &block, &[minus_d])
            .x
            .remove(0)
    }

    /// B^b_{αβ} of (5.21), p × k × k, antisymmetric in (α, β).
    pub fn curvature(&mut self) -> Vec<Vec<Vec<ExprId>>> {
        let (k, p) = (self.k(), self.p());
        let mut b = vec![vec![vec![ZERO; k]; k]; p];
        let r = self.of_independent(|c| c.position);
        let s_syms: Vec<SymId> = self
            .constraints
            .iter()
            .map(|c| self.coordinates[c.dependent].position)
            .collect();
        let a: Vec<&[ExprId]> = self
            .constraints
            .iter()
            .map(|c| &c.coefficients[..])
            .collect();
        for bb in 0..p {
            for al in 0..k {
                for be in (al + 1)..k {
                    let e = &mut self.engine;
                    let (r_al, r_be) = (r[al], r[be]);
                    let d1 = e.diff(a[bb][al], r_be);
                    let d2 = e.diff(a[bb][be], r_al);
                    let mut parts = vec![d1, e.neg(d2)];
                    for (aa, &s_sym) in s_syms.iter().enumerate() {
                        let x = e.diff(a[bb][be], s_sym);
                        let x = e.mul(a[aa][al], x);
                        let y = e.diff(a[bb][al], s_sym);
                        let y = e.mul(a[aa][be], y);
                        parts.push(x);
                        parts.push(e.neg(y));
                    }
                    let v = e.sum(&parts);
                    b[bb][al][be] = v;
                    b[bb][be][al] = e.neg(v);
                }
            }
        }
        b
    }

    /// The curvature route (5.12)–(5.20): Lc, its reduced mass matrix and the
    /// right side with the curvature term and projected forces.
    pub fn curvature_route(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> CurvatureRoute {
        self.curvature_route_parts(curvature, true)
    }

    /// The curvature route's reduced mass matrix alone (the right side left
    /// zero): what the singularity check needs when the
    /// route itself is not derived.
    pub fn reduced_mass_only(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> CurvatureRoute {
        self.curvature_route_parts(curvature, false)
    }

    fn curvature_route_parts(
        &mut self,
        curvature: &[Vec<Vec<ExprId>>],
        with_rhs: bool,
    ) -> CurvatureRoute {
        let (n, k) = (self.n(), self.k());
        let map = self.constrained_velocities();
        let qdot_c = self.constrained_qdot();
        let l = self.lagrangian;
        let r_vel = self.independent_velocities();
        let r_pos = self.of_independent(|c| c.position);
        let r_force = self.of_independent(|c| c.force);
        let q = &self.coordinates;
        let e = &mut self.engine;
        let mut memo = HashMap::default();
        let lc = e.subst(l, &map, &mut memo); // (5.12)
        let pc: Vec<ExprId> = r_vel.iter().map(|&v| e.diff(lc, v)).collect();
        let mut mass = vec![vec![ZERO; k]; k];
        for al in 0..k {
            for be in al..k {
                let m = e.diff(pc[al], r_vel[be]);
                mass[al][be] = m;
                mass[be][al] = m;
            }
        }
        // ∂L/∂ṡ_b at the constrained velocities
        let p_dep: Vec<ExprId> = self
            .constraints
            .iter()
            .map(|c| {
                let d = e.diff(l, q[c.dependent].velocity);
                e.subst(d, &map, &mut memo)
            })
            .collect();
        let mut rhs = Vec::with_capacity(k);
        if !with_rhs {
            return CurvatureRoute {
                mass,
                rhs: vec![ZERO; k],
                solution: None,
            };
        }
        for al in 0..k {
            let mut lhs = Vec::new();
            // velocity part of d/dt ∂Lc/∂ṙ_α
            for i in 0..n {
                let d = e.diff(pc[al], q[i].position);
                if d != ZERO {
                    lhs.push(e.mul(d, qdot_c[i]));
                }
            }
            lhs.push(e.diff(pc[al], self.time));
            // − ∂Lc/∂r_α
            let d = e.diff(lc, r_pos[al]);
            lhs.push(e.neg(d));
            // + Σ_a A^a_α ∂Lc/∂s_a
            for c in &self.constraints {
                let d = e.diff(lc, q[c.dependent].position);
                if d != ZERO {
                    lhs.push(e.mul(c.coefficients[al], d));
                }
            }
            // + Σ_b Σ_β B^b_αβ ṙ_β ∂L/∂ṡ_b   (moved from the right side of (5.20))
            for (b, pb) in p_dep.iter().enumerate() {
                for (be, &rv) in r_vel.iter().enumerate() {
                    let bab = curvature[b][al][be];
                    if bab != ZERO {
                        let v = e.sym(rv);
                        let t = e.mul(bab, v);
                        lhs.push(e.mul(t, *pb));
                    }
                }
            }
            // projected forces Q_r − Σ_a A^a_α Q_s at the constrained velocities
            let mut force = vec![r_force[al]];
            for c in &self.constraints {
                let qs = q[c.dependent].force;
                if qs != ZERO {
                    let t = e.mul(c.coefficients[al], qs);
                    force.push(e.neg(t));
                }
            }
            let force = e.sum(&force);
            let force = e.subst(force, &map, &mut memo);
            let lhs = e.sum(&lhs);
            rhs.push(e.sub(force, lhs));
        }
        CurvatureRoute {
            mass,
            rhs,
            solution: None,
        }
    }

    /// Solves the reduced system symbolically by LDLᵀ: exact cancellations
    /// (common factors such as m R², a pivot that is cos² ψ/4) then cost
    /// nothing at run time. Only for small systems with small entries, where
    /// this cannot swell; `None` otherwise or if a pivot is zero.
    pub fn solve_symbolic(&mut self, mass: &[Vec<ExprId>], rhs: &[ExprId]) -> Option<Vec<ExprId>> {
        let k = rhs.len();
        let e = &mut self.engine;
        if k == 0 || k > 3 {
            return None;
        }
        let small = mass.iter().flatten().all(|&x| e.num_terms(x) <= 24)
            && rhs.iter().all(|&x| e.num_terms(x) <= 64);
        if !small {
            return None;
        }
        let mut l = vec![vec![ZERO; k]; k];
        let mut d = vec![ZERO; k];
        let mut dinv = vec![ZERO; k];
        for j in 0..k {
            let mut dj = mass[j][j];
            for r in 0..j {
                let t = e.mul(l[j][r], l[j][r]);
                let t = e.mul(t, d[r]);
                dj = e.sub(dj, t);
            }
            if dj == ZERO {
                return None;
            }
            d[j] = dj;
            dinv[j] = e.pow(dj, crate::sym::Rational::MINUS_ONE);
            for i in (j + 1)..k {
                let mut v = mass[i][j];
                for r in 0..j {
                    let t = e.mul(l[i][r], l[j][r]);
                    let t = e.mul(t, d[r]);
                    v = e.sub(v, t);
                }
                l[i][j] = e.mul(v, dinv[j]);
            }
        }
        let mut y = vec![ZERO; k];
        for i in 0..k {
            let mut v = rhs[i];
            for r in 0..i {
                let t = e.mul(l[i][r], y[r]);
                v = e.sub(v, t);
            }
            y[i] = v;
        }
        let mut x = vec![ZERO; k];
        for i in (0..k).rev() {
            let mut v = e.mul(y[i], dinv[i]);
            for r in (i + 1)..k {
                let t = e.mul(l[r][i], x[r]);
                v = e.sub(v, t);
            }
            x[i] = v;
        }
        if e.overflowed() {
            return None;
        }
        Some(x)
    }

    /// E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities: substituted,
    /// or in the full q̇ whose dependent velocities the emitted code binds
    /// to their solved values.
    pub fn energy(&mut self) -> ExprId {
        let map = self.constrained_velocities();
        let l = self.lagrangian;
        let e = &mut self.engine;
        let mut parts = Vec::new();
        for v in self.coordinates.iter().map(|c| c.velocity) {
            let p = e.diff(l, v);
            let vs = e.sym(v);
            parts.push(e.mul(vs, p));
        }
        parts.push(e.neg(l));
        let en = e.sum(&parts);
        let mut memo = HashMap::default();
        let substituted = e.subst(en, &map, &mut memo);
        // Substituting the solved velocities pays when they simplify E (the
        // closed forms of small systems). When they are large (a block of
        // implicit rows), E stays in the full q̇: the emitted code binds each
        // velocity symbol to its solved value, computed once.
        let solved: usize = map.values().map(|&v| e.num_terms(v)).sum();
        if e.num_terms(substituted) <= e.num_terms(en) + solved {
            substituted
        } else {
            en
        }
    }
}
