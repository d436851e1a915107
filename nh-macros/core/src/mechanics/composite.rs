//! Economies of Kane's form and the contact rows (DESIGN §10): bodies whose
//! centres of mass are fixed in another body's frame move as one, points'
//! accelerations chain through the frames that hold them, and a uniform
//! gravity acts through the partial velocities the bodies need anyway.

use super::chains::{Chain, Link};
use super::scene::Scene;
use super::tree::Tree;
use crate::lower::values::{Mat3, Vec3, mat_vec, transpose};
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, ONE, SymId, ZERO};

/// A body's orientation, body angular velocity and elementary rotations.
type Body = (Mat3, Vec3, Vec<(usize, ExprId)>);

/// A wheel's spin: the axis k and angle θ of its orientation's last factor.
pub(super) type Spin = Option<(usize, ExprId)>;

/// A body of Kane's form, before its Jacobians are taken.
pub(super) struct Part {
    /// m (of the body and of the centres folded into it).
    pub(super) mass: ExprId,
    /// The centre of mass (world components); `None` once it is folded
    /// into a carrier's.
    pub(super) centre: Option<Vec3>,
    /// ω_b (body components), the inertia about the centre of mass (body
    /// axes, with the folded centres' parallel-axis terms) and the spin
    /// axis and angle of a wheel.
    pub(super) rotation: Option<(Vec3, Mat3, Spin)>,
    /// The orientation (body → world, by rows).
    pub(super) orientation: Option<Mat3>,
    /// (μ, d) of the centres folded into this body's: its inertia gains
    /// μ(|d|² 1 − d dᵀ) each (see the body's `Inertia`).
    pub(super) masses: Vec<(ExprId, Vec3)>,
    /// The wheels whose rotation was folded into this body's.
    pub(super) wheels: Vec<Wheel>,
    /// The elementary rotations of the orientation.
    pub(super) factors: Vec<(usize, ExprId)>,
}

