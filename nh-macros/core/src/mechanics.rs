//! The mechanics of DESIGN §4, derived symbolically: the mass matrix and
//! Euler–Lagrange terms, the constraint matrix, the multiplier route (5.9)/(5.10),
//! the constrained Lagrangian and the curvature route (5.12)–(5.21), and the
//! energy. Every function derives only what it is asked for.

use crate::model::{Model, Output};
use crate::sym::dd::Dd;
use crate::sym::{Atom, Engine, ExprId, SymId, ZERO};
use rustc_hash::FxHashMap as HashMap;

mod composite;
mod pivots;

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
    /// Kane's form of the same terms for a Lagrangian of bodies.
    pub bodies: Option<BodyTerms>,
}

/// The Euler–Lagrange terms of a Lagrangian Σ_b T_b + L_rest, body by
/// body: with v_b = J_b q̇ and ω_b = W_b q̇, d/dt ∂T_b/∂q̇ − ∂T_b/∂q =
/// m J_bᵀ a_b + W_bᵀ (I α_b + ω_b × I ω_b), a_b = J_b q̈ + J̇_b q̇ and
/// α_b = W_b q̈ + Ẇ_b q̇ (Kane's generalized inertia forces).
pub struct BodyTerms {
    /// The bodies.
    pub bodies: Vec<BodyKinematics>,
    /// M and h (forces included) of L_rest.
    pub rest_mass: Vec<Vec<ExprId>>,
    /// See `rest_mass`.
    pub rest_bias: Vec<ExprId>,
    /// γ of a uniform gravity −γ Σ m_b C_b,z taken out of L_rest: its
    /// projected force is γ Σ m_b V_b,z.
    pub gravity: Option<ExprId>,
    /// ψ̇ when the centres' Jacobians are in the heading's frame (see
    /// [`BlockTerms::heading_rate`]).
    pub heading_rate: Option<ExprId>,
    /// The coordinates (x, y) of the block's [`Planar`] translation when it
    /// moves every centre too: the bodies' sums then take the dependent
    /// velocities and accelerations of x and y as u (heading frame), and
    /// the Jacobians' columns of x and y as e_x, e_y.
    pub planar: Option<[usize; 2]>,
}

/// One body's kinematics for [`BodyTerms`].
pub struct BodyKinematics {
    /// m.
    pub mass: ExprId,
    /// J = ∂C/∂q, 3 × n (the centre's rate J̇ q̇ at q̈ = 0 is computed on
    /// the graph: `generate::motion`); `None` for a body whose centre of
    /// mass was folded into another's, empty rows when its chain's frames
    /// give it as screws (DESIGN §10).
    pub jacobian: Option<[Vec<ExprId>; 3]>,
    /// The chain the centre's acceleration follows from a contact's centre,
    /// sparing its own J̇ q̇.
    pub anchor: Option<Chain>,
    /// Its rotation, unless it is a point mass.
    pub rotation: Option<BodyRotation>,
}

/// How a point's acceleration at q̈ = 0 follows from a root point's
/// (DESIGN §10): a = J̇_root q̇ + Σ_links R(α_b × r + ω_b × (ω_b × r)),
/// each link a body frame in which the next point is fixed at offset r
/// from the last.
#[derive(Clone)]
pub struct Chain {
    /// J of the root point, 3 × n, in the frame of the bodies' J.
    pub root: [Vec<ExprId>; 3],
    /// The links, from the root on.
    pub links: Vec<Link>,
}

/// One link of a [`Chain`].
#[derive(Clone)]
pub struct Link {
    /// ω_b of the frame's body (body axes).
    pub omega: [ExprId; 3],
    /// r, body axes, constant.
    pub offset: [ExprId; 3],
    /// The frame's orientation R (body → world), turned into the frame of J.
    pub turn: [[ExprId; 3]; 3],
    /// The same frame as its elementary rotations, when it is one.
    pub frame: Option<Frame>,
}

/// The product T of a rotation's trailing constant factors.
pub(crate) type Tail = [[ExprId; 3]; 3];

/// A body frame as the product of elementary rotations R_k(θ), from which
/// its orientation R, ω_b and α_b follow step by step (DESIGN §10):
/// ω' = R_kᵀ ω + θ̇ e_k, α' = R_kᵀ α + (R_kᵀ ω) × θ̇ e_k + θ̈ e_k.
#[derive(Clone)]
pub struct Frame {
    /// The steps, left to right.
    pub steps: Vec<FrameStep>,
    /// Whether the first step is the heading R_z(ψ) that the frame of the
    /// bodies' J turns back (R = the product of the others there).
    pub heading_out: bool,
}

/// One elementary rotation of a [`Frame`].
#[derive(Clone)]
pub struct FrameStep {
    /// k.
    pub axis: usize,
    /// R_k(θ).
    pub turn: [[ExprId; 3]; 3],
    /// θ̇.
    pub rate: ExprId,
    /// ∂θ̇/∂q̇, 1 × n.
    pub rate_jacobian: Vec<ExprId>,
}

