//! # nonholonomic
//!
//! A mechanical system written as mathematics — parameters, generalized
//! coordinates, a Lagrangian and velocity constraints linear in the velocities
//! (rolling without slipping, knife edges) — becomes specialised Rust at compile
//! time. [`nonholonomic_system!`] differentiates symbolically while your crate
//! compiles and emits monomorphised code for the reduced equations of motion and,
//! on request, the Lagrange multipliers (constraint forces), the curvature of the
//! constraint distribution, the energy, the matrices and the Jacobians a
//! controller needs. The runtime ([`runtime`], re-exported by [`prelude`])
//! integrates the result without allocating.
//!
//! The mathematics follows C. Flygare, *Holonomic versus nonholonomic
//! constraints* (2012), sections 4–6, which follows A. M. Bloch, *Nonholonomic
//! Mechanics and Control*; equation numbers are the thesis's. The repository's
//! `DESIGN.md` fixes the conventions and the mathematics in full; this page is the
//! reference of the input language and of what it generates.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A knife edge (Chaplygin sled) on a plane: the blade at (x, y) may
//!     /// only move along its heading θ; the centre of mass is a ahead of it.
//!     pub struct Sled {
//!         parameters { m, J, a }
//!         coordinates { x, theta, y }
//!         lagrangian = J*dot(theta)^2/2
//!             + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
//!         constraints { dot(y) = tan(theta)*dot(x); }
//!     }
//! }
//!
//! let sled = Sled::new(2.0, 0.3, 0.5);                                // m, J, a
//! let x0 = SVector::<f64, 5>::from([0.0, 0.2, 0.0, 0.4, 0.9]);     // [x, θ, y, ẋ, θ̇]
//! let out = Dopri5::new(1e-10, 1e-12).integrate(&sled, 0.0, x0, 1.0).unwrap();
//! // the blade never slips: ẏ = tan θ ẋ holds along the motion by construction
//! let (q, rdot) = (out.x.fixed_rows::<3>(0).into_owned(), out.x.fixed_rows::<2>(3).into_owned());
//! let ydot = sled.dependent_velocities(&q, &rdot)[0];
//! assert!((ydot - q[1].tan() * rdot[0]).abs() < 1e-15);
//! ```
//!
//! # The input language
//!
//! A system is a `struct` item whose body holds the items below, in any order
//! (a `let` only after the `let`s it uses). Doc comments and attributes on the
//! struct are kept.
//!
//! | item | meaning |
//! |---|---|
//! | `parameters { a, b, .. }` | constant physical parameters; they become public fields of type `T` |
//! | `coordinates { q1, q2, .. }` | the generalized coordinates q; this order is *the* coordinate order everywhere |
//! | `inputs { u1, .. }` | optional: control inputs supplied at run time, usable in `forces` |
//! | `let NAME = expr;` | a named subexpression; may use coordinates, velocities, parameters, inputs, `t` and earlier `let`s |
//! | `lagrangian = expr;` | exactly one: L(q, q̇, t) |
//! | `forces { q: expr; .. }` | optional generalized non-potential forces Q_j (damping, actuation, forcing) |
//! | `constraints { .. }` | constraints linear in the velocities, one per dependent coordinate: explicit `dot(s) = expr;`, implicit `expr = expr;` or holonomic `f(q, t) = g(q, t);` (below) |
//! | `dependent { s1, .. }` | optional: the coordinates the implicit and holonomic constraints are solved for, in their order |
//! | `speeds { u1, .. }` | instead of `constraints`: generalized speeds u (Kane, Maggi); see [below](#generalized-speeds) |
//! | `kinematics { dot(q) = expr; .. }` | with `speeds`: q̇ = S(q, t) u + σ(q, t), one line per coordinate |
//! | `outputs { name, .. }` | optional extra generated methods (below); by default only the core API is derived |
//!
//! ## Expressions
//!
//! Numeric literals, names, `+ - * /`, unary minus, parentheses and `^` (power,
//! with mathematical precedence: `m*x^2` is m·(x²), `-x^2` is −(x²), `a^b^c` is
//! a^(b^c)); the functions below; the constant `pi`; `t` for
//! time. `dot(q)` is the velocity q̇ of coordinate `q`. `dot(NAME)` of a `let`
//! without velocities is its total time derivative Σ ∂NAME/∂q_i q̇_i + ∂NAME/∂t:
//! this is how kinetic energy is written from positions.
//!
//! | function | value | derivative; domain |
//! |---|---|---|
//! | `sin(x)`, `cos(x)`, `tan(x)` | sine, cosine, tangent (radians) | `tan` is undefined at odd multiples of π/2 |
//! | `cot(x)`, `sec(x)`, `csc(x)` | cos x / sin x, 1 / cos x, 1 / sin x | written as quotients of `sin` and `cos`; undefined where the divisor is 0 |
//! | `asin(x)`, `acos(x)` | inverse sine in [−π/2, π/2], inverse cosine in [0, π] | ±1/√(1 − x²); defined on [−1, 1] |
//! | `atan(x)` | inverse tangent in (−π/2, π/2) | 1/(1 + x²) |
//! | `atan2(y, x)` | the angle of the point (x, y), in (−π, π] | (x dy − y dx)/(x² + y²); undefined at the origin |
//! | `sinh(x)`, `cosh(x)`, `tanh(x)` | hyperbolic sine, cosine, tangent | cosh, sinh, 1 − tanh² |
//! | `exp(x)`, `ln(x)` | exponential, natural logarithm | `ln` on x > 0 |
//! | `sqrt(x)` | x^(1/2), x ≥ 0 | an even power under it is one of \|x\|: `sqrt(x^2)` is `abs(x)` |
//! | `abs(x)` | \|x\| | sign(x), taken as 0 at x = 0 |
//!
//! A constant argument outside a function's domain (`asin(2)`, `ln(0)`,
//! `atan2(0, 0)`, `cot(pi)`) is a compile error at the argument, and exact
//! values at constant arguments are folded (`acos(0)` is `pi/2`, `atan(1)`
//! is `pi/4`). There is no sign function: the generated derivative of
//! `abs(x)` is the sign of x, 0 at 0; where x ≠ 0 it is `x/abs(x)`. The
//! names `abs`, `atan`, `sinh` and the other functions added after `sin cos
//! tan exp ln sqrt` are not reserved: they are functions only where they
//! are called, so a coordinate or parameter may be named `atan`.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A particle in the plane held by a torsion spring on its polar
//!     /// angle and a V-shaped potential in y.
//!     pub struct PolarSpring {
//!         parameters { m, k, c }
//!         coordinates { x, y }
//!         lagrangian = m/2*(dot(x)^2 + dot(y)^2) - k/2*atan2(y, x)^2 - c*abs(y);
//!     }
//! }
//!
//! let s = PolarSpring::new(2.0, 3.0, 0.5);
//! // at (1, 1) the angle is π/4, and its gradient (−y, x)/r² is (−1, 1)/2
//! let a = s.accelerations(0.0, &SVector::from([1.0, 1.0]), &SVector::zeros());
//! let angle = std::f64::consts::FRAC_PI_4;
//! assert!((a[0] - 3.0 * angle / 2.0 / 2.0).abs() < 1e-14);
//! assert!((a[1] - (-3.0 * angle / 2.0 - 0.5) / 2.0).abs() < 1e-14);
//! ```
//!
//! Numbers are exact rationals of any size however written: `1/4` is one
//! quarter (never integer division), `0.1` is 1/10, `6.62607015e-34` is
//! 662607015/10⁴². They stay exact through the whole derivation; only the
//! constants in the generated code are rounded, once, to the nearest `f64`.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A pendulum written from the position of its bob.
//!     pub struct Pendulum {
//!         parameters { m, l, g }
//!         coordinates { theta }
//!         let X = l*sin(theta);
//!         let Y = -l*cos(theta);
//!         lagrangian = m/2*(dot(X)^2 + dot(Y)^2) - m*g*Y;
//!     }
//! }
//!
//! let p = Pendulum::new(1.5, 0.8, 9.81);
//! let (q, v) = (SVector::from([0.7]), SVector::from([0.3]));
//! let a = p.accelerations(0.0, &q, &v)[0];
//! assert!((a - (-9.81 / 0.8 * 0.7_f64.sin())).abs() < 1e-14);
//! ```
//!
//! ## Constraints
//!
//! `constraints { dot(s) = expr; .. }` lists velocity constraints in the form
//! (5.3) of the thesis, ṡ_a = −Σ_α A^a_α(q) ṙ_α: the left side is the velocity of
//! a distinct coordinate s, which becomes *dependent*; the right side is linear
//! and homogeneous in the velocities of the other, *independent* coordinates r,
//! with coefficients that may depend on the coordinates and parameters. With n
//! coordinates and p constraints, k = n − p velocities remain free.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// The rolling disc of the thesis, section 6: lean ψ, heading φ,
//!     /// rolling angle θ, contact point (x, y).
//!     pub struct ThesisDisc {
//!         parameters { m, R, g }
//!         coordinates { theta, phi, psi, x, y }
//!
//!         let X = x - R*sin(phi)*sin(psi);      // (6.12)
//!         let Y = y + R*cos(phi)*sin(psi);      // (6.13), sign as (6.16) uses it
//!         let Z = R*cos(psi);                   // (6.14)
//!
//!         lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
//!                    + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
//!                    - m*g*Z;
//!
//!         constraints {
//!             dot(x) = R*cos(phi)*dot(theta);   // (6.27)
//!             dot(y) = R*sin(phi)*dot(theta);   // (6.28)
//!         }
//!     }
//! }
//!
//! assert_eq!(ThesisDisc::<f64>::INDEPENDENT, [0, 1, 2]);   // θ, φ, ψ
//! assert_eq!(ThesisDisc::<f64>::DEPENDENT, [3, 4]);        // x, y
//! let disc = ThesisDisc::new(1.7, 0.35, 9.81);
//! let (th, ph, ps, thd, phd, psd) = (0.1, 0.4, 0.3_f64, 6.0, 2.0, 0.5);
//! let q = SVector::from([th, ph, ps, 0.0, 0.0]);
//! let rdot = SVector::from([thd, phd, psd]);
//! let a = disc.accelerations(0.0, &q, &rdot);
//! // the thesis's closed form (6.60)-(6.62)
//! let d = 4.0 * ps.sin().powi(2) + 3.0;
//! let psdd = 4.0 * (0.35 * (ps.sin() * phd - thd) * ps.cos() * phd + 9.81 * ps.sin()) / (5.0 * 0.35);
//! assert!((a[0] - 4.0 * ps.cos() * phd * psd / d).abs() < 1e-13);
//! assert!((a[1] + 4.0 * (2.0 * ps).sin() * phd * psd / d).abs() < 1e-13);
//! assert!((a[2] - psdd).abs() < 1e-12);
//! ```
//!
//! ### Implicit, affine, time-dependent and holonomic constraints
//!
//! Each constraint is one of four forms (DESIGN §9):
//!
//! ```text
//! constraints {
//!     dot(y) = tan(theta)*dot(x);                  // explicit, homogeneous (above)
//!     dot(x) = R*dot(beta) - Omega*y;              // explicit with an affine / time-dependent term b(q, t)
//!     cos(theta)*dot(y) - sin(theta)*dot(x) = 0;   // implicit: velocities on either side, linear in them
//!     x^2 + y^2 = l^2;                             // holonomic: no velocities, f(q, t) = 0
//! }
//! dependent { y, x }   // optional: what the implicit and holonomic constraints are solved for
//! ```
//!
//! * **Explicit**: written `dot(s) = rhs` where ṡ appears nowhere in rhs, s is
//!   not the left side of an earlier explicit constraint, and rhs uses no
//!   velocity of another explicit constraint's coordinate. The right side is
//!   linear in the velocities plus an optional velocity-free term b(q, t) (a
//!   moving support, a conveyor, a turntable); s becomes dependent.
//! * **Implicit**: any other constraint with velocities: lhs − rhs must be
//!   linear in them, Σ_i c_i(q, t) q̇_i + b(q, t) = 0, once simplified: every
//!   coefficient ∂/∂q̇_i is free of velocities, so `abs(dot(x))`,
//!   `sqrt(dot(x)^2)` (= `abs(dot(x))`) and a speed
//!   `sqrt(dot(x)^2 + dot(y)^2)` are compile errors at that term (as is the
//!   right side of an explicit constraint that is not linear in the other
//!   velocities).
//! * **Holonomic**: no velocities: f = lhs − rhs = 0. Its time derivative
//!   Σ_i ∂f/∂q_i q̇_i + ∂f/∂t = 0 is its velocity row; the generated system
//!   also projects states back onto f = 0 and reports the residual (below).
//!
//! The dependent coordinates of the implicit and holonomic constraints are those
//! listed in `dependent { .. }` (one per such constraint, in their order), else
//! chosen by this rule: constraints in order; for each, among the coordinates not
//! yet dependent whose velocity has a non-zero coefficient, the first (in
//! declared order) whose coefficient is a nonzero constant, else one on which a
//! wheel's heading depends (the first factor, about z, of the orientation of a
//! body that rolls on an `axle`), else the last declared; a candidate is kept
//! only if the block c_s of dependent-velocity coefficients so far stays
//! nonsingular at a generic point (exact zero test, then 16 random points in
//! 32-digit arithmetic), else the next is tried (constant coefficients first,
//! then from the last declared backwards, headings first), and a constraint left
//! with no candidate sends the choice back to the one before. So a differential
//! drive, a Segway or a robot towing a trailer keeps its wheels' rates
//! independent. Rows that no choice solves are a compile error at the
//! constraint; a `dependent` list that cannot work is one error at the name
//! where it fails, saying why (the coordinate does not appear in that
//! constraint, or the block is singular) and which list works (the same
//! coordinates in another order, else the automatic choice). The chosen
//! coordinates are in `DEPENDENT`, whose documentation says which constraint is
//! solved for which coordinate. At most 8 constraints may be implicit or
//! holonomic: their block is solved symbolically, by Cramer's rule up to 3
//! rows and by sparse Gaussian elimination beyond (constant pivots first, then
//! the sparsest rows and columns), so two rolling wheels (4 rows) or a bicycle
//! (4 rolling rows and a holonomic one) are accepted.
//!
//! With the block solved, ṡ = −A ṙ − β: the equations of motion are the
//! multiplier route (5.9) with s̈ = −A r̈ − Ȧ ṙ − β̇ (total time derivatives,
//! ∂/∂t included). The state stays x = [q, ṙ]; the dependent velocities are
//! computed from the constraints.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A pendulum in Cartesian coordinates (y up): solved for `y`.
//!     pub struct Pendulum {
//!         parameters { m, l, g }
//!         coordinates { x, y }
//!         lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - m*g*y;
//!         constraints { x^2 + y^2 = l^2; }
//!         outputs { multipliers }
//!     }
//! }
//!
//! assert_eq!(Pendulum::<f64>::DEPENDENT, [1]);
//! let p = Pendulum::new(1.0, 1.3, 9.81);
//! let x0 = SVector::from([1.3 * 0.5f64.sin(), -1.3 * 0.5f64.cos(), 0.0]);
//! let out = Dopri5::new(1e-10, 1e-12).integrate(&p, 0.0, x0, 10.0).unwrap();
//! assert!(out.max_residual.unwrap() <= 1e-12);   // projected after every step
//! // λ is the constraint force on y, −T y/l: the rod tension T = −λ l/y
//! let (q, r) = (out.x.fixed_rows::<2>(0).into_owned(), out.x.fixed_rows::<1>(2).into_owned());
//! let tension = -p.multipliers(out.t, &q, &r)[0] * 1.3 / q[1];
//! assert!(tension > 0.0);
//! ```
//!
//! A chart of dependent coordinates can be singular somewhere (the implicit
//! sled solved for y at θ = π/2): the generated `chart_regularity` (the signed
//! ratio det(c_s)/Π‖c_a‖ of the block, in [−1, 1]) tells the integrators
//! where, and they move to another chart of the system's atlas there (the
//! row solved for x); held in one chart (`with_chart_switching(false)`) every
//! integrator ends such a run in `SimError::Singular { cause:
//! Singularity::Chart, .. }` with the last good state. An explicit row that
//! divides by the coordinates (`dot(y) = tan(theta)*dot(x)`) is solved as
//! the implicit row with its denominators cleared, and charted alike.
//!
//! The other poles, a division by an expression of the state, or `ln`, a
//! root, `asin`, `acos` or `atan2` at the edge of its domain, in the
//! Lagrangian, the forces or the kinematics, are guards: the generated
//! `crossed_pole` checks each such denominator or argument at both ends of
//! every step, and a step that would carry the motion across ends the run
//! in `SimError::Singular { cause: Singularity::Pole("1/cos(theta)"), .. }`
//! with the last good state:
//!
//! ```rust
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// Pushed along x by a force that grows as tan θ while θ turns freely.
//!     pub struct TanForce {
//!         parameters { m, k }
//!         coordinates { x, theta }
//!         lagrangian = m*(dot(x)^2 + dot(theta)^2)/2;
//!         forces { x: k*tan(theta); }
//!     }
//! }
//!
//! let point = TanForce::new(1.0, 0.5);
//! // θ from 1.2 at 1 rad/s: the force's pole at t = π/2 − 1.2
//! let x0 = SVector::from([0.0, 1.2, 0.0, 1.0]);
//! let err = Dopri5::new(1e-8, 1e-10).integrate(&point, 0.0, x0, 1.0).unwrap_err();
//! assert!(matches!(err, SimError::Singular { cause: Singularity::Pole("1/cos(theta)"), .. }));
//! assert!(err.state().unwrap()[1] < std::f64::consts::FRAC_PI_2);
//! ```
//!
//! ## Forces, inputs and time
//!
//! `forces { q: expr; .. }` adds a generalized force Q_q to the equation of
//! coordinate q (coordinates without an entry get none). Forces may use
//! velocities, `t` and the `inputs`. A system with m inputs takes an extra
//! `u: &SVector<T, m>` as the last argument of `accelerations` and the methods
//! that need it, implements [`ControlledSystem`](runtime::ControlledSystem)
//! instead of [`OdeSystem`](runtime::OdeSystem), and [`Driven`](runtime::Driven)
//! holds an input fixed to make it an `OdeSystem` for one sampling period
//! (and, with `outputs { jacobian }`, an [`OdeJacobian`](runtime::OdeJacobian),
//! so that it runs on `Rodas4` and `GaussLegendre4` with its generated
//! Jacobian).
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A damped pendulum driven by a torque τ and shaken by a periodic torque.
//!     pub struct ForcedPendulum {
//!         parameters { m, l, g, c, A, w }
//!         coordinates { theta }
//!         inputs { tau }
//!         lagrangian = m*l^2/2*dot(theta)^2 + m*g*l*cos(theta);
//!         forces { theta: tau - c*dot(theta) + A*sin(w*t); }
//!     }
//! }
//!
//! let p = ForcedPendulum::new(1.0, 0.5, 9.81, 0.2, 0.3, 2.0);
//! let (t, q, v, u) = (0.4_f64, SVector::from([0.1]), SVector::from([1.5]), SVector::from([0.05]));
//! let expect = (0.05 - 0.2 * 1.5 + 0.3 * (2.0 * t).sin()) / 0.25 - 9.81 / 0.5 * 0.1_f64.sin();
//! assert!((p.accelerations(t, &q, &v, &u)[0] - expect).abs() < 1e-13);
//!
//! // hold u for one sampling period of 10 ms
//! let x0 = SVector::<f64, 2>::from([0.1, 1.5]);
//! let x1 = Rk4::new(1e-3).integrate(&Driven::new(&p, u), 0.0, x0, 0.01).unwrap().x;
//! assert!(x1[0] > 0.1);
//! ```
//!
//! ## Generalized speeds
//!
//! Instead of constraints, a system can be written in generalized speeds u
//! (Kane's and Maggi's form): `speeds { u1, .. }` names k speeds and
//! `kinematics { dot(q) = expr; .. }` gives the velocity of every coordinate
//! as q̇ = S(q, t) u + σ(q, t): each right side linear in the speeds, with
//! coefficients and an optional speed-free term σ that may use the
//! coordinates, parameters and `t`, but no velocity `dot(..)` and no input.
//! Every coordinate has exactly one line; S must have full column rank k
//! (checked at random points). The constraints are then built into the
//! kinematics: every q̇ = S u + σ satisfies them, for any u. A system has
//! either `constraints` or `speeds`, not both. The Lagrangian and the forces
//! are written in the velocities `dot(q)` as usual (the speeds appear only in
//! `kinematics`).
//!
//! The equations of motion are Maggi's: with E = M q̈ + h − Q the
//! Euler–Lagrange terms (M = ∂²L/∂q̇∂q̇) and q̈ = S u̇ + Ṡ u + σ̇,
//! Sᵀ(E − Q) = 0, i.e. (Sᵀ M S) u̇ = Sᵀ(Q − h − M(Ṡ u + σ̇)), solved
//! symbolically for small systems or by an unrolled LDLᵀ factorisation. The
//! state is x = [q_1 … q_n, u_1 … u_k]. A chart of speeds can be regular where
//! the explicit form is not: the Chaplygin sled below crosses θ = π/2, where
//! `dot(y) = tan(theta)*dot(x)` is singular.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// The Chaplygin sled in the speed v of its blade and its yaw rate ω.
//!     pub struct SledSpeeds {
//!         parameters { m, J, a }
//!         coordinates { x, y, theta }
//!         lagrangian = J*dot(theta)^2/2
//!             + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
//!         speeds { v, omega }
//!         kinematics {
//!             dot(x) = v*cos(theta);
//!             dot(y) = v*sin(theta);
//!             dot(theta) = omega;
//!         }
//!         outputs { energy, mass_matrix, reaction_forces }
//!     }
//! }
//!
//! let (m, j, a) = (2.0_f64, 0.3_f64, 0.5_f64);
//! let s = SledSpeeds::new(m, j, a);
//! assert_eq!(SledSpeeds::<f64>::SPEEDS, ["v", "omega"]);
//! let (q, u) = (SVector::from([0.0, 0.0, 1.5]), SVector::from([0.4, 0.9]));
//! // v̇ = a ω², (J + m a²) ω̇ = −m a v ω
//! let ud = s.accelerations(0.0, &q, &u);
//! assert!((ud[0] - a * 0.81).abs() < 1e-15 && (ud[1] + m * a * 0.36 / (j + m * a * a)).abs() < 1e-15);
//! // the mass matrix in the speeds, Sᵀ M S
//! assert!((s.mass_matrix(&q)[(1, 1)] - (j + m * a * a)).abs() < 1e-15);
//! // the blade's side force is orthogonal to the columns of S
//! let r = s.reaction_forces(0.0, &q, &u);
//! assert!((r[0] * 1.5_f64.cos() + r[1] * 1.5_f64.sin()).abs() < 1e-14 && r[2].abs() < 1e-14);
//! // through θ = π/2 and beyond
//! let x0 = SVector::<f64, 5>::from([0.0, 0.0, 1.5, 0.4, 0.9]);
//! let out = Dopri5::new(1e-10, 1e-12).integrate(&s, 0.0, x0, 3.0).unwrap();
//! assert!(out.x[2] > 1.8);
//! ```
//!
//! A system in speeds has `SPEEDS: [&str; k]` in place of `INDEPENDENT`,
//! `DEPENDENT`, `P` and `INTEGRABLE`, and `K` = k, `STATE_DIM` = n + k; its
//! methods take the speeds as `speeds: &SVector<T, k>`:
//!
//! | item | value |
//! |---|---|
//! | `velocities(&self, t, q, speeds) -> SVector<T, n>` | q̇ = S u + σ (in place of `dependent_velocities`) |
//! | `accelerations(&self, t, q, speeds[, u]) -> SVector<T, k>` | u̇ from Maggi's equations |
//! | `impl OdeSystem<T, n + k>` | ẋ = [S u + σ, u̇]; its `chart_regularity` is the Hadamard ratio det(Sᵀ M S) / Π (Sᵀ M S)_aa, in (0, 1], which tends to 0 where the speeds lose rank, so the runtime ends the run there with `SimError::Singular { cause: Singularity::Chart, .. }` |
//! | output `energy` | `energy(&self, q, speeds)`: E at q̇ = S u + σ |
//! | output `mass_matrix` | `mass_matrix(&self, q) -> SMatrix<T, k, k>`: the mass matrix *in the speeds*, Sᵀ M S |
//! | output `reaction_forces` | `reaction_forces(&self, t, q, speeds[, u]) -> SVector<T, n>`: E − Q along the motion, the constraint force that keeps q̇ in the range of S (Sᵀ(E − Q) = 0) |
//! | outputs `jacobian`, `linearization` | as below, for x = [q, u] |
//!
//! `multipliers`, `curvature`, `constraint_matrix` and `routes` belong to the
//! form with constraints and are compile errors here (`reaction_forces` is the
//! constraint force); conversely `reaction_forces` is a compile error on a
//! system with `constraints` (use `multipliers` there).
//!
//! ## Vectors, rotations and rigid bodies
//!
//! A `let` may be a 3-vector, a rotation or a 3×3 matrix as well as a scalar;
//! its kind is inferred from its value and checked wherever it is used,
//! before anything is derived (DESIGN §10). Everything lowers to scalar
//! expressions component by component, so the derivation, the pruning of
//! zeros and the common-subexpression elimination are those of scalar input.
//!
//! | written | kind | meaning |
//! |---|---|---|
//! | `[a, b, c]` | vector | components in the world frame (or in body axes, where a field says so) |
//! | `[[..], [..], [..]]`, `diag(a, b, c)` | matrix | by rows; used for inertia tensors |
//! | `rot_x(a)`, `rot_y(a)`, `rot_z(a)` | rotation | the right-handed elementary rotation by angle `a` (a function of the coordinates and `t`) |
//! | `R1 * R2`, `transpose(R)` | rotation | frames as chains of rotations: `rot_z(psi) * rot_x(theta)` turns first about z, then about the new x |
//! | `u + v`, `u - v`, `s * v`, `v / s`, `-v` | vector | componentwise; `s` a scalar |
//! | `R * v`, `M * v`, `M * N` | vector, matrix | a rotation or matrix applied to a vector, matrix products |
//! | `dot(u, v)`, `cross(u, v)`, `norm(v)` | scalar, vector, scalar | also as methods: `u.dot(v)`, `u.cross(v)`, `v.norm()` |
//! | `v.x`, `v.y`, `v.z` | scalar | components |
//! | `dot(V)` of a vector `let` | vector | its time derivative by the chain rule, as for scalars |
//! | `omega(R)`, `omega_body(R)` | vector | the angular velocity of rotation `R`, in world and in body components |
//! | `kinetic_energy(B)` | scalar | the kinetic energy of body `B` |
//!
//! The angular velocity is derived, not looked up: for each elementary
//! factor the skew matrix Ṙ Rᵀ is computed symbolically and its axial vector
//! read off, and the factors combine by the product rule
//! d(AB)/dt (AB)ᵀ = ȦAᵀ + A (ḂBᵀ) Aᵀ, so any chain of rotations (Euler angles
//! of any convention, a steered fork on a leaning frame) gets its exact ω.
//! A product of two vectors (`u * v`), a sum of different kinds, a rotation
//! built from anything but rotations (`2*R`, a matrix literal) where a
//! rotation is needed, and a vector where a scalar is needed (or the
//! reverse) are compile errors at the token.
//!
//! A **body** is an item `body NAME { mass: m, centre: C, orientation: R,
//! inertia: I }`: its mass, its centre of mass C (world components, a function
//! of the coordinates and `t`), its orientation R (body → world) and its
//! inertia tensor I about the centre of mass in body axes, symmetric,
//! products of inertia included (`center` is accepted for `centre`; a point
//! mass has neither orientation nor inertia). `kinetic_energy(NAME)` is
//! T = ½ m |Ċ|² + ½ ω_bᵀ I ω_b and may be used in the Lagrangian like any
//! scalar.
//!
//! A **rolling contact** is one line of `constraints`:
//! `rolls(NAME, radius: r, axle: a);` for a round wheel with axle `a` (a
//! constant nonzero vector in body axes), `tube: ρ` added for a torus (a
//! tyre of tube radius ρ), and no `axle` for a sphere; `centre: G` gives
//! the geometric centre where it is not the centre of mass. The body rolls
//! without slipping on the plane z = 0: its contact point P is the lowest
//! point of the rim, P − G = −r w − ρ e_z with w = (e_z − n_z n)/|e_z × n|
//! (n the world axle; w = e_z for a sphere), and the two no-slip
//! constraints say that the material point at P is at rest horizontally,
//! the x and y components of Ġ + ω × (P − G) vanish. They are implicit
//! constraints, solved for dependent velocities by the rule of DESIGN §9.
//! The radius and the tube are lengths: constants of the parameters (a
//! coordinate, `t` or a velocity in them is a compile error at the field, as
//! is a radius that simplifies to zero or a negative constant; parameters
//! are not assumed positive, so `R` is taken as given). An axle that is
//! vertical in every configuration (the wheel would lie flat, touching the
//! plane along its rim) is an error at the axle, and so is a contact whose
//! height cannot vanish: a centre that is not at the radius (times
//! |e_z × n|, plus the tube) above the plane z = 0, which is an error at the
//! centre with the height found and the height expected.
//! If the contact's height P_z is not identically zero in the coordinates
//! (a front wheel whose pitch follows from the lean and steer), P_z = 0 is
//! added as a holonomic constraint. A row of a `rolls(..)` line that the
//! constraint rows before it already imply is dropped and listed in the
//! struct's documentation: two wheels on one axle of a cart or
//! differential-drive robot, each written as `rolls(..)`, say the same
//! thing sideways, so the second wheel adds one row, not two (a written
//! constraint that repeats others stays an error). |e_z × n| vanishes when the wheel lies
//! flat; it enters the chart check, so a run that reaches that ends with
//! `SimError::Singular` instead of dividing by zero. Sliding is not
//! modelled; the ground is the plane z = 0 unless a support is given
//! (below).
//!
//! The physically correct rolling disc in ten lines: the frame F of its
//! plane (heading φ, lean ψ), the centre above the contact point (x, y), the
//! disc turned by θ about its axle:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct Disc {
//!         parameters { m, R, g }
//!         coordinates { theta, phi, psi, x, y }
//!         let F = rot_z(phi) * rot_x(-psi);          // heading, then lean
//!         let C = [x, y, 0] + R*(F*[0, 0, 1]);       // centre, above the contact point
//!         body disc {
//!             mass: m, centre: C, orientation: F*rot_y(theta),
//!             inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4),
//!         }
//!         lagrangian = kinetic_energy(disc) - m*g*C.z;
//!         constraints { rolls(disc, radius: R, axle: [0, 1, 0]); }
//!         outputs { energy }
//!     }
//! }
//!
//! let disc = Disc::new(1.7, 0.35, 9.81);
//! assert_eq!(Disc::<f64>::DEPENDENT, [3, 4]); // the contact point follows the rolling
//! let (q, rdot) = (SVector::from([0.0, 0.4, 0.3, 0.0, 0.0]), SVector::from([6.0, 2.0, 0.1]));
//! // ẋ = R cos φ θ̇: the rolling condition the contact derived
//! let sdot = disc.dependent_velocities(&q, &rdot);
//! assert!((sdot[0] - 0.35 * 0.4_f64.cos() * 6.0).abs() < 1e-14);
//! // the disc falls flat in the end: a typed outcome, not a NaN
//! let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0]);
//! match Dopri5::new(1e-9, 1e-9).integrate(&disc, 0.0, x0, 5.0) {
//!     Err(SimError::Singular { t, .. }) => assert!(t > 0.1),
//!     other => panic!("expected the chart to end at the flat disc: {other:?}"),
//! }
//! ```
//!
//! A ball with an offset centre of mass and a full inertia tensor (a
//! Chaplygin sphere), rolling on its geometric centre C:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct Ball {
//!         parameters { m, r, g, b1, b2, b3, I11, I22, I33, I12, I13, I23 }
//!         coordinates { yaw, pitch, roll, x, y }
//!         let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
//!         let C = [x, y, r];                 // geometric centre
//!         let G = C + Q*[b1, b2, b3];        // centre of mass
//!         body ball {
//!             mass: m, centre: G, orientation: Q,
//!             inertia: [[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]],
//!         }
//!         lagrangian = kinetic_energy(ball) - m*g*G.z;
//!         constraints { rolls(ball, radius: r, centre: C); }
//!     }
//! }
//! # let _ = Ball::new(1.0, 0.2, 9.81, 0.0, 0.0, -0.05, 0.02, 0.02, 0.03, 0.001, 0.0, 0.0);
//! ```
//!
//! **Ellipsoids.** `rolls(NAME, semi_axes: [a, b, c])` is an ellipsoid with
//! those semi-axes along the body axes, centred at `centre: G` (by default
//! the centre of mass): its lowest point P = G − R D² γ / √(γᵀ D² γ), with
//! D = diag(a, b, c) and γ = Rᵀ e_z the vertical in body axes, is found in
//! closed form. The rattleback, its inertia turned by δ against the
//! ellipsoid's axes and its centre's height left to the contact:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct Rattleback {
//!         parameters { a1, a2, a3, h, m, A, B, C, delta, g }
//!         coordinates { psi, theta, phi, x, y, z }
//!         let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
//!         let Cg = [x, y, z];                    // the ellipsoid's centre
//!         let G = Cg + R*[0, 0, -h];             // the centre of mass, below it
//!         body shell {
//!             mass: m, centre: G, orientation: R,
//!             inertia: rot_z(delta)*diag(A, B, C)*transpose(rot_z(delta)),
//!         }
//!         lagrangian = kinetic_energy(shell) - m*g*G.z;
//!         constraints { rolls(shell, semi_axes: [a1, a2, a3], centre: Cg); }
//!     }
//! }
//!
//! // the height row z = √(γᵀ D² γ) makes z dependent, with x and y
//! assert_eq!(Rattleback::<f64>::DEPENDENT, [3, 4, 5]);
//! # let _ = Rattleback::new(0.2, 0.03, 0.02, 0.01, 1.0, 2e-4, 1.6e-3, 1.7e-3, 0.1, 9.81);
//! ```
//!
//! **Supports that tilt or move.** `on: F` puts the plane the body rolls on
//! in the frame F: its plane z = 0 through `origin: O` (by default the
//! origin). F is a rotation — constant (an incline), of `t` (a turntable, a
//! tilting plate driven by a motion you prescribe) or of the coordinates —
//! or a body of the system, whose plane z = 0 through its centre carries
//! the contact (a platform the system drives); `origin: O` alone moves the
//! plane z = 0 (a conveyor: `origin: [v*t, 0, 0]`). Rolling means that the
//! material velocities of the two surfaces agree at the contact point:
//! Ġ + ω × (P − G) − (Ȯ + ω_F × (P − O)) has no component along the plane,
//! and the height (P − O)·N above it, N = F e_z, is a holonomic row. Every
//! shape takes a support. A ball on a turntable, whose centre circles at
//! 2/7 of the table's rate:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct TurntableBall {
//!         parameters { m, r, Omega }
//!         coordinates { x, y, yaw, pitch, roll }
//!         let table = rot_z(Omega*t);
//!         let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
//!         body ball { mass: m, centre: [x, y, r], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
//!         lagrangian = kinetic_energy(ball);
//!         constraints { rolls(ball, radius: r, on: table); }
//!     }
//! }
//!
//! let ball = TurntableBall::new(0.2, 0.05, 2.0);
//! // at rest on the table at (0.3, 0): the table carries the contact point
//! let (q, rdot) = (SVector::from([0.3, 0.0, 0.0, 0.0, 0.0]), SVector::from([0.0, 0.0, 0.0]));
//! let v: SVector<f64, 2> = ball.dependent_velocities(&q, &rdot);
//! assert!((v[1] - 2.0 * 0.3).abs() < 1e-15); // ẏ = Ω x
//! ```
//!
//! **Curved surfaces.** A ball rolls inside or outside a fixed sphere or
//! cylinder: `rolls(ball, radius: r, inside: sphere(R0, O))` (a bowl of
//! radius R0 centred at O; `sphere(R0)` centred at the origin),
//! `outside: cylinder(R0, axis, O)` (a log whose axis has the direction
//! `axis` through O). The contact point is P = G − r N with N the
//! surface's normal towards the ball, and the height row keeps the centre
//! at R0 ∓ r from the centre or the axis.
//!
//! **Convex bodies.** `support_function: h(x, y, z)` gives any strictly
//! convex body by its support function in body axes: h(d) is the largest
//! p·d over the body's points p (from its centre), for every direction
//! d = (x, y, z) — the ellipsoid's is `sqrt(a^2*x^2 + b^2*y^2 + c^2*z^2)`,
//! a body rounded by ρ adds `rho*sqrt(x^2 + y^2 + z^2)`. The contact is
//! the point ∇h(−RᵀN), in closed form; the macro checks that h is of
//! degree 1 and strictly convex. A rounded box-like pebble:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct Pebble {
//!         parameters { m, a, b, c, rho, g }
//!         coordinates { psi, theta, phi, x, y, z }
//!         let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
//!         body stone { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m*(b^2 + c^2)/5, m*(a^2 + c^2)/5, m*(a^2 + b^2)/5) }
//!         lagrangian = kinetic_energy(stone) - m*g*z;
//!         constraints { rolls(stone, support_function: sqrt(a^2*x^2 + b^2*y^2 + c^2*z^2) + rho*sqrt(x^2 + y^2 + z^2)); }
//!     }
//! }
//!
//! // resting level, the pebble's centre is c + ρ above the plane
//! let pebble = Pebble::new(0.1, 0.05, 0.03, 0.02, 0.005, 9.81);
//! let mut x0 = SVector::<f64, 9>::zeros(); // ψ, θ, φ, x, y, z, three angle rates
//! x0[5] = 0.025;
//! assert!(pebble.constraint_residual(0.0, &x0).unwrap() < 1e-17);
//! ```
//!
//! **Surfaces z = h(x, y).** `on: z = h(x, y)` rolls the body on a fixed
//! surface written as the graph of its height (terrain, a trough, a banked
//! track); in h, `x` and `y` are the surface's point. Its contact point has
//! no closed form, so you declare two coordinates for its x and y and name
//! them, `contact: [u, v]`: three holonomic rows hold the body's point
//! whose normal is the surface's at (u, v) on the surface there, and the
//! integrators' projection onto them finds the contact by Newton's method.
//! A ball in the paraboloid z = (x² + y²)/2, placed by its centre:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct BallInABowl {
//!         parameters { m, r, g }
//!         coordinates { x, y, z, yaw, pitch, roll, u, v }
//!         let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
//!         body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
//!         lagrangian = kinetic_energy(ball) - m*g*z;
//!         constraints { rolls(ball, radius: r, on: z = (x^2 + y^2)/2, contact: [u, v]); }
//!     }
//! }
//!
//! let ball = BallInABowl::new(0.2, 0.1, 9.81);
//! assert_eq!(BallInABowl::DEPENDENT, [0, 1, 2, 6, 7]); // x, y, z and the contact
//! // the centre at (0.3, 0.2), its height and the contact point guessed
//! let mut x0 = SVector::<f64, 11>::zeros();
//! (x0[0], x0[1], x0[2], x0[6], x0[7]) = (0.3, 0.2, 0.2, 0.3, 0.2);
//! ball.project(0.0, &mut x0).expect("the contact is found");
//! let (u, v) = (x0[6], x0[7]);
//! let gap = [x0[0] - u, x0[1] - v, x0[2] - (u * u + v * v) / 2.0];
//! let distance = gap.iter().map(|g| g * g).sum::<f64>().sqrt();
//! assert!((distance - 0.1).abs() < 1e-15); // the centre is r above the contact
//! assert!((gap[0] + u * gap[2]).abs() < 1e-15); // along the surface's normal
//! ```
//!
//! **Sliding points.** `slides(NAME, at: p)` keeps the body's point p
//! (body axes, from the centre of mass; by default the centre of mass) on
//! the plane z = 0 without friction, or on `on: z = h(x, y)` (which may
//! move with `t`) or the plane of a support `on: F`: one holonomic row,
//! whose multiplier is the normal force. A top spinning on a smooth table:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct SlidingTop {
//!         parameters { m, I1, I3, l, g }
//!         coordinates { x, y, z, phi, theta, psi }
//!         let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
//!         body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(I1, I1, I3) }
//!         lagrangian = kinetic_energy(top) - m*g*z;
//!         constraints { slides(top, at: [0, 0, -l]); }
//!     }
//! }
//!
//! assert_eq!(SlidingTop::DEPENDENT, [2]); // the height z = l cos θ
//! ```
//!
//! **Skates.** `skates(NAME, across: d, at: p)` is a knife edge: the body's
//! point p (body axes, from the centre of mass) has no velocity along the
//! body-fixed direction d. The Chaplygin sleigh, its blade a behind the
//! centre of mass:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     pub struct Sleigh {
//!         parameters { m, J, a }
//!         coordinates { x, y, theta }
//!         let R = rot_z(theta);
//!         body sled { mass: m, centre: [x, y, 0] + R*[a, 0, 0], orientation: R, inertia: diag(J, J, J) }
//!         lagrangian = kinetic_energy(sled);
//!         constraints { skates(sled, across: [0, 1, 0], at: [-a, 0, 0]); }
//!     }
//! }
//!
//! let sleigh = Sleigh::new(1.3, 0.4, 0.25);
//! let (q, rdot) = (SVector::from([0.0, 0.0, 0.5]), SVector::from([1.0, 0.0]));
//! // the blade's point (x, y) moves along the blade: ẏ = tan θ ẋ
//! let sdot = sleigh.dependent_velocities(&q, &rdot);
//! assert!((sdot[0] - 0.5_f64.tan()).abs() < 1e-15);
//! ```
//!
//! `outputs { contact_points }` adds `contact_points(&self, q)`, the
//! contact points of the rolling contacts as the columns of a 3 × c matrix.
//! The struct's documentation lists the vector and rotation `let`s by name,
//! each body's contribution (its fields and its body angular velocity) and
//! each rolling contact (its contact point and no-slip rows).
//!
//! # The generated API
//!
//! For `pub struct Name { .. }` with n coordinates, p constraints, k = n − p
//! independent coordinates and m inputs, the macro emits a struct
//! `Name<T = f64>` generic over the scalar (`T: nalgebra::RealField + Copy`:
//! `f64`, `f32`, or a dual or interval type) with one public field per
//! parameter, and:
//!
//! | item | meaning |
//! |---|---|
//! | `Name::new(params..)` | the parameters in declared order (a `const fn`) |
//! | `Name::from_parameters(NameParameters { .. })`, `From`, `parameters(&self)` | the parameters by name ([below](#building-and-reading-the-state)) |
//! | `Name::state(NameCoordinates { .. }, NameVelocities { .. })`, `Name::split(&x)` | the state from named parts and back |
//! | `state_from_velocities(&self, q, qdot) -> Result<SVector<T, n + k>, ConstraintViolation<T>>` | the state from the velocities of all coordinates, checked against the constraints (`(&self, t, q, qdot)` when they depend on time) |
//! | `COORDINATES: [&str; n]`, `INPUTS: [&str; m]` | names in declared order |
//! | `INDEPENDENT: [usize; k]`, `DEPENDENT: [usize; p]` | the indices of r and s in q, ascending |
//! | `N`, `K`, `P`, `STATE_DIM` | n, k, p and n + k |
//! | `INTEGRABLE: bool` | the curvature vanishes identically: the constraints are holonomic in disguise (the macro warns when velocity constraints are); `false` with affine or time-dependent terms |
//! | `dependent_velocities(&self, q, rdot) -> SVector<T, p>` | ṡ = −A(q) ṙ − β(q) (`(&self, t, q, rdot)` when a constraint depends on time) |
//! | `accelerations(&self, t, q, rdot[, u]) -> SVector<T, k>` | r̈, the reduced equations of motion (5.9) |
//! | `impl OdeSystem<T, n + k>` | ẋ = [q̇(q, ṙ), r̈] on the state x = [q_1 … q_n, ṙ_1 … ṙ_k] (`ControlledSystem<T, n + k, m>` with inputs) |
//! | its `chart_regularity` | with implicit or holonomic constraints only: det(c_s)/Π‖c_a‖, zero where the chart is singular |
//! | its `constraint_residual`, `project` | with holonomic constraints only: max \|f_i\|, and Newton's method on their dependent coordinates (at most 8 iterations, to 4 ε of the size of f's terms, `ProjectionFailure` otherwise), which the integrators apply after every accepted step unless `with_projection(false)` |
//!
//! The runtime state holds every coordinate and only the independent velocities;
//! the dependent velocities are computed from the constraints at every
//! evaluation, so an integrated motion satisfies them exactly.
//!
//! The constants do not depend on the scalar type. They are defined on
//! `Name<f64>`, so `Name::N` and `Name::COORDINATES` need no type argument
//! (`Name::<f64>::N` works as well); code generic over the scalar reads
//! them the same way, as `Name::N`.
//!
//! ## Building and reading the state
//!
//! Next to `Name`, with its visibility, the macro emits three plain structs
//! (`Clone`, `Copy`, `Debug`, `PartialEq`, generic over `T = f64`):
//!
//! | struct | fields |
//! |---|---|
//! | `NameCoordinates<T>` | one per coordinate, in declared order (also `Default`) |
//! | `NameVelocities<T>` | one per velocity of the state: each independent coordinate's, under the coordinate's name, or each generalized speed under its own name (also `Default`) |
//! | `NameParameters<T>` | one per parameter |
//!
//! A field named by a Rust keyword is a raw identifier (`r#type`). The
//! names are the system's with a suffix: a type of that name already in the
//! module is one compile error ("the name `SledCoordinates` is defined
//! multiple times") at the system's name, and nothing else; rename one of
//! them.
//! `NameCoordinates` and `NameVelocities` convert to and from the
//! `SVector`s the methods take (`From`, `.into()`).
//!
//! * `Name::state(q, v)` is the state x = [q, ṙ] (or [q, u]);
//!   `Name::split(&x)` its inverse, for an outcome's final state, an
//!   observed state or a dense-output sample.
//! * `state_from_velocities(&self, q, qdot)` takes the velocities of *all*
//!   coordinates, as they are often known (a wheel's rates, a yaw rate), in
//!   a `NameCoordinates`: it computes the dependent velocities from the
//!   independent ones and returns the state if the given ones agree with
//!   them to 1e-9 of the largest velocity, else a
//!   [`ConstraintViolation`](runtime::ConstraintViolation) naming the
//!   coordinate furthest off, with both values. It takes `t` first when
//!   the constraints depend on time, and always in generalized speeds,
//!   where the speeds are solved from q̇ = S(q, t) u + σ(q, t) by least
//!   squares and q̇ is checked against S u + σ. The coordinates are taken
//!   as given (the integrators project them onto holonomic constraints).
//! * `state_from_known_velocities(&self, q, known)` takes the velocities
//!   known for *some* coordinates (`Some` in a `NameCoordinates<Option<T>>`,
//!   `None` for the others: a robot's forward speed and turn rate rather
//!   than its wheel rates) and solves the constraints for the rest (least
//!   squares on the known rows, then checked as above). It fails with
//!   [`KnownVelocitiesError::TooFew`](runtime::KnownVelocitiesError) when
//!   the known velocities leave the motion undetermined (fewer than the
//!   state's velocities, or ones the constraints tie together, such as ẋ
//!   and ẏ of a sled) and with `Violation` when they break the constraints.
//! * `Name::from_parameters(NameParameters { .. })`, or `.into()`, builds
//!   the system by parameter name: the compiler checks that every
//!   parameter is given. `parameters(&self)` reads them back.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// The Chaplygin sled: the blade at (x, y) moves along its heading θ.
//!     pub struct Sled {
//!         parameters { m, J, a }
//!         coordinates { x, theta, y }
//!         lagrangian = J*dot(theta)^2/2
//!             + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
//!         constraints { dot(y) = tan(theta)*dot(x); }
//!     }
//! }
//!
//! let sled: Sled = SledParameters { m: 2.0, J: 0.3, a: 0.5 }.into();
//! assert_eq!((Sled::N, Sled::STATE_DIM, Sled::COORDINATES), (3, 5, ["x", "theta", "y"]));
//!
//! // the state from the coordinates and the independent velocities ẋ, θ̇ ...
//! let q = SledCoordinates { x: 0.0, theta: 0.2, y: 0.0 };
//! let x0 = Sled::state(q, SledVelocities { x: 0.4, theta: 0.9 });
//! // ... or from every velocity, checked against ẏ = tan θ ẋ
//! let qdot = SledCoordinates { x: 0.4, theta: 0.9, y: 0.2_f64.tan() * 0.4 };
//! assert_eq!(sled.state_from_velocities(q, qdot), Ok(x0));
//! // ... or from the velocities known: θ̇ and ẏ, the rest solved for
//! let known = SledCoordinates { x: None, theta: Some(0.9), y: Some(0.2_f64.tan() * 0.4) };
//! let x1 = sled.state_from_known_velocities(q, known).unwrap();
//! assert!((x1 - x0).norm() < 1e-15);
//! let sliding = SledCoordinates { y: 0.3, ..qdot };
//! let e = sled.state_from_velocities(q, sliding).unwrap_err();
//! assert_eq!(e.coordinate, "y");
//! println!("{e}"); // the velocity of `y` is 0.3 but the constraints give 0.081.. at these coordinates ..
//!
//! // integrate, and read the outcome and a sample at t = 0.5 by name
//! let mut half_way = None;
//! let out = Dopri5::new(1e-10, 1e-12)
//!     .integrate_with_outputs(&sled, 0.0, x0, 1.0, &[0.5], |_, x| half_way = Some(Sled::split(x)))
//!     .unwrap();
//! let (q1, v1) = Sled::split(&out.x);
//! let (q_half, _) = half_way.unwrap();
//! assert!(q1.theta > q_half.theta && q_half.theta > q.theta); // it turns on
//! // the blade never slips
//! let ydot = sled.dependent_velocities(&q1.into(), &v1.into())[0];
//! assert!((ydot - q1.theta.tan() * v1.x).abs() < 1e-12);
//! ```
//!
//! A name taken twice:
//!
//! ```compile_fail,E0255
//! use nonholonomic::prelude::*;
//!
//! struct SledVelocities; // the user's own type of that name
//!
//! nonholonomic_system! {
//!     pub struct Sled { // error[E0255]: the name `SledVelocities` is defined multiple times
//!         parameters { m }
//!         coordinates { x }
//!         lagrangian = m*dot(x)^2/2;
//!     }
//! }
//! ```
//!
//! ## Outputs
//!
//! `outputs { .. }` asks for more; nothing else is derived or emitted.
//!
//! | output | method | value |
//! |---|---|---|
//! | `multipliers` | `multipliers(&self, t, q, rdot[, u]) -> SVector<T, p>` | λ_a = d/dt ∂L/∂ṡ_a − ∂L/∂s_a − Q_{s_a} along the motion (5.10): the constraint forces |
//! | `curvature` | `curvature(&self, q) -> [SMatrix<T, k, k>; p]` | `B[b][(α, β)]` = B^b_{αβ} of (5.21) (homogeneous, time-independent velocity constraints only) |
//! | `energy` | `energy(&self, q, rdot) -> T` | E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities (L and the constraints must not depend on `t`) |
//! | `constraint_matrix` | `constraint_matrix(&self, q) -> SMatrix<T, p, k>` | A^a_α, minus the coefficient of ṙ_α in the solved constraint of s_a (time-independent constraints) |
//! | `contact_points` | `contact_points(&self, q) -> SMatrix<T, 3, c>` | the contact points of the c rolling contacts (`rolls(..)` lines, in order), world components, one per column |
//! | `mass_matrix` | `mass_matrix(&self, q) -> SMatrix<T, n, n>` | ∂²L/∂q̇_i∂q̇_j |
//! | `jacobian` | `jacobian(&self, t, x[, u]) -> SMatrix<T, n+k, n+k>`, `time_derivative(&self, t, x[, u]) -> SVector<T, n+k>` and `impl OdeJacobian` (with inputs `impl ControlledJacobian`, which makes `Driven` an `OdeJacobian` at the held input) | ∂f/∂x and ∂f/∂t of the first-order system, for the stiff integrators (`integrate_with_jacobian`; without this output they tell you to add it; `Rodas4` and `Rodas5P` take ∂f/∂t from here instead of a difference in t) |
//! | `sensitivities` or `sensitivities(p1, p2, ..)` (no inputs; implies `jacobian`) | `parameter_jacobian(&self, t, x) -> SMatrix<T, n+k, P>`, `variational_rhs(&self, t, x, s_p, s_x0)`, `sensitivities(&self)`, `SENSITIVITY_PARAMETERS`, `SENSITIVITY_DIM` and `impl ParameterJacobian` | ∂f/∂p for the P parameters (all, or those listed, in that order), and the system augmented with ∂x/∂p and ∂x/∂x0 (the variational equations), an `OdeSystem` of dimension (n+k)(1 + P + n+k) that any integrator integrates: forward sensitivities, with the error of the sensitivities controlled with the state's (full error control) |
//! | `linearization` | `linearization(&self, t, x, u) -> (A, B)` | A = ∂f/∂x and B = ∂f/∂u of ẋ = f(t, x, u), for controller design |
//! | `routes` (homogeneous, time-independent velocity constraints) | `accelerations_multiplier_route`, `accelerations_curvature_route`, `reduced_system`, `OPS_MULTIPLIER_ROUTE`, `OPS_CURVATURE_ROUTE`, `ROUTE` | both derivations of r̈ as separate methods with their operation counts, and the reduced system M_c r̈ = f |
//! | `momenta` (homogeneous, time-independent velocity constraints solved in closed form) | `momenta(&self, t, q, rdot[, u]) -> SVector<T, m>`, `momentum_rates(&self, t, q, rdot[, u]) -> SVector<T, m>`, `CYCLIC: [usize; m]`, `CONSERVED: [Conservation; m]` | the momenta p_k = ∂L_c/∂ṙ_k of the m cyclic coordinates (5.35), their rates ṗ_k by (5.36) without the accelerations, and whether each is conserved (`Conserved`: the rate is identically zero; `NotConserved`: the documentation gives a state where it is not; `Undecided`) |
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// The sled again, with the outputs a scene inspects.
//!     pub struct Sled {
//!         parameters { m, J, a }
//!         coordinates { x, theta, y }
//!         lagrangian = J*dot(theta)^2/2
//!             + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
//!         constraints { dot(y) = tan(theta)*dot(x); }
//!         outputs { energy, constraint_matrix, mass_matrix, multipliers, jacobian }
//!     }
//! }
//!
//! let s = Sled::new(2.0, 0.3, 0.5);
//! let (th, xd, thd) = (0.2_f64, 0.4, 0.9);
//! let q = SVector::from([0.0, th, 0.0]);
//! let rdot = SVector::from([xd, thd]);
//! // A^y_x = −tan θ: minus the coefficient of ẋ in the constraint of y
//! assert!((s.constraint_matrix(&q)[(0, 0)] + th.tan()).abs() < 1e-15);
//! assert_eq!(s.constraint_matrix(&q)[(0, 1)], 0.0);
//! // M = ∂²L/∂q̇∂q̇, in coordinate order (x, θ, y)
//! let mm = s.mass_matrix(&q);
//! assert!((mm[(1, 1)] - (0.3 + 2.0 * 0.25)).abs() < 1e-15 && (mm[(0, 1)] + 2.0 * 0.5 * th.sin()).abs() < 1e-15);
//! // E = ½ q̇ᵀ M q̇ with ẏ = tan θ ẋ
//! let qd = SVector::from([xd, thd, th.tan() * xd]);
//! assert!((s.energy(&q, &rdot) - 0.5 * qd.dot(&(mm * qd))).abs() < 1e-14);
//! // the blade's side force does no work: λ is finite and the energy is conserved
//! let x0 = SVector::<f64, 5>::from([0.0, th, 0.0, xd, thd]);
//! let out = Rodas4::new(1e-9, 1e-11).integrate_with_jacobian(&s, 0.0, x0, 2.0).unwrap();
//! let (q1, r1) = (out.x.fixed_rows::<3>(0).into_owned(), out.x.fixed_rows::<2>(3).into_owned());
//! assert!((s.energy(&q1, &r1) - s.energy(&q, &rdot)).abs() < 1e-7);
//! assert!(s.multipliers(out.t, &q1, &r1)[0].is_finite());
//! ```
//!
//! Forward sensitivities of a whole motion with respect to the parameters and
//! the initial state:
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A damped oscillator, sensitive to its stiffness and damping.
//!     pub struct Oscillator {
//!         parameters { m, c, k }
//!         coordinates { x }
//!         lagrangian = m*dot(x)^2/2 - k*x^2/2;
//!         forces { x: -c*dot(x); }
//!         outputs { sensitivities(k, c) }
//!     }
//! }
//!
//! let osc = Oscillator::new(1.0, 0.3, 4.0);
//! assert_eq!(Oscillator::SENSITIVITY_PARAMETERS, ["k", "c"]);
//! let sens = osc.sensitivities(); // an OdeSystem of dimension SENSITIVITY_DIM = 2·(1 + 2 + 2)
//! let x0 = SVector::from([1.0, 0.0]);
//! let out = Dop853::new(1e-11, 1e-13).integrate(&sens, 0.0, sens.initial_state(&x0), 3.0).unwrap();
//! let (x, dx_dp, dx_dx0) = sens.split(&out.x); // x(3), ∂x/∂(k, c) (2 × 2), ∂x/∂x0 (2 × 2)
//! // ∂x/∂k against two whole runs
//! let at_k = |k: f64| Dop853::new(1e-13, 1e-15).integrate(&Oscillator::new(1.0, 0.3, k), 0.0, x0, 3.0).unwrap().x;
//! let fd = (at_k(4.0 + 1e-5) - at_k(4.0 - 1e-5)) / 2e-5;
//! assert!((dx_dp.column(0) - fd).amax() < 1e-7);
//! assert!((x - at_k(4.0)).amax() < 1e-9 && dx_dx0[(0, 0)].is_finite());
//! ```
//!
//! Of the two derivations of r̈ — projecting the full Euler–Lagrange equations
//! with multipliers (5.9), or Bloch's form with the constrained Lagrangian and the
//! curvature (5.12)–(5.21) — both are derived when k ≤ 6 (or with `routes`) and
//! the constraints are homogeneous and time-independent, and
//! `accelerations` uses the one with fewer weighted operations; they agree to
//! rounding. Values that depend on parameters alone are computed in `new` and
//! recomputed if a parameter field is changed afterwards.
//!
//! ## Conventions
//!
//! * Coordinates keep their declared order; r and s are subsequences of it.
//! * A^a_α is *minus* the coefficient of `dot(r_α)` in the constraint of s_a, so
//!   that ṡ = −A ṙ. For the disc above, `dot(x) = R*cos(phi)*dot(theta)` gives
//!   A^x_θ = −R cos φ.
//! * Multipliers carry the thesis's sign: E = Cᵀ λ with C = [A | I] (columns
//!   in the order r, s) and E_j = d/dt ∂L/∂q̇_j − ∂L/∂q_j − Q_j. For an
//!   implicit or holonomic constraint, λ_a belongs to the row solved for s_a,
//!   ṡ_a + Σ_α A^a_α ṙ_α + β_a = 0 (coefficient 1 on ṡ_a).
//! * Names are used as written (`R`, `J`, `I1` are fine); `r#x` and `x` are one
//!   name. The generated code binds only `__nh_` names of its own: a name of
//!   the system starting with `__nh_` is a compile error at the name.
//!
//! ## Compile errors
//!
//! Malformed input is a compile error at the culprit's tokens, with a message that
//! says how to fix it; every independent mistake is reported in one compilation,
//! once (two neighbouring tokens swapped are one error at the token, and the
//! item is still read), and a stand-in with the full API is emitted so that the
//! code using the system produces no follow-up errors. A constraint that is not
//! linear in the velocities:
//!
//! ```compile_fail
//! nonholonomic::nonholonomic_system! {
//!     pub struct Bad {
//!         parameters { R }
//!         coordinates { theta, x }
//!         lagrangian = dot(theta)^2/2 + dot(x)^2/2;
//!         constraints { dot(x) = R*dot(theta)^2; }  // error: not linear in the velocities
//!     }
//! }
//! ```
//!
//! a misspelled function (the message asks "did you mean `cos`?"):
//!
//! ```compile_fail
//! nonholonomic::nonholonomic_system! {
//!     pub struct Bad {
//!         parameters { m, g, l }
//!         coordinates { theta }
//!         lagrangian = m*l^2*dot(theta)^2/2 + m*g*l*cso(theta);  // error: unknown function
//!     }
//! }
//! ```
//!
//! and a `dependent` coordinate that no implicit or holonomic constraint involves:
//!
//! ```compile_fail
//! nonholonomic::nonholonomic_system! {
//!     pub struct Bad {
//!         coordinates { x, y, theta }
//!         lagrangian = dot(x)^2/2 + dot(y)^2/2 + dot(theta)^2/2;
//!         constraints { cos(theta)*dot(y) = sin(theta)*dot(x); }
//!         dependent { theta }  // error: theta is in no such constraint
//!     }
//! }
//! ```
//!
//! The full list of error classes, each with a case in `tests/ui/`, is in the
//! user guide (`docs/guide/language.md`, compile errors). Setting `NH_STATS=1` while compiling makes the macro print each
//! system's expansion time, the operation counts of both routes and the route
//! chosen.
//!
//! # The runtime
//!
//! [`runtime`] (all of it in [`prelude`]) has the traits
//! [`OdeSystem`](runtime::OdeSystem), [`OdeJacobian`](runtime::OdeJacobian),
//! [`ControlledSystem`](runtime::ControlledSystem) and
//! [`Integrator`](runtime::Integrator), and eight integrators on one step driver:
//! [`Rk4`](runtime::Rk4), [`Dopri5`](runtime::Dopri5),
//! [`Dop853`](runtime::Dop853), [`Rodas4`](runtime::Rodas4),
//! [`Rodas5P`](runtime::Rodas5P), [`Bdf`](runtime::Bdf) (variable-order BDF),
//! [`AutoSwitch`](runtime::AutoSwitch) and [`GaussLegendre4`](runtime::GaussLegendre4). A run returns an
//! [`Outcome`](runtime::Outcome) or a [`SimError`](runtime::SimError) that
//! carries the time and the last good state; no integrator allocates per step.
//! Without the default `std` feature the facade is `no_std`.
//!
//! ## Events
//!
//! [`integrate_with_events`](runtime::Integrator::integrate_with_events)
//! locates the sign changes of functions g(t, x) ([`Events`](runtime::Events),
//! all of them returned by one closure) on the dense output of every
//! integrator, filtered by [`Direction`](runtime::Direction), terminal or
//! not; each hit is an [`EventHit`](runtime::EventHit) (which, when, the
//! state), and a terminal one ends the run with its time and state in the
//! [`Outcome`](runtime::Outcome). A disc falling flat or a bicycle falling
//! over ends at its event rather than at the singularity of its equations.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A pendulum of length l.
//!     pub struct Pendulum {
//!         parameters { m, l, g }
//!         coordinates { q }
//!         lagrangian = m*l^2/2*dot(q)^2 + m*g*l*cos(q);
//!     }
//! }
//!
//! let p = Pendulum::new(1.0, 1.0, 9.81);
//! // Released at 0.1 rad; it reaches the bottom (q falling through 0)
//! // after a quarter period, about π/2·√(l/g).
//! let bottom = Events::new(|_t: f64, x: &SVector<f64, 2>| Vector1::new(x[0]))
//!     .direction([Direction::Falling])
//!     .terminal([true]);
//! let out = Dopri5::new(1e-10, 1e-12)
//!     .integrate_with_events(&p, 0.0, SVector::from([0.1, 0.0]), 10.0, &bottom, |_| {})
//!     .unwrap();
//! assert_eq!(out.event.map(|hit| hit.index), Some(0));
//! assert!(out.x[0].abs() < 1e-12 && out.x[1] < 0.0);
//! let quarter = std::f64::consts::FRAC_PI_2 / 9.81f64.sqrt();
//! assert!((out.t - quarter).abs() < 1e-3 * quarter);
//! ```
#![forbid(unsafe_code)]
#![cfg_attr(not(feature = "std"), no_std)]

