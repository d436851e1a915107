//! The bodies' part of Cᵀ M C from the composite inertias of a tree of
//! links (DESIGN §10.4): the composite-rigid-body sums on the graph.
//!
//! A body carried along a chain of frames moves with the twists of the
//! chain's elementary rotations: its centre's partial velocities are
//! V = R₀ C + Σ_s (a_s × (r − p_s)) t_s, with a_s the step's axis, p_s its
//! pivot (the offsets of the links before it), r the centre (both from the
//! chain's root point) and t_s = ∂θ̇_s/∂q̇ C its rates, and its partial
//! angular velocities are Σ_s a_s t_s in the same axes. Writing each
//! generator g (a step, or a world axis of the root's motion) as a twist
//! (ω_g, v_g) at the root, ω_s = a_s and v_s = p_s × a_s, Kane's
//! Σ_b m VᵀV + Ωᵀ I Ω becomes Σ_{g, h} t_gᵀ (ω_g, v_g)·I_{gh} (ω_h, v_h) t_h,
//! with I_{gh} the spatial inertia of the bodies that move with both. On a
//! chain that is the subtree below the deeper one: n composite inertias,
//! each the next one's plus a link's, and one sandwich per pair of
//! generators, where the body-by-body sums take every body into every
//! entry (n³/6 products for n links).

use super::nodes::exprs;
use crate::algebra;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::{BodyTerms, Frame, FrameStep, Scene};
use crate::sym::{ExprId, ZERO};
use rustc_hash::FxHashMap as HashMap;

std::thread_local! {
    /// Whether every group is carried, and what was taken so far
    /// ([`with_composite_inertias`]).
    static ALWAYS: std::cell::Cell<(bool, Taken)> = const { std::cell::Cell::new((false, Taken { groups: 0, articulated: 0 })) };
}

/// What the composite inertias took under [`with_composite_inertias`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Taken {
    /// Groups of bodies summed as composite inertias.
    pub groups: usize,
    /// Reduced systems solved by the articulated-body recursion.
    pub articulated: usize,
}

/// Runs `f` with the composite inertias taking every group of bodies on
/// chains of frames, one body or more, whatever the estimate of
/// [`sums`], and the articulated-body recursion every tree it applies to
/// (`articulated.rs`), and counts what they took: the differential
/// verifier uses it to check them on every random system with such bodies.
pub fn with_composite_inertias<T>(f: impl FnOnce() -> T) -> (T, Taken) {
    let before = ALWAYS.with(|c| c.replace((true, Taken::default())));
    let out = f();
    let (_, taken) = ALWAYS.with(|c| c.replace(before));
    (out, taken)
}

/// Whether [`with_composite_inertias`] forces every group and tree.
pub(crate) fn forced() -> bool {
    ALWAYS.with(|c| c.get().0)
}

/// Counts a reduced system solved by the articulated-body recursion.
pub(crate) fn count_articulated() {
    ALWAYS.with(|c| {
        let (always, mut taken) = c.get();
        taken.articulated += 1;
        c.set((always, taken));
    });
}

/// Which bodies' terms of Cᵀ M C the composite inertias carry: their
/// centres' m VᵀV and their rotations' Ωᵀ I Ω.
pub(crate) struct Carried {
    pub(crate) centre: Vec<bool>,
    pub(crate) rotation: Vec<bool>,
}

impl Carried {
    /// None of `n` bodies' terms.
    pub(crate) fn none(n: usize) -> Carried {
        Carried {
            centre: vec![false; n],
            rotation: vec![false; n],
        }
    }
}

/// A generator of a group's partial velocities.
enum Source<'a> {
    /// The root point's motion along world axis x: twist (0, e_x), rates
    /// row x of J_root C.
    Root(usize),
    /// Step `j` of `frame`, turning about the offsets of `pivot`.
    Step {
        frame: &'a Frame,
        j: usize,
        pivot: Vec<Piece<'a>>,
    },
}

/// A link of a chain: its frame and its offset r (body axes).
type Piece<'a> = (&'a Frame, &'a [ExprId; 3]);

/// A body carried along its chain's frames.
struct Member<'a> {
    body: usize,
    links: Vec<Piece<'a>>,
    /// Its generators (indices into the group's), ascending.
    gens: Vec<usize>,
    /// Whether its rotation is its last frame's, with the same steps.
    rotation: bool,
}

