//! The articulated-body inertias of a tree of generators (DESIGN §10):
//! Cᵀ M C r̈ = f solved by the recursion of Featherstone's
//! articulated-body algorithm, in operations linear in the links where the
//! LDLᵀ of the dense Cᵀ M C takes k³/3.
//!
//! It applies where the composite inertias (`composite_inertia.rs`) carry
//! all of Cᵀ M C and each generator that moves turns at a multiple c_g of
//! one reduced rate of its own, every rate being some generator's: then
//! Cᵀ M C = Σ_{g, h} s_gᵀ I_{gh} s_h with s_g = c_g (ω_g, v_g), its rows
//! and columns those of the generators. The members that move with each
//! generator must form a tree (any two such sets nested or apart), the
//! generator of a set inside another's its child: the mass matrix of the
//! tree is then the joint-space inertia of a multibody system with joint
//! axes s_g, all about the root and in the world's axes (no transforms),
//! and its solve is the articulated-body algorithm with no velocities:
//! tips to root, Iᴬ_g = I_g + Σ_children (Iᴬ_c − U_c U_cᵀ / D_c) with
//! U = Iᴬ s and D = sᵀ U; then for each right side, tips to root the bias
//! forces p, u_g = f_g − s_gᵀ p_g, p_parent += p_g + U_g u_g / D_g, and root
//! to tips a_g = a_parent + s_g r̈_g with r̈_g = (u_g − U_gᵀ a_parent) / D_g.

use super::composite_inertia::{Composite, GroupNodes, Spatial, Twist, add_spatial};
use crate::algebra;
use crate::algebra::ldlt;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};

/// A spatial vector: (ω, v) or (N, F) about the root, world axes.
type Six = [Node; 6];
/// A symmetric 6 × 6 matrix (both triangles hold the same nodes).
type Sym6 = [[Node; 6]; 6];

/// The factors of the articulated-body solve: its generators, parents
/// before children.
pub(crate) struct Articulated {
    joints: Vec<Joint>,
}

/// A generator of the tree with its articulated-body factors.
struct Joint {
    parent: Option<usize>,
    /// The reduced rate it turns with.
    coord: usize,
    /// Its axis s = c (ω, v).
    s: Six,
    /// U / D.
    w: Six,
    /// 1 / D.
    inv_d: Node,
}

/// A generator placed in the tree: its group, index and parent.
struct Placed {
    group: usize,
    x: usize,
    parent: Option<usize>,
    coord: usize,
}

impl Articulated {
    /// The factors for `k` reduced rates, if the composite inertias of
    /// `comp` carry all of Cᵀ M C (`pure`: nothing else added to it) as a
    /// tree whose generators each take one rate of their own.
    pub(crate) fn of(d: &mut Dag, comp: &Composite, k: usize, pure: bool) -> Option<Articulated> {
        if !pure || comp.groups().is_empty() {
            return None;
        }
        let placed = place(comp.groups(), k)?;
        let n = placed.len();
        let mut acc: Vec<Option<Sym6>> = vec![None; n];
        let mut links = links(d, comp.groups(), &placed);
        let mut joints: Vec<Option<Joint>> = (0..n).map(|_| None).collect();
        for i in (0..n).rev() {
            let p = &placed[i];
            let g = &comp.groups()[p.group];
            let mut ia = acc[i].take().unwrap_or([[ZERO_NODE; 6]; 6]);
            if let Some(link) = links[i].take() {
                add_rigid(d, &mut ia, &link);
            }
            let c = g.rates[p.x][p.coord];
            let s = six(d, c, g.twists[p.x]);
            let u: Six = std::array::from_fn(|x| algebra::dot(d, (0..6).map(|y| (ia[x][y], s[y]))));
            let dd = algebra::dot(d, (0..6).map(|x| (s[x], u[x])));
            if dd == ZERO_NODE {
                // no inertia along the joint: structurally singular, which
                // the LDLᵀ pivots report
                return None;
            }
            d.label(
                dd,
                format!(
                    "articulated inertia along the joint of r̈{}: D = sᵀ Iᴬ s",
                    p.coord
                ),
            );
            let inv_d = d.div(ONE_NODE, dd);
            let w: Six = std::array::from_fn(|x| d.mul(u[x], inv_d));
            if let Some(par) = p.parent {
                let into = acc[par].get_or_insert([[ZERO_NODE; 6]; 6]);
                for x in 0..6 {
                    for y in x..6 {
                        let uw = d.mul(u[x], w[y]);
                        let e = d.sub(ia[x][y], uw);
                        into[x][y] = d.add(into[x][y], e);
                        into[y][x] = into[x][y];
                    }
                }
            }
            joints[i] = Some(Joint {
                parent: p.parent,
                coord: p.coord,
                s,
                w,
                inv_d,
            });
        }
        Some(Articulated {
            joints: joints.into_iter().flatten().collect(),
        })
    }

