//! Differential verification of `nonholonomic_system!` (not published).
//!
//! Random well-formed systems in the language are expanded by the engine;
//! the code it generates is interpreted ([`interp`]) and compared with an
//! independent plain derivation of the same system: its Lagrangian's
//! Euler–Lagrange equations with the constraints adjoined by multipliers,
//! evaluated numerically with forward differentiation in double-double.
#![forbid(unsafe_code)]
// Index loops over matrices read like the formulas they implement.
#![allow(clippy::needless_range_loop)]

pub mod check;
pub mod generate;
pub mod interp;
pub mod jet;
pub mod linalg;
pub mod model;
pub mod plain;
pub mod run;
pub mod sample;
pub mod scalar;
pub mod shrink;

pub use scalar::Scalar;