/// Derives the equations of motion of a mechanical system at compile time.
///
/// The input is a `struct` item in the input language described on the
/// [crate page](crate#the-input-language): `parameters`, `coordinates`,
/// `let`s, one `lagrangian`, and optionally `inputs`, `forces`, `constraints`
/// and `outputs`. The output is the struct `Name<T = f64>` with one public
/// field per parameter, its constants and methods
/// ([the generated API](crate#the-generated-api)) and its runtime trait
/// implementation.
///
/// The struct derives `Clone`, `Copy`, `Debug` and `PartialEq` (and
/// `Default` when it has no parameters); deriving one of them again is a
/// compile error that says so. Other derives and attributes pass through to
/// the struct; `#[cfg]`, `#[cfg_attr]` and lint attributes (`allow`, `warn`,
/// `deny`, `forbid`) apply to everything generated for it.
///
/// This wrapper passes the path of this crate to the procedural macro, so
/// the generated code works under a renamed dependency
/// (`nh = { package = "nonholonomic", .. }`).
///
/// With the environment variable `NH_STATS=1` set while compiling, the macro
/// prints the expansion's figures (time, operation counts of both routes,
/// the route chosen) to standard error.
#[macro_export]
macro_rules! nonholonomic_system {
    ($($system:tt)*) => {
        $crate::__private::nonholonomic_system_impl! { @crate($crate) $($system)* }
    };
}

