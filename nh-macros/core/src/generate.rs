//! Assembly of the generated struct, its inherent methods and its runtime
//! trait implementation (DESIGN §3), from the derived mechanics.

use crate::api::{Bodies, GeneratedMethod, Method};
use crate::check;
use crate::ctxt::Ctxt;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Scene;
use crate::mechanics::{CurvatureRoute, Derivation, MultiplierRoute};
use crate::model::{Model, Output};
use crate::parse::SystemDef;
use crate::sym::{Engine, ExprId, SymId, ZERO};
use proc_macro2::{Ident, TokenStream};
use quote::quote;

mod block;
mod frames;
mod motion;
mod screws;
mod speeds;
mod stand_in;

pub use stand_in::{shape_of, stand_in_shape};

/// Operations of r̈ beyond which other methods call `accelerations` (and
/// `reduced_system`) instead of repeating their code.
const LARGE_OPS: usize = 400;

/// Largest number of independent coordinates k for which the curvature
/// route is derived to compete with the multiplier route (always, with
/// `outputs { routes }`). Beyond it the curvature route's right side,
/// symbolic in all k velocities, costs more to derive than it can save.
const CURVATURE_ROUTE_MAX_K: usize = 6;

/// Which derivation `accelerations` uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Lagrange multipliers eliminated by projection, (5.9)/(5.10).
    Multiplier,
    /// The constrained Lagrangian with the curvature term, (5.20)/(5.21).
    Curvature,
}

/// Figures about one expansion, for statistics and tests.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// The struct's name.
    pub name: String,
    /// Operations of `accelerations` by the multiplier route, after CSE.
    pub ops_multiplier: usize,
    /// Operations of `accelerations` by the curvature route, after CSE.
    pub ops_curvature: usize,
    /// Of the operations of the route `accelerations` uses, those on the
    /// parameters alone: computed once per parameter set into a cache, not
    /// per call.
    pub ops_on_parameters: usize,
    /// Estimated cost (in additions) of the multiplier route.
    pub cost_multiplier: usize,
    /// Estimated cost (in additions) of the curvature route.
    pub cost_curvature: usize,
    /// The route `accelerations` uses.
    pub route: Option<Route>,
    /// Distinct expressions in the engine's graph at the end.
    pub graph_size: usize,
    /// Derivatives computed (memo misses).
    pub derivatives: usize,
    /// Whether every curvature entry is identically zero.
    pub integrable: bool,
    /// Whether that was proved symbolically (otherwise numerically).
    pub integrable_proved: bool,
    /// Which outputs were derived.
    pub derived: Vec<&'static str>,
    /// Lines of generated code (one statement or item per line, as `cargo expand` prints it).
    pub lines: usize,
    /// Whether the system is in generalized speeds (its figures are those
    /// of Maggi's equations, in the curvature route's slots).
    pub maggi: bool,
}

impl Stats {
    /// Operations of r̈ by `route`, after CSE.
    fn ops(&self, route: Route) -> usize {
        match route {
            Route::Multiplier => self.ops_multiplier,
            Route::Curvature => self.ops_curvature,
        }
    }

    /// Whether r̈ by `route`, the route `accelerations` uses, is large enough
    /// that methods needing it call `accelerations` instead of repeating its
    /// code.
    fn is_large(&self, route: Route) -> bool {
        self.ops(route) > LARGE_OPS
    }

    /// One line: operation counts, route, graph size.
    pub fn summary(&self) -> String {
        if self.maggi {
            return format!(
                "accelerations: Maggi's equations (generalized speeds) {} ops (cost {}) after CSE; {} generated lines; graph {} expressions, {} derivatives",
                self.ops_curvature,
                self.cost_curvature,
                self.lines,
                self.graph_size,
                self.derivatives
            );
        }
        let curvature = if self.ops_curvature == 0 {
            "not derived (k > 6, or constraints that are not homogeneous)".to_string()
        } else {
            format!("{} ops (cost {})", self.ops_curvature, self.cost_curvature)
        };
        format!(
            "accelerations: multiplier route {} ops (cost {}), curvature route {curvature} after CSE, using the {} route ({} ops of it on the parameters alone, cached); {} generated lines; graph {} expressions, {} derivatives; integrable: {}",
            self.ops_multiplier,
            self.cost_multiplier,
            match self.route {
                Some(Route::Multiplier) => "multiplier",
                Some(Route::Curvature) => "curvature",
                None => "(none)",
            },
            self.ops_on_parameters,
            self.lines,
            self.graph_size,
            self.derivatives,
            self.integrable
        )
    }
}

/// Where the values of a function's arguments come from.
pub(crate) struct Args {
    coord: Vec<TokenStream>,
    rvel: Vec<TokenStream>,
    /// The dependent velocities as C ṙ, for graphs that need C anyway
    /// (the accelerations and what derives from them); else solved on
    /// their own, which is cheaper without C.
    columns: bool,
}