/// A body's rotation for [`BodyKinematics`], in body axes.
pub struct BodyRotation {
    /// ω_b(q, q̇).
    pub omega: [ExprId; 3],
    /// W = ∂ω_b/∂q̇, 3 × n.
    pub jacobian: [Vec<ExprId>; 3],
    /// I about the centre of mass.
    pub inertia: Inertia,
    /// For a body symmetric about axis k of its last factor R_k(θ) (a
    /// wheel), the vectors above are turned by R_k(θ), which frees them of
    /// θ, and the torque gains −θ̇ I (e_k × ω'): (k, θ̇).
    pub spin: Option<(usize, ExprId)>,
    /// The wheels folded into this body, with ∂θ̇/∂q̇ (1 × n) each.
    pub wheels: Vec<(Wheel, Vec<ExprId>)>,
    /// Its frame as elementary rotations (not for a wheel's spin).
    pub frame: Option<Frame>,
}

/// A body's inertia about its centre of mass as it is built (DESIGN §10):
/// T (I + Σ μ(|d|² 1 − d dᵀ)) Tᵀ, I its own inertia with its wheels'
/// transverse moments, a parallel-axis term per centre folded into it and
/// T the trailing constant factors of its orientation. The generated code
/// forms the sums and the turn from their parts, where the expanded entries
/// would multiply every offset by every sine of T.
pub struct Inertia {
    /// I, body axes.
    pub own: [[ExprId; 3]; 3],
    /// (μ, d) of each centre folded in, d in body axes.
    pub masses: Vec<(ExprId, [ExprId; 3])>,
    /// T, if the body's axes are turned by trailing constant factors.
    pub tail: Option<[[ExprId; 3]; 3]>,
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

/// Whether every expression of `entries` vanishes at 16 random points in
/// double-double arithmetic (about 32 digits): any point where one exceeds
/// 1e-24 of the sum of its terms' sizes proves it nonzero; entries below that
/// at every point are taken as zero (an identity the canonical form does not
/// know, such as an angle-addition formula). Every symbol but π takes values
/// in [0.3, 1.4], the same points every build.
pub fn vanish_at_random_points(engine: &Engine, pi: SymId, entries: &[ExprId]) -> bool {
    let mut rng = crate::sym::Rng::new(0x243F_6A88_85A3_08D3);
    let mut points = 0;
    for _ in 0..64 {
        if points == 16 {
            break;
        }
        let vals = rng.point(engine.num_symbols(), pi);
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
fn velocity_degree(
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
    /// Per independent velocity, whether its entry of the reduced mass
    /// matrix Cᵀ M C vanishes (it appears nowhere in the constrained
    /// Lagrangian).
    pub silent: Vec<bool>,
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

/// The block of velocity rows c_s ṡ + c_r ṙ = 0 of a system solved by
/// elimination, for solving it numerically in the generated code with the
/// pivots chosen here (DESIGN §9): its rows' coefficients and rates.
pub struct BlockTerms {
    /// The elimination's steps in order: (pivot row, column), column b
    /// the dependent velocity of constraint b.
    pub pivots: Vec<(usize, usize)>,
    /// The rows, in the order of [`Model::velocity_rows`].
    pub rows: Vec<RowTerms>,
    /// The contacts the rows refer to.
    pub contacts: Vec<ContactTerms>,
    /// ψ̇ when the contacts' vectors are in the heading's frame
    /// (`heading_frame`): a world rate ȧ is then R ȧ = (R a)˙ + ψ̇ e_z × R a.
    pub heading_rate: Option<ExprId>,
    /// A planar translation (x, y) among the dependent coordinates, solved
    /// for in the heading's frame (see [`Planar`]).
    pub planar: Option<Planar>,
}

/// Dependent coordinates x, y that translate every contact (∂G/∂x = e_x,
/// ∂G/∂y = e_y), with the rows in the heading's frame R_z(−ψ): their
/// columns there turn with ψ (static pivots would fail at some heading), so
/// the block is solved for u = R_z(−ψ)(ẋ, ẏ), whose columns are e_x and e_y
/// (DESIGN §9), and (ẋ, ẏ) = R_z(ψ) u.
#[derive(Clone, Copy)]
pub struct Planar {
    /// The constraints (block columns) of x and y.
    pub columns: [usize; 2],
    /// R_z(ψ) restricted to the plane, by rows.
    pub turn: [[ExprId; 2]; 2],
}

/// One velocity row g(q, q̇) = 0 of a [`BlockTerms`].
pub enum RowTerms {
    /// A row as written: ∂g/∂q̇_i for every coordinate, and Σ ∂g/∂q_i q̇_i.
    Written {
        /// ∂g/∂q̇_i.
        coefficients: Vec<ExprId>,
        /// Σ_i ∂g/∂q_i q̇_i.
        along: ExprId,
    },
    /// Component `component` of contact `contact`'s material velocity.
    Contact {
        /// Index into [`BlockTerms::contacts`].
        contact: usize,
        /// 0, 1, 2: x, y, z.
        component: usize,
    },
}

/// A contact's terms: v = J_G q̇ + (W q̇) × o, its rate at q̈ = 0
/// J̇_G q̇ + (Ẇ q̇) × o + ω × ȯ, with o = −r w − ρ e_z (DESIGN §10).
pub struct ContactTerms {
    /// J_G = ∂G/∂q, 3 × n.
    pub centre_jacobian: [Vec<ExprId>; 3],
    /// ω (world components).
    pub omega: [ExprId; 3],
    /// W = ∂ω/∂q̇, 3 × n.
    pub omega_jacobian: [Vec<ExprId>; 3],
    /// The chain its centre's acceleration follows, if any.
    pub chain: Option<Chain>,
    /// The world axle n and s = |e_z × n|, for a disc or torus.
    pub axle: Option<([ExprId; 3], ExprId)>,
    /// w = (e_z − n_z n)/s as an expression, when s has no root (a wheel
    /// upright in the reference configuration: s = √c cos u): the division
    /// then cancels, and ẇ is w's rate along the motion.
    pub rim: Option<[ExprId; 3]>,
    /// r.
    pub radius: ExprId,
    /// ρ.
    pub tube: ExprId,
    /// The body's frame as elementary rotations, when it is one.
    pub frame: Option<Frame>,
}

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
        };
        if model.speeds.is_none() {
            let frame = scene.heading_frame();
            scene.contact_chains = scene.contact_chains(&frame);
            scene.block = scene.block_terms();
        }
        scene
    }

    /// Whether some dependent velocity depends on time explicitly.
    pub fn rheonomic(&self) -> bool {
        let m = self.model;
        m.constraints
            .iter()
            .any(|c| self.engine.depends_on(c.velocity, m.time))
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
        !std::iter::once(m.lagrangian)
            .chain(forces)
            .chain(constraints)
            .chain(kinematics)
            .any(|x| self.engine.depends_on(x, t))
    }
}

impl Scene<'_> {
    /// The multiplier route, the curvature and the curvature route (only its
    /// reduced mass matrix unless `both_routes`), and whether the
    /// constraints are integrable.
    pub fn derive(&mut self, both_routes: bool) -> Derivation {
        let multiplier_route = self.multiplier_route();
        // the full curvature when a route or the output uses it; otherwise
        // only as many entries as it takes to see that one does not vanish
        let (curvature, (integrable, integrable_proved)) =
            if both_routes || self.model.outputs.contains(Output::Curvature) {
                let curvature = self.curvature();
                let integrability = self.integrability(&curvature);
                (curvature, integrability)
            } else {
                (Vec::new(), self.integrability_entry_by_entry())
            };
        let curvature_route = if both_routes {
            self.curvature_route(&curvature)
        } else {
            CurvatureRoute {
                mass: Vec::new(),
                rhs: Vec::new(),
                solution: None,
            }
        };
        let silent = if both_routes {
            (0..self.model.k())
                .map(|a| curvature_route.mass[a][a] == ZERO)
                .collect()
        } else {
            self.silent_velocities(&multiplier_route.mass)
        };
        Derivation {
            silent,
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
            vanish_at_random_points(&self.engine, self.model.pi, &entries),
            false,
        )
    }

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

