//! The table of generated methods: for each, its name, arguments, form,
//! return type, documentation and the outputs that ask for it (a flat
//! table, read by the signatures and by the bodies' dispatch).

use super::Shape;
use crate::model::Output;

/// A method of the generated API: one variant per method, in the order of
/// [`METHODS`] (the order they are emitted and derived in).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeneratedMethod {
    /// `dependent_velocities`
    DependentVelocities,
    /// `velocities`: q̇ = S u + σ of a system in generalized speeds
    Velocities,
    /// `accelerations`
    Accelerations,
    /// `accelerations_multiplier_route`
    AccelerationsMultiplierRoute,
    /// `accelerations_curvature_route`
    AccelerationsCurvatureRoute,
    /// `reduced_system`
    ReducedSystem,
    /// `multipliers`
    Multipliers,
    /// `reaction_forces`
    ReactionForces,
    /// `curvature`
    Curvature,
    /// `energy`
    Energy,
    /// `momenta`: p_k = ∂Lc/∂ṙ_k of the cyclic coordinates
    Momenta,
    /// `momentum_rates`: ṗ_k of (5.36)
    MomentumRates,
    /// `symmetry_momenta`: the momenta of the declared symmetries
    SymmetryMomenta,
    /// `symmetry_momentum_rates`: their rates
    SymmetryMomentumRates,
    /// `declared_momenta`: the momenta of `momenta { .. }`
    DeclaredMomenta,
    /// `declared_momentum_rates`: their rates
    DeclaredMomentumRates,
    /// `constraint_matrix`
    ConstraintMatrix,
    /// `contact_points`
    ContactPoints,
    /// `mass_matrix`
    MassMatrix,
    /// `linearization`
    Linearization,
    /// `jacobian`
    Jacobian,
    /// `time_derivative`: ∂f/∂t
    TimeDerivative,
    /// `parameter_jacobian`: ∂f/∂p
    ParameterJacobian,
    /// `variational_rhs`: f with the right sides of the variational equations
    VariationalRhs,
    /// `sensitivities`: the system augmented with its sensitivities
    SensitivitySystem,
    /// `rhs` (or `rhs_with_input`) of the runtime trait implementation.
    Rhs,
}

/// What a generated method takes besides `&self`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arguments {
    /// `q`
    Coordinates,
    /// `q, rdot`
    Velocities,
    /// `t, q, rdot`: the dependent velocities of time-dependent constraints.
    TimedVelocities,
    /// `t, q, rdot` and `u` for a system with inputs.
    Motion,
    /// `t, x` and `u` for a system with inputs.
    State,
    /// `t, q, speeds` (no inputs).
    Kinematics,
    /// `t, x, s_p, s_x0`: a state and its sensitivities.
    Variational,
    /// Nothing but `&self`.
    Receiver,
}

/// Which systems have a generated method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// Every system.
    Any,
    /// Systems with `constraints` (or none): coordinates r, s.
    Coordinates,
    /// Systems in generalized speeds.
    Speeds,
    /// Systems with `symmetries` (in coordinates r, s).
    Symmetries,
    /// Systems with `momenta { .. }` (in coordinates r, s).
    DeclaredMomenta,
}

/// What a generated method returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Returns {
    /// A vector of p values, one per dependent coordinate.
    Dependent,
    /// A vector of k values, one per independent coordinate.
    Independent,
    /// A k × k matrix and a vector of k values.
    ReducedSystem,
    /// p antisymmetric k × k matrices.
    Curvature,
    /// One value.
    Scalar,
    /// A vector of one value per cyclic coordinate.
    Cyclic,
    /// A vector of one value per momentum of the declared symmetries.
    Symmetric,
    /// A vector of one value per declared momentum.
    Declared,
    /// A p × k matrix.
    ConstraintMatrix,
    /// A 3 × c matrix: one column per rolling contact.
    ContactPoints,
    /// An n × n matrix (k × k in generalized speeds).
    MassMatrix,
    /// A vector of n values, one per coordinate.
    Coordinates,
    /// An (n + k) × (n + k) matrix.
    StateMatrix,
    /// An (n + k) × (n + k) and an (n + k) × m matrix.
    StateAndInputMatrices,
    /// A vector of n + k values, the state's derivative.
    State,
    /// An (n + k) × P matrix, P the parameters of `sensitivities`.
    ParameterMatrix,
    /// A vector of n + k values, an (n + k) × P and an (n + k) × (n + k)
    /// matrix: the state's derivative and its sensitivities'.
    Variational,
    /// The runtime's `Sensitivities` of the system.
    SensitivitySystem,
}

