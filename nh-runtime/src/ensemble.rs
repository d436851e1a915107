//! Ensembles: many independent runs over a set of parameters or initial
//! states, in index order, sequentially or on all cores, and shards of a
//! sweep too large for one machine.

use std::fmt;
use std::ops::Range;
use std::str::FromStr;
use std::string::String;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::vec::Vec;

/// A set of independent runs, numbered by a contiguous range of indices,
/// executed by a job `Fn(usize) -> R` once per index.
///
/// The job builds everything a run needs from its index (the parameters or
/// initial state of run `i` of the sweep, and its own integrator: the
/// integrators are `&mut self` and keep per-run records, so runs never
/// share one) and returns whatever the caller keeps, typically the
/// `Result<Outcome, SimError>` of the run or a summary of it. A failing
/// run is then a typed [`SimError`](crate::SimError) in its slot, and the
/// other runs go on.
///
/// [`Ensemble::run`] returns the results in index order: `results[k]`
/// belongs to index `indices().start + k`. Sequential (the default) and
/// [`parallel`](Ensemble::parallel) (feature `rayon`) execution call the
/// same job on the same indices, so the results are identical, bit for bit,
/// as long as the job depends on nothing but its index.
///
/// A sweep too large for one machine is cut into [`Shard`]s, contiguous
/// index ranges that a batch scheduler's job array runs one per task
/// ([`Ensemble::shard`]); the shards' results, concatenated in shard order,
/// are the full sweep's.
///
/// # Panics
///
/// The ensemble itself never panics. A job that panics does not become a
/// result: the panic propagates out of [`Ensemble::run`] (sequentially at
/// once, with the later runs not started; in parallel, rayon lets the runs
/// already under way finish, then resumes the panic in the caller) and no
/// results are returned. Report failures as values (the integrators'
/// [`SimError`](crate::SimError)) or catch the panic inside the job with
/// `std::panic::catch_unwind` to keep the other runs' results.
///
/// # Example
///
/// A decay `x' = -k x` over 64 rates, in parallel when the feature `rayon`
/// is on:
///
/// ```rust
/// use nalgebra::Vector1;
/// use nh_runtime::{Dopri5, Ensemble, Integrator};
///
/// let rates: Vec<f64> = (0..64).map(|i| 0.1 * f64::from(i)).collect();
/// let ensemble = Ensemble::new(rates.len());
/// #[cfg(feature = "rayon")]
/// let ensemble = ensemble.parallel();
/// let finals = ensemble.run(|i| {
///     let k = rates[i];
///     let decay = move |_t: f64, x: &Vector1<f64>| -k * x;
///     Dopri5::new(1e-10, 1e-12).integrate(&decay, 0.0, Vector1::new(1.0), 1.0)
/// });
/// assert_eq!(finals.len(), 64);
/// let x = finals[30].as_ref().unwrap().x[0];
/// assert!((x - (-3.0f64).exp()).abs() < 1e-9);
/// ```
#[derive(Clone)]
pub struct Ensemble<P = fn(usize, usize)> {
    indices: Range<usize>,
    parallel: bool,
    progress: P,
}

/// The progress callback of an ensemble without one.
fn no_progress(_done: usize, _total: usize) {}

impl Ensemble {
    /// The runs `0..runs`, sequential, without a progress callback.
    ///
    /// ```rust
    /// use nh_runtime::Ensemble;
    ///
    /// let squares = Ensemble::new(4).run(|i| i * i);
    /// assert_eq!(squares, [0, 1, 4, 9]);
    /// assert!(Ensemble::new(0).run(|i| i).is_empty());
    /// ```
    pub fn new(runs: usize) -> Self {
        Self::over(0..runs)
    }

    /// The runs with the indices `indices` (global indices of a larger
    /// sweep), sequential, without a progress callback. An empty or
    /// reversed range has no runs.
    ///
    /// ```rust
    /// use nh_runtime::Ensemble;
    ///
    /// assert_eq!(Ensemble::over(10..13).run(|i| i), [10, 11, 12]);
    /// ```
    pub fn over(indices: Range<usize>) -> Self {
        let indices = indices.start..indices.end.max(indices.start);
        Ensemble {
            indices,
            parallel: false,
            progress: no_progress,
        }
    }

    /// Shard `shard` of a sweep of `runs` runs: the runs with the indices
    /// [`shard.range(runs)`](Shard::range).
    ///
    /// ```rust
    /// use nh_runtime::{Ensemble, Shard};
    ///
    /// let shard = Shard::new(1, 3).unwrap();
    /// assert_eq!(Ensemble::shard(10, shard).indices(), 4..7);
    /// ```
    pub fn shard(runs: usize, shard: Shard) -> Self {
        Self::over(shard.range(runs))
    }
}

