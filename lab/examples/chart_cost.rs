//! What the atlas costs a run that never switches (DESIGN §6.7): the
//! Whipple bicycle at 5 m/s with a small roll perturbation (self-stable, its
//! own chart regular throughout), 14 s by DOP853 at rtol 1e-11, integrated
//! as generated (four charts: the run goes through the atlas's segments)
//! and behind a wrapper that shows the runtime one chart (today's path,
//! bit for bit). Both take the same steps; the times are medians of
//! alternating runs. Then the slow bicycle (1 m/s), which switches charts
//! on its way to the ground: its steps, rejections, right-hand sides and
//! switches.
//!
//! ```text
//! cargo run --release -p nh-lab --example chart_cost
//! ```
use nonholonomic::prelude::*;
use std::hint::black_box;
use std::time::Instant;

#[path = "../../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)]
mod model;

/// The bicycle with one chart: every hook but the atlas forwarded.
struct OneChart<'a>(&'a model::Whipple);

impl OdeSystem<f64, 11> for OneChart<'_> {
    #[inline]
    fn rhs(&self, t: f64, x: &SVector<f64, 11>) -> SVector<f64, 11> {
        self.0.rhs(t, x)
    }
    #[inline]
    fn chart_regularity(&self, t: f64, x: &SVector<f64, 11>) -> Option<f64> {
        self.0.chart_regularity(t, x)
    }
    #[inline]
    fn crossed_pole(
        &self,
        t0: f64,
        x0: &SVector<f64, 11>,
        t1: f64,
        x1: &SVector<f64, 11>,
    ) -> Option<&'static str> {
        self.0.crossed_pole(t0, x0, t1, x1)
    }
    #[inline]
    fn constraint_residual(&self, t: f64, x: &SVector<f64, 11>) -> Option<f64> {
        self.0.constraint_residual(t, x)
    }
    #[inline]
    fn project(
        &self,
        t: f64,
        x: &mut SVector<f64, 11>,
    ) -> Result<bool, nonholonomic::runtime::ProjectionFailure<f64>> {
        self.0.project(t, x)
    }
    #[inline]
    fn is_autonomous(&self) -> bool {
        self.0.is_autonomous()
    }
}

fn riding(b: &model::Whipple, v: f64, p: f64) -> SVector<f64, 11> {
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = p;
    x0[10] = v / b.rR;
    x0
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let b = model::benchmark();
    let x0 = riding(&b, 5.0, 0.005);
    let (mut atlas, mut one) = (Vec::new(), Vec::new());
    let mut steps = (0, 0);
    for _ in 0..31 {
        let start = Instant::now();
        let out = Dop853::new(1e-11, 1e-13)
            .integrate(&b, 0.0, black_box(x0), 14.0)
            .expect("self-stable");
        atlas.push(start.elapsed().as_secs_f64());
        steps.0 = out.stats.steps;
        assert_eq!(out.stats.chart_switches, 0);
        let start = Instant::now();
        let out1 = Dop853::new(1e-11, 1e-13)
            .integrate(&OneChart(&b), 0.0, black_box(x0), 14.0)
            .expect("self-stable");
        one.push(start.elapsed().as_secs_f64());
        steps.1 = out1.stats.steps;
        assert_eq!(out.x, out1.x, "the same run");
    }
    let (ta, t1) = (median(atlas), median(one));
    println!(
        "bicycle at 5 m/s, 14 s, DOP853 rtol 1e-11: {} steps with the atlas, {} with one chart; {:.3} ms against {:.3} ms (ratio {:.3}, medians of 31)",
        steps.0,
        steps.1,
        ta * 1e3,
        t1 * 1e3,
        ta / t1
    );
    // the slow bicycle, which switches on its way down
    let slow = riding(&b, 1.0, 0.5);
    let mut dop = Dop853::new(1e-11, 1e-13);
    let out = dop.integrate(&b, 0.0, slow, 1.04);
    let out = out.expect("through the chart's singularity");
    println!(
        "bicycle at 1 m/s to t = 1.04: {} switches, {} steps, {} rejected, {} right-hand sides",
        out.stats.chart_switches, out.stats.steps, out.stats.rejected, out.stats.rhs_evals
    );
    for s in out.switches.iter() {
        println!("  t = {:.6}: chart {} -> {}", s.t, s.from, s.to);
    }
}
