//! The kinematic tree of a chain of bodies (DESIGN §10): a body's centre
//! reached from a fixed point (the origin, or a point of the mechanism
//! free of the state) through any number of links, each a body frame in
//! which the next point sits at a constant offset from the last — the
//! links of an arm or a pendulum of many bodies, written as `let`s
//! `E_i = E_{i-1} + R_i*[l, 0, 0]`. Its partial velocities then come as
//! screws and its acceleration link by link on the graph, not from the
//! expanded ∂C/∂q.

use super::chains::Chain;
use super::scene::Scene;
use crate::lower::values::{Mat3, Vec3, mat_vec, transpose};
use crate::sym::dd::Dd;
use crate::sym::{ExprId, SymId, ZERO};
use rustc_hash::FxHashMap as HashMap;

/// A frame of the tree: a body's orientation, ω_b and elementary rotations.
pub(super) type TreeFrame = (Mat3, Vec3, Vec<(usize, ExprId)>);

/// States at which an offset must take one value (the same parameters, the
/// coordinates drawn anew): the first two screen the pairs in floating
/// point, all of them confirm a link in double-double.
const STATES: usize = 6;

/// Relative tolerance of the double-double confirmation, far above its
/// rounding (about 1e-30 of the values' sizes) and far below any offset
/// that moves.
const CONFIRM: f64 = 1e-20;

/// The fewest links a tree chain takes: a point one link from a fixed
/// point has a short expanded ∂C/∂q, which the random systems of the
/// snapshot set showed to be as cheap (a point mass on one link: 91
/// operations that way, 102 as screws).
const MIN_LINKS: usize = 2;

/// The most terms a component of a moving root may have.
const ROOT_TERMS: usize = 4;

/// The points' and frames' values at [`STATES`] states.
struct Sampled {
    points: Vec<Vec<[Dd; 3]>>,
    frames: Vec<Vec<[[Dd; 3]; 3]>>,
}

/// The points a chain may pass through (the origin, the mechanism's vector
/// `let`s and the bodies' centres) and the frames of its links, sampled.
pub(super) struct Tree {
    points: Vec<Vec3>,
    frames: Vec<TreeFrame>,
    sampled: Sampled,
}

impl Scene<'_> {
    /// The tree of `frames` over the origin, the mechanism's points and
    /// `centres`.
    pub(super) fn tree(&self, frames: Vec<TreeFrame>, centres: &[Vec3]) -> Tree {
        let mut points: Vec<Vec3> = vec![[ZERO; 3]];
        for &p in self.model.points.iter().chain(centres) {
            if !points.contains(&p) {
                points.push(p);
            }
        }
        let sampled = self.sampled(&points, &frames);
        Tree {
            points,
            frames,
            sampled,
        }
    }

    /// A chain to `target` (one of the tree's points) from a fixed point
    /// through links of the tree's frames, the fewest links first; `None`
    /// if there is none or a link's offset is not confirmed constant. A
    /// chain of fewer than [`MIN_LINKS`] links is returned too, marked:
    /// only the composite inertias take it (its body's own sums do not).
    pub(super) fn tree_chain(
        &mut self,
        tree: &Tree,
        target: Vec3,
        heading: &Option<Mat3>,
    ) -> Option<(Chain, bool)> {
        let start = tree.points.iter().position(|&p| p == target)?;
        if tree.frames.is_empty() || self.fixed_point(target) {
            return None;
        }
        // a fixed root first; else a short one whose ∂p/∂q is taken
        let fixed: Vec<bool> = (tree.points.iter()).map(|&p| self.fixed_point(p)).collect();
        let short: Vec<bool> = (tree.points.iter()).map(|&p| self.short_point(p)).collect();
        let path = search(&tree.sampled, &tree.points, start, |p| fixed[p])
            .or_else(|| search(&tree.sampled, &tree.points, start, |p| fixed[p] || short[p]))?;
        let mut links = Vec::with_capacity(path.len());
        for &(from, to, f) in path.iter().rev() {
            let frame = &tree.frames[f];
            let offset = self.tree_offset(&frame.0, tree.points[to], tree.points[from])?;
            links.push(self.link(frame, offset, heading));
        }
        let root = path.last().map(|&(from, _, _)| tree.points[from])?;
        let short = links.len() < MIN_LINKS;
        Some((self.chain(root, links, heading), short))
    }

    /// Whether `p` is short enough to be a root whose ∂p/∂q is taken from
    /// its expression (a vehicle's point the arm is mounted at).
    fn short_point(&self, p: Vec3) -> bool {
        p.iter().all(|&x| self.engine.num_terms(x) <= ROOT_TERMS)
    }

    /// Whether every component of `p` is free of the state.
    fn fixed_point(&self, p: Vec3) -> bool {
        p.iter().all(|&x| self.fixed(x))
    }

    /// The values of `points` and `frames` at the states (one memo per
    /// state: the points of a chain share their expressions).
    fn sampled(&self, points: &[Vec3], frames: &[TreeFrame]) -> Sampled {
        let mut rng = crate::sym::Rng::new(0x2B99_2DDF_A232_49D6);
        let first = rng.point(self.engine.num_symbols(), self.model.pi);
        let mut sampled = Sampled {
            points: vec![Vec::with_capacity(STATES); points.len()],
            frames: vec![Vec::with_capacity(STATES); frames.len()],
        };
        for _ in 0..STATES {
            let mut s = first.clone();
            for c in &self.model.coordinates {
                s[c.position.index()] = Dd::from_f64(0.3 + 1.1 * rng.next_f64());
            }
            let mut memo = crate::sym::EvalMemo::default();
            let mut value = |x: ExprId| self.engine.eval_memo(x, &s, &mut memo);
            for (out, p) in sampled.points.iter_mut().zip(points) {
                out.push(p.map(&mut value));
            }
            for (out, f) in sampled.frames.iter_mut().zip(frames) {
                out.push(f.0.map(|row| row.map(&mut value)));
            }
        }
        sampled
    }

    /// Rᵀ(p − q) as an expression of the parameters alone (its value at
    /// q = 0), if it is constant: the sampled values confirm that, and the
    /// value at q = 0 is formed from the substituted (short) expressions.
    fn tree_offset(&mut self, r: &Mat3, p: Vec3, q: Vec3) -> Option<Vec3> {
        let zero: HashMap<SymId, ExprId> = (self.model.coordinates.iter())
            .map(|c| (c.position, ZERO))
            .collect();
        let e = &mut *self.engine;
        let mut memo = HashMap::default();
        let r0 = r.map(|row| row.map(|x| e.subst(x, &zero, &mut memo)));
        let d0 = [0, 1, 2].map(|x| {
            let (a, b) = (
                e.subst(p[x], &zero, &mut memo),
                e.subst(q[x], &zero, &mut memo),
            );
            e.sub(a, b)
        });
        let offset = mat_vec(e, &transpose(&r0), d0);
        offset.iter().all(|&x| self.fixed(x)).then_some(offset)
    }
}

