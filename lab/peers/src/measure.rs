//! Counting and timing: the wrapper every method integrates, the median
//! timer, the cost of one right-hand side and one Jacobian, and the state of
//! the machine.

use std::hint::black_box;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use cpu_time::ThreadTime;

use nonholonomic::prelude::*;

/// What a benchmarked system provides: the generated right-hand side and
/// Jacobian, shareable across threads (one peer asks for `Send + Sync`).
pub trait Sys<const D: usize>: OdeSystem<f64, D> + OdeJacobian<f64, D> + Sync {}
impl<S, const D: usize> Sys<D> for S where S: OdeSystem<f64, D> + OdeJacobian<f64, D> + Sync {}

/// The system every method integrates, ours and the peers' alike: it
/// forwards everything to the generated system and, while counting is on,
/// counts the calls of the right-hand side and of the Jacobian. Counting is
/// off in the timed runs (a predictable branch, the same for every method).
pub struct Counted<'a, S> {
    inner: &'a S,
    counting: AtomicBool,
    rhs: AtomicUsize,
    jacobian: AtomicUsize,
}

/// Calls counted in one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Calls {
    /// Right-hand sides.
    pub rhs: usize,
    /// Jacobians `∂f/∂x`.
    pub jacobian: usize,
}

impl<'a, S> Counted<'a, S> {
    /// The wrapper, not counting.
    pub fn new(inner: &'a S) -> Self {
        Self {
            inner,
            counting: AtomicBool::new(false),
            rhs: AtomicUsize::new(0),
            jacobian: AtomicUsize::new(0),
        }
    }

    /// Runs `f` with counting on and returns its result with the calls it made.
    ///
    /// ```
    /// use nh_peers::measure::Counted;
    /// use nonholonomic::prelude::*;
    ///
    /// let decay = |_t: f64, x: &SVector<f64, 1>| -x;
    /// let counted = Counted::new(&decay);
    /// let (out, calls) = counted.count(|| {
    ///     Rk4::new(0.25).integrate(&counted, 0.0, SVector::<f64, 1>::new(1.0), 1.0).unwrap()
    /// });
    /// assert_eq!((out.stats.rhs_evals, calls.rhs), (16, 16));
    /// ```
    pub fn count<R>(&self, f: impl FnOnce() -> R) -> (R, Calls) {
        self.rhs.store(0, Ordering::Relaxed);
        self.jacobian.store(0, Ordering::Relaxed);
        self.counting.store(true, Ordering::Relaxed);
        let r = f();
        self.counting.store(false, Ordering::Relaxed);
        let calls = Calls {
            rhs: self.rhs.load(Ordering::Relaxed),
            jacobian: self.jacobian.load(Ordering::Relaxed),
        };
        (r, calls)
    }

    #[inline]
    fn tick(&self, counter: &AtomicUsize) {
        if self.counting.load(Ordering::Relaxed) {
            counter.fetch_add(1, Ordering::Relaxed);
        }
    }
}

impl<S: OdeSystem<f64, D>, const D: usize> OdeSystem<f64, D> for Counted<'_, S> {
    #[inline]
    fn rhs(&self, t: f64, x: &SVector<f64, D>) -> SVector<f64, D> {
        self.tick(&self.rhs);
        self.inner.rhs(t, x)
    }
    #[inline]
    fn chart_regularity(&self, t: f64, x: &SVector<f64, D>) -> Option<f64> {
        self.inner.chart_regularity(t, x)
    }
    #[inline]
    fn crossed_pole(
        &self,
        t0: f64,
        x0: &SVector<f64, D>,
        t1: f64,
        x1: &SVector<f64, D>,
    ) -> Option<&'static str> {
        self.inner.crossed_pole(t0, x0, t1, x1)
    }
    #[inline]
    fn constraint_residual(&self, t: f64, x: &SVector<f64, D>) -> Option<f64> {
        self.inner.constraint_residual(t, x)
    }
    #[inline]
    fn project(&self, t: f64, x: &mut SVector<f64, D>) -> Result<bool, ProjectionFailure<f64>> {
        self.inner.project(t, x)
    }
    #[inline]
    fn is_autonomous(&self) -> bool {
        self.inner.is_autonomous()
    }
}