pub use nh_runtime as runtime;

/// The linear algebra the generated code and the runtime are written in
/// (states are `nalgebra::SVector`s): re-exported, so that a scene needs no
/// dependency of its own on it (and cannot end up with another version).
pub use nalgebra;

/// Everything a scene needs: the macro, the runtime traits and integrators,
/// [`nalgebra`] itself and its vector and matrix types, and `RealField` for
/// code generic over the scalar.
///
/// ```
/// use nonholonomic::prelude::*;
///
/// let v: Vector3<f64> = Vector3::new(1.0, 2.0, 2.0);
/// let m: Matrix3<f64> = Matrix3::identity() * 2.0;
/// let x: SVector<f64, 3> = m * v;
/// assert_eq!(x.norm(), 6.0);
/// let r = nalgebra::Rotation3::<f64>::from_axis_angle(&Vector3::z_axis(), 0.5);
/// fn half<T: RealField + Copy>(x: T) -> T {
///     x / (T::one() + T::one())
/// }
/// assert!((half(r.angle()) - 0.25).abs() < 1e-15);
/// ```
pub mod prelude {
    pub use crate::nonholonomic_system;
    pub use nalgebra::{
        self, Matrix2, Matrix3, Matrix4, RealField, SMatrix, SVector, Vector1, Vector2, Vector3,
        Vector4,
    };
    #[cfg(feature = "std")]
    pub use nalgebra::{DMatrix, DVector};
    pub use nh_runtime::*;
}

