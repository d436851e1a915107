//! Ensembles of Chaplygin sled runs: the parallel sweep equals the
//! sequential one bit for bit (failed runs included, as typed errors in
//! their slots), and shards of it concatenate to the whole.
use std::sync::atomic::{AtomicUsize, Ordering};

use nh_lab::systems::ChaplyginSled;
use nonholonomic::prelude::*;

type Run = Result<Outcome<f64, 5>, SimError<f64, 5>>;

/// The sweep: 8 initial headings × 8 initial turning rates (ẋ = 1) over
/// 10 s, Dormand–Prince at rtol 1e-9 with a budget of 200 step attempts.
/// The runs need 157 to 315 steps, so the fast-turning ones end in
/// `MaxSteps`, and those that turn through θ = ±π/2, the pole of the sled's
/// tan chart, end there in `Singular`: failures that must land in their
/// slots.
const RUNS: usize = 64;
const BUDGET: usize = 200;

fn initial_state(i: usize) -> SVector<f64, 5> {
    let heading = -1.4 + 0.4 * (i / 8) as f64;
    let turning = -3.0 + 6.0 * (i % 8) as f64 / 7.0;
    SVector::from([0.0, heading, 0.0, 1.0, turning])
}

/// Run `i`, with its own system and integrator, as an ensemble job does.
fn run(i: usize) -> Run {
    let sled: ChaplyginSled = ChaplyginSled::new(2.0, 0.3, 0.5);
    Dopri5::new(1e-9, 1e-12)
        .with_max_steps(BUDGET)
        .integrate(&sled, 0.0, initial_state(i), 10.0)
}

/// Everything a run returned, floats as bits: equal fingerprints are
/// bit-identical results.
fn fingerprint(run: &Run) -> (String, Option<u64>, Vec<u64>) {
    let bits = |x: &SVector<f64, 5>| x.iter().map(|v| v.to_bits()).collect();
    match run {
        Ok(o) => (format!("Ok {:?}", o.stats), Some(o.t.to_bits()), bits(&o.x)),
        Err(e) => (
            format!("{e:?}"),
            e.time().map(f64::to_bits),
            e.state().map_or_else(Vec::new, bits),
        ),
    }
}

fn fingerprints(runs: &[Run]) -> Vec<(String, Option<u64>, Vec<u64>)> {
    runs.iter().map(fingerprint).collect()
}

#[test]
fn the_parallel_sweep_is_the_sequential_one_bit_for_bit() {
    let by_hand: Vec<Run> = (0..RUNS).map(run).collect();
    let sequential = Ensemble::new(RUNS).run(run);
    let done = AtomicUsize::new(0);
    let parallel = Ensemble::new(RUNS)
        .parallel()
        .on_progress(|_, total| {
            assert_eq!(total, RUNS);
            done.fetch_add(1, Ordering::Relaxed);
        })
        .run(run);
    assert_eq!(done.into_inner(), RUNS);
    assert_eq!(fingerprints(&sequential), fingerprints(&by_hand));
    assert_eq!(fingerprints(&parallel), fingerprints(&sequential));

    // both kinds of slot occur, and the failures are the budget's or the
    // chart's pole
    let failed: Vec<usize> = (0..RUNS).filter(|&i| parallel[i].is_err()).collect();
    assert!(
        failed.len() >= 8 && failed.len() <= RUNS - 8,
        "failed runs {failed:?}"
    );
    let (mut budget, mut pole) = (0, 0);
    for &i in &failed {
        match parallel[i] {
            Err(SimError::MaxSteps { steps, t, .. }) => {
                assert_eq!(steps, BUDGET, "run {i}");
                assert!(t > 0.0 && t < 10.0, "run {i} stopped at t = {t}");
                budget += 1;
            }
            Err(SimError::Singular {
                cause: Singularity::Pole(expr),
                x,
                ..
            }) => {
                assert_eq!(expr, "1/cos(theta)", "run {i}");
                assert!(x[1].cos().abs() < 0.2, "run {i} stopped at θ = {}", x[1]);
                pole += 1;
            }
            ref other => panic!("run {i}: {other:?}"),
        }
    }
    println!(
        "{} ran to t = 10, {budget} used up their budget, {pole} met the pole",
        RUNS - failed.len()
    );
    for (i, r) in parallel.iter().enumerate() {
        if let Ok(o) = r {
            assert_eq!(o.t, 10.0, "run {i}");
            assert!(o.stats.steps + o.stats.rejected <= BUDGET, "run {i}");
        }
    }
}

#[test]
fn shards_of_the_sweep_run_in_parallel_concatenate_to_it() {
    let full = fingerprints(&Ensemble::new(RUNS).parallel().run(run));
    for count in [3, 8, 100] {
        let mut joined = Vec::new();
        for index in 0..count {
            let shard = Shard::new(index, count).unwrap();
            joined.extend(fingerprints(
                &Ensemble::shard(RUNS, shard).parallel().run(run),
            ));
        }
        assert_eq!(joined, full, "{count} shards");
    }
}
