//! The integrators' own work per step, beside the right-hand side and the
//! Jacobian: runs one method on one of the lab's discs (the scenes of the
//! side-by-side in `lab/peers`) at a fixed tolerance, through a wrapper
//! whose `rhs` and `jacobian` are never inlined, so that an instruction
//! profiler can tell the system's work from the method's.
//!
//! ```text
//! cargo build --release -p nh-lab --example step_overhead
//! valgrind --tool=callgrind --toggle-collect='step_overhead::integrate_*' \
//!     target/release/examples/step_overhead dop853 thesis 1e-8
//! callgrind_annotate --inclusive=yes callgrind.out.<pid> | grep -E 'PROGRAM|Timed'
//! ```
//!
//! Own work per attempt = (instructions of `integrate_*` − inclusive
//! instructions of `Timed::rhs` and `Timed::jacobian`) / (steps + rejected).
//!
//! Arguments: method (`dopri5`, `dop853`, `rodas4`, `rodas5p`), problem
//! (`thesis`, `rolling`, `stiff`), rtol (atol = 0.01·rtol, as in the
//! side-by-side), and optionally the number of repeated runs (default 1).
//! With the suffix `-inlined` on the method the system's functions are
//! inlined, as in the side-by-side's runs; its own work is its instructions
//! less those the never-inlined run counts in `Timed::rhs` and
//! `Timed::jacobian` (the same states, the same calls). Prints the run's
//! statistics and final state (to check that a change to the runtime leaves
//! the step sequence as it was) and, with repeated runs, the fastest run's
//! wall time and the fastest time of one right-hand side at states along
//! the motion (rough figures on a shared machine).
use nh_lab::systems::{RollingDisc, StiffDisc, ThesisDisc};
use nonholonomic::prelude::*;
use std::hint::black_box;

/// A system whose right-hand side and Jacobian are separate functions in a
/// profile (never inlined into the method).
struct Timed<'a, S>(&'a S);

/// The same system with its right-hand side and Jacobian inlined, as in
/// the side-by-side's runs.
struct Inlined<'a, S>(&'a S);

macro_rules! wrapper {
    ($name:ident, $inline:meta) => {
        impl<S: OdeSystem<f64, 8>> OdeSystem<f64, 8> for $name<'_, S> {
            #[$inline]
            fn rhs(&self, t: f64, x: &SVector<f64, 8>) -> SVector<f64, 8> {
                self.0.rhs(t, x)
            }
            fn is_autonomous(&self) -> bool {
                self.0.is_autonomous()
            }
        }

        impl<S: OdeJacobian<f64, 8>> OdeJacobian<f64, 8> for $name<'_, S> {
            #[$inline]
            fn jacobian(&self, t: f64, x: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
                self.0.jacobian(t, x)
            }
        }
    };
}

wrapper!(Timed, inline(never));
wrapper!(Inlined, inline);

type Run = Result<Outcome<f64, 8>, SimError<f64, 8>>;

#[inline(never)]
fn integrate_dopri5<S: OdeSystem<f64, 8>>(s: &S, x0: SVector<f64, 8>, t1: f64, rtol: f64) -> Run {
    Dopri5::new(rtol, 0.01 * rtol)
        .with_max_steps(1_000_000)
        .integrate(s, 0.0, x0, t1)
}

#[inline(never)]
fn integrate_dop853<S: OdeSystem<f64, 8>>(s: &S, x0: SVector<f64, 8>, t1: f64, rtol: f64) -> Run {
    Dop853::new(rtol, 0.01 * rtol)
        .with_max_steps(1_000_000)
        .integrate(s, 0.0, x0, t1)
}

#[inline(never)]
fn integrate_rodas4<S: OdeJacobian<f64, 8>>(s: &S, x0: SVector<f64, 8>, t1: f64, rtol: f64) -> Run {
    Rodas4::new(rtol, 0.01 * rtol)
        .with_max_steps(1_000_000)
        .integrate_with_jacobian(s, 0.0, x0, t1)
}

#[inline(never)]
fn integrate_rodas5p<S: OdeJacobian<f64, 8>>(
    s: &S,
    x0: SVector<f64, 8>,
    t1: f64,
    rtol: f64,
) -> Run {
    Rodas5P::new(rtol, 0.01 * rtol)
        .with_max_steps(1_000_000)
        .integrate_with_jacobian(s, 0.0, x0, t1)
}

/// The initial state `[q; ṙ]` of the discs.
fn state(q: [f64; 5], rdot: [f64; 3]) -> SVector<f64, 8> {
    SVector::<f64, 8>::from_fn(|i, _| if i < 5 { q[i] } else { rdot[i - 5] })
}

