//! The typed model of a system after lowering: what the mechanics derives
//! from. Coordinates, parameters and inputs carry their symbols; each
//! constraint says which coordinate it makes dependent and how.

use crate::ctxt::SpanRange;
use crate::sym::{ExprId, SymId};
use proc_macro2::{Ident, Span};

pub use crate::words::Output;

/// Which opt-in outputs a system asked for.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outputs {
    /// Whether each output of [`Output::ALL`] was asked for, in that order.
    requested: [bool; Output::ALL.len()],
}

impl Outputs {
    /// Whether `output` was asked for.
    pub fn contains(&self, output: Output) -> bool {
        self.requested[output as usize]
    }

    /// With the outputs the requested ones imply: `sensitivities` needs the
    /// Jacobian (`jacobian`).
    pub fn with_implied(mut self) -> Outputs {
        if self.contains(Output::Sensitivities) {
            self.requested[Output::Jacobian as usize] = true;
        }
        self
    }

    /// Sets the flag of `output`; whether it was set before.
    pub fn set(&mut self, output: Output) -> bool {
        std::mem::replace(&mut self.requested[output as usize], true)
    }
}

/// A declared one-parameter symmetry group (§5.5, DESIGN §4.1).
pub struct Symmetry {
    /// Its name as declared.
    pub name: Ident,
    /// Its generator ξ_Q: the rate of each coordinate along the group, in
    /// coordinate order (zero for the coordinates it does not move).
    pub generator: Vec<ExprId>,
}

/// A constant of the system, a field of the generated struct.
pub struct Parameter {
    /// The name as declared.
    pub name: Ident,
    /// Its symbol.
    pub sym: SymId,
}

/// A generalized coordinate q_i.
pub struct Coordinate {
    /// The name as declared.
    pub name: Ident,
    /// The symbol of q_i.
    pub position: SymId,
    /// The symbol of q̇_i.
    pub velocity: SymId,
    /// The generalized force Q_i on it (zero where none is given).
    pub force: ExprId,
}

/// An input u_j: a value given at every call, which acts through the forces.
pub struct Input {
    /// The name as declared.
    pub name: Ident,
    /// Its symbol.
    pub sym: SymId,
}

/// How a constraint was given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstraintKind {
    /// `dot(s) = Σ a_α(q) dot(r_α)`: the dependent velocity written as a
    /// linear, homogeneous form in the independent velocities (5.3).
    ExplicitVelocity,
    /// `dot(s) = Σ a_i(q, t) dot(q_i) + b(q, t)` with an affine or
    /// time-dependent term (DESIGN §9).
    ExplicitAffine,
    /// `Σ c_i(q, t) dot(q_i) + b(q, t) = 0`, velocities on either side,
    /// solved for the dependent velocity the rule or `dependent { .. }`
    /// chose (DESIGN §9).
    Implicit,
    /// `dot(s) = rhs` whose right side divides by a function of the
    /// coordinates that can vanish: an implicit row with its denominators
    /// cleared, solved for s in the system's own chart (DESIGN §9.3).
    Cleared,
    /// `f(q, t) = 0`: no velocities; its time derivative is the velocity row
    /// (DESIGN §9).
    Holonomic,
}

impl ConstraintKind {
    /// Where the dependent velocity comes from, for the generated code's
    /// labels.
    pub fn velocity_source(self) -> &'static str {
        match self {
            ConstraintKind::ExplicitVelocity => "dependent velocity from the constraint (5.3)",
            ConstraintKind::ExplicitAffine => "dependent velocity from the affine constraint",
            ConstraintKind::Implicit | ConstraintKind::Cleared | ConstraintKind::Holonomic => {
                "dependent velocity solved from the constraint rows"
            }
        }
    }

    /// How the generated documentation names the form.
    pub fn describe(self) -> &'static str {
        match self {
            ConstraintKind::ExplicitVelocity => "explicit",
            ConstraintKind::ExplicitAffine => "explicit, affine or time-dependent",
            ConstraintKind::Implicit => "implicit",
            ConstraintKind::Cleared => "explicit, solved with its denominators cleared",
            ConstraintKind::Holonomic => "holonomic",
        }
    }
}