impl Args {
    /// The arguments `q` and `rdot` (`speeds`, in generalized speeds).
    fn vectors(m: &Scene<'_>) -> Args {
        let vel = velocity_arg(m);
        Args {
            coord: (0..m.n()).map(|i| quote!(q[#i])).collect(),
            rvel: (0..m.k()).map(|j| quote!(#vel[#j])).collect(),
            columns: false,
        }
    }

    /// The same arguments for a graph of the accelerations.
    fn moving(self) -> Args {
        Args {
            columns: true,
            ..self
        }
    }

    /// The state `x` = [q, ṙ] (or [q, u]).
    pub(crate) fn state(m: &Scene<'_>) -> Args {
        let (n, k) = (m.n(), m.k());
        Args {
            coord: (0..n).map(|i| quote!(x[#i])).collect(),
            rvel: (0..k)
                .map(|j| {
                    let ix = n + j;
                    quote!(x[#ix])
                })
                .collect(),
            columns: false,
        }
    }
}

/// The argument holding the state's velocity part: `rdot`, or `speeds`.
fn velocity_arg(m: &Scene<'_>) -> Ident {
    crate::api::velocity_argument(m.speeds.is_some())
}

/// A graph with every symbol of the model bound to its source.
pub(crate) fn bound_dag(m: &Scene<'_>, args: &Args) -> Dag {
    let mut d = Dag::new();
    for (i, c) in m.coordinates.iter().enumerate() {
        let l = d.leaf_named(
            args.coord[i].clone(),
            &format!("q_{}", syn::ext::IdentExt::unraw(&c.name)),
        );
        d.bind(c.position, l);
    }
    let mut rdot = Vec::with_capacity(m.k());
    for (j, &i) in m.independent().iter().enumerate() {
        let c = &m.coordinates[i];
        let l = d.leaf_named(
            args.rvel[j].clone(),
            &format!("dot_{}", syn::ext::IdentExt::unraw(&c.name)),
        );
        d.bind(c.velocity, l);
        rdot.push(l);
    }
    for p in &m.parameters {
        let name = &p.name;
        let l = d.leaf_param(
            quote!(self.#name),
            &format!("p_{}", syn::ext::IdentExt::unraw(name)),
        );
        d.bind(p.sym, l);
    }
    for (j, u) in m.inputs.iter().enumerate() {
        let l = d.leaf_named(
            quote!(u[#j]),
            &format!("u_{}", syn::ext::IdentExt::unraw(&u.name)),
        );
        d.bind(u.sym, l);
    }
    let t = d.leaf_named(quote!(t), "time");
    d.bind(m.time, t);
    let pi = d.pi();
    d.bind(m.pi, pi);
    if let Some(sp) = &m.speeds {
        bind_speeds(&mut d, m, sp, args);
    }
    // dependent velocities: computed from the constraints (5.3)
    if let Some(bt) = &m.block {
        let sdot = if args.columns {
            let columns = block::velocity_columns(&mut d, m, bt);
            (0..m.constraints.len())
                .map(|a| {
                    let pairs = columns.iter().zip(&rdot).map(|(c, &v)| (c[a], v));
                    dot(&mut d, ZERO_NODE, pairs)
                })
                .collect()
        } else {
            block::dependent_velocities(&mut d, m, bt, &rdot)
        };
        for (c, v) in m.constraints.iter().zip(sdot) {
            let s = &m.coordinates[c.dependent];
            d.label(
                v,
                format!("dot({}): the block of velocity rows solved by LU", s.name),
            );
            let v = d.opaque(v);
            d.bind(s.velocity, v);
        }
        return d;
    }
    for c in &m.constraints {
        let s = &m.coordinates[c.dependent];
        let v = d.expr(m.engine, c.velocity);
        d.label(v, format!("dot({}): {}", s.name, c.kind.velocity_source()));
        // one node the rates along the motion can hold (Op::Opaque)
        let v = d.opaque(v);
        d.bind(s.velocity, v);
    }
    d
}

/// The speeds bound to the state's velocity part, and each q̇_i to its
/// kinematics (S u + σ)_i.
fn bind_speeds(d: &mut Dag, m: &Scene<'_>, sp: &crate::model::Speeds, args: &Args) {
    let mut leaves = Vec::with_capacity(sp.syms.len());
    for (j, (u, &sym)) in sp.names.iter().zip(&sp.syms).enumerate() {
        let name = format!("speed_{}", syn::ext::IdentExt::unraw(u));
        let l = d.leaf_named(args.rvel[j].clone(), &name);
        d.bind(sym, l);
        leaves.push(l);
    }
    for (c, &w) in m.coordinates.iter().zip(&sp.velocities) {
        let v = d.expr(m.engine, w);
        if !leaves.contains(&v) {
            d.label(
                v,
                format!("dot({}) from the kinematics q̇ = S u + σ", c.name),
            );
        }
        d.bind(c.velocity, v);
    }
}

fn exprs(d: &mut Dag, m: &Scene<'_>, v: &[ExprId]) -> Vec<Node> {
    v.iter().map(|&e| d.expr(m.engine, e)).collect()
}

fn matrix(d: &mut Dag, m: &Scene<'_>, v: &[Vec<ExprId>]) -> Vec<Vec<Node>> {
    v.iter().map(|row| exprs(d, m, row)).collect()
}

/// The multiplier route in the graph: returns (r̈, q̈-independent parts) and
/// keeps the mass matrix and bias for the multipliers.
struct MultiplierNodes {
    rdd: Vec<Node>,
    mass: Vec<Vec<Node>>,
    bias: Vec<Node>,
    c: Vec<Vec<Node>>,
    acc_bias: Vec<Node>,
    pivots: Vec<Node>,
    /// The LDLᵀ factorisation of Cᵀ M C, reused for derivatives.
    fac: crate::emit::Ldlt,
}

fn multiplier_nodes(d: &mut Dag, m: &Scene<'_>, r: &MultiplierRoute) -> MultiplierNodes {
    let (n, k) = (m.n(), m.k());
    let mass = matrix(d, m, &r.mass);
    for (i, row) in mass.iter().enumerate() {
        for (j, &x) in row.iter().enumerate().skip(i) {
            d.label(x, format!("mass matrix ∂²L/∂q̇{i}∂q̇{j}"));
        }
    }
    let bias = exprs(d, m, &r.bias);
    for (i, &x) in bias.iter().enumerate() {
        d.label(
            x,
            format!("Euler–Lagrange term {i} without accelerations (3.9), forces included"),
        );
    }
    // q̇ = C ṙ with C = [I; −A] (rows in coordinate order)
    let mut c = vec![vec![ZERO_NODE; k]; n];
    for (j, &i) in m.independent().iter().enumerate() {
        c[i][j] = ONE_NODE;
    }
    // q̈ = C r̈ + acc_bias, acc_bias_s = −Ȧ ṙ
    let mut acc_bias = vec![ZERO_NODE; n];
    if let Some(bt) = &m.block {
        let columns = block::velocity_columns(d, m, bt);
        let bias = block::dependent_bias(d, m, bt);
        for (a, con) in m.constraints.iter().enumerate() {
            for b in 0..k {
                c[con.dependent][b] = columns[b][a];
            }
            acc_bias[con.dependent] = bias[a];
        }
    } else {
        for con in &m.constraints {
            for b in 0..k {
                let x = d.expr(m.engine, con.coefficients[b]);
                c[con.dependent][b] = d.neg(x);
            }
        }
        for (a, &s) in m.dependent().iter().enumerate() {
            acc_bias[s] = d.expr(m.engine, r.dependent_bias[a]);
        }
    }
    // Cᵀ M C r̈ = −Cᵀ (M acc_bias + h)   (5.9)
    // Kane's form where it is cheaper than the expanded Lagrangian's terms
    // (without the expanded terms, Kane's form alone: LAGRANGIAN_TERMS_COMPARED)
    let lagrange = (!r.mass.is_empty()).then(|| projection(d, &mass, &bias, &c, &acc_bias));
    let (mr, f) = match &r.bodies {
        Some(bt) => {
            let ops = |d: &Dag, (mr, f): &(Vec<Vec<Node>>, Vec<Node>)| {
                let all: Vec<Node> = mr.iter().flatten().chain(f).copied().collect();
                d.op_count(&all)
            };
            let (c, acc_bias) = in_heading(d, m, bt, (&c, &acc_bias));
            let kane = body_projection(d, m, bt, &c, &acc_bias);
            match lagrange {
                Some(lagrange) if ops(d, &lagrange) <= ops(d, &kane) => lagrange,
                _ => kane,
            }
        }
        // without Kane's form the expanded terms are always derived
        None => lagrange.unwrap_or_default(),
    };
    for (a, row) in mr.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("projected mass matrix (Cᵀ M C)[{a}][{b}] of (5.9)"),
            );
        }
    }
    let fac = d.factor_symmetric(&mr);
    let rdd = d.solve_factored(&fac, &f);
    for (a, &v) in rdd.iter().enumerate() {
        d.label(v, format!("r̈{a}: (5.9) solved by LDLᵀ"));
    }
    MultiplierNodes {
        rdd,
        mass,
        bias,
        c,
        acc_bias,
        pivots: fac.d.clone(),
        fac,
    }
}

/// C and acc_bias for Kane's sums: with a planar pair (x, y), its rows
/// those of u = R_z(−ψ)(ẋ, ẏ) and u̇ (see [`planar_columns`]).
fn in_heading(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &crate::mechanics::BodyTerms,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let (mut c, mut acc_bias) = (c.to_vec(), acc_bias.to_vec());
    if let (Some(planar), Some(block)) = (bt.planar, &m.block) {
        let columns = block::velocity_columns_in_heading(d, m, block);
        let bias = block::dependent_bias_in_heading(d, m, block);
        for (a, con) in m.constraints.iter().enumerate() {
            if planar.contains(&con.dependent) {
                for (b, col) in columns.iter().enumerate() {
                    c[con.dependent][b] = col[a];
                }
                acc_bias[con.dependent] = bias[a];
            }
        }
    }
    (c, acc_bias)
}

/// Cᵀ M C and −Cᵀ (M acc_bias + h) of (5.9).
fn projection(
    d: &mut Dag,
    mass: &[Vec<Node>],
    bias: &[Node],
    c: &[Vec<Node>],
    acc_bias: &[Node],
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let (n, k) = (c.len(), c.first().map_or(0, Vec::len));
    let mut mc = vec![vec![ZERO_NODE; k]; n];
    for i in 0..n {
        for b in 0..k {
            mc[i][b] = dot(d, ZERO_NODE, (0..n).map(|j| (mass[i][j], c[j][b])));
        }
    }
    let mut mr = vec![vec![ZERO_NODE; k]; k];
    for a in 0..k {
        for b in a..k {
            let acc = dot(d, ZERO_NODE, (0..n).map(|i| (c[i][a], mc[i][b])));
            mr[a][b] = acc;
            mr[b][a] = acc;
        }
    }
    let g: Vec<Node> = (0..n)
        .map(|i| dot(d, bias[i], (0..n).map(|j| (mass[i][j], acc_bias[j]))))
        .collect();
    let f = (0..k)
        .map(|a| {
            let acc = dot(d, ZERO_NODE, (0..n).map(|i| (c[i][a], g[i])));
            d.neg(acc)
        })
        .collect();
    (mr, f)
}

/// Cᵀ M C and −Cᵀ (M acc_bias + h) of (5.9) body by body (Kane's form,
/// DESIGN §10): with the partial velocities V = J C and Ω = W C,
/// Cᵀ M C = Σ m VᵀV + Ωᵀ I Ω, and the inertia forces at r̈ = 0 are
/// m Vᵀ a + Ωᵀ (I α + ω × I ω) with a = J acc_bias + J̇ q̇,
/// α = W acc_bias + Ẇ q̇; the rest of the Lagrangian as in (5.9).
fn body_projection(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &crate::mechanics::BodyTerms,
    c: &[Vec<Node>],
    acc_bias: &[Node],
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let rest_mass = matrix(d, m, &bt.rest_mass);
    let rest_bias = exprs(d, m, &bt.rest_bias);
    let (mut mr, mut f) = projection(d, &rest_mass, &rest_bias, c, acc_bias);
    for f in f.iter_mut() {
        *f = d.neg(*f);
    }
    let motion = motion::Motion::of(d, m, bt.heading_rate);
    let gravity = bt.gravity.map(|g| d.expr(m.engine, g));
    for b in &bt.bodies {
        if let Some(jacobian) = &b.jacobian {
            let mass = d.expr(m.engine, b.mass);
            let (v, mut a) = centre_partials(
                d,
                m,
                &motion,
                (jacobian, &b.anchor),
                (c, acc_bias, bt.planar),
            );
            if let Some(g) = gravity {
                // the weight through the partial velocities: m Vᵀ (a + γ e_z)
                a[2] = d.add(a[2], g);
            }
            // m VᵀV: the mass multiplies each sum, not each partial velocity
            for i in 0..mr.len() {
                for j in i..mr.len() {
                    let vv = dot(d, ZERO_NODE, (0..3).map(|x| (v[x][i], v[x][j])));
                    mr[i][j] = dot(d, mr[i][j], [(mass, vv)]);
                    mr[j][i] = mr[i][j];
                }
            }
            let ma: Vec<Node> = a.iter().map(|&x| d.mul(mass, x)).collect();
            for (i, fi) in f.iter_mut().enumerate() {
                *fi = force_along(d, *fi, &v, &ma, i);
            }
        }
        if let Some(rot) = &b.rotation {
            let (omega, om, alpha) = body_turning(d, m, &motion, rot, (c, acc_bias));
            let inertia = inertia_nodes(d, m, &rot.inertia);
            let i_om: Vec<Vec<Node>> = (0..3)
                .map(|x| {
                    (0..om[0].len())
                        .map(|a| dot(d, ZERO_NODE, (0..3).map(|y| (inertia[x][y], om[y][a]))))
                        .collect()
                })
                .collect();
            let i_alpha: Vec<Node> = (0..3)
                .map(|x| dot(d, ZERO_NODE, (0..3).map(|y| (inertia[x][y], alpha[y]))))
                .collect();
            let i_omega: Vec<Node> = (0..3)
                .map(|x| dot(d, ZERO_NODE, (0..3).map(|y| (inertia[x][y], omega[y]))))
                .collect();
            let gyro = cross_nodes(d, &omega, &i_omega);
            let mut torque: Vec<Node> = (0..3).map(|x| d.add(i_alpha[x], gyro[x])).collect();
            if let Some((k, rate)) = rot.spin {
                // −θ̇ I (e_k × ω'), from turning α by R_k(θ)
                let rate = d.expr(m.engine, rate);
                let mut axis = [ZERO_NODE; 3];
                axis[k] = ONE_NODE;
                let ek_omega = cross_nodes(d, &axis, &omega);
                for (x, t) in torque.iter_mut().enumerate() {
                    let i_e = dot(d, ZERO_NODE, (0..3).map(|y| (inertia[x][y], ek_omega[y])));
                    let s = d.mul(rate, i_e);
                    *t = d.sub(*t, s);
                }
            }
            add_inertia(d, &mut mr, &mut f, &om, &i_om, &torque);
            for (wheel, jacobian) in &rot.wheels {
                let turning = Turning {
                    omega: &omega,
                    om: &om,
                    alpha: &alpha,
                };
                add_wheel(
                    d,
                    m,
                    &motion,
                    (wheel, jacobian),
                    &turning,
                    (c, acc_bias),
                    (&mut mr, &mut f),
                );
            }
        }
    }
    let f = f.into_iter().map(|x| d.neg(x)).collect();
    (mr, f)
}

/// A body's inertia T (I + Σ μ(|d|² 1 − d dᵀ)) Tᵀ from its parts
/// ([`crate::mechanics::Inertia`]), symmetric.
fn inertia_nodes(
    d: &mut Dag,
    m: &Scene<'_>,
    inertia: &crate::mechanics::Inertia,
) -> Vec<Vec<Node>> {
    let mut sum = matrix(d, m, &inertia.own.map(|r| r.to_vec()));
    for (mu, offset) in &inertia.masses {
        let mu = d.expr(m.engine, *mu);
        let v = exprs(d, m, offset);
        for a in 0..3 {
            for b in a..3 {
                // (|d|² 1 − d dᵀ)_ab: Σ_{k≠a} d_k² on the diagonal, −d_a d_b off it
                let t = match a == b {
                    true => (0..3)
                        .filter(|&k| k != a)
                        .fold(ZERO_NODE, |acc, k| dot(d, acc, [(v[k], v[k])])),
                    false => {
                        let p = d.mul(v[a], v[b]);
                        d.neg(p)
                    }
                };
                let t = d.mul(mu, t);
                sum[a][b] = d.add(sum[a][b], t);
                sum[b][a] = sum[a][b];
            }
        }
    }
    let Some(tail) = &inertia.tail else {
        return sum;
    };
    let t = matrix(d, m, &tail.map(|r| r.to_vec()));
    let ts: Vec<Vec<Node>> = (0..3)
        .map(|a| {
            (0..3)
                .map(|b| dot(d, ZERO_NODE, (0..3).map(|k| (t[a][k], sum[k][b]))))
                .collect()
        })
        .collect();
    let mut out = vec![vec![ZERO_NODE; 3]; 3];
    for a in 0..3 {
        for b in a..3 {
            out[a][b] = dot(d, ZERO_NODE, (0..3).map(|k| (ts[a][k], t[b][k])));
            out[b][a] = out[a][b];
        }
    }
    out
}

/// A point's acceleration at q̈ = 0 along its chain (DESIGN §10):
/// J̇_root q̇ + Σ R(α_b × r + ω_b × (ω_b × r)), α_b = Ẇ q̇.
pub(crate) fn chain_rate(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &motion::Motion,
    chain: &crate::mechanics::Chain,
    planar: Option<[usize; 2]>,
) -> [Node; 3] {
    let mut root = matrix(d, m, &chain.root);
    planar_columns(&mut root, planar, false);
    let mut a = motion.rate_of_jacobian(d, &root, true);
    if let Some(pieces) = screws::link_pieces(d, m, &chain.links) {
        // in the frame of J: α × R r + ω × (ω × R r) per link
        for (frame, off) in pieces {
            let (omega, alpha) = frames::world_motion(d, m, motion, frame);
            let tangential = cross_nodes(d, &alpha, &off);
            let wr = cross_nodes(d, &omega, &off);
            let normal = cross_nodes(d, &omega, &wr);
            a = [0, 1, 2].map(|x| {
                let t = d.add(tangential[x], normal[x]);
                d.add(a[x], t)
            });
        }
        return a;
    }
    for link in &chain.links {
        let (omega, alpha0, turn) = match &link.frame {
            Some(frame) => {
                let f = frames::frame_motion(d, m, motion, frame);
                let turn = frames::orientation(d, m, frame);
                (f.omega, f.alpha0, turn.map(|row| row.to_vec()).to_vec())
            }
            None => {
                let omega = exprs(d, m, &link.omega);
                let omega = [omega[0], omega[1], omega[2]];
                let alpha0 = motion.rate(d, omega, false);
                let turn = matrix(d, m, &link.turn.map(|row| row.to_vec()));
                (omega, alpha0, turn)
            }
        };
        let r = exprs(d, m, &link.offset);
        let tangential = cross_nodes(d, &alpha0, &r);
        let wr = cross_nodes(d, &omega, &r);
        let normal = cross_nodes(d, &omega, &wr);
        let body: Vec<Node> = (0..3).map(|x| d.add(tangential[x], normal[x])).collect();
        a = [0, 1, 2].map(|x| dot(d, a[x], (0..3).map(|y| (turn[x][y], body[y]))));
    }
    a
}

/// The columns of a planar pair (x, y) of a Jacobian in the heading's
/// frame: e_x and e_y where the dependent rows are u = R_z(−ψ)(ẋ, ẏ)
/// (`constant`), or zero in a rate at q̈ = 0, to which a column constant in
/// the world adds nothing.
pub(crate) fn planar_columns(j: &mut [Vec<Node>], planar: Option<[usize; 2]>, constant: bool) {
    for (axis, i) in planar.into_iter().flat_map(|p| p.into_iter().enumerate()) {
        for (x, row) in j.iter_mut().enumerate() {
            row[i] = if constant && x == axis {
                ONE_NODE
            } else {
                ZERO_NODE
            };
        }
    }
}

/// A body centre's partial velocities V = J C and acceleration at r̈ = 0,
/// J acc_bias + J̇ q̇: along its chain as screws where its links have frames.
fn centre_partials(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &motion::Motion,
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
    let Some(pieces) = screws::link_pieces(d, m, &chain.links) else {
        let j = j(d);
        return partial_and_bias(d, &j, &accel0, c, acc_bias);
    };
    let screws = screws::Screws::of(d, m, &chain.root, &pieces, planar);
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
fn body_turning(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &motion::Motion,
    rot: &crate::mechanics::BodyRotation,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
) -> (Vec<Node>, Vec<Vec<Node>>, Vec<Node>) {
    let w = matrix(d, m, &rot.jacobian);
    let (omega, alpha0) = match &rot.frame {
        Some(frame) => {
            let f = frames::frame_motion(d, m, motion, frame);
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
struct Turning<'a> {
    omega: &'a [Node],
    om: &'a [Vec<Node>],
    alpha: &'a [Node],
}

/// The inertia forces of a wheel folded into `carrier` (DESIGN §10): its
/// spin s = ω_k + θ̇ with S = ∂s/∂ṙ adds C S Sᵀ to Cᵀ M C and
/// C S ṡ₀ + C s Ωᵀ(ω × e_k) to the forces at r̈ = 0.
fn add_wheel(
    d: &mut Dag,
    m: &Scene<'_>,
    motion: &motion::Motion,
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
    let gyro = cross_nodes(d, carrier.omega, &axis);
    let c_s = d.mul(moment, s);
    for (a, fa) in f.iter_mut().enumerate() {
        let along = dot(d, ZERO_NODE, (0..3).map(|x| (carrier.om[x][a], gyro[x])));
        *fa = dot(d, *fa, [(c_s, along)]);
    }
}

/// The partial velocities P = J C (rows of J × k) and the rate at r̈ = 0,
/// J acc_bias + rate0.
fn partial_and_bias(
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
                .map(|a| dot(d, ZERO_NODE, (0..n).map(|i| (row[i], c[i][a]))))
                .collect()
        })
        .collect();
    let rate = j
        .iter()
        .zip(rate0)
        .map(|(row, &r0)| dot(d, r0, (0..n).map(|i| (row[i], acc_bias[i]))))
        .collect();
    (p, rate)
}

/// mr += Pᵀ Q (upper triangle mirrored) and f += Pᵀ force.
fn add_inertia(
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
            let x = dot(d, mr[a][b], (0..p.len()).map(|x| (p[x][a], q[x][b])));
            mr[a][b] = x;
            mr[b][a] = x;
        }
        f[a] = force_along(d, f[a], p, force, a);
    }
}

/// fa + (Pᵀ force)_a: a force's part along the partial velocities a.
fn force_along(d: &mut Dag, fa: Node, p: &[Vec<Node>], force: &[Node], a: usize) -> Node {
    dot(d, fa, (0..p.len()).map(|x| (p[x][a], force[x])))
}

/// u × v.
fn cross_nodes(d: &mut Dag, u: &[Node], v: &[Node]) -> Vec<Node> {
    (0..3)
        .map(|x| {
            let (y, z) = ((x + 1) % 3, (x + 2) % 3);
            let a = d.mul(u[y], v[z]);
            let b = d.mul(u[z], v[y]);
            d.sub(a, b)
        })
        .collect()
}

impl MultiplierNodes {
    /// q̈ = C r̈ + acc_bias at these nodes' r̈.
    fn qdd(&self, d: &mut Dag) -> Vec<Node> {
        (0..self.c.len())
            .map(|i| {
                let pairs = self.c[i].iter().copied().zip(self.rdd.iter().copied());
                dot(d, self.acc_bias[i], pairs)
            })
            .collect()
    }

    /// The Euler–Lagrange term E_i = (M q̈ + h)_i (3.9) at accelerations `qdd`.
    fn euler_lagrange(&self, d: &mut Dag, i: usize, qdd: &[Node]) -> Node {
        let pairs = self.mass[i].iter().copied().zip(qdd.iter().copied());
        dot(d, self.bias[i], pairs)
    }
}

/// `init + Σ x·y` over `pairs`, added up in order.
fn dot(d: &mut Dag, init: Node, pairs: impl IntoIterator<Item = (Node, Node)>) -> Node {
    let mut acc = init;
    for (x, y) in pairs {
        let t = d.mul(x, y);
        acc = d.add(acc, t);
    }
    acc
}

fn curvature_nodes(d: &mut Dag, m: &Scene<'_>, r: &CurvatureRoute) -> (Vec<Node>, Vec<Node>) {
    let mass = matrix(d, m, &r.mass);
    for (a, row) in mass.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("reduced mass matrix ∂²Lc/∂ṙ{a}∂ṙ{b} of the constrained Lagrangian (5.12)"),
            );
        }
    }
    if let Some(sol) = &r.solution {
        let x = exprs(d, m, sol);
        for (a, &v) in x.iter().enumerate() {
            d.label(
                v,
                format!("r̈{a}: (5.20) with the reduced mass matrix inverted symbolically (LDLᵀ)"),
            );
        }
        return (x, Vec::new());
    }
    let rhs = exprs(d, m, &r.rhs);
    for (a, &x) in rhs.iter().enumerate() {
        d.label(x, format!("right side {a} of (5.20): projected forces minus the velocity terms and the curvature term Σ B ṙ ∂L/∂ṡ (5.21)"));
    }
    let (x, piv) = d.solve_symmetric(&mass, &rhs);
    for (a, &v) in x.iter().enumerate() {
        d.label(v, format!("r̈{a}: the reduced mass matrix solved by LDLᵀ"));
    }
    (x, piv)
}

fn vector_expr(k: usize, items: &[TokenStream]) -> TokenStream {
    quote!(__nh_private::nalgebra::SVector::<T, #k>::from([#(#items),*]))
}

impl Route {
    /// The method computing r̈ by this route alone.
    fn method(self) -> GeneratedMethod {
        match self {
            Route::Multiplier => GeneratedMethod::AccelerationsMultiplierRoute,
            Route::Curvature => GeneratedMethod::AccelerationsCurvatureRoute,
        }
    }

    /// The route's description in the generated docs.
    fn doc(self) -> &'static str {
        self.method().spec().doc
    }

    /// The other route.
    fn other(self) -> Route {
        match self {
            Route::Multiplier => Route::Curvature,
            Route::Curvature => Route::Multiplier,
        }
    }
}

/// The graph of r̈ by each route, from the comparison of the routes, until
/// a method emits it: the chosen route's for `accelerations`, the other's
/// for its own method with `outputs { routes }`.
#[derive(Default)]
struct RouteGraphs {
    multiplier: Option<(Dag, Vec<Node>)>,
    curvature: Option<(Dag, Vec<Node>)>,
}

impl RouteGraphs {
    fn slot(&mut self, route: Route) -> &mut Option<(Dag, Vec<Node>)> {
        match route {
            Route::Multiplier => &mut self.multiplier,
            Route::Curvature => &mut self.curvature,
        }
    }
}

/// Method bodies computed from the derivation, on demand: a method that is
/// not requested is never emitted.
struct Derived<'a, 'b> {
    m: &'a mut Scene<'b>,
    dv: Derivation,
    route: Route,
    stats: &'a mut Stats,
    /// Parameter-only values hoisted out of the methods: the code computing
    /// each method's share of the cache, and the cache length so far.
    hoist_blocks: Vec<TokenStream>,
    hoist_len: usize,
    hoist_seen: rustc_hash::FxHashMap<String, usize>,
    /// The graphs of r̈ built when the routes were compared.
    graphs: RouteGraphs,
    /// Maggi's terms, for a system in generalized speeds.
    maggi: Option<crate::mechanics::MaggiTerms>,
    /// The parameters of `sensitivities`, in order.
    sensitivity_params: Vec<Ident>,
}

impl Derived<'_, '_> {
    /// Emits a method's values; those that depend on parameters alone are
    /// computed once, when the parameters are set, into a cache the method
    /// reads (see `api::expand`).
    fn emit_hoisted(&mut self, d: &Dag, outs: &[Node]) -> (TokenStream, Vec<TokenStream>) {
        // `NH_HOIST=0` while compiling turns hoisting off (to measure it)
        let enabled = std::env::var_os("NH_HOIST").is_none_or(|v| v != "0");
        let hoisted = if self.m.parameters.is_empty() || !enabled {
            Vec::new()
        } else {
            d.hoistable(outs)
        };
        if hoisted.is_empty() {
            return d.emit(outs);
        }
        let (htext, houts) = d.emit_text(&hoisted, &rustc_hash::FxHashMap::default());
        // methods that hoist the same values share their cache slots
        let key = format!("{htext} => {}", houts.join(","));
        let base = match self.hoist_seen.get(&key) {
            Some(&base) => base,
            None => {
                let base = self.hoist_len;
                let mut block = htext;
                for (j, v) in houts.iter().enumerate() {
                    block.push_str(&format!("__nh_hoisted[{}] = {v};\n", base + j));
                }
                let hstmts = crate::emit::parse_text(&block);
                self.hoist_blocks.push(quote!({ #hstmts }));
                self.hoist_len += hoisted.len();
                self.hoist_seen.insert(key, base);
                base
            }
        };
        let given: rustc_hash::FxHashMap<Node, TokenStream> = hoisted
            .iter()
            .enumerate()
            .map(|(j, &h)| {
                let i = base + j;
                (h, quote!(__nh_cache[#i]))
            })
            .collect();
        let (stmts, o) = d.emit_with(outs, &given);
        // the cache read in place (no copy), or the values afresh if a
        // parameter changed since it was filled
        let read = quote! {
            let __nh_fresh;
            let __nh_cache = if self.__nh_cache_current() {
                &self.__nh_cache
            } else {
                __nh_fresh = self.__nh_compute_cache();
                &__nh_fresh
            };
        };
        (quote!(#read #stmts), o)
    }

    fn acc_nodes(&self, d: &mut Dag, route: Route) -> Vec<Node> {
        match route {
            Route::Multiplier => multiplier_nodes(d, self.m, &self.dv.multiplier_route).rdd,
            Route::Curvature => curvature_nodes(d, self.m, &self.dv.curvature_route).0,
        }
    }

    /// r̈ by `route`, from the route's graph.
    fn accelerations(&mut self, route: Route) -> TokenStream {
        let k = self.m.k();
        // the route's graph, built once when the routes were compared
        let (d, rdd) = match self.graphs.slot(route).take() {
            Some(g) => g,
            None => {
                let mut d = bound_dag(self.m, &Args::vectors(self.m).moving());
                let rdd = self.acc_nodes(&mut d, route);
                (d, rdd)
            }
        };
        let (stmts, o) = self.emit_hoisted(&d, &rdd);
        let ret = vector_expr(k, &o);
        let vel = velocity_arg(self.m);
        quote! { let _ = (t, q, #vel); #stmts #ret }
    }

    /// Operations of r̈ by `route`, after CSE.
    fn ops(&self, route: Route) -> usize {
        self.stats.ops(route)
    }

    /// The documentation of `accelerations`: what it computes, and by which
    /// route at what cost.
    fn accelerations_doc(&self) -> String {
        let u_doc = if self.m.inputs.is_empty() {
            ""
        } else {
            "\n\n`u` holds the inputs in declared order."
        };
        let used = self.ops(self.route);
        let other = match self.ops(self.route.other()) {
            0 if !self.m.homogeneous => {
                "the curvature route needs homogeneous, time-independent velocity constraints"
                    .to_string()
            }
            0 => {
                "the curvature route is derived for k ≤ 6 or with `outputs { routes }`".to_string()
            }
            other => format!("the other route needs {other}"),
        };
        format!(
            "{}{u_doc}\n\nDerived by {}; {used} operations after common-subexpression elimination ({other}). The k × k reduced mass matrix is factorised as LDLᵀ, unrolled, with its structural zeros pruned.",
            GeneratedMethod::Accelerations.spec().doc,
            self.route.doc(),
        )
    }

    /// The documentation of the method of `route` when `accelerations` uses
    /// the other.
    fn other_route_doc(&self, route: Route) -> String {
        format!(
            "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
            route.doc(),
            self.ops(route)
        )
    }
}

impl Derived<'_, '_> {
    /// Is the chosen route's r̈ large enough that methods needing it call
    /// [`accelerations`] instead of repeating its code? (Small systems keep
    /// one fused body per method: their shared work is a few operations.)
    fn is_large(&self) -> bool {
        self.stats.is_large(self.route)
    }

    /// `, u` when the system has inputs (to forward them to another method).
    fn u_forward(&self) -> TokenStream {
        if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(, u)
        }
    }

    /// r̈ by the curvature route of a large system: `reduced_system`'s Mc and
    /// f solved by an unrolled LDLᵀ.
    fn curvature_route_from_reduced(&mut self) -> TokenStream {
        let k = self.m.k();
        let u = self.u_forward();
        let mut d = bound_dag(self.m, &Args::vectors(self.m));
        let mass: Vec<Vec<Node>> = (0..k)
            .map(|a| (0..k).map(|b| d.leaf(quote!(__nh_mc[(#a, #b)]))).collect())
            .collect();
        let rhs: Vec<Node> = (0..k).map(|a| d.leaf(quote!(__nh_f[#a]))).collect();
        let (x, _) = d.solve_symmetric(&mass, &rhs);
        let (stmts, o) = d.emit(&x);
        let ret = vector_expr(k, &o);
        quote! {
            let (__nh_mc, __nh_f) = self.reduced_system(t, q, rdot #u);
            #stmts #ret
        }
    }

    /// The state variables in order: q, then ṙ.
    fn state_vars(&self) -> Vec<SymId> {
        self.m
            .positions()
            .chain(self.m.independent_velocities())
            .collect()
    }

    /// ∂f/∂z for each variable z of `vars`, as rows of f = [q̇, r̈] (n + k
    /// rows, one column per variable): the dependent velocities differentiated
    /// symbolically, r̈ through the reduced solve, ∂r̈/∂z = Mc⁻¹ (∂f/∂z −
    /// (∂Mc/∂z) r̈), with one factorisation for every column.
    fn derivative_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        if let Some(sol) = self.dv.curvature_route.solution.clone() {
            // r̈ in closed form: differentiate it directly (factors that cancel
            // in r̈, such as the mass, then cancel in its derivatives too)
            let mut out = self.velocity_rows(d, vars);
            for (c, &z) in vars.iter().enumerate() {
                for al in 0..k {
                    let e = self.m.engine.diff(sol[al], z);
                    out[n + al][c] = d.expr(self.m.engine, e);
                }
            }
            return out;
        }
        if self.route == Route::Multiplier {
            return self.multiplier_columns(d, vars);
        }
        let mass = matrix(d, self.m, &self.dv.curvature_route.mass);
        let rhs = exprs(d, self.m, &self.dv.curvature_route.rhs);
        let fac = d.factor_symmetric(&mass);
        let rdd = d.solve_factored(&fac, &rhs);
        let mut out = self.velocity_rows(d, vars);
        for (c, &z) in vars.iter().enumerate() {
            let mut col_rhs = Vec::with_capacity(k);
            for al in 0..k {
                let df = self.m.engine.diff(self.dv.curvature_route.rhs[al], z);
                let mut v = d.expr(self.m.engine, df);
                for be in 0..k {
                    let dm = self.m.engine.diff(self.dv.curvature_route.mass[al][be], z);
                    if dm != ZERO {
                        let dmn = d.expr(self.m.engine, dm);
                        let t = d.mul(dmn, rdd[be]);
                        v = d.sub(v, t);
                    }
                }
                col_rhs.push(v);
            }
            let col = d.solve_factored(&fac, &col_rhs);
            for al in 0..k {
                out[n + al][c] = col[al];
            }
        }
        out
    }

    /// ∂f/∂z through the multiplier route (5.9): r̈ solves R(z, r̈) = Cᵀ E = 0
    /// with E = M q̈ + h and q̈ = C r̈ + b (b = −Ȧ ṙ), so ∂r̈/∂z =
    /// −(Cᵀ M C)⁻¹ ∂R/∂z at fixed r̈, with the factorisation of r̈'s own solve.
    /// Each ∂/∂z is a total derivative: the dependent velocities ṡ(q, ṙ) in
    /// M, h and b are differentiated through the constraints (5.3).
    fn multiplier_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mn = multiplier_nodes(d, self.m, &self.dv.multiplier_route);
        let qdd = mn.qdd(d);
        let e_nodes: Vec<Node> = (0..n).map(|i| mn.euler_lagrange(d, i, &qdd)).collect();
        let mut out = self.velocity_rows(d, vars);
        for (col, &z) in vars.iter().enumerate() {
            let dsdot: Vec<Node> = (0..self.m.p())
                .map(|a| {
                    let e = self.m.engine.diff(self.m.constraints[a].velocity, z);
                    d.expr(self.m.engine, e)
                })
                .collect();
            // ∂C/∂z: only the rows of the dependent coordinates, −∂A/∂z
            let mut dc = vec![vec![ZERO_NODE; k]; n];
            let dependent = self.m.dependent().to_vec();
            for (a, &s) in dependent.iter().enumerate() {
                for b in 0..k {
                    let e = self.total_diff(d, self.m.constraints[a].coefficients[b], z, &dsdot);
                    dc[s][b] = d.neg(e);
                }
            }
            // ∂q̈/∂z at fixed r̈
            let mut dqdd = vec![ZERO_NODE; n];
            for (a, &s) in dependent.iter().enumerate() {
                let acc = self.total_diff(d, self.dv.multiplier_route.dependent_bias[a], z, &dsdot);
                dqdd[s] = dot(d, acc, (0..k).map(|b| (dc[s][b], mn.rdd[b])));
            }
            // ∂E/∂z = ∂M/∂z q̈ + M ∂q̈/∂z + ∂h/∂z
            let mut de = Vec::with_capacity(n);
            for i in 0..n {
                let mut acc = self.total_diff(d, self.dv.multiplier_route.bias[i], z, &dsdot);
                for j in 0..n {
                    let dm = self.total_diff(d, self.dv.multiplier_route.mass[i][j], z, &dsdot);
                    let t = d.mul(dm, qdd[j]);
                    acc = d.add(acc, t);
                    let t = d.mul(mn.mass[i][j], dqdd[j]);
                    acc = d.add(acc, t);
                }
                de.push(acc);
            }
            // −∂R/∂z = −Σ_i (∂C_iα/∂z E_i + C_iα ∂E_i/∂z)
            let mut rhs = Vec::with_capacity(k);
            for al in 0..k {
                let pairs = (0..n).flat_map(|i| [(dc[i][al], e_nodes[i]), (mn.c[i][al], de[i])]);
                let acc = dot(d, ZERO_NODE, pairs);
                rhs.push(d.neg(acc));
            }
            let x = d.solve_factored(&mn.fac, &rhs);
            for al in 0..k {
                out[n + al][col] = x[al];
            }
        }
        out
    }

    /// The total derivative of `e` with respect to `z` as a node: ∂e/∂z plus
    /// Σ_a ∂e/∂ṡ_a ∂ṡ_a/∂z, the dependent velocities ṡ being functions of
    /// q and ṙ through the constraints.
    fn total_diff(&mut self, d: &mut Dag, e: ExprId, z: SymId, dsdot: &[Node]) -> Node {
        let direct = self.m.engine.diff(e, z);
        let mut acc = d.expr(self.m.engine, direct);
        let model = self.m.model;
        for (a, c) in model.constraints.iter().enumerate() {
            if dsdot[a] == ZERO_NODE {
                continue;
            }
            let de = self
                .m
                .engine
                .diff(e, model.coordinates[c.dependent].velocity);
            if de != ZERO {
                let x = d.expr(self.m.engine, de);
                let t = d.mul(x, dsdot[a]);
                acc = d.add(acc, t);
            }
        }
        acc
    }

    /// The rows of q̇ in ∂f/∂z (the first n rows; the other k are zero).
    fn velocity_rows(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mut out = vec![vec![ZERO_NODE; vars.len()]; n + k];
        if self.m.speeds.is_some() {
            let w = self.m.constrained_qdot();
            for i in 0..n {
                for (c, &z) in vars.iter().enumerate() {
                    let e = self.m.engine.diff(w[i], z);
                    out[i][c] = d.expr(self.m.engine, e);
                }
            }
            return out;
        }
        for i in 0..n {
            match self.m.constraints.iter().find(|c| c.dependent == i) {
                None => {
                    let velocity = self.m.coordinates[i].velocity;
                    if let Some(c) = vars.iter().position(|&z| z == velocity) {
                        out[i][c] = ONE_NODE;
                    }
                }
                Some(con) => {
                    let sdot = con.velocity;
                    for (c, &z) in vars.iter().enumerate() {
                        let e = self.m.engine.diff(sdot, z);
                        out[i][c] = d.expr(self.m.engine, e);
                    }
                }
            }
        }
        out
    }
}

impl Derived<'_, '_> {
    /// `dependent_velocities`: ṡ = −A ṙ (5.3).
    fn dependent_velocities_body(&mut self) -> TokenStream {
        let p = self.m.p();
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let outs: Vec<Node> = match self.m.block {
            // solved numerically, bound in the graph
            Some(_) => self
                .m
                .constraints
                .iter()
                .filter_map(|c| d.bound(self.m.coordinates[c.dependent].velocity))
                .collect(),
            None => {
                let sdot: Vec<ExprId> = self.m.constraints.iter().map(|c| c.velocity).collect();
                exprs(&mut d, self.m, &sdot)
            }
        };
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let ret = vector_expr(p, &o);
        let t = if self.m.rheonomic() {
            quote!(t,)
        } else {
            quote!()
        };
        quote! { let _ = (#t q, rdot); #stmts #ret }
    }

    /// `reduced_system`: Mc and f of the curvature route (5.20).
    fn reduced_system_body(&mut self) -> TokenStream {
        let k = self.m.k();
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mass = matrix(&mut d, self.m, &self.dv.curvature_route.mass);
        let rhs = exprs(&mut d, self.m, &self.dv.curvature_route.rhs);
        let mut outs: Vec<Node> = mass.iter().flatten().copied().collect();
        outs.extend(&rhs);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let (mo, fo) = o.split_at(k * k);
        let kk = quote!(__nh_private::nalgebra::SMatrix::<T, #k, #k>);
        let f = vector_expr(k, fo);
        quote! { let _ = (t, q, rdot); #stmts (#kk::from_row_slice(&[#(#mo),*]), #f) }
    }

    /// `multipliers`: λ = E_s along the motion (5.10).
    fn multipliers_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mut mn = multiplier_nodes(&mut d, self.m, &self.dv.multiplier_route);
        let large = self.is_large();
        let u = self.u_forward();
        let prologue = if large {
            // r̈ from `accelerations`, not a second copy of its solve
            mn.rdd = (0..k).map(|b| d.leaf(quote!(__nh_rdd[#b]))).collect();
            quote!(let __nh_rdd = self.accelerations(t, q, rdot #u);)
        } else {
            quote!()
        };
        // q̈ = C r̈ + acc_bias; λ_a = E_{s_a} = (M q̈ + h)_{s_a}   (5.10)
        let qdd = mn.qdd(&mut d);
        let mut lam = Vec::with_capacity(p);
        for (a, &s) in self.m.dependent().iter().enumerate() {
            let acc = mn.euler_lagrange(&mut d, s, &qdd);
            d.label(acc, format!("λ{a} = E_(s{a}) (5.10)"));
            lam.push(acc);
        }
        let (stmts, o) = self.emit_hoisted(&d, &lam);
        let ret = vector_expr(p, &o);
        quote! { let _ = (t, q, rdot); #prologue #stmts #ret }
    }

    /// `curvature`: the coefficients B of (5.21).
    fn curvature_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mut nodes = Vec::new();
        let mut places = Vec::new();
        for (b, mat) in self.dv.curvature.iter().enumerate() {
            for al in 0..k {
                for be in (al + 1)..k {
                    if mat[al][be] != ZERO {
                        let x = d.expr(self.m.engine, mat[al][be]);
                        d.label(x, format!("B^{b}_({al},{be}) (5.21)"));
                        nodes.push(x);
                        places.push((b, al, be));
                    }
                }
            }
        }
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let mut sets = TokenStream::new();
        for ((b, al, be), v) in places.iter().zip(&o) {
            sets.extend(quote! {
                __nh_b[#b][(#al, #be)] = #v;
                __nh_b[#b][(#be, #al)] = -#v;
            });
        }
        let kk = quote!(__nh_private::nalgebra::SMatrix<T, #k, #k>);
        let kk_expr = quote!(__nh_private::nalgebra::SMatrix::<T, #k, #k>);
        let mutable = if places.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        quote! {
            let _ = q;
            #stmts
            let #mutable __nh_b: [#kk; #p] = [#kk_expr::zeros(); #p];
            #sets
            __nh_b
        }
    }

    /// `energy`: E = Σ q̇ ∂L/∂q̇ − L.
    fn energy_body(&mut self) -> TokenStream {
        let args = Args::vectors(self.m);
        let en = self.dv.energy.unwrap_or(ZERO);
        let mut d = bound_dag(self.m, &args);
        let node = d.expr(self.m.engine, en);
        let (stmts, o) = self.emit_hoisted(&d, &[node]);
        let v = &o[0];
        let vel = velocity_arg(self.m);
        quote! { let _ = (q, #vel); #stmts #v }
    }

    /// `constraint_matrix`: A of (5.3).
    fn constraint_matrix_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let flat: Vec<ExprId> = self
            .m
            .constraints
            .iter()
            .flat_map(|c| c.coefficients.iter().copied())
            .collect();
        self.matrix_of_q(p, k, &flat)
    }

    /// `contact_points`: the rolling contacts' points, one per column.
    fn contact_points_body(&mut self) -> TokenStream {
        let c = self.m.contacts.len();
        let flat: Vec<ExprId> = (0..3)
            .flat_map(|i| self.m.contacts.iter().map(move |p| p[i]))
            .collect();
        self.matrix_of_q(3, c, &flat)
    }

    /// `mass_matrix`: ∂²L/∂q̇∂q̇.
    fn mass_matrix_body(&mut self) -> TokenStream {
        let n = self.m.n();
        let mass = &self.dv.multiplier_route.mass;
        let flat: Vec<ExprId> = mass.iter().flatten().copied().collect();
        self.matrix_of_q(n, n, &flat)
    }

    /// A method of `q` returning the `rows` × `cols` matrix of the entries
    /// `flat`, row by row.
    fn matrix_of_q(&mut self, rows: usize, cols: usize, flat: &[ExprId]) -> TokenStream {
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let nodes = exprs(&mut d, self.m, flat);
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let ty = quote!(__nh_private::nalgebra::SMatrix::<T, #rows, #cols>);
        quote! { let _ = q; #stmts #ty::from_row_slice(&[#(#o),*]) }
    }

    /// `jacobian`: ∂f/∂x of the first-order system.
    fn jacobian_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let dim = n + k;
        let args_x = Args::state(self.m).moving();
        let mut d = bound_dag(self.m, &args_x);
        let vars = self.state_vars();
        let jac = self.derivative_columns(&mut d, &vars);
        let flat: Vec<Node> = jac.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        quote! { let _ = (t, x); #u #stmts #dd::from_row_slice(&[#(#o),*]) }
    }

    /// `time_derivative`: ∂f/∂t at fixed x (zero, not derived, for an
    /// autonomous system).
    fn time_derivative_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        if self.m.autonomous() {
            return quote! { let _ = (t, x); #u __nh_private::nalgebra::SVector::<T, #dim>::zeros() };
        }
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let column = self.derivative_columns(&mut d, &[self.m.time]);
        let flat: Vec<Node> = column.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let ret = vector_expr(dim, &o);
        quote! { let _ = (t, x); #u #stmts #ret }
    }

    /// The symbols of the parameters of `sensitivities`, in their order.
    fn sensitivity_syms(&self) -> Vec<SymId> {
        self.sensitivity_params
            .iter()
            .filter_map(|p| self.m.parameters.iter().find(|q| q.name == *p))
            .map(|p| p.sym)
            .collect()
    }

    /// `parameter_jacobian`: ∂f/∂p.
    fn parameter_jacobian_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let vars = self.sensitivity_syms();
        let cols = self.derivative_columns(&mut d, &vars);
        let flat: Vec<Node> = cols.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let p = vars.len();
        let dp = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #p>);
        quote! { let _ = (t, x); #stmts #dp::from_row_slice(&[#(#o),*]) }
    }

    /// `variational_rhs`: f, (∂f/∂x) S_p + ∂f/∂p and (∂f/∂x) S_x0 in one
    /// graph: the products are sums over the entries of ∂f/∂x that are not
    /// structurally zero, and every value is computed once.
    fn variational_rhs_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let state = self.state_vars();
        let params = self.sensitivity_syms();
        let p = params.len();
        let mut vars = state.clone();
        vars.extend(&params);
        let cols = self.derivative_columns(&mut d, &vars);
        let mut outs = self.rhs_nodes(&mut d);
        let s_p: Vec<Vec<Node>> = (0..dim)
            .map(|i| (0..p).map(|j| d.leaf(quote!(s_p[(#i, #j)]))).collect())
            .collect();
        let s_x0: Vec<Vec<Node>> = (0..dim)
            .map(|i| (0..dim).map(|j| d.leaf(quote!(s_x0[(#i, #j)]))).collect())
            .collect();
        for (sens, bias) in [(&s_p, true), (&s_x0, false)] {
            let width = sens.first().map_or(0, Vec::len);
            for row in &cols {
                for j in 0..width {
                    let init = if bias { row[dim + j] } else { ZERO_NODE };
                    let pairs = (0..dim).map(|i| (row[i], sens[i][j]));
                    outs.push(dot(&mut d, init, pairs));
                }
            }
        }
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let (f, rest) = o.split_at(dim);
        let (dsp, dsx) = rest.split_at(dim * p);
        let xty = vector_expr(dim, f);
        let dp = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #p>);
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        quote! {
            let _ = (t, x, s_p, s_x0);
            #stmts
            (#xty, #dp::from_row_slice(&[#(#dsp),*]), #dd::from_row_slice(&[#(#dsx),*]))
        }
    }

    /// f = [q̇, r̈] as nodes of `d` (bound to the state).
    fn rhs_nodes(&mut self, d: &mut Dag) -> Vec<Node> {
        let mut f: Vec<Node> = self
            .m
            .coordinates
            .iter()
            .map(|c| d.bound(c.velocity).unwrap_or(ZERO_NODE))
            .collect();
        f.extend(self.acc_nodes(d, self.route));
        f
    }

    /// `linearization`: A = ∂f/∂x and B = ∂f/∂u.
    fn linearization_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let (dim, m_in) = (n + k, self.m.inputs.len());
        let args_x = Args::state(self.m).moving();
        let mut d = bound_dag(self.m, &args_x);
        let mut vars = self.state_vars();
        vars.extend(self.m.inputs.iter().map(|u| u.sym));
        let cols = self.derivative_columns(&mut d, &vars);
        let a: Vec<Node> = cols
            .iter()
            .flat_map(|row| row[..dim].iter().copied())
            .collect();
        let b: Vec<Node> = cols
            .iter()
            .flat_map(|row| row[dim..].iter().copied())
            .collect();
        let mut all = a.clone();
        all.extend(&b);
        let (stmts, o) = self.emit_hoisted(&d, &all);
        let (ao, bo) = o.split_at(a.len());
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        let du = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #m_in>);
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        quote! { let _ = (t, x); #u #stmts (#dd::from_row_slice(&[#(#ao),*]), #du::from_row_slice(&[#(#bo),*])) }
    }

    /// The runtime's `rhs`: q̇ and r̈ from their inlined methods.
    fn rhs_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let u = self.u_forward();
        let t = if self.m.rheonomic() {
            quote!(t,)
        } else {
            quote!()
        };
        let ret = vector_expr(n + k, &{
            let mut v: Vec<TokenStream> = Vec::with_capacity(n + k);
            let (mut j, mut a) = (0usize, 0usize);
            for i in 0..n {
                if self.m.independent().contains(&i) {
                    v.push(quote!(__nh_rdot[#j]));
                    j += 1;
                } else {
                    v.push(quote!(__nh_sdot[#a]));
                    a += 1;
                }
            }
            v.extend((0..k).map(|b| quote!(__nh_rdd[#b])));
            v
        });
        quote! {
            let __nh_q = x.fixed_rows::<#n>(0).into_owned();
            let __nh_rdot = x.fixed_rows::<#k>(#n).into_owned();
            let __nh_sdot = self.dependent_velocities(#t &__nh_q, &__nh_rdot);
            let __nh_rdd = self.accelerations(t, &__nh_q, &__nh_rdot #u);
            #ret
        }
    }
}

impl Bodies for Derived<'_, '_> {
    fn method(&mut self, method: GeneratedMethod) -> Method {
        let spec = method.spec();
        if let Some(output) = spec.requested_by
            && output != Output::Routes
        {
            self.stats.derived.push(spec.name);
        }
        let static_doc = || spec.doc.to_string();
        let (doc, body) = match method {
            GeneratedMethod::DependentVelocities => {
                (static_doc(), self.dependent_velocities_body())
            }
            GeneratedMethod::Accelerations if self.maggi.is_some() => {
                (self.speeds_accelerations_doc(), self.accelerations(self.route))
            }
            GeneratedMethod::Accelerations => {
                (self.accelerations_doc(), self.accelerations(self.route))
            }
            GeneratedMethod::Velocities => (static_doc(), self.velocities_body()),
            GeneratedMethod::ReactionForces => (static_doc(), self.reaction_forces_body()),
            GeneratedMethod::MassMatrix if self.maggi.is_some() => (
                "The mass matrix in the speeds, Sᵀ M S (the mass matrix of Maggi's equations (Sᵀ M S) u̇ = .., with M = ∂²L/∂q̇∂q̇ and S = ∂q̇/∂u): rows and columns follow [`Self::SPEEDS`].".to_string(),
                self.speeds_mass_matrix_body(),
            ),
            GeneratedMethod::Rhs if self.maggi.is_some() => (
                "ẋ for the state x = [q, u]: ẋ = [S u + σ, u̇], with u̇ from Maggi's equations.".to_string(),
                self.speeds_rhs_body(),
            ),
            GeneratedMethod::AccelerationsMultiplierRoute
            | GeneratedMethod::AccelerationsCurvatureRoute
                if method == self.route.method() =>
            {
                let u = self.u_forward();
                let doc = format!(
                    "r̈ by {}, the route [`Self::accelerations`] uses ({} operations).",
                    self.route.doc(),
                    self.ops(self.route)
                );
                (doc, quote! { self.accelerations(t, q, rdot #u) })
            }
            GeneratedMethod::AccelerationsCurvatureRoute if self.is_large() => (
                self.other_route_doc(Route::Curvature),
                self.curvature_route_from_reduced(),
            ),
            GeneratedMethod::AccelerationsMultiplierRoute => (
                self.other_route_doc(Route::Multiplier),
                self.accelerations(Route::Multiplier),
            ),
            GeneratedMethod::AccelerationsCurvatureRoute => (
                self.other_route_doc(Route::Curvature),
                self.accelerations(Route::Curvature),
            ),
            GeneratedMethod::ReducedSystem => (static_doc(), self.reduced_system_body()),
            GeneratedMethod::Multipliers => (static_doc(), self.multipliers_body()),
            GeneratedMethod::Curvature => (static_doc(), self.curvature_body()),
            GeneratedMethod::Energy => (static_doc(), self.energy_body()),
            GeneratedMethod::ConstraintMatrix => (static_doc(), self.constraint_matrix_body()),
            GeneratedMethod::ContactPoints => (static_doc(), self.contact_points_body()),
            GeneratedMethod::MassMatrix => (static_doc(), self.mass_matrix_body()),
            GeneratedMethod::Linearization if self.maggi.is_some() => (
                "The linearisation of the first-order system ẋ = f(t, x, u), x = [q, u_speeds], at (t, x, u): A = ∂f/∂x and B = ∂f/∂u, derived symbolically through Maggi's equations (as for the Jacobian). For controller design: δẋ ≈ A δx + B δu.".to_string(),
                self.linearization_body(),
            ),
            GeneratedMethod::Linearization => (static_doc(), self.linearization_body()),
            GeneratedMethod::Jacobian if self.m.outputs.contains(Output::Linearization) => {
                // the linearisation's A is this Jacobian: one copy of the code
                let u = self.u_forward();
                let system = if self.maggi.is_some() {
                    "The Jacobian ∂f/∂x of the first-order system x = [q, u] ↦ [S u + σ, u̇]"
                } else {
                    spec.doc
                };
                let doc = format!(
                    "{system}: the matrix A of [`Self::linearization`], derived symbolically through the reduced solve.",
                );
                (doc, quote! { self.linearization(t, x #u).0 })
            }
            GeneratedMethod::Jacobian if self.maggi.is_some() => {
                let doc = "The Jacobian ∂f/∂x of the first-order system x = [q, u] ↦ [S u + σ, u̇], derived symbolically: the kinematics differentiated directly, u̇ through Maggi's equations, ∂u̇/∂z = (Sᵀ M S)⁻¹ (∂f/∂z − ∂(Sᵀ M S)/∂z u̇) with one factorisation for every column.".to_string();
                (doc, self.jacobian_body())
            }
            GeneratedMethod::Jacobian => {
                let doc = format!(
                    "{}, derived symbolically through the reduced solve: ∂r̈/∂z = Mc⁻¹ (∂f/∂z − (∂Mc/∂z) r̈) with the curvature route's Mc and f (5.20), reusing one LDLᵀ factorisation for every column.",
                    spec.doc
                );
                (doc, self.jacobian_body())
            }
            GeneratedMethod::TimeDerivative => (static_doc(), self.time_derivative_body()),
            GeneratedMethod::ParameterJacobian => (static_doc(), self.parameter_jacobian_body()),
            GeneratedMethod::VariationalRhs => (static_doc(), self.variational_rhs_body()),
            GeneratedMethod::SensitivitySystem => (
                static_doc(),
                quote!(__nh_private::nh_runtime::Sensitivities::new(self)),
            ),
            // q̇ and r̈ from their methods, inlined (one copy of the code;
            // measured as fast as a fused body)
            GeneratedMethod::Rhs if self.maggi.is_some() => (
                "ẋ for the state x = [q, u] of a system in generalized speeds: ẋ = [S u + σ, u̇], u̇ by Maggi's equations.".to_string(),
                self.rhs_body(),
            ),
            GeneratedMethod::Rhs => (static_doc(), self.rhs_body()),
        };
        Method { doc, body }
    }

    fn runtime_hooks(&mut self, xty: &TokenStream) -> TokenStream {
        let mut hooks = if self.maggi.is_some() {
            self.chart_regularity()
        } else {
            crate::manifold::methods(self.m, xty)
        };
        hooks.extend(crate::poles::method(self.m, xty));
        if !self.m.autonomous() {
            return hooks;
        }
        quote! {
            #hooks
            /// Nothing in the definition depends on `t` explicitly: ∂f/∂t = 0.
            #[inline]
            fn is_autonomous(&self) -> bool {
                true
            }
        }
    }

    fn description(&self) -> Vec<String> {
        self.m.description.clone()
    }

    fn hoisting(&mut self) -> (usize, TokenStream) {
        let blocks = &self.hoist_blocks;
        (self.hoist_len, quote!(#(#blocks)*))
    }

    fn route_consts(&mut self) -> TokenStream {
        let (om, oc) = (self.stats.ops_multiplier, self.stats.ops_curvature);
        let chosen = match self.route {
            Route::Multiplier => "multiplier",
            Route::Curvature => "curvature",
        };
        self.stats.derived.push("routes");
        quote! {
            /// Operations (after CSE) of r̈ by the multiplier route (5.9).
            pub const OPS_MULTIPLIER_ROUTE: usize = #om;
            /// Operations (after CSE) of r̈ by the curvature route (5.20).
            pub const OPS_CURVATURE_ROUTE: usize = #oc;
            /// The route [`Self::accelerations`] uses: `"multiplier"` or `"curvature"`.
            pub const ROUTE: &'static str = #chosen;
        }
    }
}

/// Builds the whole expansion for a lowered model: derives the mechanics,
/// checks them, builds each route's graph of r̈ to choose one, and emits
/// the API from the derivation and those graphs.
pub fn generate(
    def: &SystemDef,
    model: &Model,
    engine: &mut Engine,
    cx: &mut Ctxt,
) -> (TokenStream, Stats) {
    let mut stats = Stats {
        name: def.name.to_string(),
        ..Stats::default()
    };
    let _ = crate::emit::take_unrepresentable();
    let mut m = Scene::new(model, engine);
    if m.speeds.is_some() {
        return generate_speeds(def, m, cx, stats);
    }
    // the curvature route pays for small systems (its closed forms); beyond
    // CURVATURE_ROUTE_MAX_K independent coordinates it is derived only when
    // `routes` asks for it, and `accelerations` takes the multiplier route
    // (only for homogeneous, time-independent velocity constraints: DESIGN §9)
    let both_routes =
        m.homogeneous && (m.outputs.contains(Output::Routes) || m.k() <= CURVATURE_ROUTE_MAX_K);
    let mut dv = crate::mechanics::derive(&mut m, both_routes);
    stats.derived.extend([
        if both_routes {
            "accelerations (both routes)"
        } else {
            "accelerations (multiplier route)"
        },
        "curvature terms",
    ]);
    // (5.21) decides integrability of the homogeneous part only: with affine
    // or time-dependent terms the constraints are not called integrable
    dv.integrable &= !m.affine;
    stats.integrable = dv.integrable;
    stats.integrable_proved = dv.integrable_proved;
    if !derivation_checked(def, &mut m, &mut dv, cx) {
        return (TokenStream::new(), stats);
    }
    let compared = compare_routes(&mut m, &mut dv, both_routes);
    if !check::regular(def, &compared.pivots, cx) {
        return (TokenStream::new(), stats);
    }
    let route = compared.choose(&mut stats);
    let graphs = compared.keep(route, &m, &dv, &stats);
    let (integrable, proved) = (dv.integrable, dv.integrable_proved);
    let mut shape = shape_of(def);
    shape.integrable = integrable;
    shape.outputs = m.outputs;
    shape.independent = m.independent().to_vec();
    shape.dependent = m.dependent().to_vec();
    shape.dependent_doc = dependent_doc(&m);
    shape.affine = m.affine;
    shape.rheonomic = m.rheonomic();
    let mut bodies = Derived {
        m: &mut m,
        dv,
        route,
        stats: &mut stats,
        hoist_blocks: Vec::new(),
        hoist_len: 0,
        hoist_seen: rustc_hash::FxHashMap::default(),
        graphs,
        maggi: None,
        sensitivity_params: shape.sensitivity_params.clone(),
    };
    let mut tokens = crate::api::expand(&shape, &mut bodies);
    let velocity_constraints = m.constraints.iter().any(|c| c.holonomic.is_none());
    if integrable && velocity_constraints {
        tokens.extend(integrability_warning(
            def,
            m.constraints_span.unwrap_or(def.name.span()),
            proved,
        ));
    }
    finish(def, &m, cx, tokens, stats)
}

/// The checks of a derivation within the engine's limits, with the energy
/// derived in between if asked for (once the rest is known to be within
/// them). False after an error.
fn derivation_checked(
    def: &SystemDef,
    m: &mut Scene<'_>,
    dv: &mut Derivation,
    cx: &mut Ctxt,
) -> bool {
    if !check::within_limits(def, m, cx) {
        return false;
    }
    if m.outputs.contains(Output::Energy) {
        dv.energy = Some(m.energy());
    }
    check::derivation(def, m, dv, cx) && check::forms(def, m, cx)
}

/// The expansion once every method is emitted: empty if a constant of the
/// generated code is beyond `f64`, with the engine's figures.
fn finish(
    def: &SystemDef,
    m: &Scene<'_>,
    cx: &mut Ctxt,
    tokens: TokenStream,
    mut stats: Stats,
) -> (TokenStream, Stats) {
    if !check::representable(def, m, cx) {
        return (TokenStream::new(), stats);
    }
    stats.graph_size = m.engine.num_exprs();
    stats.derivatives = m.engine.counters.derivatives;
    (tokens, stats)
}

/// The reduced system of `dv.curvature_route` (graph `reduced`, solved
/// numerically, with pivots `pivots`) solved symbolically instead, if that
/// is cheaper; the solution is then kept in the derivation.
fn solved_if_cheaper(
    m: &mut Scene<'_>,
    dv: &mut Derivation,
    reduced: (Dag, Vec<Node>),
    pivots: &[Node],
) -> (Dag, Vec<Node>) {
    let (cmass, crhs) = (
        dv.curvature_route.mass.clone(),
        dv.curvature_route.rhs.clone(),
    );
    if pivots.iter().all(|&p| p != ZERO_NODE)
        && let Some(sol) = m.solve_symbolic(&cmass, &crhs)
    {
        let mut d3 = bound_dag(m, &Args::vectors(m));
        let x3 = exprs(&mut d3, m, &sol);
        if d3.cost_estimate(&x3) < reduced.0.cost_estimate(&reduced.1) {
            dv.curvature_route.solution = Some(sol);
            return (d3, x3);
        }
    }
    reduced
}

/// The expansion of a system in generalized speeds (DESIGN §9): Maggi's
/// equations, solved like the curvature route's reduced system.
fn generate_speeds(
    def: &SystemDef,
    mut m: Scene<'_>,
    cx: &mut Ctxt,
    mut stats: Stats,
) -> (TokenStream, Stats) {
    let (mut dv, terms) = crate::mechanics::derive_maggi(&mut m);
    stats.derived.push("accelerations (Maggi's equations)");
    if !derivation_checked(def, &mut m, &mut dv, cx) {
        return (TokenStream::new(), stats);
    }
    let mut d = bound_dag(&m, &Args::vectors(&m));
    let (udot, pivots) = curvature_nodes(&mut d, &m, &dv.curvature_route);
    if !check::regular(def, &pivots, cx) {
        return (TokenStream::new(), stats);
    }
    let (d, udot) = solved_if_cheaper(&mut m, &mut dv, (d, udot), &pivots);
    stats.ops_curvature = d.op_count(&udot);
    stats.cost_curvature = d.cost_estimate(&udot);
    stats.route = Some(Route::Curvature);
    stats.maggi = true;
    let mut shape = shape_of(def);
    shape.outputs = m.outputs;
    let mut bodies = Derived {
        m: &mut m,
        dv,
        route: Route::Curvature,
        stats: &mut stats,
        hoist_blocks: Vec::new(),
        hoist_len: 0,
        hoist_seen: rustc_hash::FxHashMap::default(),
        graphs: RouteGraphs {
            multiplier: None,
            curvature: Some((d, udot)),
        },
        maggi: Some(terms),
        sensitivity_params: shape.sensitivity_params.clone(),
    };
    let tokens = crate::api::expand(&shape, &mut bodies);
    finish(def, &m, cx, tokens, stats)
}

/// The documentation of `DEPENDENT` when some constraint is implicit or
/// holonomic: which coordinate each constraint is solved for.
fn dependent_doc(m: &Scene<'_>) -> Option<String> {
    m.chart?;
    let mut doc = String::from(
        " Indices in `q` of the dependent coordinates s (one per constraint), ascending. Each constraint is solved for one of them (DESIGN §9):\n",
    );
    for c in &m.constraints {
        doc.push_str(&format!(
            "\n - `{}` ({}): solved for `{}`",
            c.source,
            c.kind.describe(),
            m.coordinates[c.dependent].name
        ));
    }
    doc.push_str("\n\n`dependent_velocities` and `multipliers` follow this order; the multiplier λ_a belongs to the constraint solved for s_a, normalised as ṡ_a + Σ A^a_α ṙ_α + β_a = 0.");
    Some(doc)
}

/// The graphs of r̈ by both routes, built to compare their costs.
struct ComparedRoutes {
    multiplier: (Dag, Vec<Node>),
    /// Empty when the curvature route is not derived.
    curvature: (Dag, Vec<Node>),
    both_routes: bool,
    /// The pivots of both routes' factorisations of the reduced mass matrix.
    pivots: Vec<Node>,
}

/// Builds the graph of r̈ by each route (the curvature route's with the
/// reduced system solved symbolically, if that is cheaper).
fn compare_routes(m: &mut Scene<'_>, dv: &mut Derivation, both_routes: bool) -> ComparedRoutes {
    let args_v = Args::vectors(m).moving();
    let mut d1 = bound_dag(m, &args_v);
    let mn = multiplier_nodes(&mut d1, m, &dv.multiplier_route);
    let mut d2 = bound_dag(m, &args_v);
    let (mut rdd2, piv2) = if both_routes {
        curvature_nodes(&mut d2, m, &dv.curvature_route)
    } else {
        (Vec::new(), Vec::new())
    };
    if both_routes {
        (d2, rdd2) = solved_if_cheaper(m, dv, (d2, rdd2), &piv2);
    }
    ComparedRoutes {
        multiplier: (d1, mn.rdd),
        curvature: (d2, rdd2),
        both_routes,
        pivots: mn.pivots.into_iter().chain(piv2).collect(),
    }
}

impl ComparedRoutes {
    /// Records both routes' figures and chooses the cheaper.
    fn choose(&self, stats: &mut Stats) -> Route {
        let ((d1, rdd1), (d2, rdd2)) = (&self.multiplier, &self.curvature);
        stats.ops_multiplier = d1.op_count(rdd1);
        stats.ops_curvature = d2.op_count(rdd2);
        stats.cost_multiplier = d1.cost_estimate(rdd1);
        stats.cost_curvature = d2.cost_estimate(rdd2);
        let route = if self.both_routes && stats.cost_curvature <= stats.cost_multiplier {
            Route::Curvature
        } else {
            Route::Multiplier
        };
        stats.route = Some(route);
        let (d, rdd) = match route {
            Route::Multiplier => (d1, rdd1),
            Route::Curvature => (d2, rdd2),
        };
        stats.ops_on_parameters = d.op_count(&d.hoistable(rdd));
        route
    }

    /// The graphs a method will emit: the chosen route's, and with `routes`
    /// the other's, unless its method emits another graph (the curvature
    /// route of a large system is solved from `reduced_system`; solved
    /// symbolically, it is emitted with its steps labelled).
    fn keep(self, route: Route, m: &Scene<'_>, dv: &Derivation, stats: &Stats) -> RouteGraphs {
        let other_kept = m.outputs.contains(Output::Routes)
            && (route == Route::Curvature
                || (dv.curvature_route.solution.is_none() && !stats.is_large(route)));
        let mut graphs = RouteGraphs::default();
        let (multiplier, curvature) = (self.multiplier, self.curvature);
        if route == Route::Multiplier || other_kept {
            graphs.multiplier = Some(multiplier);
        }
        if route == Route::Curvature || other_kept {
            graphs.curvature = Some(curvature);
        }
        graphs
    }
}

/// A compile-time warning on stable Rust, which has no warning a
/// procedural macro can emit: the use of a deprecated item, whose note is
/// the message. rustc words it "use of deprecated {kind} `{path}`: {note}";
/// the item is a `macro_rules!` macro local to an anonymous constant,
/// whose path is its bare name, so the warning's first words say what it is:
/// "use of deprecated macro `LineWheel_has_integrable_constraints`: a
/// warning, not a deprecation: ..." (a constant's path would read
/// `_::name`). Its invocation carries the span of the `constraints`
/// keyword, where the warning points; it is the lint `deprecated`, so
/// `#[allow(deprecated)]` on the system silences it.
fn integrability_warning(def: &SystemDef, span: proc_macro2::Span, proved: bool) -> TokenStream {
    let how = if proved {
        "every curvature coefficient B^b_αβ of (5.21) vanishes identically"
    } else {
        "every curvature coefficient B^b_αβ of (5.21) evaluates to zero (to 1e-24 of its terms, in 32-digit arithmetic) at 16 random points, though the simplifier could not prove it"
    };
    let name = syn::ext::IdentExt::unraw(&def.name);
    let note = format!(
        "a warning, not a deprecation: {how}, so the constraints of `{name}` are holonomic in disguise. Integrate them and eliminate the dependent coordinates (a smaller system with no constraints), or keep them: the equations of motion are still correct. `{name}::INTEGRABLE` is `true`; `#[allow(deprecated)]` on the struct silences this warning."
    );
    let item = proc_macro2::Ident::new(&format!("{name}_has_integrable_constraints"), span);
    let inherited = crate::attrs::inherited(&def.attrs);
    quote::quote_spanned! {span=>
        #(#inherited)*
        const _: () = {
            #[deprecated(note = #note)]
            macro_rules! #item {
                () => {};
            }
            #item!();
        };
    }
}

/// Lines of code the way a pretty-printer lays them out: one per statement,
/// item, attribute and brace.
pub fn count_lines(tokens: &TokenStream) -> usize {
    let mut lines = 0;
    for tt in tokens.clone() {
        match tt {
            proc_macro2::TokenTree::Punct(p) if p.as_char() == ';' || p.as_char() == '#' => {
                lines += 1
            }
            proc_macro2::TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace => {
                lines += 2 + count_lines(&g.stream())
            }
            _ => {}
        }
    }
    lines
}
