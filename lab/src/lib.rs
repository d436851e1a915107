//! # nh-lab
//!
//! The project's test lab, kept out of the published `nonholonomic` crate:
//! everything here is written against the facade's public API exactly as a
//! user's crate would be.
//!
//! * [`systems`] — the ready-made scenes (the thesis's rolling disc, the
//!   physically correct thin disc, a stiff disc, the Chaplygin sled, the
//!   knife edge on an incline) used by the examples, tests and benchmarks.
//! * [`scenes`] — scenes with an independent reference (the stiff disc's
//!   state at its end, from SymPy and mpmath), for the tests and reports.
//! * [`stability`] — the stability suite: named cases with explicit expected
//!   outcomes (`tests/stability.rs` asserts every row;
//!   `cargo run --release -p nh-lab --example stability_report` prints them).
//! * [`report`] — work–precision reports: CSV, Markdown and log–log SVG
//!   charts (`cargo run --release -p nh-lab --example work_precision`), and
//!   a progress bar for the long runs.
//!
//! The benchmarks live in `benches/`: `routes` (per-call times of both
//! derivation routes) and `accelerations` (generated against hand-written
//! code, interleaved in one run).
//!
//! The side-by-side against other Rust ODE solvers (ode_solvers, diffsol,
//! russell_ode) at equal error, and against the physical limit, is the
//! separate unpublished crate `lab/peers` (`nh-peers`), kept outside the
//! workspace so that its dependencies are never compiled by the workspace's
//! builds and tests:
//!
//! ```text
//! cargo run --release --manifest-path lab/peers/Cargo.toml
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod report;
pub mod scenes;
pub mod stability;
pub mod systems;
