//! Kane's form on the graph (DESIGN §10): each body's generalized inertia
//! forces projected on the partial velocities, from its centre, rotation,
//! inertia and wheels.

use super::articulated::Articulated;
use super::chains::chain_rate;
use super::composite_inertia::{self, Composite};
use super::nodes::{planar_columns, projection};
use crate::algebra;

use super::nodes::{exprs, force_along, inertia_nodes, matrix};
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Scene;
use crate::sym::{ExprId, ZERO};

/// Cᵀ M C and the right side of (5.9) by Kane's form, and the composite
/// inertias they took.
pub(crate) struct Projection {
    pub(crate) mass: Vec<Vec<Node>>,
    pub(crate) rhs: Vec<Node>,
    /// The composite inertias, if taken, and whether they carry all of
    /// Cᵀ M C (no other body's, wheel's or term's part added to it).
    composite: Option<(Composite, bool)>,
}

impl Projection {
    /// The articulated-body factors of Cᵀ M C (`articulated.rs`), where the
    /// composite inertias carry all of it as a tree of generators.
    pub(crate) fn articulated(&self, d: &mut Dag) -> Option<Articulated> {
        let (comp, pure) = self.composite.as_ref()?;
        Articulated::of(d, comp, self.rhs.len(), *pure)
    }
}

/// Cᵀ M C and −Cᵀ (M acc_bias + h) of (5.9) by Kane's form
/// ([`projection_of`]), the bodies on chains of frames summed body by body
/// or as composite inertias, whichever [`composite_inertia::sums`] takes
/// (when it compares them, both are built and the one with fewer
/// operations kept).
pub(crate) fn body_projection(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &crate::mechanics::BodyTerms,
    c: &[Vec<Node>],
    acc_bias: &[Node],
) -> Projection {
    match composite_inertia::sums(bt, c) {
        composite_inertia::Sums::ByBody => projection_of(d, m, bt, (c, acc_bias), false),
        composite_inertia::Sums::Composite => projection_of(d, m, bt, (c, acc_bias), true),
        composite_inertia::Sums::Compare => {
            let ops = |d: &Dag, p: &Projection| {
                let all: Vec<Node> = p.mass.iter().flatten().chain(&p.rhs).copied().collect();
                d.op_count(&all)
            };
            let mut trial = d.clone();
            let composite = projection_of(&mut trial, m, bt, (c, acc_bias), true);
            let by_body = projection_of(d, m, bt, (c, acc_bias), false);
            if ops(&trial, &composite) < ops(d, &by_body) {
                *d = trial;
                return composite;
            }
            by_body
        }
    }
}

/// Cᵀ M C and −Cᵀ (M acc_bias + h) of (5.9) body by body (Kane's form,
/// DESIGN §10), the bodies on chains of frames as composite inertias
/// (`composite_inertia.rs`) when `composite`: with the partial velocities V = J C and Ω = W C,
/// Cᵀ M C = Σ m VᵀV + Ωᵀ I Ω, and the inertia forces at r̈ = 0 are
/// m Vᵀ a + Ωᵀ (I α + ω × I ω) with a = J acc_bias + J̇ q̇,
/// α = W acc_bias + Ẇ q̇; the rest of the Lagrangian as in (5.9).
fn projection_of(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &crate::mechanics::BodyTerms,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
    composite: bool,
) -> Projection {
    let rest_mass = matrix(d, m, &bt.rest_mass);
    let rest_bias = exprs(d, m, &bt.rest_bias);
    let (mut mr, mut f) = projection(d, &rest_mass, &rest_bias, c, acc_bias);
    for f in f.iter_mut() {
        *f = d.neg(*f);
    }
    let motion = super::motion::Motion::of(d, m, bt.heading_rate);
    let gravity = bt
        .gravity
        .map(|g| g.map(|x| (x != ZERO).then(|| d.expr(m.engine, x))));
    let mut comp = match composite {
        true => Composite::build(d, m, bt, (c, acc_bias), &mut mr),
        false => Composite::none(bt.bodies.len()),
    };
    let sums = Sums {
        motion: &motion,
        gravity: &gravity,
        c,
        acc_bias,
        planar: bt.planar,
    };
    for (at, b) in bt.bodies.iter().enumerate() {
        let force = match comp.carried.centre[at] {
            true => Some(carried_centre(d, m, &sums, b, at, &comp)),
            false => {
                body_centre(d, m, &sums, b, (&mut mr, &mut f));
                None
            }
        };
        let torque = match &b.rotation {
            Some(rot) if comp.carried.rotation[at] => {
                Some(carried_rotation(d, m, &sums, rot, at, &comp))
            }
            Some(rot) => {
                body_rotation(d, m, &sums, rot, (&mut mr, &mut f));
                None
            }
            None => None,
        };
        if let Some(force) = force {
            comp.add_force(d, at, force, torque);
        }
    }
    comp.project_forces(d, &mut f);
    let f = f.into_iter().map(|x| d.neg(x)).collect();
    let pure = composite && carries_all(bt, &comp.carried);
    Projection {
        mass: mr,
        rhs: f,
        composite: composite.then_some((comp, pure)),
    }
}