    /// The multiplier route's symbolic pieces.
    pub fn multiplier_route(&mut self) -> MultiplierRoute {
        let n = self.model.n();
        let bodies = self.body_terms();
        let (mass, bias) = if self.needs_lagrangian_terms(bodies.is_some()) {
            self.euler_lagrange_terms(self.model.lagrangian, true)
        } else {
            (Vec::new(), Vec::new())
        };
        // with a block solved numerically, the accelerations take its rates
        // on the graph; the symbolic −Ȧṙ serves only outputs that
        // differentiate it
        let dependent_bias =
            if self.block.is_some() && !self.model.outputs.differentiate_derivation() {
                Vec::new()
            } else if self.model.velocity_rows.is_empty() {
                self.dependent_bias_from_solutions()
            } else {
                self.dependent_bias_from_rows()
            };
        debug_assert!(mass.len() == n || (mass.is_empty() && bodies.is_some()));
        MultiplierRoute {
            mass,
            bias,
            dependent_bias,
            bodies,
        }
    }

    /// Whether the expanded Lagrangian's M and h are derived. Always without
    /// Kane's form of the bodies; with it, when an output uses them (the
    /// multipliers, the mass matrix, the reaction forces, both routes, or a
    /// derivative of the equations), when the Lagrangian is small enough
    /// that its expanded form may be the cheaper
    /// ([`LAGRANGIAN_TERMS_COMPARED`]), or when it is not quadratic in the
    /// velocities ([`velocity_degree`]: the reduced mass matrix cannot be
    /// sampled from it for [`Model::silent_velocities`]).
    fn needs_lagrangian_terms(&self, kane: bool) -> bool {
        let used = [
            Output::Multipliers,
            Output::MassMatrix,
            Output::ReactionForces,
            Output::Routes,
        ];
        !kane
            || used.into_iter().any(|o| self.model.outputs.contains(o))
            || self.model.outputs.differentiate_derivation()
            || self.engine.num_terms(self.model.lagrangian) <= LAGRANGIAN_TERMS_COMPARED
            || !self.quadratic_in_velocities(self.model.lagrangian)
    }

    /// Whether `l` is a polynomial of degree at most two in the velocities,
    /// so that vᵀ M v = l(q, v) + l(q, −v) − 2 l(q, 0) exactly.
    fn quadratic_in_velocities(&self, l: ExprId) -> bool {
        let velocities: Vec<SymId> = self.model.coordinates.iter().map(|c| c.velocity).collect();
        velocity_degree(&self.engine, l, &velocities, &mut HashMap::default())
            .is_some_and(|d| d <= 2)
    }