impl Scene<'_> {
    /// Folds every centre of mass fixed in another body's frame into that
    /// body's: with d = Rᵀ(C_b − C_a) constant, the pair moves as the mass
    /// M = m_a + m_b at G = C_a + R (m_b/M) d, and the carrier's inertia gains
    /// μ(|d|² 1 − d dᵀ), μ = m_a m_b/M, since
    /// m_a|Ċ_a|² + m_b|Ċ_b|² = M|Ġ|² + μ|ω × R d|². The folded body keeps its
    /// own rotation. A carrier spinning as a wheel is passed over (the added
    /// inertia is not symmetric about its axis).
    pub(super) fn fold_fixed_centres(&mut self, parts: &mut [Part]) {
        for b in 0..parts.len() {
            let Some(cb) = parts[b].centre else { continue };
            for a in 0..parts.len() {
                if a != b && self.fold_into(parts, a, cb, parts[b].mass) {
                    parts[b].centre = None;
                    break;
                }
            }
        }
    }

    /// Folds the mass `mb` at `cb` into part `a` if `cb` is fixed in its
    /// frame; whether it did.
    fn fold_into(&mut self, parts: &mut [Part], a: usize, cb: Vec3, mb: ExprId) -> bool {
        let p = &parts[a];
        let (Some(ca), Some(r), Some((_, _, None))) = (p.centre, p.orientation, p.rotation) else {
            return false;
        };
        let ma = p.mass;
        if !self.offset_may_be_fixed(&r, cb, ca) {
            return false;
        }
        let e = &mut *self.engine;
        let rel = [0, 1, 2].map(|x| e.sub(cb[x], ca[x]));
        let d = mat_vec(e, &transpose(&r), rel);
        let (Some(d0), Some(d1), Some(d2)) = (
            self.constant_in_state(d[0]),
            self.constant_in_state(d[1]),
            self.constant_in_state(d[2]),
        ) else {
            return false;
        };
        let d = [d0, d1, d2];
        if !(self.fixed(ma) && self.fixed(mb)) {
            return false;
        }
        let e = &mut *self.engine;
        let total = e.add(ma, mb);
        let share = e.div(mb, total);
        let offset = d.map(|x| e.mul(share, x));
        let shift = mat_vec(e, &r, offset);
        let centre = [0, 1, 2].map(|x| e.add(ca[x], shift[x]));
        let product = e.mul(ma, mb);
        let mu = e.div(product, total);
        let p = &mut parts[a];
        p.mass = total;
        p.centre = Some(centre);
        p.masses.push((mu, d));
        true
    }

    /// Folds every wheel turning on an axle of another body into it: with
    /// the wheel's ω = ω_a + θ̇ e_k (the carrier's axes) and its inertia
    /// A(1 − e_k e_kᵀ) + C e_k e_kᵀ, its kinetic energy is
    /// ½ ω_aᵀ A(1 − e_k e_kᵀ) ω_a + ½ C s², s = ω_a,k + θ̇, so the carrier's
    /// inertia gains the transverse part and the wheel keeps only its spin s
    /// (DESIGN §10).
    pub(super) fn fold_wheels(&mut self, parts: &mut [Part]) {
        for b in 0..parts.len() {
            let Some((omega, inertia, Some((k, angle)))) = parts[b].rotation else {
                continue;
            };
            let e = &mut *self.engine;
            let turn = crate::lower::values::elementary(e, k, angle);
            let turned = mat_vec(e, &turn, omega);
            let rate = self.along_motion(angle);
            for a in 0..parts.len() {
                if a != b && self.carries(&parts[a], turned, k, rate) {
                    let wheel = Wheel {
                        axis: k,
                        moment: inertia[k][k],
                        rate,
                    };
                    let transverse = inertia[(k + 1) % 3][(k + 1) % 3];
                    let p = &mut parts[a];
                    if let Some((_, carrier, _)) = p.rotation.as_mut() {
                        for (x, row) in carrier.iter_mut().enumerate() {
                            if x != k {
                                row[x] = self.engine.add(row[x], transverse);
                            }
                        }
                    }
                    p.wheels.push(wheel);
                    parts[b].rotation = None;
                    break;
                }
            }
        }
    }

    /// Whether a wheel whose ω in its carrier's axes is `turned` spins at
    /// `rate` about axis k of `carrier`: turned − θ̇ e_k = ω_carrier (first
    /// at one state in floating point, then at 16 in double-double).
    fn carries(&mut self, carrier: &Part, turned: Vec3, k: usize, rate: ExprId) -> bool {
        let Some((omega, _, None)) = carrier.rotation else {
            return false;
        };
        let e = &mut *self.engine;
        let gap = [0, 1, 2].map(|x| {
            let own = if x == k {
                e.sub(turned[x], rate)
            } else {
                turned[x]
            };
            e.sub(own, omega[x])
        });
        let [a, _] = self.two_states();
        let small = gap.iter().all(|&x| {
            let (v, scale) = self.engine.eval_with_scale(x, &a);
            let (v, scale) = (v.to_f64(), scale.to_f64());
            v.is_finite() && v.abs() <= 1e-9 * (1.0 + scale)
        });
        small && vanish_at_random_points(self.engine, self.model.pi, &gap)
    }

    /// The chain of a body's centre from a contact's centre whose own rate
    /// is computed (a root, DESIGN §10), if the body does not spin.
    /// Else, the chain of its centre from a fixed point through any number
    /// of links ([`Scene::tree_chain`]), or, for a chain too short to
    /// anchor the body's own sums, in the second place.
    /// `tree` is built on the first call that needs it, from `centres`.
    pub(super) fn anchor(
        &mut self,
        part: &Part,
        frame: &Option<Mat3>,
        (tree, centres): (&mut Option<Tree>, &[Vec3]),
    ) -> (Option<Chain>, Option<Chain>) {
        let Some(c) = part.centre else {
            return (None, None);
        };
        let spins = !matches!(part.rotation, Some((_, _, None)));
        if !spins && let Some(chain) = self.contact_anchor(c, frame) {
            return (Some(chain), None);
        }
        if tree.is_none() {
            *tree = Some(self.tree(self.tree_frames(), centres));
        }
        match tree.as_ref().and_then(|t| self.tree_chain(t, c, frame)) {
            Some((chain, true)) => (None, Some(chain)),
            Some((chain, false)) => (Some(chain), None),
            None => (None, None),
        }
    }

    /// The chain of a centre `c` from a contact's centre, if there is one.
    fn contact_anchor(&mut self, c: Vec3, frame: &Option<Mat3>) -> Option<Chain> {
        let roots: Vec<Vec3> = self
            .model
            .contact_kinematics
            .iter()
            .zip(&self.contact_chains)
            .filter(|(_, chain)| chain.is_none())
            .map(|(k, _)| k.centre)
            .collect();
        self.chain_to(c, &roots, frame)
    }

    /// Per contact, a chain of its centre from an earlier contact's centre
    /// (none for the roots, whose J̇ q̇ is computed).
    pub(super) fn contact_chains(&mut self, frame: &Option<Mat3>) -> Vec<Option<Chain>> {
        let centres: Vec<Vec3> = self
            .model
            .contact_kinematics
            .iter()
            .map(|k| k.centre)
            .collect();
        let mut roots = Vec::new();
        let mut chains = Vec::new();
        for c in centres {
            let chain = self.chain_to(c, &roots, frame);
            if chain.is_none() {
                roots.push(c);
            }
            chains.push(chain);
        }
        chains
    }

    /// A chain to `target` from one of `roots`: one frame in which target −
    /// root is fixed, or two through a point of [`Model::points`] (a joint).
    fn chain_to(&mut self, target: Vec3, roots: &[Vec3], frame: &Option<Mat3>) -> Option<Chain> {
        if roots.is_empty() {
            return None;
        }
        let frames = self.frames();
        for &root in roots {
            for f in &frames {
                if let Some(r) = self.offset_in(&f.0, target, root) {
                    let link = self.link(f, r, frame);
                    return Some(self.chain(root, vec![link], frame));
                }
            }
        }
        let joints: Vec<Vec3> = self.model.points.clone();
        for joint in joints {
            if joint == target || roots.contains(&joint) {
                continue;
            }
            for f2 in &frames {
                let Some(r2) = self.offset_in(&f2.0, target, joint) else {
                    continue;
                };
                for &root in roots {
                    for f1 in &frames {
                        if let Some(r1) = self.offset_in(&f1.0, joint, root) {
                            let links = vec![self.link(f1, r1, frame), self.link(f2, r2, frame)];
                            return Some(self.chain(root, links, frame));
                        }
                    }
                }
            }
        }
        None
    }

    /// The orientations, body angular velocities and elementary rotations
    /// of the bodies that do not spin as wheels.
    fn frames(&self) -> Vec<Body> {
        let Some(split) = &self.model.kinetic else {
            return Vec::new();
        };
        split
            .bodies
            .iter()
            .filter(|b| b.spin.is_none())
            .filter_map(|b| Some((b.orientation?, b.rotation?.0, b.factors.clone())))
            .collect()
    }

    /// The frames of every body with elementary rotations, spinning or not:
    /// the links of a kinematic tree (a link of a chain turns about the
    /// axis of its last factor like a wheel when its inertia is symmetric
    /// about that axis).
    fn tree_frames(&self) -> Vec<Body> {
        let Some(split) = &self.model.kinetic else {
            return Vec::new();
        };
        (split.bodies.iter())
            .filter(|b| !b.factors.is_empty())
            .filter_map(|b| Some((b.orientation?, b.rotation?.0, b.factors.clone())))
            .collect()
    }

    /// Rᵀ(p − q), if constant.
    fn offset_in(&mut self, r: &Mat3, p: Vec3, q: Vec3) -> Option<Vec3> {
        if !self.offset_may_be_fixed(r, p, q) {
            return None;
        }
        let e = &mut *self.engine;
        let rel = [0, 1, 2].map(|x| e.sub(p[x], q[x]));
        let offset = mat_vec(e, &transpose(r), rel);
        let mut out = [ZERO; 3];
        for (o, x) in out.iter_mut().zip(offset) {
            *o = self.constant_in_state(x)?;
        }
        Some(out)
    }

    /// A link of frame `f` holding the next point at `offset`. Its turn R
    /// (in the frame of J) is formed only for a link without elementary
    /// rotations, the only one whose acceleration takes it.
    pub(super) fn link(&mut self, f: &Body, offset: Vec3, frame: &Option<Mat3>) -> Link {
        let (kept, tail) = self.trimmed(&f.2);
        let (offset, steps) = match (self.frame_of(&kept, frame.is_some()), tail) {
            (Some(steps), Some(tail)) => (mat_vec(self.engine, &tail, offset), Some(steps)),
            _ => (offset, self.frame_of(&f.2, frame.is_some())),
        };
        let turn = match (frame, &steps) {
            (Some(h), None) => crate::lower::values::mat_mat(self.engine, h, &f.0),
            _ => f.0,
        };
        Link {
            omega: f.1,
            offset,
            turn,
            frame: steps,
        }
    }

    pub(super) fn chain(&mut self, root: Vec3, links: Vec<Link>, frame: &Option<Mat3>) -> Chain {
        let jacobian = root.map(|x| self.positional_jacobian(x));
        Chain {
            root: self.in_frame(frame, jacobian),
            links,
        }
    }

    /// `x` as an expression of the parameters alone, if it does not change
    /// with the state: free of it, or depending on the coordinates only
    /// through an identity the canonical form does not know (a product of
    /// rotations RᵀR): x is then its value at q = 0, which x − x(q = 0)
    /// vanishing at random points shows.
    fn constant_in_state(&mut self, x: ExprId) -> Option<ExprId> {
        if self.fixed(x) {
            return Some(x);
        }
        let syms = self.engine.free_symbols(x).to_vec();
        let velocities = |s: &SymId| {
            *s == self.model.time
                || self.model.inputs.iter().any(|u| u.sym == *s)
                || self.model.coordinates.iter().any(|c| c.velocity == *s)
        };
        if syms.iter().any(velocities) || self.varies(x) {
            return None;
        }
        let zero: rustc_hash::FxHashMap<SymId, ExprId> = self
            .model
            .coordinates
            .iter()
            .map(|c| (c.position, ZERO))
            .collect();
        let at_zero = self.engine.subst(x, &zero, &mut Default::default());
        let change = self.engine.sub(x, at_zero);
        (self.fixed(at_zero) && vanish_at_random_points(self.engine, self.model.pi, &[change]))
            .then_some(at_zero)
    }

    /// Whether Rᵀ(p − q) takes the same value at two states (the same
    /// parameters), in floating point: a quick test that spares forming the
    /// products symbolically for the pairs that are not fixed.
    fn offset_may_be_fixed(&mut self, r: &Mat3, p: Vec3, q: Vec3) -> bool {
        let [x, y] = [0, 1].map(|s| {
            let mut v = |x: ExprId| self.sample(x, s);
            let rel = [0, 1, 2].map(|i| v(p[i]) - v(q[i]));
            let r = r.map(|row| row.map(&mut v));
            [0, 1, 2].map(|j| (0..3).map(|i| r[i][j] * rel[i]).sum::<f64>())
        });
        (0..3).all(|i| {
            let size = 1.0 + x[i].abs().max(y[i].abs());
            !(x[i] - y[i]).is_finite() || (x[i] - y[i]).abs() <= 1e-9 * size
        })
    }

    /// The value of `x` at state `s` (0 or 1) of [`Scene::two_states`],
    /// memoised for the whole derivation.
    fn sample(&mut self, x: ExprId, s: usize) -> f64 {
        let symbols = self.engine.num_symbols();
        if self
            .samples
            .as_ref()
            .is_none_or(|m| m.states[0].len() != symbols)
        {
            let states = self.two_states();
            self.samples = Some(Box::new(super::scene::Samples {
                states,
                memos: Default::default(),
            }));
        }
        let samples = self.samples.as_mut().expect("just filled");
        let memo = &mut samples.memos[s];
        self.engine.eval_memo(x, &samples.states[s], memo).to_f64()
    }

    /// The symbols' values at two states with the same parameters.
    fn two_states(&self) -> [Vec<crate::sym::dd::Dd>; 2] {
        use crate::sym::dd::Dd;
        let mut rng = crate::sym::Rng::new(0x4528_21E6_38D0_1377);
        let a = rng.point(self.engine.num_symbols(), self.model.pi);
        let mut b = a.clone();
        for c in &self.model.coordinates {
            b[c.position.index()] = Dd::from_f64(0.3 + 1.1 * rng.next_f64());
        }
        [a, b]
    }

    /// Whether `x` takes different values at two states (the same
    /// parameters): a quick test before the exact one.
    fn varies(&self, x: ExprId) -> bool {
        let [a, b] = self.two_states();
        let (x0, scale) = self.engine.eval_with_scale(x, &a);
        let x1 = self.engine.eval_with_scale(x, &b).0;
        let (x0, x1, scale) = (x0.to_f64(), x1.to_f64(), scale.to_f64());
        x0.is_finite() && x1.is_finite() && (x0 - x1).abs() > 1e-9 * scale
    }

    /// Whether `x` is free of the coordinates, velocities, inputs and t.
    pub(super) fn fixed(&self, x: ExprId) -> bool {
        let moving = |s: &SymId| {
            *s == self.model.time
                || self.model.inputs.iter().any(|u| u.sym == *s)
                || self
                    .model
                    .coordinates
                    .iter()
                    .any(|c| c.position == *s || c.velocity == *s)
        };
        !self.engine.free_symbols(x).iter().any(moving)
    }

    /// A uniform gravity in `rest` = L − Σ T_b along a world axis: the
    /// first of z, y, x along which [`Scene::gravity_along`] finds one (y
    /// and x only without a block of rolling contacts), as γ e_k in the
    /// axes of the centres' partial velocities (the heading's frame turns
    /// e_x and e_y, and leaves e_z); and the rest of `rest`.
    pub(super) fn gravity(&mut self, parts: &[Part], rest: ExprId) -> Option<(Vec3, ExprId)> {
        let axes = match self.block.is_none() {
            true => &[2, 1, 0][..],
            false => &[2][..],
        };
        for &k in axes {
            if let Some((g, rest)) = self.gravity_along(parts, rest, k) {
                let frame = match k {
                    2 => None,
                    _ => self.heading_frame(),
                };
                let weight = [0, 1, 2].map(|x| match frame {
                    Some(h) => self.engine.mul(g, h[x][k]),
                    None if x == k => g,
                    None => ZERO,
                });
                return Some((weight, rest));
            }
        }
        None
    }

    /// A uniform gravity in `rest` along world axis k: the γ (free of the
    /// state) that leaves the fewest terms in rest + γ Σ m_b C_b,k, if
    /// that is fewer than rest has, and that remainder. Its Euler–Lagrange
    /// terms are then γ Σ m_b ∂C_b,k/∂q, projected γ Σ m_b V_b,k.
    fn gravity_along(
        &mut self,
        parts: &[Part],
        rest: ExprId,
        k: usize,
    ) -> Option<(ExprId, ExprId)> {
        let e = &mut *self.engine;
        let heights: Vec<ExprId> = parts
            .iter()
            .filter_map(|p| p.centre.map(|c| e.mul(p.mass, c[k])))
            .collect();
        let weight = e.sum(&heights);
        if self.fixed(weight) || rest == ZERO {
            return None;
        }
        let mut candidates = self.gravity_candidates(weight, rest);
        let (w, r) = (self.sample(weight, 0), self.sample(rest, 0));
        let mut matched = Vec::new();
        for &g in &candidates {
            let g_value = self.sample(g, 0);
            if (r + g_value * w).abs() <= 1e-9 * (r.abs() + (g_value * w).abs()) {
                matched.push(g);
            }
        }
        if !matched.is_empty() {
            // rest is exactly −γ Σ m C_z at a random state: test only those
            candidates = matched.clone();
        }
        let mut best = (self.engine.num_terms(rest), None);
        for g in candidates {
            let e = &mut *self.engine;
            let w = e.mul(g, weight);
            let r = e.add(rest, w);
            let n = e.num_terms(r);
            if n < best.0 {
                best = (n, Some((g, r)));
            }
        }
        if let Some((_, ZERO)) = best.1 {
            return best.1;
        }
        // a remainder the canonical form does not cancel (long sums kept as
        // atoms, `sym::SCALED_MIN`) but that vanishes at random points is
        // zero: the whole rest was the weight
        for &g in &matched {
            let e = &mut *self.engine;
            let w = e.mul(g, weight);
            let r = e.add(rest, w);
            if vanish_at_random_points(self.engine, self.model.pi, &[r]) {
                return Some((g, ZERO));
            }
        }
        best.1
    }

    /// Every parameter and its negative, ±1 and the leading terms' ratio.
    fn gravity_candidates(&mut self, weight: ExprId, rest: ExprId) -> Vec<ExprId> {
        let mut candidates: Vec<ExprId> = Vec::new();
        for p in &self.model.parameters {
            let g = self.engine.sym(p.sym);
            candidates.push(g);
            candidates.push(self.engine.neg(g));
        }
        candidates.push(ONE);
        candidates.push(self.engine.int(-1));
        if let Some(c) = self.leading_ratio(weight, rest) {
            candidates.push(c);
        }
        candidates
    }

    /// −c_rest/c_weight for the first term of `weight` that `rest` has too
    /// (a gravity written as a number).
    fn leading_ratio(&mut self, weight: ExprId, rest: ExprId) -> Option<ExprId> {
        let e = &self.engine;
        let (m, cw) = *e.terms(weight).first()?;
        let &(_, cr) = e.terms(rest).iter().find(|(n, _)| *n == m)?;
        let ratio = cr.checked_div(cw)?;
        let c = self.engine.constant(ratio);
        Some(self.engine.neg(c))
    }
}

/// A wheel turning at θ̇ about axis k of the body that carries it, whose
/// rotation is folded into its carrier's (DESIGN §10): the carrier's
/// inertia holds the wheel's transverse moment A, and the wheel adds only
/// its spin s = ω_k + θ̇ about the axle, with the moment C: the generalized
/// inertia forces C S ṡ + C s Ωᵀ(ω × e_k), S = ∂s/∂ṙ.
#[derive(Clone, Copy)]
pub struct Wheel {
    /// k.
    pub axis: usize,
    /// C, the moment about the axle.
    pub moment: ExprId,
    /// θ̇.
    pub rate: ExprId,
}