impl<P: Fn(usize, usize) + Sync> Ensemble<P> {
    /// The global indices of the runs, in the order of the results.
    pub fn indices(&self) -> Range<usize> {
        self.indices.clone()
    }

    /// The number of runs.
    ///
    /// ```rust
    /// use nh_runtime::Ensemble;
    ///
    /// assert_eq!(Ensemble::over(5..9).len(), 4);
    /// assert!(Ensemble::over(9..5).is_empty());
    /// ```
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// Whether there are no runs.
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }

    /// Runs the jobs on rayon's thread pool, one task per run, on all cores
    /// (or on as many threads as `RAYON_NUM_THREADS` says; call
    /// [`run`](Ensemble::run) inside `ThreadPool::install` to use a pool of
    /// your own). The results are the same as sequentially, in the same
    /// order. Feature `rayon`.
    ///
    /// ```rust
    /// use nh_runtime::Ensemble;
    ///
    /// let cubes = Ensemble::new(100).parallel().run(|i| i * i * i);
    /// assert_eq!(cubes, Ensemble::new(100).run(|i| i * i * i));
    /// ```
    #[cfg(feature = "rayon")]
    pub fn parallel(mut self) -> Self {
        self.parallel = true;
        self
    }

    /// Runs the jobs one after the other on the calling thread (the
    /// default).
    pub fn sequential(mut self) -> Self {
        self.parallel = false;
        self
    }

    /// Whether the runs go to rayon's thread pool.
    pub fn is_parallel(&self) -> bool {
        self.parallel
    }

    /// Calls `progress(done, total)` after each finished run, with `done`
    /// the number of runs finished so far (each of `1..=total` exactly once)
    /// and `total` this ensemble's [`len`](Ensemble::len). In parallel it is
    /// called from the worker threads, possibly at the same time and not
    /// necessarily in the order of `done`; a progress bar that counts
    /// (`inc(1)`) or keeps the largest `done` shows the right figure.
    ///
    /// ```rust
    /// use std::sync::atomic::{AtomicUsize, Ordering};
    /// use nh_runtime::Ensemble;
    ///
    /// let (calls, last) = (AtomicUsize::new(0), AtomicUsize::new(0));
    /// Ensemble::new(5)
    ///     .on_progress(|done, total| {
    ///         calls.fetch_add(1, Ordering::Relaxed);
    ///         last.fetch_max(done, Ordering::Relaxed);
    ///         assert_eq!(total, 5);
    ///     })
    ///     .run(|i| i);
    /// assert_eq!((calls.into_inner(), last.into_inner()), (5, 5));
    /// ```
    pub fn on_progress<Q: Fn(usize, usize) + Sync>(self, progress: Q) -> Ensemble<Q> {
        Ensemble {
            indices: self.indices,
            parallel: self.parallel,
            progress,
        }
    }

    /// Calls `job(i)` for every index `i` of the ensemble and returns the
    /// results in index order (`results[k]` is run `indices().start + k`).
    /// Allocates the result vector once.
    ///
    /// # Panics
    ///
    /// Only if `job` or the progress callback panics; see
    /// [the type's documentation](Ensemble#panics).
    pub fn run<R, F>(&self, job: F) -> Vec<R>
    where
        R: Send,
        F: Fn(usize) -> R + Sync,
    {
        let (total, done) = (self.len(), AtomicUsize::new(0));
        let one = |i: usize| {
            let result = job(i);
            (self.progress)(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            result
        };
        #[cfg(feature = "rayon")]
        if self.parallel {
            use rayon::iter::{IntoParallelIterator, ParallelIterator};
            return self.indices().into_par_iter().map(one).collect();
        }
        self.indices().map(one).collect()
    }

    /// Runs the members in groups of `W` consecutive indices, one call of
    /// `job(group)` per group, for a job that advances `W` members together
    /// in the lanes of a SIMD type (DESIGN §6.8; [`Rk4::integrate_lanes`](crate::Rk4::integrate_lanes)
    /// with `W = WideF64x4::LANES`), and returns the results in index order
    /// as [`run`](Ensemble::run) does. When the member count is not a
    /// multiple of `W` the last group is shorter: the job fills the lanes
    /// past its end as it likes and those results are dropped. In parallel
    /// each group is one task; the progress callback counts members.
    ///
    /// # Panics
    ///
    /// If `W` is 0, or as [`run`](Ensemble::run) does.
    ///
    /// # Example
    ///
    /// Ten decay rates, four per call:
    ///
    /// ```rust
    /// use nalgebra::Vector1;
    /// use nh_runtime::{Ensemble, Rk4, WideF64x4};
    ///
    /// let rate = |i: usize| 0.1 * i as f64;
    /// let finals = Ensemble::new(10).run_lanes(|group| {
    ///     let k: [f64; 4] = core::array::from_fn(|l| rate(group.start + l));
    ///     let k = WideF64x4::from(k);
    ///     let decay = move |_t: WideF64x4, x: &Vector1<WideF64x4>| x * -k;
    ///     let x0 = Vector1::new(WideF64x4::from([1.0; 4]));
    ///     let out = Rk4::new(0.01).integrate_lanes(&decay, 0.0, x0, 1.0).unwrap();
    ///     core::array::from_fn::<_, 4, _>(|l| out.lane(l).map(|(_, x)| x[0]))
    /// });
    /// assert_eq!(finals.len(), 10);
    /// assert!((finals[9].unwrap() - (-0.9f64).exp()).abs() < 1e-9);
    /// ```
    pub fn run_lanes<R, F, const W: usize>(&self, job: F) -> Vec<R>
    where
        R: Send,
        F: Fn(Range<usize>) -> [R; W] + Sync,
    {
        assert!(W > 0, "a group of lanes has at least one lane");
        let (indices, total, done) = (self.indices(), self.len(), AtomicUsize::new(0));
        let group = |g: usize| {
            let start = indices.start + g * W;
            let members = start..(start + W).min(indices.end);
            let len = members.len();
            let results = job(members);
            let before = done.fetch_add(len, Ordering::Relaxed);
            (1..=len).for_each(|k| (self.progress)(before + k, total));
            results.into_iter().take(len)
        };
        let groups = total.div_ceil(W);
        #[cfg(feature = "rayon")]
        if self.parallel {
            use rayon::iter::{IntoParallelIterator, ParallelIterator};
            return (0..groups).into_par_iter().flat_map_iter(group).collect();
        }
        (0..groups).flat_map(group).collect()
    }
}