    /// M_ij = ∂²l/∂q̇_i∂q̇_j and h_j = Σ_i ∂²l/∂q̇_j∂q_i q̇_i + ∂²l/∂q̇_j∂t
    /// − ∂l/∂q_j (− Q_j `with_forces`) of a Lagrangian (or part of one) l.
    fn euler_lagrange_terms(
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
            let e = &mut self.engine;
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

    /// Σ_i ∂x/∂q_i q̇_i: the rate of x along the motion, t held fixed.
    pub fn along_motion(&mut self, x: ExprId) -> ExprId {
        let e = &mut self.engine;
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

    /// Kane's form of the bodies' Euler–Lagrange terms (DESIGN §10), when
    /// the Lagrangian adds up kinetic energies of bodies: per body the
    /// Jacobians of its centre and angular velocity and their rates, and
    /// the terms of the rest of the Lagrangian (with the forces).
    fn body_terms(&mut self) -> Option<BodyTerms> {
        if self.model.speeds.is_some() {
            return None;
        }
        let split = self.model.kinetic.as_ref()?;
        let rest = split.rest;
        let mut parts: Vec<composite::Part> = split
            .bodies
            .iter()
            .map(|b| composite::Part {
                mass: b.mass,
                centre: Some(b.centre),
                rotation: b.rotation.map(|(omega, inertia)| (omega, inertia, b.spin)),
                orientation: b.orientation,
                masses: Vec::new(),
                wheels: Vec::new(),
                factors: b.factors.clone(),
            })
            .collect();
        let (gravity, rest) = match self.gravity(&parts, rest) {
            Some((g, r)) => (Some(g), r),
            None => (None, rest),
        };
        self.fold_fixed_centres(&mut parts);
        self.fold_wheels(&mut parts);
        let frame = self.heading_frame();
        let centres: Vec<[ExprId; 3]> = parts.iter().filter_map(|p| p.centre).collect();
        let bodies = parts
            .into_iter()
            .map(|part| {
                let anchor = self.anchor(&part, &frame);
                // a chain of frames gives the partial velocities as screws
                let screwed = (anchor.as_ref())
                    .is_some_and(|chain| chain.links.iter().all(|l| l.frame.is_some()));
                let jacobian = part.centre.map(|centre| match screwed {
                    true => Default::default(),
                    false => {
                        let jacobian = centre.map(|x| self.positional_jacobian(x));
                        self.in_frame(&frame, jacobian)
                    }
                });
                let wheels = part
                    .wheels
                    .iter()
                    .map(|w| (*w, self.velocity_jacobian(w.rate)));
                let wheels = wheels.collect();
                let turned_out = frame.is_some();
                let rotation = part.rotation.map(|(omega, own, spin)| {
                    let inertia = Inertia {
                        own,
                        masses: part.masses.clone(),
                        tail: None,
                    };
                    let rot = BodyRotation {
                        wheels,
                        ..self.body_rotation(omega, inertia, spin)
                    };
                    match spin {
                        None => self.without_tail(rot, &part.factors, turned_out),
                        Some(_) => rot,
                    }
                });
                BodyKinematics {
                    mass: part.mass,
                    jacobian,
                    anchor,
                    rotation,
                }
            })
            .collect();
        let (rest_mass, rest_bias) = self.euler_lagrange_terms(rest, true);
        let planar = self.planar_bodies(&centres, (&rest_mass, &rest_bias));
        Some(BodyTerms {
            bodies,
            rest_mass,
            rest_bias,
            gravity,
            heading_rate: self.heading_rate(),
            planar,
        })
    }

    /// The coordinates (x, y) of the block's [`Planar`] translation if they
    /// also translate every body's centre (∂C/∂x = e_x, ∂C/∂y = e_y) and
    /// the rest of the Lagrangian has no terms in them.
    fn planar_bodies(
        &mut self,
        centres: &[[ExprId; 3]],
        (rest_mass, rest_bias): (&[Vec<ExprId>], &[ExprId]),
    ) -> Option<[usize; 2]> {
        let planar = self.block.as_ref()?.planar?;
        let coords = planar.columns.map(|a| self.model.constraints[a].dependent);
        for (axis, &i) in coords.iter().enumerate() {
            let q = self.model.coordinates[i].position;
            if !centres.iter().all(|c| self.translates(c, q, axis)) {
                return None;
            }
            let row = rest_mass[i].iter().chain(rest_mass.iter().map(|r| &r[i]));
            if rest_bias[i] != ZERO || row.copied().any(|x| x != ZERO) {
                return None;
            }
        }
        Some(coords)
    }

    /// A body's rotation for Kane's form; a wheel's vectors turned by its
    /// spin R_k(θ).
    fn body_rotation(
        &mut self,
        omega: [ExprId; 3],
        inertia: Inertia,
        spin: Option<(usize, ExprId)>,
    ) -> BodyRotation {
        let (omega, spin) = match spin {
            Some((k, angle)) => {
                let e = &mut self.engine;
                let turn = crate::lower::values::elementary(e, k, angle);
                let omega = crate::lower::values::mat_vec(e, &turn, omega);
                (omega, Some((k, self.along_motion(angle))))
            }
            None => (omega, None),
        };
        BodyRotation {
            jacobian: omega.map(|w| self.velocity_jacobian(w)),
            omega,
            inertia,
            spin,
            wheels: Vec::new(),
            frame: None,
        }
    }

    /// The frame of a body's elementary rotations; `heading_out` when the
    /// bodies' vectors are in the heading's frame, which needs the first
    /// factor to be the heading R_z(ψ).
    fn frame_of(&mut self, factors: &[(usize, ExprId)], heading_out: bool) -> Option<Frame> {
        if factors.is_empty() || (heading_out && factors.first() != Some(&(2, self.heading()?))) {
            return None;
        }
        let steps = factors
            .iter()
            .map(|&(axis, angle)| {
                let rate = self.along_motion(angle);
                FrameStep {
                    axis,
                    turn: crate::lower::values::elementary(&mut self.engine, axis, angle),
                    rate,
                    rate_jacobian: self.velocity_jacobian(rate),
                }
            })
            .collect();
        Some(Frame { steps, heading_out })
    }

    /// The factors without their trailing constant ones, and the product T
    /// of those (R = R' T, so a body vector v is T v in the axes of R').
    pub(crate) fn trimmed(
        &mut self,
        factors: &[(usize, ExprId)],
    ) -> (Vec<(usize, ExprId)>, Option<Tail>) {
        let mut kept = factors.to_vec();
        let mut tail: Option<[[ExprId; 3]; 3]> = None;
        while let Some(&(k, angle)) = kept.last() {
            if !self.fixed(angle) {
                break;
            }
            kept.pop();
            let f = crate::lower::values::elementary(&mut self.engine, k, angle);
            tail = Some(match tail {
                Some(t) => crate::lower::values::mat_mat(&mut self.engine, &f, &t),
                None => f,
            });
        }
        (kept, tail)
    }

    /// ω_b of the product of `factors` (body components): ω' = Fᵀ ω + θ̇ e_k
    /// step by step.
    fn body_omega(&mut self, factors: &[(usize, ExprId)]) -> [ExprId; 3] {
        use crate::lower::values::{chain_omega, scale3, unit};
        let own: Vec<[ExprId; 3]> = factors
            .iter()
            .map(|&(k, angle)| {
                let rate = self.along_motion(angle);
                scale3(&mut self.engine, rate, unit(k))
            })
            .collect();
        chain_omega(&mut self.engine, factors, &own, false)
    }

    /// A body's rotation in the axes of its orientation without the
    /// trailing constant factors T (DESIGN §10): ω_b' = T ω_b from the
    /// other factors and I' = T I Tᵀ, when its wheels turn about the axis of
    /// every factor of T (which leaves their part of I as it is).
    fn without_tail(
        &mut self,
        rot: BodyRotation,
        factors: &[(usize, ExprId)],
        heading_out: bool,
    ) -> BodyRotation {
        let (kept, Some(tail)) = self.trimmed(factors) else {
            return BodyRotation {
                frame: self.frame_of(factors, heading_out),
                ..rot
            };
        };
        let axes_kept = rot
            .wheels
            .iter()
            .all(|(w, _)| factors[kept.len()..].iter().all(|&(k, _)| k == w.axis));
        let Some(frame) = self.frame_of(&kept, heading_out).filter(|_| axes_kept) else {
            return BodyRotation {
                frame: self.frame_of(factors, heading_out),
                ..rot
            };
        };
        let omega = self.body_omega(&kept);
        let inertia = Inertia {
            tail: Some(tail),
            ..rot.inertia
        };
        BodyRotation {
            jacobian: omega.map(|w| self.velocity_jacobian(w)),
            omega,
            inertia,
            frame: Some(frame),
            ..rot
        }
    }

    /// The block's terms, for a block of homogeneous velocity rows solved by
    /// elimination (`None` otherwise, or if no pivot order is regular at
    /// both test points).
    fn block_terms(&mut self) -> Option<BlockTerms> {
        // homogeneous, time-independent rows only: a row whose coefficients
        // move with t (not affine: b = 0) keeps the symbolic elimination,
        // whose dependent velocities take t
        let timed =
            (self.model.velocity_rows.iter()).any(|&g| self.engine.depends_on(g, self.model.time));
        if self.model.velocity_rows.is_empty()
            || self.model.affine
            || timed
            || self.model.speeds.is_some()
        {
            return None;
        }
        let planar = self.planar();
        let pivots = self.block_pivots(planar.as_ref())?;
        let frame = self.heading_frame();
        let contacts = self.model.contact_kinematics.clone();
        let chains = self.contact_chains.clone();
        let contacts = contacts
            .into_iter()
            .enumerate()
            .map(|(i, c)| {
                let centre_jacobian = c.centre.map(|x| self.positional_jacobian(x));
                let centre_jacobian = self.in_frame(&frame, centre_jacobian);
                let omega_jacobian = c.omega.map(|w| self.velocity_jacobian(w));
                let omega_jacobian = self.in_frame(&frame, omega_jacobian);
                let turn = |m: &mut Scene<'_>, v: [ExprId; 3]| match &frame {
                    Some(r) => crate::lower::values::mat_vec(&mut m.engine, r, v),
                    None => v,
                };
                ContactTerms {
                    chain: chains.get(i).cloned().flatten(),
                    centre_jacobian,
                    omega: turn(self, c.omega),
                    omega_jacobian,
                    axle: c.axle.map(|(n, s)| (turn(self, n), s)),
                    rim: c.axle.and_then(|(n, s)| {
                        let n = turn(self, n);
                        self.rim_without_root(n, s)
                    }),
                    radius: c.radius,
                    tube: c.tube,
                    frame: self.frame_of(&c.factors, frame.is_some()),
                }
            })
            .collect();
        let rows = self.model.velocity_rows.clone();
        let rows = rows
            .iter()
            .zip(self.model.row_contacts.clone())
            .map(|(&g, source)| match source {
                Some((contact, component)) => RowTerms::Contact { contact, component },
                None => RowTerms::Written {
                    coefficients: self.velocity_jacobian(g),
                    along: self.along_motion(g),
                },
            })
            .collect();
        Some(BlockTerms {
            pivots,
            rows,
            contacts,
            heading_rate: self.heading_rate(),
            planar,
        })
    }

    /// The [`Planar`] translation of the block, if its rows are all
    /// contacts' in the heading's frame and two dependent coordinates
    /// translate every contact along e_x and e_y.
    fn planar(&mut self) -> Option<Planar> {
        let psi = self.heading()?;
        if self.model.row_contacts.iter().any(Option::is_none) {
            return None;
        }
        let contacts = self.model.contact_kinematics.clone();
        let along = |m: &mut Scene<'_>, axis: usize| {
            let dependent: Vec<usize> = m.constraints.iter().map(|con| con.dependent).collect();
            dependent.into_iter().position(|i| {
                let (q, v) = (m.coordinates[i].position, m.coordinates[i].velocity);
                contacts.iter().all(|k| {
                    let turns = k.omega.iter().any(|&w| m.engine.diff(w, v) != ZERO);
                    m.translates(&k.centre, q, axis) && !turns
                })
            })
        };
        let columns = [along(self, 0)?, along(self, 1)?];
        let r = crate::lower::values::elementary(&mut self.engine, 2, psi);
        Some(Planar {
            columns,
            turn: [[r[0][0], r[0][1]], [r[1][0], r[1][1]]],
        })
    }