/// Runs `method` (`-inlined`: with the system's functions inlined)
/// `repeats` times on `sys` and prints the last outcome.
fn run<S: OdeJacobian<f64, 8>>(
    sys: &S,
    x0: SVector<f64, 8>,
    t1: f64,
    method: &str,
    rtol: f64,
    repeats: usize,
) {
    let (name, inlined) = match method.strip_suffix("-inlined") {
        Some(name) => (name, true),
        None => (method, false),
    };
    if inlined {
        let f = match name {
            "dopri5" => integrate_dopri5::<Inlined<S>>,
            "dop853" => integrate_dop853::<Inlined<S>>,
            "rodas4" => integrate_rodas4::<Inlined<S>>,
            "rodas5p" => integrate_rodas5p::<Inlined<S>>,
            other => panic!("unknown method {other}"),
        };
        repeat(
            || f(black_box(&Inlined(sys)), black_box(x0), t1, rtol),
            method,
            rtol,
            repeats,
        );
    } else {
        let f = match name {
            "dopri5" => integrate_dopri5::<Timed<S>>,
            "dop853" => integrate_dop853::<Timed<S>>,
            "rodas4" => integrate_rodas4::<Timed<S>>,
            "rodas5p" => integrate_rodas5p::<Timed<S>>,
            other => panic!("unknown method {other}"),
        };
        repeat(
            || f(black_box(&Timed(sys)), black_box(x0), t1, rtol),
            method,
            rtol,
            repeats,
        );
    }
    if repeats > 1 {
        let states = states_along(sys, x0, t1);
        let rhs = rhs_seconds(&Inlined(sys), &states);
        let chained = chained_rhs_seconds(&Inlined(sys), &states);
        println!(
            "fastest RHS {:.1} ns per call, {:.1} ns per call in a chain of dependent calls",
            rhs * 1e9,
            chained * 1e9
        );
    }
}

/// The fastest of 50 batches of calls of `sys.rhs` at `states`, per call
/// (seconds).
fn rhs_seconds<S: OdeSystem<f64, 8>>(sys: &S, states: &[(f64, SVector<f64, 8>)]) -> f64 {
    let calls = 100 * states.len();
    (0..50)
        .map(|_| {
            let start = std::time::Instant::now();
            for _ in 0..100 {
                for (t, x) in states {
                    black_box(sys.rhs(black_box(*t), black_box(x)));
                }
            }
            start.elapsed().as_secs_f64() / calls as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// The fastest of 50 chains of calls of `sys.rhs`, per call (seconds): each
/// call's argument depends on the previous call's result (`x + 1e-9·f`, as
/// a Runge–Kutta stage depends on the one before), so that the calls cannot
/// overlap as the independent calls of [`rhs_seconds`] can.
fn chained_rhs_seconds<S: OdeSystem<f64, 8>>(sys: &S, states: &[(f64, SVector<f64, 8>)]) -> f64 {
    let calls = 100 * states.len();
    (0..50)
        .map(|_| {
            let start = std::time::Instant::now();
            for (t, x) in states {
                let mut y = *x;
                for _ in 0..100 {
                    y += sys.rhs(*t, &y) * 1e-9;
                }
                black_box(y);
            }
            start.elapsed().as_secs_f64() / calls as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// States along the motion from `x0` (Dop853, rtol 1e-8) at 20 times in
/// `(0, t1]`.
fn states_along<S: OdeSystem<f64, 8>>(
    sys: &S,
    x0: SVector<f64, 8>,
    t1: f64,
) -> Vec<(f64, SVector<f64, 8>)> {
    (1..=20)
        .map(|k| {
            let t = t1 * k as f64 / 20.0;
            let out = Dop853::new(1e-8, 1e-10)
                .integrate(sys, 0.0, x0, t)
                .expect("the reference motion");
            (t, out.x)
        })
        .collect()
}

/// Runs `f` `repeats` times and prints the last outcome.
fn repeat(f: impl Fn() -> Run, method: &str, rtol: f64, repeats: usize) {
    let mut last = None;
    let mut seconds = f64::INFINITY;
    for _ in 0..repeats {
        let start = std::time::Instant::now();
        last = Some(f());
        seconds = seconds.min(start.elapsed().as_secs_f64());
    }
    let out = last.expect("at least one run").expect("the run succeeds");
    let s = out.stats;
    println!(
        "{method} rtol {rtol:e}: steps {} rejected {} rhs {} jacobians {} (x {repeats} runs)",
        s.steps, s.rejected, s.rhs_evals, s.jacobian_evals
    );
    println!("x(t1) = {:?}", out.x.as_slice());
    println!(
        "fastest run {seconds:.3e} s, {:.1} ns per RHS evaluated (wall time: a rough figure on a shared machine)",
        seconds * 1e9 / s.rhs_evals as f64
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let method = args.get(1).map_or("dop853", String::as_str);
    let problem = args.get(2).map_or("thesis", String::as_str);
    let rtol: f64 = args.get(3).map_or(1e-8, |a| a.parse().expect("rtol"));
    let repeats: usize = args.get(4).map_or(1, |a| a.parse().expect("repeats"));
    let (m, r, g) = (1.7, 0.35, 9.81);
    match problem {
        "thesis" => {
            let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
            run(&ThesisDisc::new(m, r, g), x0, 5.0, method, rtol, repeats);
        }
        "rolling" => {
            let x0 = state([0.0, 0.0, 0.2, 0.0, 0.0], [15.0, 1.0, 0.3]);
            run(&RollingDisc::new(m, r, g), x0, 5.0, method, rtol, repeats);
        }
        "stiff" => {
            let k = 1e6;
            let inertia = 1.25 * m * r * r; // as in the side-by-side
            let c = 2.0 * (k * inertia).sqrt();
            let x0 = state([0.0, 0.0, 0.3, 0.0, 0.0], [6.0, 20.0, 0.5]);
            let sys = StiffDisc::new(m, r, g, k, c, 0.2);
            run(&sys, x0, 1.0, method, rtol, repeats);
        }
        other => panic!("unknown problem {other}"),
    }
}