/// One row of the table of generated methods.
pub struct MethodSpec {
    /// The method.
    pub method: GeneratedMethod,
    /// Its name in the generated code.
    pub name: &'static str,
    /// Its documentation, or (for the accelerations and the Jacobian) the
    /// opening the derivation completes with its figures; for a route's
    /// method, the route's description.
    pub doc: &'static str,
    /// What it takes.
    pub takes: Arguments,
    /// What it returns.
    pub returns: Returns,
    /// The output that asks for it; `None` for a method every system has.
    pub requested_by: Option<Output>,
    /// Which systems have it.
    pub form: Form,
}

/// Every generated method, in the order they are emitted and derived in
/// (`rhs` last: the runtime trait calls the others).
pub const METHODS: [MethodSpec; 26] = [
    MethodSpec {
        method: GeneratedMethod::DependentVelocities,
        name: "dependent_velocities",
        doc: "The dependent velocities ṡ = −A(q) ṙ of the constraints (5.3), in the order of [`Self::DEPENDENT`].",
        takes: Arguments::Velocities,
        returns: Returns::Dependent,
        requested_by: None,
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::Velocities,
        name: "velocities",
        doc: "The velocities q̇ = S(q, t) u + σ(q, t) of the coordinates at the speeds `speeds` (the kinematics), in coordinate order.",
        takes: Arguments::Kinematics,
        returns: Returns::Coordinates,
        requested_by: None,
        form: Form::Speeds,
    },
    MethodSpec {
        method: GeneratedMethod::Accelerations,
        name: "accelerations",
        doc: "The reduced equations of motion: r̈, the accelerations of the independent coordinates (in the order of [`Self::INDEPENDENT`]) at time `t`, coordinates `q` and independent velocities `rdot`.",
        takes: Arguments::Motion,
        returns: Returns::Independent,
        requested_by: None,
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::AccelerationsMultiplierRoute,
        name: "accelerations_multiplier_route",
        doc: "the multiplier route: the Euler–Lagrange terms (3.9) projected onto the constraint distribution, (5.9)",
        takes: Arguments::Motion,
        returns: Returns::Independent,
        requested_by: Some(Output::Routes),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::AccelerationsCurvatureRoute,
        name: "accelerations_curvature_route",
        doc: "the curvature route: the constrained Lagrangian Lc (5.12) with the curvature term of (5.20)–(5.21)",
        takes: Arguments::Motion,
        returns: Returns::Independent,
        requested_by: Some(Output::Routes),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::ReducedSystem,
        name: "reduced_system",
        doc: "The reduced equations Mc r̈ = f of the curvature route as a matrix and a vector: Mc = ∂²Lc/∂ṙ∂ṙ (5.12) and f the right side of (5.20). [`Self::accelerations`] solves them by an unrolled LDLᵀ factorisation.",
        takes: Arguments::Motion,
        returns: Returns::ReducedSystem,
        requested_by: Some(Output::Routes),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::Multipliers,
        name: "multipliers",
        doc: "The Lagrange multipliers λ_a = d/dt ∂L/∂ṡ_a − ∂L/∂s_a − Q_{s_a} along the motion (5.10), one per dependent coordinate: the generalized constraint forces, with the sign convention E(L) = Cᵀλ, C = [A | I].",
        takes: Arguments::Motion,
        returns: Returns::Dependent,
        requested_by: Some(Output::Multipliers),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::ReactionForces,
        name: "reaction_forces",
        doc: "The reaction forces E − Q along the motion, one per coordinate: the Euler–Lagrange terms d/dt ∂L/∂q̇ − ∂L/∂q minus the applied forces, at q̇ = S u + σ and q̈ = S u̇ + Ṡ u + σ̇. They are the generalized constraint forces that keep q̇ in the range of S, orthogonal to its columns: Sᵀ(E − Q) = 0 (Maggi's equations).",
        takes: Arguments::Motion,
        returns: Returns::Coordinates,
        requested_by: Some(Output::ReactionForces),
        form: Form::Speeds,
    },
    MethodSpec {
        method: GeneratedMethod::Curvature,
        name: "curvature",
        doc: "The curvature of the constraint connection, (5.21): `B[b][(α, β)]` = B^b_{αβ}, antisymmetric in (α, β); entries that are identically zero are not computed.",
        takes: Arguments::Coordinates,
        returns: Returns::Curvature,
        requested_by: Some(Output::Curvature),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::Energy,
        name: "energy",
        doc: "The energy E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities.",
        takes: Arguments::Velocities,
        returns: Returns::Scalar,
        requested_by: Some(Output::Energy),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::Momenta,
        name: "momenta",
        doc: "The momenta p_k = ∂Lc/∂ṙ_k conjugate to the cyclic coordinates (5.35), in the order of [`Self::CYCLIC`], at the constrained velocities.",
        takes: Arguments::Motion,
        returns: Returns::Cyclic,
        requested_by: Some(Output::Momenta),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::MomentumRates,
        name: "momentum_rates",
        doc: "The rates ṗ_k of the momenta of the cyclic coordinates along the motion, by (5.36): ṗ_k = ∂Lc/∂r_k + Q_k − Σ_b Σ_β B^b_{kβ} ṙ_β ∂L/∂ṡ_b − Σ_a A^a_k (∂Lc/∂s_a + Q_{s_a}), in the order of [`Self::CYCLIC`]; [`Self::CONSERVED`] says which vanish identically. Without the accelerations: the rate follows from the state.",
        takes: Arguments::Motion,
        returns: Returns::Cyclic,
        requested_by: Some(Output::Momenta),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::SymmetryMomenta,
        name: "symmetry_momenta",
        doc: "The momenta J = ⟨∂L/∂q̇, ξ(q)⟩ along the directions ξ(q) of the declared symmetries that the constraints allow, at the constrained velocities, in the order of [`Self::SYMMETRY_CONSERVED`] (whose documentation gives each direction).",
        takes: Arguments::Motion,
        returns: Returns::Symmetric,
        requested_by: None,
        form: Form::Symmetries,
    },
    MethodSpec {
        method: GeneratedMethod::SymmetryMomentumRates,
        name: "symmetry_momentum_rates",
        doc: "The rates of [`Self::symmetry_momenta`] along the motion by the nonholonomic momentum equation, dJ/dt = ⟨∂L/∂q̇, Σ_i ċ_i ξ_i⟩ + ⟨Q, ξ(q)⟩, without the accelerations.",
        takes: Arguments::Motion,
        returns: Returns::Symmetric,
        requested_by: None,
        form: Form::Symmetries,
    },
    MethodSpec {
        method: GeneratedMethod::DeclaredMomenta,
        name: "declared_momenta",
        doc: "The declared momenta J = ⟨∂L/∂q̇, X(q)⟩ along their directions X(q) (`momenta { .. }`), at the constrained velocities, in the order of [`Self::MOMENTA`]; [`Self::MOMENTUM_CONSERVED`] says which are conserved.",
        takes: Arguments::Motion,
        returns: Returns::Declared,
        requested_by: None,
        form: Form::DeclaredMomenta,
    },
    MethodSpec {
        method: GeneratedMethod::DeclaredMomentumRates,
        name: "declared_momentum_rates",
        doc: "The rates of [`Self::declared_momenta`] along the motion, by Lagrange–d'Alembert: the constraint forces do no work along a direction X(q) the constraints allow, so dJ/dt = ⟨∂L/∂q, X⟩ + ⟨∂L/∂q̇, Ẋ⟩ + ⟨Q, X⟩ with Ẋ = (∂X/∂q) q̇, without the accelerations.",
        takes: Arguments::Motion,
        returns: Returns::Declared,
        requested_by: None,
        form: Form::DeclaredMomenta,
    },
    MethodSpec {
        method: GeneratedMethod::ConstraintMatrix,
        name: "constraint_matrix",
        doc: "The constraint matrix A^a_α of ṡ_a = −Σ_α A^a_α ṙ_α (5.3): rows follow [`Self::DEPENDENT`], columns [`Self::INDEPENDENT`].",
        takes: Arguments::Coordinates,
        returns: Returns::ConstraintMatrix,
        requested_by: Some(Output::ConstraintMatrix),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::ContactPoints,
        name: "contact_points",
        doc: "The contact points of the rolling contacts with the plane z = 0, world components: column c is the lowest point of the rim of the c-th `rolls(..)` line, in the order written (DESIGN §10).",
        takes: Arguments::Coordinates,
        returns: Returns::ContactPoints,
        requested_by: Some(Output::ContactPoints),
        form: Form::Coordinates,
    },
    MethodSpec {
        method: GeneratedMethod::MassMatrix,
        name: "mass_matrix",
        doc: "The mass matrix ∂²L/∂q̇_i∂q̇_j in coordinate order.",
        takes: Arguments::Coordinates,
        returns: Returns::MassMatrix,
        requested_by: Some(Output::MassMatrix),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::Linearization,
        name: "linearization",
        doc: "The linearisation of the first-order system ẋ = f(t, x, u) at (t, x, u): A = ∂f/∂x and B = ∂f/∂u, derived symbolically through the reduced solve (as for the Jacobian): ∂r̈/∂z = Mc⁻¹ (∂f/∂z − (∂Mc/∂z) r̈) (5.20). For controller design: δẋ ≈ A δx + B δu.",
        takes: Arguments::State,
        returns: Returns::StateAndInputMatrices,
        requested_by: Some(Output::Linearization),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::Jacobian,
        name: "jacobian",
        doc: "The Jacobian ∂f/∂x of the first-order system x = [q, ṙ] ↦ [q̇, r̈]",
        takes: Arguments::State,
        returns: Returns::StateMatrix,
        requested_by: Some(Output::Jacobian),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::TimeDerivative,
        name: "time_derivative",
        doc: "The partial derivative ∂f/∂t of the first-order system at fixed x (zero for a system whose definition does not depend on `t`), derived symbolically like the Jacobian; the implicit integrators take it from here instead of differencing f in t.",
        takes: Arguments::State,
        returns: Returns::State,
        requested_by: Some(Output::Jacobian),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::ParameterJacobian,
        name: "parameter_jacobian",
        doc: "The derivative ∂f/∂p of the first-order system with respect to the parameters of [`Self::SENSITIVITY_PARAMETERS`] (one column each, in that order), derived symbolically through the reduced solve: ∂r̈/∂p = Mc⁻¹ (∂f/∂p − (∂Mc/∂p) r̈).",
        takes: Arguments::State,
        returns: Returns::ParameterMatrix,
        requested_by: Some(Output::Sensitivities),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::VariationalRhs,
        name: "variational_rhs",
        doc: "The right-hand side of the variational equations at (t, x) with the sensitivities `s_p` = ∂x/∂p and `s_x0` = ∂x/∂x0: (f, (∂f/∂x) s_p + ∂f/∂p, (∂f/∂x) s_x0), in one body with common subexpressions shared and the structural zeros of ∂f/∂x pruned from the products.",
        takes: Arguments::Variational,
        returns: Returns::Variational,
        requested_by: Some(Output::Sensitivities),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::SensitivitySystem,
        name: "sensitivities",
        doc: "The system with its forward sensitivities, ∂x/∂p (the parameters of [`Self::SENSITIVITY_PARAMETERS`]) and ∂x/∂x0: an `OdeSystem` of dimension [`Self::SENSITIVITY_DIM`] that any integrator integrates (adaptive methods then control the error of the sensitivities too). Start it from `initial_state(&x0)`, read a result with `split(&x)`.",
        takes: Arguments::Receiver,
        returns: Returns::SensitivitySystem,
        requested_by: Some(Output::Sensitivities),
        form: Form::Any,
    },
    MethodSpec {
        method: GeneratedMethod::Rhs,
        name: "rhs",
        doc: "ẋ for the state x = [q, ṙ]: ẋ = [q̇(q, ṙ), r̈], with the dependent velocities from the constraints.",
        takes: Arguments::State,
        returns: Returns::State,
        requested_by: None,
        form: Form::Any,
    },
];

impl GeneratedMethod {
    /// Its row of [`METHODS`].
    pub fn spec(self) -> &'static MethodSpec {
        &METHODS[self as usize]
    }
}

impl MethodSpec {
    /// Whether a system of this shape has this method.
    pub fn is_requested(&self, shape: &Shape) -> bool {
        let form = match self.form {
            Form::Any => true,
            Form::Coordinates => !shape.in_speeds(),
            Form::Speeds => shape.in_speeds(),
            Form::Symmetries => !shape.in_speeds() && !shape.symmetries.is_empty(),
            Form::DeclaredMomenta => !shape.in_speeds() && !shape.momentum_names.is_empty(),
        };
        form && self.requested_by.is_none_or(|o| shape.outputs.contains(o))
    }
}