/// Bodies on chains from the same root point.
struct Group<'a> {
    root: &'a [Vec<ExprId>; 3],
    gens: Vec<Source<'a>>,
    members: Vec<Member<'a>>,
}

/// A spatial inertia about the root: mass, first moment h = Σ m r and
/// second moment J = Σ m (|r|² 1 − r rᵀ) + R I Rᵀ.
#[derive(Clone, Copy)]
pub(crate) struct Spatial {
    pub(crate) mass: Node,
    pub(crate) h: [Node; 3],
    pub(crate) j: [[Node; 3]; 3],
}

/// How Cᵀ M C takes the bodies on chains of frames.
#[derive(Clone, Copy, PartialEq, Debug)]
pub(crate) enum Sums {
    /// Body by body: no group, or one whose composite sums are estimated
    /// at over 3 times the body-by-body ones.
    ByBody,
    /// From the composite inertias: estimated at under half.
    Composite,
    /// Both built and the fewer operations taken (estimates in between,
    /// which missed by up to 30% on the chains of `examples/chains.rs`).
    Compare,
}

/// Whether a group's composite sums, estimated at `composite` against
/// `by_body`, are worth building (at most 3 times the estimate).
fn worth_trying(by_body: usize, composite: usize) -> bool {
    composite <= 3 * by_body
}

/// The way of [`Sums`] for the bodies of `bt` with reduced velocities `c`.
pub(crate) fn sums(bt: &BodyTerms, c: &[Vec<Node>]) -> Sums {
    if bt.planar.is_some() {
        return Sums::ByBody;
    }
    let (always, _) = ALWAYS.with(std::cell::Cell::get);
    let mut way = Sums::ByBody;
    for group in groups(&bt.bodies, always) {
        if always {
            return Sums::Composite;
        }
        let (by_body, composite) = estimates(&group, &rate_columns(&group, c));
        if 2 * composite < by_body {
            return Sums::Composite;
        }
        if worth_trying(by_body, composite) {
            way = Sums::Compare;
        }
    }
    way
}

/// The composite inertias' terms of Cᵀ M C and the nodes their forces
/// take: per group its generators' twists and rates and per member its
/// centre r and the acceleration twist Σ_g (ω_g, v_g) σ_g of its frame at
/// the accelerations given (σ_g = the generator's rate at them), summed in
/// chain order so that a chain's members share their prefixes.
pub(crate) struct Composite {
    pub(crate) carried: Carried,
    groups: Vec<GroupNodes>,
    /// Per body, its (group, member) if carried.
    at: Vec<Option<(usize, usize)>>,
}

/// A group's nodes (see [`Composite`]): per generator its twist, rates,
/// the columns they reach and the members that move with it; per member
/// its spatial inertia about the root, centre and acceleration twist.
pub(crate) struct GroupNodes {
    pub(crate) twists: Vec<Twist>,
    pub(crate) rates: Vec<Vec<Node>>,
    pub(crate) cols: Vec<Vec<usize>>,
    pub(crate) sets: Vec<Vec<usize>>,
    pub(crate) own: Vec<Spatial>,
    centres: Vec<[Node; 3]>,
    accels: Vec<Twist>,
    /// Per member, the force F = m a on its centre and the moment about
    /// the root N = r × F + R τ, once given ([`Composite::add_force`]).
    wrenches: Vec<Twist>,
}

/// A twist (ω, v) at the root, or a wrench (N, F) about it.
pub(crate) type Twist = ([Node; 3], [Node; 3]);

impl Composite {
    /// Nothing carried for `n` bodies.
    pub(crate) fn none(n: usize) -> Composite {
        Composite {
            carried: Carried::none(n),
            groups: Vec::new(),
            at: vec![None; n],
        }
    }