/// Whether the composite inertias' `carried` terms are all of Cᵀ M C: no
/// rest of the Lagrangian with accelerations, every body's centre and
/// rotation carried.
fn carries_all(bt: &crate::mechanics::BodyTerms, carried: &composite_inertia::Carried) -> bool {
    bt.rest_mass.iter().flatten().all(|&e| e == ZERO)
        && bt.bodies.iter().enumerate().all(|(at, b)| {
            (carried.centre[at] || b.jacobian.is_none())
                && (b.rotation.is_none() || carried.rotation[at])
        })
}

/// What every body's terms take in [`projection_of`].
struct Sums<'a> {
    motion: &'a super::motion::Motion,
    gravity: &'a Option<[Option<Node>; 3]>,
    c: &'a [Vec<Node>],
    acc_bias: &'a [Node],
    planar: Option<[usize; 2]>,
}

/// A body's centre body by body: m VᵀV into `mr`, Vᵀ m (a + γ e_k) into `f`.
fn body_centre(
    d: &mut Dag,
    m: &Scene<'_>,
    s: &Sums<'_>,
    b: &crate::mechanics::BodyKinematics,
    (mr, f): (&mut [Vec<Node>], &mut [Node]),
) {
    let Some(jacobian) = &b.jacobian else {
        return;
    };
    let mass = d.expr(m.engine, b.mass);
    let (v, mut a) = centre_partials(
        d,
        m,
        s.motion,
        (jacobian, &b.anchor),
        (s.c, s.acc_bias, s.planar),
    );
    // the weight through the partial velocities: m Vᵀ (a + γ e_k)
    with_weight(d, s, &mut a);
    // m VᵀV: the mass multiplies each sum, not each partial velocity
    for i in 0..mr.len() {
        for j in i..mr.len() {
            let vv = algebra::dot(d, (0..3).map(|x| (v[x][i], v[x][j])));
            mr[i][j] = algebra::dot_from(d, mr[i][j], [(mass, vv)]);
            mr[j][i] = mr[i][j];
        }
    }
    let ma: Vec<Node> = a.iter().map(|&x| d.mul(mass, x)).collect();
    for (i, fi) in f.iter_mut().enumerate() {
        *fi = force_along(d, *fi, &v, &ma, i);
    }
}

/// A carried body's inertia force m (a + γ e_k) on its centre, its
/// acceleration from its chain's rate at q̈ = 0 and the group's twists.
fn carried_centre(
    d: &mut Dag,
    m: &Scene<'_>,
    s: &Sums<'_>,
    b: &crate::mechanics::BodyKinematics,
    at: usize,
    comp: &Composite,
) -> [Node; 3] {
    let mass = d.expr(m.engine, b.mass);
    let rate0 = match b.anchor.as_ref().or(b.short_chain.as_ref()) {
        Some(chain) => chain_rate(d, m, s.motion, chain, s.planar),
        None => [ZERO_NODE; 3],
    };
    let given = comp.centre_acceleration(d, at).unwrap_or([ZERO_NODE; 3]);
    let mut a = algebra::add3(d, rate0, given);
    with_weight(d, s, &mut a);
    algebra::scale3(d, mass, a)
}

/// a + γ e_k: a centre's acceleration with the weight per unit mass.
fn with_weight(d: &mut Dag, s: &Sums<'_>, a: &mut [Node]) {
    for (x, g) in s.gravity.iter().flatten().enumerate() {
        if let Some(g) = g {
            a[x] = d.add(a[x], *g);
        }
    }
}

/// A carried body's torque I α + ω × I ω, turned into the frame of J:
/// α = α₀ + Rᵀ A_ω from its frame's steps and the group's twists.
fn carried_rotation(
    d: &mut Dag,
    m: &Scene<'_>,
    s: &Sums<'_>,
    rot: &crate::mechanics::BodyRotation,
    at: usize,
    comp: &Composite,
) -> [Node; 3] {
    let Some(frame) = composite_inertia::carried_frame(rot) else {
        return [ZERO_NODE; 3];
    };
    let fm = super::frames::frame_motion(d, m, s.motion, frame);
    let turn = super::frames::orientation(d, m, frame);
    let given = comp.angular_acceleration(at).unwrap_or([ZERO_NODE; 3]);
    let back = algebra::mat_t_vec(d, &turn, given);
    let alpha = algebra::add3(d, fm.alpha0, back);
    let inertia = inertia_nodes(d, m, &rot.inertia);
    let i_alpha = [0, 1, 2].map(|x| algebra::dot(d, (0..3).map(|y| (inertia[x][y], alpha[y]))));
    let i_omega = [0, 1, 2].map(|x| algebra::dot(d, (0..3).map(|y| (inertia[x][y], fm.omega[y]))));
    let gyro = algebra::cross(d, fm.omega, i_omega);
    let torque = algebra::add3(d, i_alpha, gyro);
    algebra::mat_vec(d, &turn, torque)
}

