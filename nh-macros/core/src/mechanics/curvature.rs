//! The curvature B^b_{αβ} of (5.21) and the curvature route: the
//! constrained Lagrangian Lc (5.12) and the reduced equations Mc r̈ = f of
//! (5.20), solved symbolically when that is cheaper.

use super::reduced::Reduced;
use super::scene::Scene;
use crate::algebra::ldlt::Updates;
use crate::sym::dd::Dd;
use crate::sym::dual::Duals;

/// The columns one evaluation of the bodies' centres differentiates along
/// ([`Scene::masses_sampled_along`]).
const LANES: usize = 8;
use crate::sym::{ExprId, ZERO};
use rustc_hash::FxHashMap as HashMap;

impl Scene<'_> {
    /// B^b_{αβ} of (5.21), p × k × k, antisymmetric in (α, β).
    pub fn curvature(&mut self) -> Vec<Vec<Vec<ExprId>>> {
        let (k, p) = (self.model.k(), self.model.p());
        let mut b = vec![vec![vec![ZERO; k]; k]; p];
        for bb in 0..p {
            for al in 0..k {
                for be in (al + 1)..k {
                    let v = self.curvature_entry(bb, al, be);
                    b[bb][al][be] = v;
                    b[bb][be][al] = self.engine.neg(v);
                }
            }
        }
        b
    }

    /// B^b_{αβ} of (5.21) for α < β.
    pub(crate) fn curvature_entry(&mut self, bb: usize, al: usize, be: usize) -> ExprId {
        let r = self.model.of_independent(|c| c.position);
        let (r_al, r_be) = (r[al], r[be]);
        let e = &mut *self.engine;
        let a = |aa: usize, x: usize| self.model.constraints[aa].coefficients[x];
        let d1 = e.diff(a(bb, al), r_be);
        let d2 = e.diff(a(bb, be), r_al);
        let mut parts = vec![d1, e.neg(d2)];
        for (aa, c) in self.model.constraints.iter().enumerate() {
            let s_sym = self.model.coordinates[c.dependent].position;
            let x = e.diff(a(bb, be), s_sym);
            let x = e.mul(a(aa, al), x);
            let y = e.diff(a(bb, al), s_sym);
            let y = e.mul(a(aa, be), y);
            parts.push(x);
            parts.push(e.neg(y));
        }
        e.sum(&parts)
    }

    /// The curvature route (5.12)–(5.20): Lc, its reduced mass matrix and the
    /// right side with the curvature term and projected forces.
    pub fn curvature_route(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> Reduced {
        self.curvature_route_parts(curvature)
    }

    /// Per independent velocity ṙ_a, whether (Cᵀ M C)_aa vanishes, with
    /// C = [I; −A]: evaluated at 16 random points in double-double
    /// arithmetic, zero where it stays below 1e-24 of the sum of its terms'
    /// sizes at every point (as [`vanish_at_random_points`]); cheaper than
    /// the reduced mass matrix of the constrained Lagrangian when the
    /// curvature route is not derived.
    pub(crate) fn silent_velocities(&self, mass: &[Vec<ExprId>]) -> Vec<bool> {
        use crate::sym::dd::Dd;
        let (n, k) = (self.model.n(), self.model.k());
        let mut silent = vec![true; k];
        let mut rng = crate::sym::Rng::new(0xA409_3822_299F_31D0);
        for _ in 0..16 {
            if !silent.contains(&true) {
                break;
            }
            let mut vals = rng.point(self.engine.num_symbols(), self.model.pi);
            let mut memo = crate::sym::EvalMemo::default();
            let mut column = |a: usize| -> Vec<Dd> {
                let mut c = vec![Dd::ZERO; n];
                c[self.model.independent()[a]] = Dd::from_f64(1.0);
                for con in &self.model.constraints {
                    let x = self.engine.eval_memo(con.coefficients[a], &vals, &mut memo);
                    c[con.dependent] = Dd::ZERO - x;
                }
                c
            };
            let columns: Vec<Vec<Dd>> = (0..k).map(&mut column).collect();
            let open: Vec<usize> = (0..k).filter(|&a| silent[a]).collect();
            let values = match mass.is_empty() {
                false => (open.iter())
                    .map(|&a| self.mass_along(mass, &columns[a], &vals, &mut memo))
                    .collect(),
                true => {
                    let open: Vec<&[Dd]> = open.iter().map(|&a| &columns[a][..]).collect();
                    self.masses_sampled_along(&open, &mut vals)
                }
            };
            for (&a, (value, scale)) in open.iter().zip(values) {
                if value.abs().to_f64() > 1e-24 * scale.to_f64() {
                    silent[a] = false;
                }
            }
        }
        silent
    }

    /// cᵀ M c from M's entries at a point, with the sum of its terms' sizes.
    pub(crate) fn mass_along(
        &self,
        mass: &[Vec<ExprId>],
        c: &[Dd],
        vals: &[Dd],
        memo: &mut crate::sym::EvalMemo<Dd>,
    ) -> (Dd, Dd) {
        let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
        let moving = || (0..c.len()).filter(|&i| c[i].to_f64() != 0.0);
        for i in moving() {
            for j in moving() {
                let m = self.engine.eval_memo(mass[i][j], vals, memo);
                let t = c[i] * c[j] * m;
                value = value + t;
                scale = scale + t.abs();
            }
        }
        (value, scale)
    }

    /// cᵀ M c sampled from the Lagrangian, quadratic in the velocities, for
    /// each column c of `columns`: L(q, c) + L(q, −c) − 2 L(q, 0), with the
    /// sum of the samples' sizes. For a Lagrangian of bodies, Σ_b 2 T_b(q, c)
    /// from each body's velocity and ω_b at q̇ = c (the centre's velocity
    /// J c by forward differentiation of its position, [`LANES`] columns
    /// per evaluation) and the rest sampled so: the expanded kinetic
    /// energies, the largest part of L, are not evaluated. The velocities in
    /// `vals` are overwritten.
    pub(crate) fn masses_sampled_along(&self, columns: &[&[Dd]], vals: &mut [Dd]) -> Vec<(Dd, Dd)> {
        let Some(split) = &self.model.kinetic else {
            // without the split nothing is folded
            let l = self.model.lagrangian_folded;
            return (columns.iter())
                .map(|c| self.lagrangian_sampled_along(l, c, vals))
                .collect();
        };
        let speeds = self.centre_speeds(columns, vals);
        let mut out = Vec::with_capacity(columns.len());
        for (a, c) in columns.iter().enumerate() {
            let (mut value, mut scale) = self.lagrangian_sampled_along(split.rest, c, vals);
            for (coordinate, &ci) in self.model.coordinates.iter().zip(c.iter()) {
                vals[coordinate.velocity.index()] = ci;
            }
            let mut memo = Default::default();
            for (body, speed) in split.bodies.iter().zip(&speeds) {
                let m = self.engine.eval_memo(body.mass, vals, &mut memo);
                for v in speed.iter().map(|v| v[a]) {
                    value = value + m * v * v;
                    scale = scale + (m * v * v).abs();
                }
                if let Some((omega, inertia)) = &body.rotation {
                    let w = omega.map(|x| self.engine.eval_memo(x, vals, &mut memo));
                    for (row, &wi) in inertia.iter().zip(&w) {
                        for (&i, &wj) in row.iter().zip(&w) {
                            let t = wi * self.engine.eval_memo(i, vals, &mut memo) * wj;
                            value = value + t;
                            scale = scale + t.abs();
                        }
                    }
                }
            }
            out.push((value, scale));
        }
        out
    }

    /// Per body, the components of its centre's velocity J c for each
    /// column c of `columns` (indexed [body][component][column]), by
    /// forward differentiation of the positions, [`LANES`] columns per
    /// evaluation with one memo for all the bodies (a chain's centres
    /// share their subterms).
    fn centre_speeds(&self, columns: &[&[Dd]], vals: &[Dd]) -> Vec<[Vec<Dd>; 3]> {
        let bodies = self.model.kinetic.iter().flat_map(|k| &k.bodies);
        let mut speeds: Vec<[Vec<Dd>; 3]> = bodies.clone().map(|_| Default::default()).collect();
        for batch in columns.chunks(LANES) {
            let moving: Vec<Duals<LANES>> = (vals.iter().enumerate())
                .map(|(i, &v)| {
                    let mut x = Duals::constant(v);
                    for (k, coordinate) in self.model.coordinates.iter().enumerate() {
                        if coordinate.position.index() == i {
                            for (d, c) in x.derivatives.iter_mut().zip(batch) {
                                *d = c[k];
                            }
                        }
                    }
                    x
                })
                .collect();
            let mut memo = Default::default();
            for (body, speed) in bodies.clone().zip(speeds.iter_mut()) {
                for (x, out) in body.centre.iter().zip(speed.iter_mut()) {
                    let v = self.engine.eval_memo(*x, &moving, &mut memo);
                    out.extend_from_slice(&v.derivatives[..batch.len()]);
                }
            }
        }
        speeds
    }

    /// `l`(q, c) + `l`(q, −c) − 2 `l`(q, 0) for `l` quadratic in the
    /// velocities, with the sum of the samples' sizes.
    fn lagrangian_sampled_along(&self, l: ExprId, c: &[Dd], vals: &mut [Dd]) -> (Dd, Dd) {
        let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
        for (sign, weight) in [(1.0, 1.0), (-1.0, 1.0), (0.0, -2.0)] {
            for (coordinate, &ci) in self.model.coordinates.iter().zip(c) {
                vals[coordinate.velocity.index()] = Dd::from_f64(sign) * ci;
            }
            let (l, size) = self.engine.eval_with_scale(l, vals);
            value = value + Dd::from_f64(weight) * l;
            scale = scale + Dd::from_f64(weight.abs()) * size;
        }
        (value, scale)
    }

    pub(crate) fn curvature_route_parts(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> Reduced {
        let (n, k) = (self.model.n(), self.model.k());
        let map = self.constrained_velocities();
        let qdot_c = self.constrained_qdot();
        let l = self.lagrangian();
        let r_vel = self.model.independent_velocities();
        let r_pos = self.model.of_independent(|c| c.position);
        let r_force = self.model.of_independent(|c| c.force);
        let q = &self.model.coordinates;
        let e = &mut *self.engine;
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
            .model
            .constraints
            .iter()
            .map(|c| {
                let d = e.diff(l, q[c.dependent].velocity);
                e.subst(d, &map, &mut memo)
            })
            .collect();
        let mut rhs = Vec::with_capacity(k);
        for al in 0..k {
            let mut lhs = Vec::new();
            // velocity part of d/dt ∂Lc/∂ṙ_α
            for i in 0..n {
                let d = e.diff(pc[al], q[i].position);
                if d != ZERO {
                    lhs.push(e.mul(d, qdot_c[i]));
                }
            }
            lhs.push(e.diff(pc[al], self.model.time));
            // − ∂Lc/∂r_α
            let d = e.diff(lc, r_pos[al]);
            lhs.push(e.neg(d));
            // + Σ_a A^a_α ∂Lc/∂s_a
            for c in &self.model.constraints {
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
            for c in &self.model.constraints {
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
        Reduced {
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
        let e = &mut *self.engine;
        if k == 0 || k > 3 {
            return None;
        }
        let small = mass.iter().flatten().all(|&x| e.num_terms(x) <= 24)
            && rhs.iter().all(|&x| e.num_terms(x) <= 64);
        if !small {
            return None;
        }
        let x = crate::algebra::ldlt::solve_nonsingular(e, mass, rhs, Updates::Formed)?;
        if e.overflowed() {
            return None;
        }
        Some(x)
    }
}

#[cfg(test)]
mod sled_tests {
    use super::super::scene::Scene;
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled's curvature B^y_{xθ} = −B^y_{θx} = ±sec²θ, and its reduced
    /// equations Mc = diag(m sec²θ, J) whose solution is the closed form of
    /// the motion: the speed along the blade ẋ/cos θ is constant, so
    /// ẍ = −tan θ θ̇ ẋ, and θ̈ = 0.
    #[test]
    fn the_sleds_curvature_and_reduced_equations() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let b = scene.curvature();
        let reduced = scene.curvature_route(&b);
        let at = sled_at();
        let v = |e| value(&model, scene.engine, e, &at);
        let sec2 = 1.0 / 0.3f64.cos().powi(2);
        assert!(close(v(b[0][0][1]).abs(), sec2));
        assert!(close(v(b[0][1][0]), -v(b[0][0][1])));
        assert_eq!((v(b[0][0][0]), v(b[0][1][1])), (0.0, 0.0));
        let mass = [[2.0 * sec2, 0.0], [0.0, 0.5]];
        for (row, want) in reduced.mass.iter().zip(mass) {
            for (&e, w) in row.iter().zip(want) {
                assert!(close(v(e), w));
            }
        }
        let xdd = v(reduced.rhs[0]) / (2.0 * sec2);
        assert!(close(xdd, -(0.3f64.tan()) * -1.1 * 0.7), "{xdd}");
        assert_eq!(v(reduced.rhs[1]), 0.0);
    }
}