    /// Whether a right side is solved in fewer operations by these factors
    /// than by the LDLᵀ factors `fac` of the same k × k matrix (measured on
    /// a right side of fresh leaves, the factors' own operations apart).
    pub(crate) fn solves_cheaper(&self, d: &mut Dag, fac: &ldlt::Ldlt<Node>, k: usize) -> bool {
        let rhs: Vec<Node> = (0..k)
            .map(|a| d.leaf(quote::quote!(__nh_probe[#a])))
            .collect();
        let dense = ldlt::solve(d, fac, &rhs);
        let tree = self.solve(d, &rhs);
        let factors: Vec<Node> = (fac.d.iter().copied())
            .chain(
                self.joints
                    .iter()
                    .flat_map(|j| j.w.into_iter().chain([j.inv_d])),
            )
            .collect();
        let with = |d: &Dag, x: &[Node]| {
            let all: Vec<Node> = x.iter().chain(&factors).copied().collect();
            d.op_count(&all)
        };
        with(d, &tree) < with(d, &dense)
    }

    /// x with (Cᵀ M C) x = f.
    pub(crate) fn solve(&self, d: &mut Dag, f: &[Node]) -> Vec<Node> {
        let n = self.joints.len();
        let mut p = vec![[ZERO_NODE; 6]; n];
        let mut u = vec![ZERO_NODE; n];
        for i in (0..n).rev() {
            let j = &self.joints[i];
            let sp = algebra::dot(d, (0..6).map(|x| (j.s[x], p[i][x])));
            u[i] = d.sub(f[j.coord], sp);
            if let Some(par) = j.parent {
                for x in 0..6 {
                    let t = algebra::dot_from(d, p[i][x], [(j.w[x], u[i])]);
                    p[par][x] = d.add(p[par][x], t);
                }
            }
        }
        let mut a = vec![[ZERO_NODE; 6]; n];
        let mut out = vec![ZERO_NODE; f.len()];
        for i in 0..n {
            let j = &self.joints[i];
            let ap = j.parent.map_or([ZERO_NODE; 6], |par| a[par]);
            let wa = algebra::dot(d, (0..6).map(|x| (j.w[x], ap[x])));
            let own = d.mul(j.inv_d, u[i]);
            let y = d.sub(own, wa);
            a[i] = std::array::from_fn(|x| algebra::dot_from(d, ap[x], [(j.s[x], y)]));
            out[j.coord] = y;
        }
        out
    }
}

/// Whether the articulated-body solve `tree` is taken over the LDLᵀ
/// solve `dense` (both in `d`): when it takes fewer operations, or
/// whenever the composite inertias are forced (the verifier's pass), and
/// then counted.
pub(crate) fn preferred(d: &Dag, tree: &[Node], dense: &[Node]) -> bool {
    let take = super::composite_inertia::forced() || d.op_count(tree) < d.op_count(dense);
    if take {
        super::composite_inertia::count_articulated();
    }
    take
}

/// c (ω, v).
fn six(d: &mut Dag, c: Node, (w, v): Twist) -> Six {
    std::array::from_fn(|x| {
        if x < 3 {
            d.mul(c, w[x])
        } else {
            d.mul(c, v[x - 3])
        }
    })
}

/// The generators that move, parents before children, if they form trees
/// each of whose generators takes one reduced rate, all `k` of them once.
fn place(groups: &[GroupNodes], k: usize) -> Option<Vec<Placed>> {
    let mut placed = Vec::new();
    let mut taken = vec![false; k];
    for (gi, g) in groups.iter().enumerate() {
        let mut moving: Vec<usize> = Vec::new();
        for (x, cols) in g.cols.iter().enumerate() {
            match cols.as_slice() {
                [] => {}
                [a] if !g.sets[x].is_empty() && !std::mem::replace(&mut taken[*a], true) => {
                    moving.push(x);
                }
                _ => return None,
            }
        }
        // larger sets first (equal sets in the order of the generators)
        moving.sort_by_key(|&x| (std::cmp::Reverse(g.sets[x].len()), x));
        let start = placed.len();
        for (i, &x) in moving.iter().enumerate() {
            let mut parent = None;
            for (j, &y) in moving[..i].iter().enumerate() {
                match nesting(&g.sets[y], &g.sets[x]) {
                    Nesting::Inside => parent = Some(start + j),
                    Nesting::Apart => {}
                    Nesting::Crossing => return None,
                }
            }
            placed.push(Placed {
                group: gi,
                x,
                parent,
                coord: g.cols[x][0],
            });
        }
    }
    taken.iter().all(|&t| t).then_some(placed)
}

/// How a later generator's set lies to an earlier one's (at least as large).
enum Nesting {
    Inside,
    Apart,
    Crossing,
}

fn nesting(outer: &[usize], inner: &[usize]) -> Nesting {
    let common = inner
        .iter()
        .filter(|x| outer.binary_search(x).is_ok())
        .count();
    match common {
        0 => Nesting::Apart,
        c if c == inner.len() => Nesting::Inside,
        _ => Nesting::Crossing,
    }
}

/// Each placed generator's own inertia: the members whose deepest moving
/// generator it is.
fn links(d: &mut Dag, groups: &[GroupNodes], placed: &[Placed]) -> Vec<Option<Spatial>> {
    let mut deepest: Vec<Vec<Option<usize>>> =
        groups.iter().map(|g| vec![None; g.own.len()]).collect();
    for (i, p) in placed.iter().enumerate() {
        for &m in &groups[p.group].sets[p.x] {
            deepest[p.group][m] = Some(i);
        }
    }
    let mut out: Vec<Vec<Spatial>> = placed.iter().map(|_| Vec::new()).collect();
    for (gi, g) in groups.iter().enumerate() {
        for (m, at) in deepest[gi].iter().enumerate() {
            if let Some(i) = at {
                out[*i].push(g.own[m]);
            }
        }
    }
    out.into_iter()
        .map(|v| v.into_iter().reduce(|a, b| add_spatial(d, &a, &b)))
        .collect()
}

/// ia += the rigid inertia of `s`: [[J, [h]×], [[h]×ᵀ, m 1]] in (ω, v).
fn add_rigid(d: &mut Dag, ia: &mut Sym6, s: &Spatial) {
    for x in 0..3 {
        for y in x..3 {
            ia[x][y] = d.add(ia[x][y], s.j[x][y]);
        }
        ia[x + 3][x + 3] = d.add(ia[x + 3][x + 3], s.mass);
        // [h]× row x: (h × v)_x = h_{x+1} v_{x+2} − h_{x+2} v_{x+1}
        let (y1, y2) = ((x + 1) % 3, (x + 2) % 3);
        ia[x][3 + y2] = d.add(ia[x][3 + y2], s.h[y1]);
        ia[x][3 + y1] = d.sub(ia[x][3 + y1], s.h[y2]);
    }
    for x in 0..6 {
        for y in 0..x {
            ia[x][y] = ia[y][x];
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::algebra::ldlt;
    use crate::generate::graph::{Args, bound_dag};
    use crate::generate::multipliers::multiplier_nodes;
    use crate::mechanics::Scene;
    use crate::testing::{lowered, node_value};

    /// A tree of three links (two hung from the first, one of them on a
    /// universal joint) from a fixed point: its composite inertias
    /// carry all of Cᵀ M C, and the articulated-body solve of (5.9) gives
    /// the LDLᵀ solve's r̈ on the same graph.
    const TREE: &str = "pub struct Tree {
        parameters { m, l, g }
        coordinates { a, b, c, e }
        let P = [1/2, 0, 0];
        let R1 = rot_z(a); let C1 = P + R1*[l/2, 0, 1/5]; let E1 = P + R1*[l, 0, 0];
        let R2 = R1*rot_y(b)*rot_x(c); let C2 = E1 + R2*[l/2, 1/3, 0];
        let R3 = R1*rot_x(e); let C3 = E1 + R3*[0, l/2, 1/4];
        body b1 { mass: m, centre: C1, orientation: R1, inertia: diag(1, 2, 3) }
        body b2 { mass: m/2, centre: C2, orientation: R2, inertia: diag(1/2, 1, 3/2) }
        body b3 { mass: 2*m, centre: C3, orientation: R3, inertia: diag(3, 1, 2) }
        lagrangian = kinetic_energy(b1) + kinetic_energy(b2) + kinetic_energy(b3)
            - g*(C1.z + m*C2.z);
    }";

    #[test]
    fn the_articulated_solve_agrees_with_the_dense_one() {
        let (model, mut engine) = lowered(TREE);
        let mut scene = Scene::new(&model, &mut engine);
        let dv = crate::mechanics::derive(&mut scene, false);
        let mut d = bound_dag(&scene, &Args::vectors(&scene));
        let (mn, taken) = super::super::with_composite_inertias(|| {
            multiplier_nodes(&mut d, &scene, &dv.multiplier_route, dv.kane.as_ref())
        });
        assert!(taken.articulated >= 1, "{taken:?}");
        let dense = ldlt::solve(&mut d, &mn.fac, &mn.projected_rhs);
        let at = [
            ("m", 1.3),
            ("l", 0.8),
            ("g", 9.81),
            ("a", 0.4),
            ("b", -0.7),
            ("c", 0.3),
            ("e", 1.1),
            ("dot(a)", 0.9),
            ("dot(b)", 0.2),
            ("dot(c)", -1.3),
            ("dot(e)", 0.6),
        ];
        for (&t, &x) in mn.rdd.iter().zip(&dense) {
            let (t, x) = (
                node_value(&model, &d, t, &at),
                node_value(&model, &d, x, &at),
            );
            assert!((t - x).abs() <= 1e-12 * (1.0 + x.abs()), "{t} against {x}");
        }
    }
}
