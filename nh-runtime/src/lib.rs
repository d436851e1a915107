//! Runtime for generated nonholonomic systems: ODE traits, integrators and
//! their outcomes.
//!
//! The `nonholonomic_system!` macro emits types implementing [`OdeSystem`]
//! (and, with inputs, [`ControlledSystem`]); this crate integrates them.
//!
//! * Systems: [`OdeSystem`], [`OdeJacobian`], [`ControlledSystem`],
//!   [`ControlledJacobian`] and the [`Driven`] adapter (a controlled system
//!   with a held input, with its Jacobian at that input). Closures
//!   `Fn(T, &SVector<T, D>) -> SVector<T, D>` are `OdeSystem`s too.
//! * Forward sensitivities: [`ParameterJacobian`] (`∂f/∂p` and the
//!   variational equations) and [`Sensitivities`], the system augmented
//!   with `∂x/∂p` and `∂x/∂x0`, which any integrator integrates.
//! * States from velocities: [`ConstraintViolation`] (velocities that break
//!   the constraints) and [`speeds_from_velocities`], behind the generated
//!   `state_from_velocities`.
//! * Integrators ([`Integrator`]), each named for the published method or
//!   code it implements, with its order (the former names `DormandPrince`
//!   and `Rosenbrock` remain as deprecated aliases of [`Dopri5`] and
//!   [`Rodas4`]):
//!   * [`Rk4`]: classical Runge–Kutta, fixed step (order 4);
//!   * [`Dopri5`]: adaptive 5(4), after Hairer's `DOPRI5`;
//!   * [`Dop853`]: adaptive 8(5,3), after Hairer's `DOP853`;
//!   * [`Rodas4`]: RODAS4, adaptive, L-stable, linearly implicit
//!     (order 4), for stiff problems;
//!   * [`Rodas5P`]: Steinebach's Rodas5P, the same kind of method of order
//!     5, for stiff problems at tight tolerances;
//!   * [`Bdf`]: variable-order (1–5) NDF/BDF multistep method in the form of
//!     MATLAB's `ode15s`, implicit, for stiff problems at moderate tolerances;
//!   * [`GaussLegendre4`]: 2-stage Gauss–Legendre collocation, fixed step,
//!     implicit, symplectic (order 4);
//!   * [`AutoSwitch`]: [`Dopri5`] while the problem is not stiff,
//!     RODAS4 while it is, switching automatically both ways.
//!
//!   Which to use: [`Dopri5`] for everyday non-stiff problems at
//!   moderate tolerances, [`Dop853`] when tolerances are tight, [`Rodas4`]
//!   when the problem is stiff (explicit methods crawl, or `Dopri5`
//!   reports [`Stats::stiffness_detected`]), [`Bdf`] when it is stiff and
//!   right-hand sides are what costs (it needs about one per step, against
//!   six for [`Rodas4`]), [`Rodas5P`] when it is stiff and
//!   the tolerance tight (below about `1e-7`), [`AutoSwitch`] when it is
//!   stiff only at times or you do not know, and [`GaussLegendre4`] for long
//!   runs of conservative (Hamiltonian) systems, where it keeps the energy
//!   error bounded; [`Rk4`] when a fixed, cheap, explicit step is wanted
//!   (e.g. real-time loops).
//! * Every accepted step comes with a continuous extension ([`Step`]):
//!   [`Integrator::integrate_with_steps`] hands it out, and
//!   [`Integrator::integrate_with_outputs`] samples the solution at
//!   requested times without changing the steps.
//! * Events ([`Events`]): the sign changes of functions `g(t, x)`, located
//!   on the dense output, filtered by [`Direction`], terminal or not,
//!   reported as [`EventHit`]s by [`Integrator::integrate_with_events`].
//! * Results: [`Outcome`] with [`Stats`], or a [`SimError`] that carries the
//!   last good state.
//! * Charts: a system whose atlas has several charts
//!   ([`OdeSystem::charts`]: the same positions, other velocities as state)
//!   is integrated over them, each integrator moving to a better chart
//!   where the current one degrades and handing everything back in chart
//!   0's layout; the switches are recorded in [`Outcome::switches`]
//!   ([`ChartSwitches`]).
//! * Many runs: [`Ensemble`] runs a job per index of a parameter or
//!   initial-state sweep and returns the results in index order,
//!   sequentially or (feature `rayon`) on all cores with identical results;
//!   [`Shard`] cuts a sweep into contiguous index ranges for a batch
//!   scheduler's job array (feature `std`).
//! * One step driver runs every integrator: a method supplies only its
//!   stages, error estimate and dense output; acceptance, step-size control
//!   (Hairer's PI controller, or a fixed step for [`Rk4`],
//!   [`GaussLegendre4`] and `with_fixed_step`), step budgets (100 000
//!   attempts for the adaptive methods, 1 000 000 steps for the fixed-step
//!   ones, both `with_max_steps`), stiffness detection, observers, output
//!   times and the typed failures are the same for all of them.
//!
//! # Tolerances and the error norm
//!
//! The adaptive integrators ([`Dopri5`], [`Dop853`], [`Rodas4`],
//! [`Rodas5P`], [`Bdf`], [`AutoSwitch`])
//! take a relative tolerance `rtol` (> 0) and an absolute tolerance `atol`
//! (≥ 0): one pair for every component with `new(rtol, atol)`
//! ([`ScalarTolerance`]), or one pair per component with
//! `with_tolerances(rtol, atol)` (vectors of the state's dimension,
//! [`PerComponentTolerance`]). A positive `rtol_i` below `10·eps` is raised
//! to `10·eps`. A step from `x` to `x_new` with local error estimate `err`
//! (its solution minus the embedded one) is accepted when Hairer's
//! root-mean-square norm
//!
//! ```text
//! ‖err‖ = sqrt( (1/D) · Σ_i (err_i / sk_i)² ),   sk_i = atol_i + rtol_i · max(|x_i|, |x_new_i|)
//! ```
//!
//! is at most 1 (a component whose error is exactly zero counts as zero,
//! also with `sk_i = 0`). [`Dop853`] weighs its two estimators (orders 5
//! and 3) with the same `sk_i`, as Hairer's `DOP853` does. Being an
//! average, the norm lets one component's error exceed its `sk_i` by up to
//! `√D` in a step; give a component that must be held tighter a smaller
//! tolerance. Since `sk_i` is the error allowed per step, the global error
//! is typically a small multiple of it.
//!
//! ```rust
//! use nalgebra::Vector2;
//! use nh_runtime::{Dop853, Integrator};
//!
//! // A position in metres (≈ 1e3) and a small angle in radians (≈ 1e-4).
//! let sys = |_t: f64, x: &Vector2<f64>| Vector2::new(-0.5 * x[0], -2.0 * x[1]);
//! let mut dop = Dop853::new(1e-9, 0.0)
//!     .with_tolerances(Vector2::new(1e-9, 1e-9), Vector2::new(1e-6, 1e-15));
//! let out = dop.integrate(&sys, 0.0, Vector2::new(1e3, 1e-4), 3.0).unwrap();
//! assert!((out.x[0] - 1e3 * (-1.5f64).exp()).abs() < 1e-5);
//! assert!((out.x[1] - 1e-4 * (-6.0f64).exp()).abs() < 1e-14);
//! ```
//!
//! Everything is generic over `T: nalgebra::RealField + Copy` (`f64`, `f32`,
//! ...) and works on stack-allocated `SVector`s; no integrator allocates per
//! step, and only [`GaussLegendre4`] allocates at all (its `D×D` Newton
//! workspace, once per call). Without the default `std` feature the crate
//! is `#![no_std]`; the `alloc` feature (implied by `std`) enables
//! [`GaussLegendre4`].
//!
//! # Example
//!
//! ```rust
//! use nalgebra::Vector2;
//! use nh_runtime::{Dopri5, Integrator, OdeSystem};
//!
//! /// A pendulum `θ'' = -sin θ` as `(θ, ω)`.
//! struct Pendulum;
//!
//! impl OdeSystem<f64, 2> for Pendulum {
//!     fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
//!         Vector2::new(x[1], -x[0].sin())
//!     }
//! }
//!
//! let energy = |x: &Vector2<f64>| 0.5 * x[1] * x[1] - x[0].cos();
//! let x0 = Vector2::new(1.0, 0.0);
//! let out = Dopri5::new(1e-10, 1e-12)
//!     .integrate(&Pendulum, 0.0, x0, 20.0)
//!     .expect("pendulum integrates");
//! assert_eq!(out.t, 20.0);
//! assert!((energy(&out.x) - energy(&x0)).abs() < 1e-8);
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