    /// Adds every group's composite-inertia terms to the upper triangle of
    /// `mr` (then mirrored); `acc_bias` the accelerations q̈ at r̈ = 0.
    pub(crate) fn build(
        d: &mut Dag,
        m: &Scene<'_>,
        bt: &BodyTerms,
        (c, acc_bias): (&[Vec<Node>], &[Node]),
        mr: &mut [Vec<Node>],
    ) -> Composite {
        let mut out = Composite::none(bt.bodies.len());
        let (always, _) = ALWAYS.with(std::cell::Cell::get);
        for group in groups(&bt.bodies, always) {
            let cols = rate_columns(&group, c);
            // a group estimated at over 3 times stays body by body beside
            // another that is taken
            let (by_body, composite) = estimates(&group, &cols);
            if !always && !worth_trying(by_body, composite) {
                continue;
            }
            let nodes = add_group(d, m, bt, (&group, cols), (c, acc_bias), mr);
            ALWAYS.with(|x| {
                let (always, mut taken) = x.get();
                taken.groups += 1;
                x.set((always, taken));
            });
            for (i, member) in group.members.iter().enumerate() {
                out.carried.centre[member.body] = true;
                out.carried.rotation[member.body] = member.rotation;
                out.at[member.body] = Some((out.groups.len(), i));
            }
            out.groups.push(nodes);
        }
        out
    }

    /// The groups taken, in the order built.
    pub(crate) fn groups(&self) -> &[GroupNodes] {
        &self.groups
    }

    /// A carried body's centre acceleration from the accelerations given,
    /// A_v + A_ω × r (its rate at q̈ = 0 apart).
    pub(crate) fn centre_acceleration(&self, d: &mut Dag, body: usize) -> Option<[Node; 3]> {
        let (g, i) = self.at[body]?;
        let g = &self.groups[g];
        let (w, v) = g.accels[i];
        let wr = algebra::cross(d, w, g.centres[i]);
        Some(algebra::add3(d, v, wr))
    }

    /// A carried body's angular acceleration from the accelerations given,
    /// A_ω (in the frame of J; its rate at q̈ = 0 apart).
    pub(crate) fn angular_acceleration(&self, body: usize) -> Option<[Node; 3]> {
        let (g, i) = self.at[body]?;
        Some(self.groups[g].accels[i].0)
    }

    /// A carried body's inertia force F on its centre and, if its rotation
    /// is carried, its torque τ in the frame of J: the wrench about the
    /// root, r × F + τ and F.
    pub(crate) fn add_force(
        &mut self,
        d: &mut Dag,
        body: usize,
        force: [Node; 3],
        torque: Option<[Node; 3]>,
    ) {
        let Some((g, i)) = self.at[body] else {
            return;
        };
        let g = &mut self.groups[g];
        let mut moment = algebra::cross(d, g.centres[i], force);
        if let Some(t) = torque {
            moment = algebra::add3(d, moment, t);
        }
        g.wrenches[i] = (moment, force);
    }

    /// f += Σ_g t_g (ω_g·N_g + v_g·F_g) with (N_g, F_g) the wrench of the
    /// members that move with g: Σ_b V_bᵀ F_b + Ω_bᵀ τ_b of the carried
    /// bodies, each subtree's wrench the next one's plus a link's.
    pub(crate) fn project_forces(&self, d: &mut Dag, f: &mut [Node]) {
        for g in &self.groups {
            let mut memo: HashMap<Vec<usize>, Twist> = HashMap::default();
            for (x, set) in g.sets.iter().enumerate() {
                if set.is_empty() || g.cols[x].is_empty() {
                    continue;
                }
                let (n, force) = wrench(d, &mut memo, &g.wrenches, set);
                let (w, v) = g.twists[x];
                let along = algebra::dot(d, w.into_iter().zip(n).chain(v.into_iter().zip(force)));
                for &a in &g.cols[x] {
                    f[a] = algebra::dot_from(d, f[a], [(g.rates[x][a], along)]);
                }
            }
        }
    }
}

/// The wrench of `set` (ascending), memoised like [`composite`].
fn wrench(
    d: &mut Dag,
    memo: &mut HashMap<Vec<usize>, Twist>,
    own: &[Twist],
    set: &[usize],
) -> Twist {
    suffix_sum(d, memo, own, set, |d, (rn, rf), (n, f)| {
        (algebra::add3(d, *rn, *n), algebra::add3(d, *rf, *f))
    })
}

