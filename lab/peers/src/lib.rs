//! # nh-peers: the side-by-side at equal error
//!
//! The runtime's integrators against the Rust peers — `ode_solvers`
//! (Dopri5, Dop853, Rk4), `diffsol` (bdf, esdirk34, tr_bdf2, tsit45) and
//! `russell_ode` (Radau5, DoPri5, DoPri8) — and against the physical limit,
//! on three problems: the thesis's disc, the physically correct rolling disc
//! and the stiff disc (k = 1e6). Every method integrates the same generated
//! right-hand side (and, where it takes one, the same generated Jacobian).
//!
//! ```text
//! cargo run --release --manifest-path lab/peers/Cargo.toml
//! cargo run --release --manifest-path lab/peers/Cargo.toml -- --problems stiff_disc --methods bdf,Rodas4
//! ```
//!
//! For each problem each method runs over a ladder (relative tolerances
//! 1e-3 … 1e-13 in half decades, absolute = 1e-2 × relative; step sizes for
//! the fixed-step methods), its error measured against one reference final
//! state (our Dop853 at rtol 1e-14, checked against ode_solvers' Dop853 and a
//! second method: see [`problems`]). Times are CPU times of the measuring
//! thread (every method runs on one thread), medians of repeated runs
//! ([`measure::median_time`]). At each target error (1e-6, 1e-8, 1e-10) a method's time is read
//! off its ladder (log time interpolated linearly in log error between the
//! two runs that bracket the target, the best such pair); a suite's best is
//! its fastest method there. The physical limit is the fewest right-hand
//! sides any method needed for that error (read off the same way) times the
//! measured cost of one call. A method's own work per step is its time
//! per step less its right-hand sides and Jacobians at their measured costs.
//!
//! Adding one of our integrators to the comparison is one entry in
//! [`methods::our_methods`].
//!
//! Prints Markdown tables; writes `target/reports/peers.csv` and
//! `target/reports/peers_<problem>.svg` (the copies in `docs/` are from a
//! run of this program).
//!
//! This crate is not a member of the main workspace: the peers are not
//! compiled by the workspace's tests.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod analysis;
pub mod measure;
pub mod methods;
pub mod output;
pub mod problems;
