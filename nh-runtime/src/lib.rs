//! Runtime for generated nonholonomic systems: ODE traits, integrators and
//! their outcomes.
//!
//! The `nonholonomic_system!` macro emits types implementing [`OdeSystem`]
//! (and, with inputs, [`ControlledSystem`]); this crate integrates them.
//!
//! * Systems: [`OdeSystem`], [`OdeJacobian`], [`ControlledSystem`] and the
//!   [`Driven`] adapter (a controlled system with a held input). Closures
//!   `Fn(T, &SVector<T, D>) -> SVector<T, D>` are `OdeSystem`s too.
//! * Integrators ([`Integrator`]): [`Rk4`] (classical, fixed step) and
//!   [`DormandPrince`] (adaptive 5(4), after Hairer's `DOPRI5`).
//! * Results: [`Outcome`] with [`Stats`], or a [`SimError`] that carries the
//!   last good state.
//!
//! Everything is generic over `T: nalgebra::RealField + Copy` (`f64`, `f32`,
//! ...), works on stack-allocated `SVector`s and never allocates on the
//! heap. Without the default `std` feature the crate is `#![no_std]`.
//!
//! # Example
//!
//! ```rust
//! use nalgebra::Vector2;
//! use nh_runtime::{DormandPrince, Integrator, OdeSystem};
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
//! let out = DormandPrince::new(1e-10, 1e-12)
//!     .integrate(&Pendulum, 0.0, x0, 20.0)
//!     .expect("pendulum integrates");
//! assert_eq!(out.t, 20.0);
//! assert!((energy(&out.x) - energy(&x0)).abs() < 1e-8);
//! ```
#![cfg_attr(not(feature = "std"), no_std)]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod common;
mod dopri5;
mod outcome;
mod rk4;
mod system;

pub use dopri5::DormandPrince;
pub use outcome::{Outcome, SimError, Stats};
pub use rk4::Rk4;
pub use system::{ControlledSystem, Driven, Integrator, OdeJacobian, OdeSystem};