/// One nonholonomic constraint, solved for the velocity of its dependent
/// coordinate s_a: ṡ_a = −Σ_α A^a_α ṙ_α (5.3).
pub struct Constraint {
    /// How it was given.
    pub kind: ConstraintKind,
    /// The index of the dependent coordinate s_a.
    pub dependent: usize,
    /// ṡ_a as a function of the coordinates and the independent velocities
    /// (as written, for [`ConstraintKind::ExplicitVelocity`]).
    pub velocity: ExprId,
    /// The row A^a_· of the constraint matrix: minus the coefficient of each
    /// independent velocity ṙ_α, in the order of [`Model::independent`].
    pub coefficients: Vec<ExprId>,
    /// f(q, t) of a [`ConstraintKind::Holonomic`] constraint.
    pub holonomic: Option<ExprId>,
    /// The constraint as written, for the generated documentation.
    pub source: String,
}

/// A system in generalized speeds (DESIGN §9): q̇ = S(q, t) u + σ(q, t).
pub struct Speeds {
    /// Span of the `speeds` keyword (for diagnostics).
    pub span: Span,
    /// The speeds u as declared.
    pub names: Vec<Ident>,
    /// Their symbols.
    pub syms: Vec<SymId>,
    /// q̇_i = Σ_a S_ia u_a + σ_i per coordinate, in coordinate order.
    pub velocities: Vec<ExprId>,
}

/// Which coordinates are independent and which dependent: the partition
/// the constraints make.
pub struct Partition {
    independent: Vec<usize>,
    dependent: Vec<usize>,
}

impl Partition {
    /// The partition of `n` coordinates by `constraints` (at most one per
    /// coordinate), which it sorts into coordinate order.
    pub fn of(n: usize, constraints: &mut [Constraint]) -> Partition {
        constraints.sort_by_key(|c| c.dependent);
        let dependent: Vec<usize> = constraints.iter().map(|c| c.dependent).collect();
        let independent = (0..n).filter(|i| !dependent.contains(i)).collect();
        Partition {
            independent,
            dependent,
        }
    }
}

