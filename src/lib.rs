//! # nonholonomic
//!
//! A mechanical system written as mathematics — parameters, coordinates, a
//! Lagrangian and velocity constraints linear in the velocities (rolling
//! without slipping, knife edges) — becomes specialised Rust at compile time.
//! [`nonholonomic_system!`] differentiates symbolically and emits
//! monomorphised code for the reduced equations of motion, the Lagrange
//! multipliers and the curvature of the constraint connection, following
//! Flygare (2012), sections 4–6, and Bloch, *Nonholonomic Mechanics and Control*.
//!
//! ```
//! use nonholonomic::prelude::*;
//!
//! nonholonomic_system! {
//!     /// A knife edge (Chaplygin sled) on a plane.
//!     pub struct Sled {
//!         parameters { m, J, a }
//!         coordinates { x, theta, y }
//!         lagrangian = J*dot(theta)^2/2
//!             + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
//!         constraints { dot(y) = tan(theta)*dot(x); }
//!     }
//! }
//!
//! let sled = Sled::new(2.0, 0.3, 0.5);
//! let x0 = SVector::<f64, 5>::from([0.0, 0.2, 0.0, 0.4, 0.9]); // [x, θ, y, ẋ, θ̇]
//! let out = DormandPrince::new(1e-10, 1e-12).integrate(&sled, 0.0, x0, 1.0).unwrap();
//! assert!(out.x.iter().all(|v| v.is_finite()));
//! ```
//!
//! The input language, the generated API and the conventions are described in
//! the repository's `DESIGN.md` and README.
#![forbid(unsafe_code)]
#![cfg_attr(not(feature = "std"), no_std)]

/// Derives the equations of motion of a mechanical system with linear
/// velocity constraints at compile time: `pub struct Name { parameters { .. }
/// coordinates { .. } lagrangian = ..; constraints { .. } }` becomes a struct
/// `Name<T = f64>` with one public field per parameter, and its methods
/// (`new`, `accelerations`, `dependent_velocities`, the requested outputs)
/// and runtime trait implementation. The input language and the generated
/// API are described in the README.
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

/// Everything a scene needs: the macro, the runtime traits and integrators,
/// and nalgebra's static vectors.
pub mod prelude {
    pub use crate::nonholonomic_system;
    pub use nalgebra::{SMatrix, SVector};
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