/// A body's rotation body by body: Ωᵀ I Ω into `mr`, Ωᵀ (I α + ω × I ω)
/// (and its spin's and wheels' terms) into `f`.
fn body_rotation(
    d: &mut Dag,
    m: &Scene<'_>,
    s: &Sums<'_>,
    rot: &crate::mechanics::BodyRotation,
    (mr, f): (&mut [Vec<Node>], &mut [Node]),
) {
    let (c, acc_bias) = (s.c, s.acc_bias);
    let (omega, om, alpha) = body_turning(d, m, s.motion, rot, (c, acc_bias));
    let inertia = inertia_nodes(d, m, &rot.inertia);
    let i_om: Vec<Vec<Node>> = (0..3)
        .map(|x| {
            (0..om[0].len())
                .map(|a| algebra::dot(d, (0..3).map(|y| (inertia[x][y], om[y][a]))))
                .collect()
        })
        .collect();
    let i_alpha: Vec<Node> = (0..3)
        .map(|x| algebra::dot(d, (0..3).map(|y| (inertia[x][y], alpha[y]))))
        .collect();
    let i_omega: Vec<Node> = (0..3)
        .map(|x| algebra::dot(d, (0..3).map(|y| (inertia[x][y], omega[y]))))
        .collect();
    let gyro = algebra::cross(d, &omega, &i_omega);
    let mut torque: Vec<Node> = (0..3).map(|x| d.add(i_alpha[x], gyro[x])).collect();
    if let Some((k, rate)) = rot.spin {
        // −θ̇ I (e_k × ω'), from turning α by R_k(θ)
        let rate = d.expr(m.engine, rate);
        let mut axis = [ZERO_NODE; 3];
        axis[k] = ONE_NODE;
        let ek_omega = algebra::cross(d, axis, &omega);
        for (x, t) in torque.iter_mut().enumerate() {
            let i_e = algebra::dot(d, (0..3).map(|y| (inertia[x][y], ek_omega[y])));
            let s = d.mul(rate, i_e);
            *t = d.sub(*t, s);
        }
    }
    add_inertia(d, mr, f, &om, &i_om, &torque);
    for (wheel, jacobian) in &rot.wheels {
        let turning = Turning {
            omega: &omega,
            om: &om,
            alpha: &alpha,
        };
        add_wheel(
            d,
            m,
            s.motion,
            (wheel, jacobian),
            &turning,
            (c, acc_bias),
            (mr, f),
        );
    }
}

/// A body centre's partial velocities V = J C and acceleration at r̈ = 0,
/// J acc_bias + J̇ q̇: along its chain as screws where its links have frames.
pub(crate) fn centre_partials(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &super::motion::Motion,
    (jacobian, anchor): (&[Vec<ExprId>; 3], &Option<crate::mechanics::Chain>),
    (c, acc_bias, planar): (&[Vec<Node>], &[Node], Option<[usize; 2]>),
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let j = |d: &mut Dag| {
        let mut j = matrix(d, m, jacobian);
        planar_columns(&mut j, planar, true);
        j
    };
    let Some(chain) = anchor else {
        let j = j(d);
        let mut moving = j.clone();
        planar_columns(&mut moving, planar, false);
        let accel0 = motion.rate_of_jacobian(d, &moving, true);
        return partial_and_bias(d, &j, &accel0, c, acc_bias);
    };
    let accel0 = chain_rate(d, m, motion, chain, planar);
    let Some(pieces) = super::screws::link_pieces(d, m, &chain.links) else {
        let j = j(d);
        return partial_and_bias(d, &j, &accel0, c, acc_bias);
    };
    let screws = super::screws::Screws::of(d, m, &chain.root, &pieces, planar);
    let k = c.first().map_or(0, Vec::len);
    let columns: Vec<[Node; 3]> = (0..k)
        .map(|a| {
            let col: Vec<Node> = c.iter().map(|row| row[a]).collect();
            screws.times(d, &col)
        })
        .collect();
    let v = (0..3)
        .map(|x| columns.iter().map(|col| col[x]).collect())
        .collect();
    let bias = screws.times(d, acc_bias);
    let a = (0..3).map(|x| d.add(accel0[x], bias[x])).collect();
    (v, a)
}