impl<P> fmt::Debug for Ensemble<P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Ensemble")
            .field("indices", &self.indices)
            .field("parallel", &self.parallel)
            .finish_non_exhaustive()
    }
}

/// Shard `index` of `count` (`index` in `0..count`) of a sweep: the
/// contiguous range of run indices one machine, or one task of a batch
/// scheduler's job array, runs.
///
/// The `count` shards of a sweep of `n` runs are consecutive ranges that
/// cover `0..n` in order without overlap, and their sizes differ by at most
/// one: the first `n % count` shards have `n / count + 1` runs, the others
/// `n / count`. Each shard's results, written with their global indices
/// and concatenated in shard order, are the full sweep's.
///
/// With a job array numbered from 0 (e.g. `sbatch --array=0-7`), one task
/// takes its shard from the scheduler's variables:
///
/// ```rust,no_run
/// use nh_runtime::{Ensemble, Shard};
///
/// let shard = Shard::from_env("SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT")?;
/// let results = Ensemble::shard(1_000_000, shard).run(|i| i % 7);
/// # Ok::<(), nh_runtime::ShardError>(())
/// ```
///
/// A scheduler that numbers its tasks from 1 (`SGE_TASK_ID`, `PBS_ARRAYID`
/// with `-t 1-8`) needs `Shard::new(id - 1, count)`; a shard can also be
/// read from a command line as `"3/8"` (index 3 of 8).
///
/// # Example
///
/// ```rust
/// use nh_runtime::Shard;
///
/// let shards: Vec<_> = (0..4).map(|k| Shard::new(k, 4).unwrap().range(10)).collect();
/// assert_eq!(shards, [0..3, 3..6, 6..8, 8..10]);
/// assert_eq!("3/8".parse::<Shard>().unwrap().range(80), 30..40);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// Shard `index` of `count`; an error unless `index < count`.
    ///
    /// ```rust
    /// use nh_runtime::{Shard, ShardError};
    ///
    /// assert!(Shard::new(7, 8).is_ok());
    /// assert_eq!(Shard::new(8, 8), Err(ShardError::IndexOutOfRange { index: 8, count: 8 }));
    /// assert_eq!(Shard::new(0, 0), Err(ShardError::IndexOutOfRange { index: 0, count: 0 }));
    /// ```
    pub fn new(index: usize, count: usize) -> Result<Self, ShardError> {
        if index < count {
            Ok(Shard { index, count })
        } else {
            Err(ShardError::IndexOutOfRange { index, count })
        }
    }

    /// The shard's index, in `0..count`.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The number of shards.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The run indices of this shard of a sweep of `runs` runs (balanced:
    /// the shards' sizes differ by at most one; without overflow for every
    /// `runs`).
    ///
    /// ```rust
    /// use nh_runtime::Shard;
    ///
    /// assert_eq!(Shard::new(2, 3).unwrap().range(7), 5..7);
    /// assert_eq!(Shard::new(4, 5).unwrap().range(3), 3..3); // more shards than runs
    /// ```
    pub fn range(&self, runs: usize) -> Range<usize> {
        let (base, extra) = (runs / self.count, runs % self.count);
        let start = self.index * base + self.index.min(extra);
        start..start + base + usize::from(self.index < extra)
    }

    /// The shard named by two environment variables holding the index
    /// (from 0) and the count, e.g. `("SLURM_ARRAY_TASK_ID",
    /// "SLURM_ARRAY_TASK_COUNT")`.
    ///
    /// # Errors
    ///
    /// [`ShardError::MissingVariable`] when a variable is not set (or not
    /// Unicode), [`ShardError::Malformed`] when it is not a number,
    /// [`ShardError::IndexOutOfRange`] unless index < count.
    pub fn from_env(index_var: &str, count_var: &str) -> Result<Self, ShardError> {
        let read = |name: &str| -> Result<usize, ShardError> {
            let text = std::env::var(name).map_err(|_| ShardError::MissingVariable {
                name: String::from(name),
            })?;
            parse_count(&text)
        };
        Shard::new(read(index_var)?, read(count_var)?)
    }
}