/// A system after lowering: everything the mechanics needs, as symbols and
/// expressions of one engine.
pub struct Model {
    /// The declared one-parameter symmetry groups (`symmetries { .. }`).
    pub symmetries: Vec<Symmetry>,
    /// The directions X of the declared momenta (`momenta { .. }`), each
    /// written as a generator is: J = ⟨∂L/∂q̇, X⟩ along it.
    pub momentum_directions: Vec<Symmetry>,
    /// Parameters in declared order.
    pub parameters: Vec<Parameter>,
    /// Coordinates in declared order (THE coordinate order).
    pub coordinates: Vec<Coordinate>,
    /// Inputs in declared order.
    pub inputs: Vec<Input>,
    /// Time t.
    pub time: SymId,
    /// π.
    pub pi: SymId,
    /// L(q, q̇, t), with the kinetic energy of each body of
    /// [`Model::kinetic`] whose expansion would be large folded into one
    /// symbol ([`KineticBody::folded`]): `Scene::lagrangian` is L expanded.
    /// The folded symbols are free of t and of the state.
    pub lagrangian_folded: ExprId,
    /// The constraints, one per dependent coordinate, in coordinate order
    /// (the order of [`Model::dependent`]).
    pub constraints: Vec<Constraint>,
    /// The partition of the coordinates by the constraints.
    pub partition: Partition,
    /// Requested outputs.
    pub outputs: Outputs,
    /// The generalized speeds and kinematics, for a system written in them
    /// (it then has no constraints).
    pub speeds: Option<Speeds>,
    /// Whether every constraint is a homogeneous, time-independent velocity
    /// constraint (the curvature route and `curvature` need that).
    pub homogeneous: bool,
    /// Whether some constraint has an affine or time-dependent term b(q, t).
    pub affine: bool,
    /// The signed Hadamard ratio det(c_s)/Π‖c_a‖ of the implicit and
    /// holonomic rows (with explicit rows substituted), in [−1, 1] and zero
    /// where the chart is singular; `None` when every constraint is explicit.
    pub chart: Option<ExprId>,
    /// The atlas of the implicit and holonomic rows (DESIGN §9.3): this
    /// chart first, then the others; empty when this chart is never
    /// singular or the system keeps one chart.
    pub atlas: Vec<crate::lower::atlas::Chart>,
    /// Span of the `constraints` keyword, if any (for diagnostics).
    pub constraints_span: Option<Span>,
    /// The velocity rows g_a(q, q̇, t) = 0 of a system whose constraints are
    /// all implicit or holonomic and solved by elimination (more than
    /// three), in the order of [`Model::constraints`]; empty otherwise. Their
    /// derivative gives the dependent accelerations without differentiating
    /// the eliminated solutions (DESIGN §9).
    pub velocity_rows: Vec<ExprId>,
    /// The contact points of the `rolls(..)` lines, in order (world
    /// components).
    pub contacts: Vec<[ExprId; 3]>,
    /// Lines of the struct's documentation on its vector, rotation and
    /// matrix `let`s, bodies and rolling contacts, as lowered (DESIGN §10).
    pub description: Vec<String>,
    /// The first subexpression of the input whose value is a constant beyond
    /// the range of `f64` (where an error about such a constant in the
    /// generated code points).
    pub huge_constant: Option<SpanRange>,
    /// The bodies whose `kinetic_energy(..)` the Lagrangian adds up, with
    /// L − Σ T_b: Kane's form of their Euler–Lagrange terms (DESIGN §10).
    pub kinetic: Option<KineticSplit>,
    /// The kinematics of the `rolls(..)` lines, in order, for their rows'
    /// derivatives in closed form (DESIGN §10).
    pub contact_kinematics: Vec<ContactKinematics>,
    /// The vector `let`s free of velocities (world components): points of
    /// the mechanism through which accelerations chain (DESIGN §10).
    pub points: Vec<[ExprId; 3]>,
    /// Per entry of [`Model::velocity_rows`], the contact and component
    /// (0: x, 1: y, 2: z) of its material velocity it is, if it comes from a
    /// `rolls(..)` line.
    pub row_contacts: Vec<Option<(usize, usize)>>,
    /// Where in the input the stages after lowering derive from (see
    /// [`Places`]).
    pub places: Places,
    /// The expressions as written (the Lagrangian, the forces, each
    /// written constraint's lhs − rhs, the kinematics), whose poles and
    /// domain edges the runtime guards (`crate::poles`).
    pub written: Vec<ExprId>,
}

/// The parts of the input the stages after lowering derive from: the
/// sites they name to the engine while they work, where an error for a
/// limit exceeded points (DESIGN §5).
#[derive(Clone, Copy, Debug)]
pub struct Places {
    /// The Lagrangian as written.
    pub lagrangian: SpanRange,
    /// The `constraints` keyword (the system's name without one).
    pub constraints: SpanRange,
}

/// A rolling contact: the material velocity of the contact point is
/// v = Ġ + ω × o with o = P − G = −r w − ρ e_z, w = (e_z − n_z n)/s,
/// s = |e_z × n| (w = e_z for a sphere).
#[derive(Clone)]
pub struct ContactKinematics {
    /// The geometric centre G(q).
    pub centre: [ExprId; 3],
    /// The world components of the body's angular velocity ω(q, q̇).
    pub omega: [ExprId; 3],
    /// The axle n(q) in world components and s(q), for a disc or torus.
    pub axle: Option<([ExprId; 3], ExprId)>,
    /// r.
    pub radius: ExprId,
    /// ρ (zero but for a torus).
    pub tube: ExprId,
    /// The elementary rotations (axis, angle) of the body's orientation.
    pub factors: Vec<(usize, ExprId)>,
}