/// The bodies carried along chains of frames, grouped by root point: the
/// groups of two bodies or more, or of one too when `single`.
fn groups(bodies: &[crate::mechanics::BodyKinematics], single: bool) -> Vec<Group<'_>> {
    let mut groups: Vec<Group<'_>> = Vec::new();
    for (i, b) in bodies.iter().enumerate() {
        let (Some(_), Some(chain)) = (&b.jacobian, b.anchor.as_ref().or(b.short_chain.as_ref()))
        else {
            continue;
        };
        let links: Option<Vec<Piece<'_>>> = chain
            .links
            .iter()
            .map(|l| Some((l.frame.as_ref()?, &l.offset)))
            .collect();
        let Some(links) = links else {
            continue;
        };
        let Some(heading_out) = common_heading(&links) else {
            continue;
        };
        let at = match groups.iter().position(|g| *g.root == chain.root) {
            Some(at) => at,
            None => {
                groups.push(Group {
                    root: &chain.root,
                    gens: (0..3)
                        .filter(|&x| chain.root[x].iter().any(|&e| e != ZERO))
                        .map(Source::Root)
                        .collect(),
                    members: Vec::new(),
                });
                groups.len() - 1
            }
        };
        let g = &mut groups[at];
        let mut gens = step_gens(g, &links);
        gens.extend((0..g.gens.len()).filter(|&x| matches!(g.gens[x], Source::Root(_))));
        gens.sort_unstable();
        let rotation = rotation_carried(g, b, &gens, heading_out);
        g.members.push(Member {
            body: i,
            links,
            gens,
            rotation,
        });
    }
    groups.retain(|g| single || g.members.len() >= 2);
    groups
}

/// The links' common `heading_out`, if they agree.
fn common_heading(links: &[Piece<'_>]) -> Option<bool> {
    let out = links.first()?.0.heading_out;
    links.iter().all(|l| l.0.heading_out == out).then_some(out)
}

/// The generators of a chain's steps (each prefix of steps once, those
/// that turn), added to the group's where new.
fn step_gens<'a>(g: &mut Group<'a>, links: &[Piece<'a>]) -> Vec<usize> {
    let mut gens: Vec<usize> = Vec::new();
    let mut seen: Vec<&[FrameStep]> = Vec::new();
    for &(frame, _) in links {
        for j in 0..frame.steps.len() {
            let prefix = &frame.steps[..=j];
            let turns = prefix[j].rate_jacobian.iter().any(|&e| e != ZERO);
            if !turns || seen.iter().any(|s| same_steps(s, prefix)) {
                continue;
            }
            seen.push(prefix);
            let pivot: Vec<Piece<'a>> = links
                .iter()
                .copied()
                .filter(|l| !has_prefix(l.0, prefix))
                .collect();
            let found = g.gens.iter().position(|s| match s {
                Source::Step {
                    frame: f,
                    j: k,
                    pivot: p,
                } => {
                    same_steps(&f.steps[..=*k], prefix)
                        && f.heading_out == frame.heading_out
                        && same_links(p, &pivot)
                }
                Source::Root(_) => false,
            });
            gens.push(found.unwrap_or_else(|| {
                g.gens.push(Source::Step { frame, j, pivot });
                g.gens.len() - 1
            }));
        }
    }
    gens
}

/// Whether a body's rotation is carried: no spin or wheels, and its frame's
/// turning steps are exactly the chain's.
fn rotation_carried(
    g: &Group<'_>,
    b: &crate::mechanics::BodyKinematics,
    gens: &[usize],
    heading: bool,
) -> bool {
    let Some(rot) = &b.rotation else {
        return false;
    };
    let Some(frame) = carried_frame(rot).filter(|f| f.heading_out == heading) else {
        return false;
    };
    if !rot.wheels.is_empty() {
        return false;
    }
    let mut own = Vec::new();
    for j in 0..frame.steps.len() {
        let prefix = &frame.steps[..=j];
        if prefix[j].rate_jacobian.iter().all(|&e| e == ZERO) {
            continue;
        }
        let found = gens.iter().copied().find(|&x| match &g.gens[x] {
            Source::Step { frame: f, j: k, .. } => same_steps(&f.steps[..=*k], prefix),
            Source::Root(_) => false,
        });
        match found {
            Some(x) => own.push(x),
            None => return false,
        }
    }
    own.sort_unstable();
    let steps: Vec<usize> = gens
        .iter()
        .copied()
        .filter(|&x| matches!(g.gens[x], Source::Step { .. }))
        .collect();
    own == steps
}

/// The frame a carried rotation turns with: its own, or with its spin.
pub(crate) fn carried_frame(rot: &crate::mechanics::BodyRotation) -> Option<&Frame> {
    match rot.spin {
        None => rot.frame.as_ref(),
        Some(_) => rot.spun_frame.as_ref(),
    }
}

fn has_prefix(frame: &Frame, prefix: &[FrameStep]) -> bool {
    let steps = &frame.steps;
    steps.len() >= prefix.len() && same_steps(&steps[..prefix.len()], prefix)
}

fn same_links(a: &[Piece<'_>], b: &[Piece<'_>]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|((f, r), (g, s))| {
            r == s && f.heading_out == g.heading_out && same_steps(&f.steps, &g.steps)
        })
}