impl<S: OdeJacobian<f64, D>, const D: usize> OdeJacobian<f64, D> for Counted<'_, S> {
    #[inline]
    fn jacobian(&self, t: f64, x: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.tick(&self.jacobian);
        self.inner.jacobian(t, x)
    }
}

/// Timed repeats of one run: at least this many…
pub const MIN_REPEATS: usize = 5;
/// …and at least this much CPU time in all (short runs are repeated more)…
pub const MIN_SECONDS: f64 = 0.05;
/// …but never more than this many.
pub const MAX_REPEATS: usize = 200;

/// The time of one run: CPU time of the measuring thread (what the tables
/// report: on a shared machine it leaves out the time other processes had
/// the core) and wall time, both medians over the repeats, in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Median CPU time of this thread.
    pub cpu: f64,
    /// Median wall time.
    pub wall: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The median times of repeated calls of `f` and the last result: at least
/// [`MIN_REPEATS`] calls and [`MIN_SECONDS`] of CPU time in all (at most
/// [`MAX_REPEATS`] calls).
pub fn median_time<R>(mut f: impl FnMut() -> R) -> (Timing, R) {
    let (mut cpu, mut wall) = (Vec::new(), Vec::new());
    let mut total = 0.0;
    let mut last;
    loop {
        let (c0, w0) = (ThreadTime::now(), Instant::now());
        last = black_box(f());
        let (dc, dw) = (c0.elapsed().as_secs_f64(), w0.elapsed().as_secs_f64());
        cpu.push(dc);
        wall.push(dw);
        total += dc;
        if cpu.len() >= MAX_REPEATS || (cpu.len() >= MIN_REPEATS && total >= MIN_SECONDS) {
            break;
        }
    }
    let timing = Timing {
        cpu: median(cpu),
        wall: median(wall),
    };
    (timing, last)
}

/// CPU seconds per call of `f` over `states`, after 0.2 s of warm-up: the
/// median over 301 batches,
/// each batch 100 calls per state.
fn seconds_per_call<const D: usize, R>(
    states: &[(f64, SVector<f64, D>)],
    f: impl Fn(f64, &SVector<f64, D>) -> R,
) -> f64 {
    const PER_BATCH: usize = 100;
    let batch = || {
        for _ in 0..PER_BATCH {
            for (t, x) in states {
                black_box(f(black_box(*t), black_box(x)));
            }
        }
    };
    // warm up for 0.2 s of CPU time first: the first milliseconds of a
    // process (or after a sleep) can run at a lower clock, and one problem's
    // cost measured then made its limit 1.6 times too high
    let warm = ThreadTime::now();
    while warm.elapsed().as_secs_f64() < 0.2 {
        batch();
    }
    let times: Vec<f64> = (0..301)
        .map(|_| {
            let start = ThreadTime::now();
            batch();
            start.elapsed().as_secs_f64()
        })
        .collect();
    median(times) / (PER_BATCH * states.len().max(1)) as f64
}

/// The measured cost of one right-hand side of `sys` at the given states (seconds).
pub fn rhs_cost<S: Sys<D>, const D: usize>(sys: &S, states: &[(f64, SVector<f64, D>)]) -> f64 {
    seconds_per_call(states, |t, x| sys.rhs(t, x))
}

/// The measured cost of one Jacobian of `sys` at the given states (seconds).
pub fn jacobian_cost<S: Sys<D>, const D: usize>(sys: &S, states: &[(f64, SVector<f64, D>)]) -> f64 {
    seconds_per_call(states, |t, x| sys.jacobian(t, x))
}

/// The machine's state in one line: CPU, cores, load averages and the
/// number of running processes (from `/proc` where there is one).
pub fn machine_state() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let load = std::fs::read_to_string("/proc/loadavg")
        .map(|s| {
            let f: Vec<&str> = s.split_whitespace().collect();
            format!(
                "load average {} {} {} (1, 5, 15 min), running/total processes {}",
                f.first().unwrap_or(&"?"),
                f.get(1).unwrap_or(&"?"),
                f.get(2).unwrap_or(&"?"),
                f.get(3).unwrap_or(&"?")
            )
        })
        .unwrap_or_else(|_| "load unknown".into());
    format!("{cpu}, {cores} cores available, {load}")
}