/// A non-negative integer, or [`ShardError::Malformed`].
fn parse_count(text: &str) -> Result<usize, ShardError> {
    text.trim().parse().map_err(|_| ShardError::Malformed {
        text: String::from(text),
    })
}

impl FromStr for Shard {
    type Err = ShardError;

    /// `"index/count"`, e.g. `"3/8"`.
    fn from_str(text: &str) -> Result<Self, ShardError> {
        let malformed = || ShardError::Malformed {
            text: String::from(text),
        };
        let (index, count) = text.split_once('/').ok_or_else(malformed)?;
        let (index, count) = (parse_count(index), parse_count(count));
        Shard::new(
            index.map_err(|_| malformed())?,
            count.map_err(|_| malformed())?,
        )
    }
}

impl fmt::Display for Shard {
    /// `index/count`, as [`FromStr`] reads it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Why a [`Shard`] could not be made.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ShardError {
    /// The index is not below the count (or the count is 0).
    IndexOutOfRange {
        /// The index asked for.
        index: usize,
        /// The number of shards.
        count: usize,
    },
    /// A shard, an index or a count that is not `index/count` or a
    /// non-negative integer.
    Malformed {
        /// The text as given.
        text: String,
    },
    /// An environment variable that is not set.
    MissingVariable {
        /// The variable's name.
        name: String,
    },
}

impl fmt::Display for ShardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShardError::IndexOutOfRange { index, count } => write!(
                f,
                "shard {index} of {count} does not exist: shards are numbered 0 to count - 1, and count is at least 1"
            ),
            ShardError::Malformed { text } => write!(
                f,
                "`{text}` is not a shard: expected `index/count` or a non-negative integer"
            ),
            ShardError::MissingVariable { name } => {
                write!(f, "the environment variable {name} is not set")
            }
        }
    }
}

impl std::error::Error for ShardError {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::format;