/// Whether two runs of steps are the same rotations.
fn same_steps(a: &[FrameStep], b: &[FrameStep]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.axis == y.axis && x.turn == y.turn)
}

/// The columns of C a generator's rates can reach (structurally).
fn rate_columns(g: &Group<'_>, c: &[Vec<Node>]) -> Vec<Vec<usize>> {
    let k = c.first().map_or(0, Vec::len);
    g.gens
        .iter()
        .map(|s| {
            let row = match s {
                Source::Root(x) => &g.root[*x],
                Source::Step { frame, j, .. } => &frame.steps[*j].rate_jacobian,
            };
            (0..k)
                .filter(|&a| (0..c.len()).any(|i| row[i] != ZERO && c[i][a] != ZERO_NODE))
                .collect()
        })
        .collect()
}

/// The estimated operations of the body-by-body sums and of the composite
/// ones: a pair of columns costs about 7 operations per body and part
/// there, a pair of generators' columns about 10 here, plus 40 per
/// generator and per body for the twists and inertias (for spatial links;
/// a planar chain's constant axes make the composite sums cheaper).
fn estimates(g: &Group<'_>, cols: &[Vec<usize>]) -> (usize, usize) {
    let mut by_body = 0usize;
    for member in &g.members {
        let mut reach: Vec<usize> = member.gens.iter().flat_map(|&x| cols[x].clone()).collect();
        reach.sort_unstable();
        reach.dedup();
        let pairs = reach.len() * (reach.len() + 1) / 2;
        by_body += 7 * pairs * (1 + usize::from(member.rotation));
    }
    let sets = member_sets(g);
    let mut composite = 40 * (g.gens.len() + g.members.len());
    for a in 0..g.gens.len() {
        for b in a..g.gens.len() {
            if !intersect(&sets[a], &sets[b]).is_empty() {
                composite += 10 * cols[a].len() * cols[b].len();
            }
        }
    }
    (by_body, composite)
}

/// For each generator, the members (ascending) that move with it.
fn member_sets(g: &Group<'_>) -> Vec<Vec<usize>> {
    let mut sets = vec![Vec::new(); g.gens.len()];
    for (i, member) in g.members.iter().enumerate() {
        for &x in &member.gens {
            sets[x].push(i);
        }
    }
    sets
}

fn intersect(a: &[usize], b: &[usize]) -> Vec<usize> {
    a.iter()
        .copied()
        .filter(|x| b.binary_search(x).is_ok())
        .collect()
}