#[cfg(feature = "alloc")]
extern crate alloc;

mod auto_switch;
mod bdf;
mod charts;
mod checks;
mod conservation;
mod crossing;
mod dop853;
mod dopri5;
mod driver;
#[cfg(feature = "std")]
mod ensemble;
mod euler;
mod events;
#[cfg(feature = "alloc")]
mod gauss_legendre4;
mod jacobian;
mod lanes;
mod lie;
mod linalg;
mod method;
mod numeric;
mod outcome;
mod rk4;
mod rodas4;
mod rodas5p;
mod rodas_tableau;
mod rosenbrock;
mod sensitivity;
mod settings;
mod sink;
mod state;
mod step;
mod step_size;
mod system;
mod tolerance;

pub use auto_switch::{AutoSwitch, Regime, Switch};
pub use bdf::Bdf;
pub use conservation::Conservation;
pub use crossing::{Direction, EventHit};
pub use dop853::Dop853;
pub use dopri5::Dopri5;
#[cfg(feature = "std")]
pub use ensemble::{Ensemble, Shard, ShardError};
pub use euler::{EulerSequence, FreeRotation};
pub use events::Events;
#[cfg(feature = "alloc")]
pub use gauss_legendre4::GaussLegendre4;
pub use lanes::{LaneControlledSystem, LaneOutcome, LaneSystem, Lanes, WideF64x4};
pub use outcome::{ChartSwitch, ChartSwitches, Outcome, SimError, Singularity, Stats};
pub use rk4::Rk4;
pub use rodas4::Rodas4;
pub use rodas5p::Rodas5P;
pub use sensitivity::{ParameterJacobian, Sensitivities};
pub use state::{
    ConstraintViolation, KnownVelocitiesError, speeds_from_velocities, velocities_from_known,
};
pub use step::Step;
pub use system::{
    ControlledJacobian, ControlledSystem, Driven, Integrator, OdeJacobian, OdeSystem,
    ProjectionFailure,
};
pub use tolerance::{ErrorTolerance, PerComponentTolerance, ScalarTolerance};

// The former names of the integrators, from before they were named for the
// method each implements.

/// The former name of [`Dopri5`], kept so that code written for 0.1
/// compiles: `DormandPrince::new(rtol, atol)`, `DormandPrince::<f64>` and
/// the builders are those of [`Dopri5`], with the same steps and results.
#[deprecated(
    since = "0.2.0",
    note = "renamed `Dopri5`: integrators are named for their method"
)]
pub type DormandPrince<T, Tol = ScalarTolerance<T>> = Dopri5<T, Tol>;

/// The former name of [`Rodas4`], kept so that code written for 0.1
/// compiles: `Rosenbrock::new(rtol, atol)`, `Rosenbrock::<f64>`, the
/// builders and `integrate_with_jacobian` are those of [`Rodas4`], with the
/// same steps and results.
#[deprecated(
    since = "0.2.0",
    note = "renamed `Rodas4`: integrators are named for their method"
)]
pub type Rosenbrock<T, Tol = ScalarTolerance<T>> = Rodas4<T, Tol>;