    /// Every (runs, count) with runs < 200 and count ≤ 40: the shards are
    /// consecutive, cover `0..runs` in order and differ in size by ≤ 1.
    #[test]
    fn shards_cover_the_sweep_in_order_without_overlap() {
        for runs in 0..200 {
            for count in 1..=40 {
                let ranges: Vec<_> = (0..count)
                    .map(|k| Shard::new(k, count).unwrap().range(runs))
                    .collect();
                let flat: Vec<usize> = ranges.iter().cloned().flatten().collect();
                assert_eq!(
                    flat,
                    (0..runs).collect::<Vec<_>>(),
                    "{runs} runs, {count} shards"
                );
                let sizes: Vec<usize> = ranges.iter().map(|r| r.len()).collect();
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "{runs} runs, {count} shards: sizes {sizes:?}");
                assert_eq!(*hi, runs.div_ceil(count));
            }
        }
    }

    #[test]
    fn shards_of_huge_sweeps_do_not_overflow() {
        let count = 1000;
        let last = Shard::new(count - 1, count).unwrap().range(usize::MAX);
        assert_eq!(last.end, usize::MAX);
        let mut end = 0;
        for k in 0..count {
            let r = Shard::new(k, count).unwrap().range(usize::MAX);
            assert_eq!(r.start, end);
            end = r.end;
        }
        assert_eq!(end, usize::MAX);
    }

    #[test]
    fn shard_results_concatenate_to_the_full_sweep() {
        let job = |i: usize| (i as f64).sqrt().sin();
        let full = Ensemble::new(103).run(job);
        let mut joined = Vec::new();
        for k in 0..8 {
            joined.extend(Ensemble::shard(103, Shard::new(k, 8).unwrap()).run(job));
        }
        assert_eq!(joined, full);
    }

    #[test]
    fn shards_parse_and_print_as_index_slash_count() {
        let shard: Shard = " 3/8".trim().parse().unwrap();
        assert_eq!((shard.index(), shard.count()), (3, 8));
        assert_eq!(format!("{shard}"), "3/8");
        for bad in ["3", "3/", "/8", "a/8", "3/8/1", "-1/8", ""] {
            assert_eq!(
                bad.parse::<Shard>(),
                Err(ShardError::Malformed { text: bad.into() }),
                "{bad:?}"
            );
        }
        assert_eq!(
            "8/8".parse::<Shard>(),
            Err(ShardError::IndexOutOfRange { index: 8, count: 8 })
        );
    }

    #[test]
    fn shards_from_missing_environment_variables_are_errors() {
        let missing = "NH_RUNTIME_TEST_SURELY_UNSET_VARIABLE";
        assert_eq!(
            Shard::from_env(missing, missing),
            Err(ShardError::MissingVariable {
                name: missing.into()
            })
        );
    }

    #[test]
    fn an_empty_ensemble_runs_nothing_and_reports_no_progress() {
        let calls = AtomicUsize::new(0);
        let (high, low) = (9, 3);
        for ensemble in [
            Ensemble::new(0),
            Ensemble::over(7..7),
            Ensemble::over(high..low),
        ] {
            let ensemble = ensemble.on_progress(|_, _| {
                calls.fetch_add(1, Ordering::Relaxed);
            });
            assert!(ensemble.is_empty());
            let results: Vec<usize> = ensemble.run(|i| panic!("run {i} of an empty ensemble"));
            assert!(results.is_empty());
        }
        assert_eq!(calls.into_inner(), 0);
    }

    #[test]
    fn sequential_progress_counts_up_in_order() {
        let seen = std::sync::Mutex::new(Vec::new());
        let results = Ensemble::over(10..14)
            .on_progress(|done, total| seen.lock().unwrap().push((done, total)))
            .run(|i| i + 1);
        assert_eq!(results, [11, 12, 13, 14]);
        assert_eq!(seen.into_inner().unwrap(), [(1, 4), (2, 4), (3, 4), (4, 4)]);
    }

    #[test]
    fn a_panicking_job_propagates_out_of_a_sequential_run() {
        let started = AtomicUsize::new(0);
        let caught = std::panic::catch_unwind(|| {
            Ensemble::new(10).run(|i| {
                started.fetch_add(1, Ordering::Relaxed);
                assert!(i != 3, "run 3 panics");
                i
            })
        });
        assert!(caught.is_err());
        assert_eq!(
            started.into_inner(),
            4,
            "runs after the panic are not started"
        );
    }

    #[cfg(feature = "rayon")]
    mod parallel {
        use super::*;

        #[test]
        fn parallel_results_are_the_sequential_ones_in_order() {
            let job = |i: usize| {
                let x = i as f64;
                (0..1000).fold(x, |acc, k| (acc + f64::from(k)).sin() * 1.5)
            };
            let ensemble = Ensemble::over(17..1017);
            let sequential = ensemble.clone().run(job);
            let parallel = ensemble.parallel().run(job);
            assert_eq!(parallel.len(), 1000);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&parallel), bits(&sequential));
        }

        #[test]
        fn parallel_progress_reports_every_count_once() {
            let seen = std::sync::Mutex::new(Vec::new());
            Ensemble::new(500)
                .parallel()
                .on_progress(|done, total| {
                    assert_eq!(total, 500);
                    seen.lock().unwrap().push(done);
                })
                .run(|i| i);
            let mut seen = seen.into_inner().unwrap();
            seen.sort_unstable();
            assert_eq!(seen, (1..=500).collect::<Vec<_>>());
        }

        #[test]
        fn a_panicking_job_propagates_out_of_a_parallel_run() {
            let caught = std::panic::catch_unwind(|| {
                Ensemble::new(64).parallel().run(|i| {
                    assert!(i != 40, "run 40 panics");
                    i
                })
            });
            let message = caught.unwrap_err();
            assert_eq!(message.downcast_ref::<&str>(), Some(&"run 40 panics"));
        }
    }
}