/// A Lagrangian L = Σ_b T_b + L_rest, T_b the kinetic energies of bodies.
pub struct KineticSplit {
    /// The bodies, as their kinetic energies were formed.
    pub bodies: Vec<KineticBody>,
    /// L − Σ_b T_b (the potential and any other terms).
    pub rest: ExprId,
}

/// One body of a [`KineticSplit`]: T = ½ m |Ċ|² + ½ ω_bᵀ I ω_b.
pub struct KineticBody {
    /// The mass m.
    pub mass: ExprId,
    /// The centre of mass C(q), world components.
    pub centre: [ExprId; 3],
    /// The body components ω_b(q, q̇) of its angular velocity and the
    /// inertia I about the centre of mass in body axes; `None` for a point
    /// mass.
    pub rotation: Option<([ExprId; 3], [[ExprId; 3]; 3])>,
    /// Its orientation (body → world, by rows), for a body that is not a
    /// point mass.
    pub orientation: Option<[[ExprId; 3]; 3]>,
    /// The angle ψ of its orientation's leading `rot_z` factor, if any.
    pub heading: Option<ExprId>,
    /// The axis k and angle θ of its orientation's last factor, when the
    /// inertia is symmetric about that axis (a wheel's spin).
    pub spin: Option<(usize, ExprId)>,
    /// The elementary rotations (axis, angle) its orientation is the
    /// product of, left to right (empty for a point mass).
    pub factors: Vec<(usize, ExprId)>,
    /// The symbol standing for its kinetic energy in
    /// [`Model::lagrangian_folded`], when the expansion would be large (a
    /// link of a chain): Kane's form of the multiplier route does not take
    /// it, and what does expands it (`Scene::lagrangian`).
    pub folded: Option<SymId>,
}

impl Model {
    /// Indices of the independent coordinates r, ascending.
    pub fn independent(&self) -> &[usize] {
        &self.partition.independent
    }

    /// Indices of the dependent coordinates s, ascending (the order of
    /// [`Model::constraints`]).
    pub fn dependent(&self) -> &[usize] {
        &self.partition.dependent
    }

    /// Number of coordinates n.
    pub fn n(&self) -> usize {
        self.coordinates.len()
    }

    /// Number of independent coordinates k (of speeds, for a system in
    /// generalized speeds): the length of the state's velocity part.
    pub fn k(&self) -> usize {
        match &self.speeds {
            Some(s) => s.syms.len(),
            None => self.independent().len(),
        }
    }

    /// Number of constraints p.
    pub fn p(&self) -> usize {
        self.dependent().len()
    }

    /// The symbols of the coordinates, in coordinate order.
    pub fn positions(&self) -> impl Iterator<Item = SymId> + '_ {
        self.coordinates.iter().map(|c| c.position)
    }

    /// `f` of each independent coordinate, in their order.
    pub fn of_independent<T>(&self, f: impl Fn(&Coordinate) -> T) -> Vec<T> {
        self.independent()
            .iter()
            .map(|&i| f(&self.coordinates[i]))
            .collect()
    }

    /// The holonomic constraints: (dependent coordinate, f).
    pub fn holonomic(&self) -> Vec<(usize, ExprId)> {
        self.constraints
            .iter()
            .filter_map(|c| c.holonomic.map(|f| (c.dependent, f)))
            .collect()
    }

    /// The symbols of the velocities of the independent coordinates ṙ (the
    /// speeds u, for a system in generalized speeds): the state's velocity part.
    pub fn independent_velocities(&self) -> Vec<SymId> {
        match &self.speeds {
            Some(s) => s.syms.clone(),
            None => self.of_independent(|c| c.velocity),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Output, Outputs};

    #[test]
    fn outputs_are_indexed_by_their_place_in_all() {
        for (i, o) in Output::ALL.into_iter().enumerate() {
            assert_eq!(o as usize, i);
            let mut outputs = Outputs::default();
            assert!(!outputs.set(o));
            assert!(outputs.contains(o));
            assert!(outputs.set(o));
        }
    }
}