    /// Whether ∂p/∂q = e_axis exactly.
    fn translates(&mut self, p: &[ExprId; 3], q: SymId, axis: usize) -> bool {
        (0..3).all(|x| {
            let want = if x == axis { crate::sym::ONE } else { ZERO };
            self.engine.diff(p[x], q) == want
        })
    }

    /// w = (e_z − n_z n)/s (w_z = s) if s has no fractional powers.
    fn rim_without_root(&mut self, n: [ExprId; 3], s: ExprId) -> Option<[ExprId; 3]> {
        let e = &mut self.engine;
        let rooted = e
            .terms(s)
            .iter()
            .any(|&(m, _)| e.factors(m).iter().any(|(_, p)| !p.is_integer()));
        if rooted {
            return None;
        }
        let w = [0, 1].map(|x| {
            let t = e.mul(n[2], n[x]);
            let t = e.div(t, s);
            e.neg(t)
        });
        Some([w[0], w[1], s])
    }

    /// The elimination steps (pivot row, column) of the block c_s
    /// (columns: the constraints' dependent velocities), chosen by
    /// [`pivots::Block::elimination_order`] from the entries' kinds and
    /// their values at the coordinates' zero (the usual operating point)
    /// and at a random state; `None` if a column has no pivot at either.
    fn block_pivots(&mut self, planar: Option<&Planar>) -> Option<Vec<(usize, usize)>> {
        let deps: Vec<SymId> = self
            .model
            .constraints
            .iter()
            .map(|c| self.model.coordinates[c.dependent].velocity)
            .collect();
        let rows = self.model.velocity_rows.clone();
        let mut block: Vec<Vec<ExprId>> = rows
            .iter()
            .map(|&g| deps.iter().map(|&v| self.engine.diff(g, v)).collect())
            .collect();
        if let Some(planar) = planar {
            block = self.planar_block(&block, planar)?;
        }
        let mut rng = crate::sym::Rng::new(0x1319_8A2E_0370_7344);
        let mut at = |zero: bool| -> Vec<Vec<f64>> {
            let mut vals = rng.point(self.engine.num_symbols(), self.model.pi);
            if zero {
                for c in &self.model.coordinates {
                    vals[c.position.index()] = Dd::ZERO;
                }
            }
            block
                .iter()
                .map(|r| {
                    r.iter()
                        .map(|&x| self.engine.eval(x, &vals).to_f64())
                        .collect()
                })
                .collect()
        };
        let (at_zero, at_random) = (at(true), at(false));
        let kinds = block
            .iter()
            .map(|r| {
                r.iter()
                    .map(|&x| match self.engine.as_constant(x) {
                        _ if x == ZERO => pivots::Entry::Zero,
                        Some(_) => pivots::Entry::Constant,
                        None => pivots::Entry::Varying,
                    })
                    .collect()
            })
            .collect();
        pivots::Block {
            kinds,
            at_zero,
            at_random,
        }
        .elimination_order()
    }

