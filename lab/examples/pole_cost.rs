//! The cost of the chart check on a run that never comes near the chart's
//! singularity: the lab's Chaplygin sled (the tan chart, `dot(y) =
//! tan(theta)*dot(x)`, cleared to an implicit row with an atlas of two
//! charts, DESIGN §9.3; before that, one pole guard cos θ, §9.2) from θ = 0
//! with a slowly decaying turn (θ stays below 1.1), integrated by
//! Dormand–Prince at rtol 1e-8, as generated and behind a wrapper that
//! hides its chart (one chart, no regularity, no pole check). Both runs
//! take the same steps; the difference of their instructions is the
//! check's.
//!
//! ```text
//! cargo build --release -p nh-lab --example pole_cost
//! valgrind --tool=callgrind target/release/examples/pole_cost guarded
//! valgrind --tool=callgrind target/release/examples/pole_cost hidden
//! ```
use nh_lab::systems::ChaplyginSled;
use nonholonomic::prelude::*;
use std::hint::black_box;

/// The sled without its pole check (the runtime's default).
struct Hidden<'a>(&'a ChaplyginSled);

impl OdeSystem<f64, 5> for Hidden<'_> {
    #[inline]
    fn rhs(&self, t: f64, x: &SVector<f64, 5>) -> SVector<f64, 5> {
        self.0.rhs(t, x)
    }
    #[inline]
    fn is_autonomous(&self) -> bool {
        true
    }
}

fn main() {
    let mode = std::env::args().nth(1).unwrap_or_else(|| "guarded".into());
    let sled = ChaplyginSled::new(1.0, 0.3, 0.4);
    let x0 = SVector::<f64, 5>::new(0.0, 0.0, 0.0, 1.0, 0.8);
    let mut dp = Dopri5::new(1e-8, 1e-10);
    let run = match mode.as_str() {
        "hidden" => dp.integrate(&Hidden(&sled), 0.0, black_box(x0), 20.0),
        _ => dp.integrate(&sled, 0.0, black_box(x0), 20.0),
    };
    let out = run.expect("no pole on the way");
    println!(
        "{mode}: {} steps, {} rejected, {} right-hand sides, theta(t1) = {:.6}",
        out.stats.steps, out.stats.rejected, out.stats.rhs_evals, out.x[1]
    );
}