/// A body's ω, its partial angular velocities Ω = W C and α at r̈ = 0
/// (body axes): step by step along its frame's elementary rotations where
/// it has them, else from ω_b's expression.
pub(crate) fn body_turning(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &super::motion::Motion,
    rot: &crate::mechanics::BodyRotation,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
) -> (Vec<Node>, Vec<Vec<Node>>, Vec<Node>) {
    let w = matrix(d, m, &rot.jacobian);
    let (omega, alpha0) = match &rot.frame {
        Some(frame) => {
            let f = super::frames::frame_motion(d, m, motion, frame);
            (f.omega, f.alpha0)
        }
        None => {
            let omega = exprs(d, m, &rot.omega);
            let omega = [omega[0], omega[1], omega[2]];
            (omega, motion.rate(d, omega, false))
        }
    };
    let (om, alpha) = partial_and_bias(d, &w, &alpha0, c, acc_bias);
    (omega.to_vec(), om, alpha)
}

/// A body's ω, its partial angular velocities Ω and α at r̈ = 0 (body axes).
pub(crate) struct Turning<'a> {
    pub(crate) omega: &'a [Node],
    pub(crate) om: &'a [Vec<Node>],
    pub(crate) alpha: &'a [Node],
}

/// The inertia forces of a wheel folded into `carrier` (DESIGN §10): its
/// spin s = ω_k + θ̇ with S = ∂s/∂ṙ adds C S Sᵀ to Cᵀ M C and
/// C S ṡ₀ + C s Ωᵀ(ω × e_k) to the forces at r̈ = 0.
pub(crate) fn add_wheel(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &super::motion::Motion,
    (wheel, jacobian): (&crate::mechanics::Wheel, &Vec<ExprId>),
    carrier: &Turning,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
    (mr, f): (&mut [Vec<Node>], &mut [Node]),
) {
    let k = wheel.axis;
    let moment = d.expr(m.engine, wheel.moment);
    let rate = d.expr(m.engine, wheel.rate);
    let rate0 = motion.rate_of(d, rate);
    let j = vec![exprs(d, m, jacobian)];
    let (theta, theta0) = partial_and_bias(d, &j, &[rate0], c, acc_bias);
    let s = d.add(carrier.omega[k], rate);
    let partial: Vec<Node> = (0..f.len())
        .map(|a| d.add(carrier.om[k][a], theta[0][a]))
        .collect();
    let sdot0 = d.add(carrier.alpha[k], theta0[0]);
    let c_partial: Vec<Node> = partial.iter().map(|&x| d.mul(moment, x)).collect();
    let c_sdot0 = d.mul(moment, sdot0);
    add_inertia(d, mr, f, &[partial], &[c_partial], &[c_sdot0]);
    let mut axis = [ZERO_NODE; 3];
    axis[k] = ONE_NODE;
    let gyro = algebra::cross(d, carrier.omega, axis);
    let c_s = d.mul(moment, s);
    for (a, fa) in f.iter_mut().enumerate() {
        let along = algebra::dot(d, (0..3).map(|x| (carrier.om[x][a], gyro[x])));
        *fa = algebra::dot_from(d, *fa, [(c_s, along)]);
    }
}

/// The partial velocities P = J C (rows of J × k) and the rate at r̈ = 0,
/// J acc_bias + rate0.
pub(crate) fn partial_and_bias(
    d: &mut Dag,
    j: &[Vec<Node>],
    rate0: &[Node],
    c: &[Vec<Node>],
    acc_bias: &[Node],
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let (n, k) = (c.len(), c.first().map_or(0, Vec::len));
    let p = j
        .iter()
        .map(|row| {
            (0..k)
                .map(|a| algebra::dot(d, (0..n).map(|i| (row[i], c[i][a]))))
                .collect()
        })
        .collect();
    let rate = j
        .iter()
        .zip(rate0)
        .map(|(row, &r0)| algebra::dot_from(d, r0, (0..n).map(|i| (row[i], acc_bias[i]))))
        .collect();
    (p, rate)
}

/// mr += Pᵀ Q (upper triangle mirrored) and f += Pᵀ force.
pub(crate) fn add_inertia(
    d: &mut Dag,
    mr: &mut [Vec<Node>],
    f: &mut [Node],
    p: &[Vec<Node>],
    q: &[Vec<Node>],
    force: &[Node],
) {
    let k = f.len();
    for a in 0..k {
        for b in a..k {
            let x = algebra::dot_from(d, mr[a][b], (0..p.len()).map(|x| (p[x][a], q[x][b])));
            mr[a][b] = x;
            mr[b][a] = x;
        }
        f[a] = force_along(d, f[a], p, force, a);
    }
}