    /// The block as the generated code solves it with a [`Planar`]
    /// translation: each contact's rows turned into the heading's frame,
    /// the columns of x and y those of u (e_x, e_y).
    fn planar_block(&mut self, block: &[Vec<ExprId>], planar: &Planar) -> Option<Vec<Vec<ExprId>>> {
        let frame = self.heading_frame()?;
        let sources = self.model.row_contacts.clone();
        let row_of = |c: usize, x: usize| sources.iter().position(|s| *s == Some((c, x)));
        let mut out = Vec::with_capacity(block.len());
        for source in &sources {
            let (c, k) = (*source)?;
            let row: Vec<ExprId> = (0..block[0].len())
                .map(|col| {
                    if let Some(u) = planar.columns.iter().position(|&p| p == col) {
                        return if u == k { crate::sym::ONE } else { ZERO };
                    }
                    let terms: Vec<ExprId> = (0..3)
                        .filter(|&x| frame[k][x] != ZERO)
                        .filter_map(|x| {
                            row_of(c, x).map(|r| self.engine.mul(frame[k][x], block[r][col]))
                        })
                        .collect();
                    self.engine.sum(&terms)
                })
                .collect();
            out.push(row);
        }
        Some(out)
    }

    /// R_z(−ψ) for the heading ψ every rotating body's orientation starts
    /// with (`rot_z(ψ) * ..`), if they agree. Kane's sums and the contact
    /// rows are the same in any frame turned by a rotation R(q) applied to
    /// every world vector (VᵀV, Vᵀa, and the rows' combinations); in the
    /// heading's frame the bodies' and contacts' vectors are free of ψ.
    fn heading_frame(&mut self) -> Option<[[ExprId; 3]; 3]> {
        let back = self.heading()?;
        let back = self.engine.neg(back);
        Some(crate::lower::values::elementary(&mut self.engine, 2, back))
    }

