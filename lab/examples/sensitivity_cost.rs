//! Cost of the forward sensitivities, in right-hand sides: the time of one
//! call of the augmented right-hand side (`Sensitivities::rhs`, the state
//! with ∂x/∂p and ∂x/∂x0) against one call of the plain right-hand side, per
//! sensitivity (column of [∂x/∂p | ∂x/∂x0]); for the generated
//! `variational_rhs` (one CSE'd graph, structural zeros of ∂f/∂x pruned) and
//! for the trait's default (the generated `jacobian` and
//! `parameter_jacobian`, multiplied densely).
//!
//! ```text
//! cargo run --release -p nh-lab --example sensitivity_cost
//! ```
//!
//! Prints a Markdown table. Wall-clock figures: run it on a quiet machine
//! (each the fastest of 15 rounds).
use nh_lab::systems::{RollingDisc, ThesisDisc};
use nonholonomic::prelude::*;
use std::hint::black_box;
use std::time::Instant;

nonholonomic_system! {
    /// The Chaplygin sled (`nh_lab::systems::ChaplyginSled`) with its
    /// constraint written implicitly, the form these figures were measured on.
    pub struct ChaplyginSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
            + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; }
        outputs { sensitivities }
    }
}

/// The same system through the trait's default `variational_rhs`: the
/// generated Jacobians multiplied densely.
struct Dense<'a, S>(&'a S);

impl<S: OdeSystem<f64, D>, const D: usize> OdeSystem<f64, D> for Dense<'_, S> {
    fn rhs(&self, t: f64, x: &SVector<f64, D>) -> SVector<f64, D> {
        self.0.rhs(t, x)
    }
}

impl<S: OdeJacobian<f64, D>, const D: usize> OdeJacobian<f64, D> for Dense<'_, S> {
    fn jacobian(&self, t: f64, x: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.0.jacobian(t, x)
    }
}

impl<S: ParameterJacobian<f64, D, P>, const D: usize, const P: usize> ParameterJacobian<f64, D, P>
    for Dense<'_, S>
{
    fn parameter_jacobian(&self, t: f64, x: &SVector<f64, D>) -> SMatrix<f64, D, P> {
        self.0.parameter_jacobian(t, x)
    }
}

/// Nanoseconds per call of `f` over the states `xs`: the fastest of 15
/// rounds (the least disturbed by other work on the machine).
fn ns_per_call<const A: usize>(
    xs: &[SVector<f64, A>],
    f: impl Fn(&SVector<f64, A>) -> SVector<f64, A>,
) -> f64 {
    let rounds = 15;
    let reps = (2_000_000 / (A * xs.len())).max(10);
    let mut times: Vec<f64> = (0..rounds)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..reps {
                for x in xs {
                    black_box(f(black_box(x)));
                }
            }
            start.elapsed().as_nanos() as f64 / (reps * xs.len()) as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[0]
}

/// Augmented states around `x`: the state perturbed, random sensitivities.
fn states<S, const D: usize, const P: usize, const A: usize>(
    sens: &Sensitivities<'_, S, D, P, A>,
    x: SVector<f64, D>,
) -> Vec<SVector<f64, A>> {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..16)
        .map(|_| {
            let xi = x.map(|v| v + 0.1 * uniform());
            let mut a = sens.initial_state(&xi);
            for v in a.iter_mut().skip(D) {
                *v += uniform();
            }
            a
        })
        .collect()
}

/// One row of the table.
fn row<S, const D: usize, const P: usize, const A: usize>(name: &str, sys: &S, x: SVector<f64, D>)
where
    S: ParameterJacobian<f64, D, P>,
{
    let sens = Sensitivities::<_, D, P, A>::new(sys);
    let dense_sys = Dense(sys);
    let dense = Sensitivities::<_, D, P, A>::new(&dense_sys);
    let xs = states(&sens, x);
    let plain: Vec<SVector<f64, D>> = xs.iter().map(|a| sens.split(a).0).collect();
    let t_rhs = ns_per_call(&plain, |x| sys.rhs(0.0, x));
    let t_aug = ns_per_call(&xs, |a| sens.rhs(0.0, a));
    let t_dense = ns_per_call(&xs, |a| dense.rhs(0.0, a));
    let columns = (P + D) as f64;
    let per = |t: f64| (t - t_rhs) / t_rhs / columns;
    println!(
        "| {name} | {D} | {P} | {} | {t_rhs:.1} | {t_aug:.1} | {:.2} | {t_dense:.1} | {:.2} |",
        P + D,
        per(t_aug),
        per(t_dense)
    );
}

fn main() {
    println!(
        "| system | D | P | sensitivities | rhs (ns) | augmented rhs, generated (ns) | extra rhs per sensitivity | augmented rhs, dense (ns) | extra rhs per sensitivity |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let disc_x = SVector::from([0.1, 0.2, 0.3, 0.4, 0.5, 6.0, 20.0, 0.5]);
    row::<_, 8, 3, { 8 * 12 }>("thesis disc", &ThesisDisc::new(1.7, 0.35, 9.81), disc_x);
    row::<_, 8, 3, { 8 * 12 }>("rolling disc", &RollingDisc::new(1.7, 0.35, 9.81), disc_x);
    let sled_x = SVector::from([0.1, 0.4, 0.2, 0.5, 0.9]);
    row::<_, 5, 3, { 5 * 9 }>("Chaplygin sled", &ChaplyginSled::new(2.0, 0.3, 0.5), sled_x);
}