/// The group's terms t_gᵀ (ω_g, v_g)·I_{gh} (ω_h, v_h) t_h into `mr`.
fn add_group(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &BodyTerms,
    (g, cols): (&Group<'_>, Vec<Vec<usize>>),
    (c, acc_bias): (&[Vec<Node>], &[Node]),
    mr: &mut [Vec<Node>],
) -> GroupNodes {
    let twists: Vec<Twist> = g.gens.iter().map(|s| twist(d, m, s)).collect();
    let rows: Vec<Vec<Node>> = g.gens.iter().map(|s| row_of(d, m, g, s)).collect();
    let rates: Vec<Vec<Node>> = rows.iter().map(|row| times_columns(d, row, c)).collect();
    let centres: Vec<[Node; 3]> = (g.members.iter())
        .map(|x| offsets_sum(d, m, &x.links))
        .collect();
    let own: Vec<Spatial> = (g.members.iter().zip(&centres))
        .map(|(x, &r)| member_inertia(d, m, bt, x, r))
        .collect();
    let sets = member_sets(g);
    let mut composites: HashMap<Vec<usize>, Spatial> = HashMap::default();
    let mut forces: HashMap<(Vec<usize>, usize), [[Node; 3]; 2]> = HashMap::default();
    for a in 0..g.gens.len() {
        for b in a..g.gens.len() {
            let common = intersect(&sets[a], &sets[b]);
            if common.is_empty() || cols[a].is_empty() || cols[b].is_empty() {
                continue;
            }
            // the momentum of the deeper generator's twist, the other's dotted in
            let (deep, other) = if common == sets[a] { (a, b) } else { (b, a) };
            let key = (common, deep);
            let f = match forces.get(&key) {
                Some(f) => *f,
                None => {
                    let inertia = composite(d, &mut composites, &own, &key.0);
                    let f = momentum(d, &inertia, twists[deep]);
                    forces.insert(key, f);
                    f
                }
            };
            let (w, v) = twists[other];
            let sandwich = algebra::dot(d, w.into_iter().zip(f[0]).chain(v.into_iter().zip(f[1])));
            add_outer(
                d,
                mr,
                sandwich,
                (&rates[a], &cols[a]),
                (&rates[b], &cols[b]),
                a == b,
            );
        }
    }
    for a in 0..mr.len() {
        for b in a + 1..mr.len() {
            mr[b][a] = mr[a][b];
        }
    }
    let sigma: Vec<Node> = (rows.iter())
        .map(|row| algebra::dot(d, row.iter().copied().zip(acc_bias.iter().copied())))
        .collect();
    let accels = (g.members.iter())
        .map(|x| {
            x.gens
                .iter()
                .fold(([ZERO_NODE; 3], [ZERO_NODE; 3]), |(w, v), &k| {
                    let (tw, tv) = twists[k];
                    let w = [0, 1, 2].map(|y| algebra::dot_from(d, w[y], [(tw[y], sigma[k])]));
                    let v = [0, 1, 2].map(|y| algebra::dot_from(d, v[y], [(tv[y], sigma[k])]));
                    (w, v)
                })
        })
        .collect();
    let zero = ([ZERO_NODE; 3], [ZERO_NODE; 3]);
    GroupNodes {
        wrenches: vec![zero; g.members.len()],
        own,
        twists,
        rates,
        cols,
        sets,
        centres,
        accels,
    }
}

/// mr += s (t tᵀ) when `same`, else s (t uᵀ + u tᵀ), upper triangle.
fn add_outer(
    d: &mut Dag,
    mr: &mut [Vec<Node>],
    s: Node,
    (t, tc): (&[Node], &[usize]),
    (u, uc): (&[Node], &[usize]),
    same: bool,
) {
    for &a in tc {
        for &b in uc {
            if same && b < a {
                continue;
            }
            let tu = d.mul(t[a], u[b]);
            let mut term = d.mul(s, tu);
            if a == b && !same {
                let two = d.constant(crate::sym::Rational::int(2));
                term = d.mul(two, term);
            }
            let (i, j) = (a.min(b), a.max(b));
            mr[i][j] = d.add(mr[i][j], term);
        }
    }
}

/// A generator's twist (ω, v) at the root's origin.
fn twist(d: &mut Dag, m: &Scene<'_>, s: &Source<'_>) -> ([Node; 3], [Node; 3]) {
    match s {
        Source::Root(x) => {
            let mut v = [ZERO_NODE; 3];
            v[*x] = ONE_NODE;
            ([ZERO_NODE; 3], v)
        }
        Source::Step { frame, j, pivot } => {
            let axis = super::frames::world_axes(d, m, frame)[*j];
            let p = offsets_sum(d, m, pivot);
            (axis, algebra::cross(d, p, axis))
        }
    }
}

/// A generator's rates t = row C.
fn times_columns(d: &mut Dag, row: &[Node], c: &[Vec<Node>]) -> Vec<Node> {
    let k = c.first().map_or(0, Vec::len);
    (0..k)
        .map(|a| algebra::dot(d, (0..c.len()).map(|i| (row[i], c[i][a]))))
        .collect()
}

/// A generator's rate's row ∂θ̇/∂q̇ (n), or the root's row of J.
fn row_of(d: &mut Dag, m: &Scene<'_>, g: &Group<'_>, s: &Source<'_>) -> Vec<Node> {
    match s {
        Source::Root(x) => exprs(d, m, &g.root[*x]),
        Source::Step { frame, j, .. } => exprs(d, m, &frame.steps[*j].rate_jacobian),
    }
}

/// Σ R_l r_l over links, in order (the nodes of `screws::link_pieces`).
fn offsets_sum(d: &mut Dag, m: &Scene<'_>, links: &[Piece<'_>]) -> [Node; 3] {
    let mut sum = [ZERO_NODE; 3];
    for &(frame, offset) in links {
        let turn = super::frames::orientation(d, m, frame);
        let r = exprs(d, m, offset);
        let off = algebra::mat_vec(d, &turn, &r);
        sum = algebra::add3(d, sum, off);
    }
    sum
}