    /// ψ̇ of [`Model::heading_frame`]'s heading, if there is one.
    fn heading_rate(&mut self) -> Option<ExprId> {
        let psi = self.heading()?;
        Some(self.along_motion(psi))
    }

    /// The heading ψ every rotating body's orientation starts with.
    fn heading(&self) -> Option<ExprId> {
        let split = self.model.kinetic.as_ref()?;
        let mut headings = split
            .bodies
            .iter()
            .filter(|b| b.rotation.is_some())
            .map(|b| b.heading);
        let first = headings.next()??;
        headings.all(|h| h == Some(first)).then_some(first)
    }

    /// The columns of a 3 × n Jacobian turned into `frame`.
    fn in_frame(
        &mut self,
        frame: &Option<[[ExprId; 3]; 3]>,
        jacobian: [Vec<ExprId>; 3],
    ) -> [Vec<ExprId>; 3] {
        let Some(r) = frame else {
            return jacobian;
        };
        let e = &mut self.engine;
        let mut turned: [Vec<ExprId>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        for i in 0..jacobian[0].len() {
            let column = [jacobian[0][i], jacobian[1][i], jacobian[2][i]];
            let column = crate::lower::values::mat_vec(e, r, column);
            for (x, t) in turned.iter_mut().enumerate() {
                t.push(column[x]);
            }
        }
        turned
    }

    /// ∂x/∂q_i for every coordinate.
    fn positional_jacobian(&mut self, x: ExprId) -> Vec<ExprId> {
        let e = &mut self.engine;
        self.model
            .coordinates
            .iter()
            .map(|c| e.diff(x, c.position))
            .collect()
    }

    /// ∂x/∂q̇_i for every coordinate.
    fn velocity_jacobian(&mut self, x: ExprId) -> Vec<ExprId> {
        let e = &mut self.engine;
        self.model
            .coordinates
            .iter()
            .map(|c| e.diff(x, c.velocity))
            .collect()
    }

    /// −(Ȧ ṙ)_a − β̇_a from the solved velocities ṡ_a(q, ṙ, t).
    fn dependent_bias_from_solutions(&mut self) -> Vec<ExprId> {
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
    fn dependent_bias_from_rows(&mut self) -> Vec<ExprId> {
        let rows = self.model.velocity_rows.clone();
        let e = &mut self.engine;
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
    fn curvature_entry(&mut self, bb: usize, al: usize, be: usize) -> ExprId {
        let r = self.model.of_independent(|c| c.position);
        let (r_al, r_be) = (r[al], r[be]);
        let e = &mut self.engine;
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

    /// [`Model::integrability`] without the whole curvature: entry by
    /// entry, stopping at the first that does not vanish. An entry seen not
    /// to vanish at a random point settles it without symbolic derivatives
    /// ([`Model::curvature_entry_seen_nonzero`]).
    fn integrability_entry_by_entry(&mut self) -> (bool, bool) {
        let (k, p) = (self.model.k(), self.model.p());
        let mut proved = true;
        for bb in 0..p {
            for al in 0..k {
                for be in (al + 1)..k {
                    if self.curvature_entry_seen_nonzero(bb, al, be) {
                        return (false, false);
                    }
                    let v = self.curvature_entry(bb, al, be);
                    if v == ZERO {
                        continue;
                    }
                    if !vanish_at_random_points(&self.engine, self.model.pi, &[v]) {
                        return (false, false);
                    }
                    proved = false;
                }
            }
        }
        (true, proved)
    }

    /// Whether B^b_{αβ} of (5.21) is seen not to vanish at one of four
    /// random points, its derivatives ∂A/∂q taken by forward
    /// differentiation in double-double arithmetic (no symbolic
    /// derivative). Not vanishing means exceeding 1e-20 of the sum of its
    /// parts' sizes, far above the rounding of 32 digits; an entry that does
    /// not is left to the symbolic test.
    fn curvature_entry_seen_nonzero(&self, bb: usize, al: usize, be: usize) -> bool {
        use crate::sym::dd::Dd;
        use crate::sym::dual::Dual;
        let r = self.model.of_independent(|c| c.position);
        let (e, a) = (&self.engine, |aa: usize, x: usize| {
            self.model.constraints[aa].coefficients[x]
        });
        let mut rng = crate::sym::Rng::new(0x1319_8A2E_0370_7344);
        for _ in 0..4 {
            let point = rng.point(e.num_symbols(), self.model.pi);
            // ∂A^b_x/∂(seed) at the point
            let slope = |x: usize, seed: SymId| -> Dd {
                let mut vals: Vec<Dual> = point.iter().map(|&v| Dual::constant(v)).collect();
                vals[seed.index()] = Dual::variable(point[seed.index()]);
                e.eval(a(bb, x), &vals).derivative
            };
            let mut parts = vec![slope(al, r[be]), Dd::ZERO - slope(be, r[al])];
            for (aa, c) in self.model.constraints.iter().enumerate() {
                let s = self.model.coordinates[c.dependent].position;
                parts.push(e.eval(a(aa, al), &point) * slope(be, s));
                parts.push(Dd::ZERO - e.eval(a(aa, be), &point) * slope(al, s));
            }
            let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
            for &x in &parts {
                value = value + x;
                scale = scale + x.abs();
            }
            if value.is_finite()
                && scale.is_finite()
                && value.abs().to_f64() > 1e-20 * scale.to_f64()
            {
                return true;
            }
        }
        false
    }

    /// The curvature route (5.12)–(5.20): Lc, its reduced mass matrix and the
    /// right side with the curvature term and projected forces.
    pub fn curvature_route(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> CurvatureRoute {
        self.curvature_route_parts(curvature)
    }

    /// Per independent velocity ṙ_a, whether (Cᵀ M C)_aa vanishes, with
    /// C = [I; −A]: evaluated at 16 random points in double-double
    /// arithmetic, zero where it stays below 1e-24 of the sum of its terms'
    /// sizes at every point (as [`vanish_at_random_points`]); cheaper than
    /// the reduced mass matrix of the constrained Lagrangian when the
    /// curvature route is not derived.
    fn silent_velocities(&self, mass: &[Vec<ExprId>]) -> Vec<bool> {
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
            for (a, c) in columns.iter().enumerate() {
                if !silent[a] {
                    continue;
                }
                let (value, scale) = match mass.is_empty() {
                    false => self.mass_along(mass, c, &vals, &mut memo),
                    true => self.mass_sampled_along(c, &mut vals),
                };
                if value.abs().to_f64() > 1e-24 * scale.to_f64() {
                    silent[a] = false;
                }
            }
        }
        silent
    }

    /// cᵀ M c from M's entries at a point, with the sum of its terms' sizes.
    fn mass_along(
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

    /// cᵀ M c sampled from the Lagrangian, quadratic in the velocities:
    /// L(q, c) + L(q, −c) − 2 L(q, 0), with the sum of the samples' sizes.
    /// The velocities in `vals` are overwritten.
    fn mass_sampled_along(&self, c: &[Dd], vals: &mut [Dd]) -> (Dd, Dd) {
        let (mut value, mut scale) = (Dd::ZERO, Dd::ZERO);
        for (sign, weight) in [(1.0, 1.0), (-1.0, 1.0), (0.0, -2.0)] {
            for (coordinate, &ci) in self.model.coordinates.iter().zip(c) {
                vals[coordinate.velocity.index()] = Dd::from_f64(sign) * ci;
            }
            let (l, size) = self.engine.eval_with_scale(self.model.lagrangian, vals);
            value = value + Dd::from_f64(weight) * l;
            scale = scale + Dd::from_f64(weight.abs()) * size;
        }
        (value, scale)
    }

    fn curvature_route_parts(&mut self, curvature: &[Vec<Vec<ExprId>>]) -> CurvatureRoute {
        let (n, k) = (self.model.n(), self.model.k());
        let map = self.constrained_velocities();
        let qdot_c = self.constrained_qdot();
        let l = self.model.lagrangian;
        let r_vel = self.model.independent_velocities();
        let r_pos = self.model.of_independent(|c| c.position);
        let r_force = self.model.of_independent(|c| c.force);
        let q = &self.model.coordinates;
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
        let l = self.model.lagrangian;
        let e = &mut self.engine;
        let mut parts = Vec::new();
        for v in self.model.coordinates.iter().map(|c| c.velocity) {
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