/// Paths used by generated code; not part of the public API.
#[doc(hidden)]
pub mod __private {
    pub use nalgebra;
    pub use nh_macros::nonholonomic_system as nonholonomic_system_impl;
    pub use nh_runtime;
}

/// The README's code examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The user guide's tutorial, compiled and run as doctests.
#[doc = include_str!("../docs/guide/tutorial.md")]
#[cfg(doctest)]
pub struct GuideTutorialDoctests;

/// The user guide's language page, compiled and run as doctests.
#[doc = include_str!("../docs/guide/language.md")]
#[cfg(doctest)]
pub struct GuideLanguageDoctests;

/// The user guide's runtime page, compiled and run as doctests.
#[doc = include_str!("../docs/guide/runtime.md")]
#[cfg(doctest)]
pub struct GuideRuntimeDoctests;

/// The user guide's gallery, compiled and run as doctests.
#[doc = include_str!("../docs/guide/gallery.md")]
#[cfg(doctest)]
pub struct GuideGalleryDoctests;

/// The user guide's performance page, compiled and run as doctests.
#[doc = include_str!("../docs/guide/performance.md")]
#[cfg(doctest)]
pub struct GuidePerformanceDoctests;

/// The user guide's index, compiled and run as doctests.
#[doc = include_str!("../docs/guide/README.md")]
#[cfg(doctest)]
pub struct GuideIndexDoctests;