/// A member's spatial inertia about the root.
fn member_inertia(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &BodyTerms,
    x: &Member<'_>,
    r: [Node; 3],
) -> Spatial {
    let b = &bt.bodies[x.body];
    let mass = d.expr(m.engine, b.mass);
    let h = algebra::scale3(d, mass, r);
    let mut j = [[ZERO_NODE; 3]; 3];
    for a in 0..3 {
        for c in a..3 {
            let t = super::nodes::point_inertia(d, &r, (a, c));
            j[a][c] = d.mul(mass, t);
        }
    }
    let carried = b.rotation.as_ref().filter(|_| x.rotation);
    if let Some((rot, frame)) = carried.and_then(|r| Some((r, carried_frame(r)?))) {
        let turn = super::frames::orientation(d, m, frame);
        let inertia = super::nodes::inertia_nodes(d, m, &rot.inertia);
        let ri = algebra::mat_mat(d, &turn, &inertia);
        for a in 0..3 {
            for c in a..3 {
                let t = algebra::dot(d, (0..3).map(|k| (ri[a][k], turn[c][k])));
                j[a][c] = d.add(j[a][c], t);
            }
        }
    }
    for a in 0..3 {
        for c in 0..a {
            j[a][c] = j[c][a];
        }
    }
    Spatial { mass, h, j }
}

/// The composite inertia of `set` (ascending), memoised so that nested
/// sets share their sums.
fn composite(
    d: &mut Dag,
    memo: &mut HashMap<Vec<usize>, Spatial>,
    own: &[Spatial],
    set: &[usize],
) -> Spatial {
    suffix_sum(d, memo, own, set, add_spatial)
}

/// The sum over `set` (ascending) of `own`: its first member's plus the
/// rest's, each suffix memoised, so that a chain's nested sets (suffixes
/// of one another) share their nodes.
fn suffix_sum<V: Copy>(
    d: &mut Dag,
    memo: &mut HashMap<Vec<usize>, V>,
    own: &[V],
    set: &[usize],
    add: impl Fn(&mut Dag, &V, &V) -> V,
) -> V {
    // the longest memoised suffix (or none), then the longer ones
    let start = (0..set.len())
        .find(|&i| memo.contains_key(&set[i..]))
        .unwrap_or(set.len());
    for i in (0..start).rev() {
        let x = own[set[i]];
        let sum = match memo.get(&set[i + 1..]) {
            Some(rest) => add(d, rest, &x),
            None => x,
        };
        memo.insert(set[i..].to_vec(), sum);
    }
    memo[set]
}

pub(crate) fn add_spatial(d: &mut Dag, a: &Spatial, b: &Spatial) -> Spatial {
    Spatial {
        mass: d.add(a.mass, b.mass),
        h: algebra::add3(d, a.h, b.h),
        j: [0, 1, 2].map(|x| algebra::add3(d, a.j[x], b.j[x])),
    }
}

/// I (ω, v) about the root: (h × v + J ω, m v + ω × h).
fn momentum(d: &mut Dag, s: &Spatial, (w, v): ([Node; 3], [Node; 3])) -> [[Node; 3]; 2] {
    let hv = algebra::cross(d, s.h, v);
    let jw = [0, 1, 2].map(|x| algebra::dot_from(d, hv[x], (0..3).map(|y| (s.j[x][y], w[y]))));
    let wh = algebra::cross(d, w, s.h);
    let mv = [0, 1, 2].map(|x| algebra::dot_from(d, wh[x], [(s.mass, v[x])]));
    [jw, mv]
}