/// The links (from, to, frame) of the shortest path from a root to point `start`,
/// target first, breadth first over the points: `to` = `from` + R r with r
/// constant in frame R at every sampled state.
fn search(
    s: &Sampled,
    points: &[Vec3],
    start: usize,
    is_root: impl Fn(usize) -> bool,
) -> Option<Vec<(usize, usize, usize)>> {
    let mut reached: Vec<Option<(usize, usize)>> = vec![None; points.len()];
    let mut frontier = vec![start];
    let mut seen = vec![false; points.len()];
    seen[start] = true;
    while !frontier.is_empty() {
        let mut next = Vec::new();
        for &to in &frontier {
            for from in 0..points.len() {
                if seen[from] || points[from] == points[to] {
                    continue;
                }
                let Some(f) = (0..s.frames.len()).find(|&f| fixed_offset(s, f, to, from)) else {
                    continue;
                };
                seen[from] = true;
                reached[from] = Some((to, f));
                if is_root(from) {
                    let mut path = Vec::new();
                    let mut at = from;
                    while let Some((to, f)) = reached[at] {
                        path.push((at, to, f));
                        at = to;
                    }
                    path.reverse();
                    return Some(path);
                }
                next.push(from);
            }
        }
        frontier = next;
    }
    None
}

/// Whether R_fᵀ(p_to − p_from) takes one value at every sampled state:
/// screened at two in floating point, confirmed at all in double-double.
fn fixed_offset(s: &Sampled, f: usize, to: usize, from: usize) -> bool {
    let offset = |k: usize| -> ([Dd; 3], f64) {
        let (r, p, q) = (&s.frames[f][k], &s.points[to][k], &s.points[from][k]);
        let d = [0, 1, 2].map(|x| p[x] - q[x]);
        let size = (0..3).fold(1.0f64, |m, x| {
            m.max(p[x].abs().to_f64()).max(q[x].abs().to_f64())
        });
        (
            [0, 1, 2].map(|j| (0..3).fold(Dd::ZERO, |acc, i| acc + r[i][j] * d[i])),
            size,
        )
    };
    let (first, size) = offset(0);
    let close =
        |a: [Dd; 3], tol: f64| (0..3).all(|x| (a[x] - first[x]).abs().to_f64() <= tol * size);
    close(offset(1).0, 1e-9) && (1..STATES).all(|k| close(offset(k).0, CONFIRM))
}
