//! Monte Carlo in lanes: 102,400 runs of the Whipple bicycle over forward
//! speed and a random initial perturbation, four runs per call
//! (`WideF64x4`, DESIGN §6.8), on all cores.
//!
//! ```text
//! cargo run --release -p nh-lab --example monte_carlo
//! RUSTFLAGS="-C target-cpu=native" cargo run --release -p nh-lab --example monte_carlo
//! ```
//!
//! Each run starts upright and straight ahead at a speed of 0.1 … 10 m/s
//! (100 speeds) with roll and steer rates drawn uniformly from a square of
//! half-width a (four amplitudes a, 256 draws each), and runs 12 s with
//! `Rk4` (h = 0.02 s), sampled every 0.2 s. A run *stays upright* when its
//! roll never exceeds 1 rad, its perturbation (roll² + steer² + (roll
//! rate² + steer rate²)/10) peaks lower over the last 2 s than over 4–6 s
//! (after the fast modes have died out, the motion decays exactly when the
//! slowest mode does) and its roll stays within 0.1 rad over the last 2 s
//! (below the weave speed the nonlinear bicycle can settle into a weave of
//! 0.2–0.4 rad that neither grows nor decays). For small perturbations the fraction that stays
//! upright therefore steps from 0 to 1 at the linear weave speed and back
//! at the capsize speed (4.29 and 6.02 m/s, computed here from the
//! generated linearisation), which the example checks and draws
//! (`target/whipple_monte_carlo.svg`).
//!
//! The same classification runs on a subset (every 25th run) with the
//! scalar ensemble, one state per call (`Ensemble::run`, `Rk4::integrate`
//! without projection, as the lanes run), and with the lanes' own loop at
//! `T = f64` (one lane: the gain of the SIMD width alone): the example
//! reports runs per second of each and checks that every run of the subset
//! ends alike in all three.
#[path = "../../examples/whipple_bicycle/model.rs"]
#[allow(dead_code)]
mod model;

use std::time::Instant;

use indicatif::ProgressBar;
use nh_lab::report::progress_bar;
use nonholonomic::prelude::*;
use nonholonomic::runtime::{Lanes, WideF64x4};
use plotters::prelude::*;

type L = WideF64x4;
/// Lanes per call.
const W: usize = 4;
/// Speeds 0.1, 0.2, …, 10 m/s.
const SPEEDS: usize = 100;
/// Half-widths of the square of initial roll and steer rates, rad/s.
const AMPLITUDES: [f64; 4] = [0.05, 0.2, 0.5, 1.0];
/// Draws per speed and amplitude.
const DRAWS: usize = 256;
const RUNS: usize = SPEEDS * AMPLITUDES.len() * DRAWS;
/// Step, sampling interval and end of a run, s.
const H: f64 = 0.02;
const SAMPLE: f64 = 0.2;
const SAMPLES: usize = 60;
/// The scalar ensemble runs every `SUBSET`-th run.
const SUBSET: usize = 25;

fn speed(i: usize) -> f64 {
    0.1 * (i / (AMPLITUDES.len() * DRAWS) + 1) as f64
}

fn amplitude(i: usize) -> usize {
    i / DRAWS % AMPLITUDES.len()
}

/// A uniform number in [−1, 1) from `seed` (SplitMix64).
fn uniform(seed: u64) -> f64 {
    let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The initial state of run `i`: upright, straight, at its speed, with its
/// drawn roll and steer rates.
fn initial(i: usize) -> SVector<f64, 11> {
    let a = AMPLITUDES[amplitude(i)];
    let mut x = SVector::<f64, 11>::zeros();
    x[8] = a * uniform(2 * i as u64);
    x[9] = a * uniform(2 * i as u64 + 1);
    x[10] = speed(i) / 0.3; // the rear wheel's rate (rR = 0.3 m)
    x
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fate {
    Upright,
    /// The perturbation grew or kept weaving, the bicycle still up at 12 s.
    Growing,
    /// Roll beyond 1 rad (or the state turned non-finite lying down).
    Fell,
}

/// The perturbation's peaks over 4–6 s and 10–12 s, and the roll's over
/// 10–12 s.
#[derive(Clone, Copy, Default)]
struct Record {
    mid: f64,
    end: f64,
    end_roll: f64,
    fell: bool,
}

impl Record {
    /// Takes sample `k` (at k·0.2 s) of a state.
    fn sample(&mut self, k: usize, x: &SVector<f64, 11>) {
        if !x[0].is_finite() || x[0].abs() > 1.0 {
            self.fell = true;
        }
        let size = x[0] * x[0] + x[1] * x[1] + (x[8] * x[8] + x[9] * x[9]) / 10.0;
        match k {
            20..=30 => self.mid = self.mid.max(size),
            50..=60 => {
                self.end = self.end.max(size);
                self.end_roll = self.end_roll.max(x[0].abs());
            }
            _ => {}
        }
    }

    fn fate(&self) -> Fate {
        if self.fell {
            Fate::Fell
        } else if self.end < self.mid && self.end_roll < 0.1 {
            Fate::Upright
        } else {
            Fate::Growing
        }
    }
}

/// Runs `members` in the lanes of one state (`T` with `W` lanes: four
/// with `WideF64x4`, one with `f64`).
fn in_lanes<T, const W: usize>(bike: &model::Whipple<T>, members: [usize; W]) -> [Fate; W]
where
    T: Lanes<Element = f64>,
{
    let starts = members.map(initial);
    let mut x = SVector::<T, 11>::from_fn(|r, _| {
        let mut v = T::splat(0.0);
        (0..W).for_each(|l| v.replace(l, starts[l][r]));
        v
    });
    let mut records = [Record::default(); W];
    let rk4 = Rk4::new(H);
    for k in 1..=SAMPLES {
        let (t0, t1) = ((k - 1) as f64 * SAMPLE, k as f64 * SAMPLE);
        let out = rk4
            .integrate_lanes(bike, t0, x, t1)
            .expect("valid settings");
        for (l, record) in records.iter_mut().enumerate() {
            match out.lane(l) {
                Ok((_, xl)) => record.sample(k, &xl),
                Err(_) => record.fell = true,
            }
        }
        if records.iter().all(|r| r.fell) {
            break;
        }
        x = out.x;
    }
    records.map(|r| r.fate())
}

/// The members of a group of at most `W` consecutive runs; lanes past its
/// end repeat its last run.
fn members<const W: usize>(group: std::ops::Range<usize>) -> [usize; W] {
    core::array::from_fn(|l| (group.start + l).min(group.end - 1))
}

/// Run `i` with one state per call.
fn scalar(bike: &model::Whipple, i: usize) -> Fate {
    let mut x = initial(i);
    let mut record = Record::default();
    let mut rk4 = Rk4::new(H).with_projection(false);
    for k in 1..=SAMPLES {
        let (t0, t1) = ((k - 1) as f64 * SAMPLE, k as f64 * SAMPLE);
        match rk4.integrate(bike, t0, x, t1) {
            Ok(out) => {
                record.sample(k, &out.x);
                x = out.x;
            }
            Err(_) => record.fell = true,
        }
        if record.fell {
            break;
        }
    }
    record.fate()
}

fn main() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let bike_lanes = model::benchmark_in::<L>();
    let (fates, t_lanes) = timed("in lanes", RUNS, |bar| {
        Ensemble::new(RUNS)
            .parallel()
            .on_progress(|_, _| bar.inc(1))
            .run_lanes(|group| in_lanes::<L, W>(&bike_lanes, members(group)))
    });
    let bike = model::benchmark();
    let subset: Vec<usize> = (0..RUNS).step_by(SUBSET).collect();
    let (scalar_fates, t_scalar) = timed("scalar", subset.len(), |bar| {
        Ensemble::new(subset.len())
            .parallel()
            .on_progress(|_, _| bar.inc(1))
            .run(|k| scalar(&bike, subset[k]))
    });
    let (one_lane, t_one) = timed("one lane", subset.len(), |bar| {
        Ensemble::new(subset.len())
            .parallel()
            .on_progress(|_, _| bar.inc(1))
            .run_lanes(|k| in_lanes::<f64, 1>(&bike, [subset[k.start]]))
    });
    let differing = subset
        .iter()
        .zip(&scalar_fates)
        .zip(&one_lane)
        .filter(|((i, f), g)| fates[**i] != **f || **f != **g)
        .count();

    let (lanes_rate, scalar_rate) = (RUNS as f64 / t_lanes, subset.len() as f64 / t_scalar);
    println!(
        "{RUNS} runs of 12 s (Rk4, h = {H} s) on {cores} cores: in lanes of {W} {t_lanes:.1} s, {lanes_rate:.0} runs/s"
    );
    println!(
        "scalar ensemble on every {SUBSET}th run ({} runs): {t_scalar:.1} s, {scalar_rate:.0} runs/s; lanes {:.2}x its throughput; runs ending differently in lanes, scalar or one lane: {differing}",
        subset.len(),
        lanes_rate / scalar_rate
    );
    let one_rate = subset.len() as f64 / t_one;
    println!(
        "the same subset through the lanes' loop with f64 (one lane): {t_one:.1} s, {one_rate:.0} runs/s; lanes {:.2}x its throughput",
        lanes_rate / one_rate
    );

    let weave = model::stability_boundary(&bike, 3.0, 5.0);
    let capsize = model::stability_boundary(&bike, 5.0, 7.0);
    let fractions = upright_fractions(&fates);
    println!("\nlinear stability window: weave {weave:.3} m/s, capsize {capsize:.3} m/s");
    println!(
        "| a (rad/s) | upright window (fraction ≥ ½) | least fraction inside the linear window | greatest outside | runs upright | fell |"
    );
    println!("|---:|---|---:|---:|---:|---:|");
    for (a, curve) in AMPLITUDES.iter().zip(&fractions) {
        let window = window(curve);
        let count = |fate: Fate| {
            (0..RUNS)
                .filter(|&i| AMPLITUDES[amplitude(i)] == *a && fates[i] == fate)
                .count()
        };
        let (upright, fell) = (count(Fate::Upright), count(Fate::Fell));
        let text = window.map_or("none".to_string(), |(lo, hi)| {
            format!("{lo:.1} … {hi:.1} m/s")
        });
        let inside = |v: f64| v > weave && v < capsize;
        let least_in = curve
            .iter()
            .filter(|p| inside(p.0))
            .map(|p| p.1)
            .fold(1.0, f64::min);
        let most_out = curve
            .iter()
            .filter(|p| !inside(p.0))
            .map(|p| p.1)
            .fold(0.0, f64::max);
        println!("| {a} | {text} | {least_in:.3} | {most_out:.3} | {upright} | {fell} |");
    }
    match plot(&fractions, weave, capsize, "target/whipple_monte_carlo.svg") {
        Ok(()) => println!("\nwrote target/whipple_monte_carlo.svg"),
        Err(e) => println!("\ncould not write the plot: {e}"),
    }
}

/// `runs` members run by `job` with a progress bar labelled `label`: the
/// results and the seconds they took.
fn timed<R>(label: &str, runs: usize, job: impl FnOnce(&ProgressBar) -> Vec<R>) -> (Vec<R>, f64) {
    let bar = progress_bar(runs);
    bar.set_message(label.to_string());
    let start = Instant::now();
    let results = job(&bar);
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    (results, seconds)
}

/// Per amplitude, the fraction of runs that stay upright at each speed.
fn upright_fractions(fates: &[Fate]) -> Vec<Vec<(f64, f64)>> {
    (0..AMPLITUDES.len())
        .map(|a| {
            (0..SPEEDS)
                .map(|s| {
                    let first = (s * AMPLITUDES.len() + a) * DRAWS;
                    let up = fates[first..first + DRAWS]
                        .iter()
                        .filter(|f| **f == Fate::Upright)
                        .count();
                    (speed(first), up as f64 / DRAWS as f64)
                })
                .collect()
        })
        .collect()
}

/// The lowest and highest speed at which at least half the runs stay
/// upright.
fn window(curve: &[(f64, f64)]) -> Option<(f64, f64)> {
    let up: Vec<f64> = curve.iter().filter(|p| p.1 >= 0.5).map(|p| p.0).collect();
    Some((*up.first()?, *up.last()?))
}

fn plot(
    fractions: &[Vec<(f64, f64)>],
    weave: f64,
    capsize: f64,
    path: &str,
) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("target")?;
    let root = SVGBackend::new(path, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Whipple bicycle: fraction upright after 12 s ({RUNS} runs)"),
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..10.0, 0.0..1.05)?;
    chart
        .configure_mesh()
        .x_desc("forward speed v [m/s]")
        .y_desc("fraction that stays upright")
        .draw()?;
    let colours = [BLUE, GREEN, MAGENTA, RED];
    for ((a, curve), colour) in AMPLITUDES.iter().zip(fractions).zip(colours) {
        chart
            .draw_series(LineSeries::new(
                curve.iter().copied(),
                colour.stroke_width(2),
            ))?
            .label(format!("roll and steer rates up to {a} rad/s"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour));
    }
    for (v, what) in [(weave, "weave"), (capsize, "capsize")] {
        chart.draw_series(LineSeries::new([(v, 0.0), (v, 1.05)], BLACK.mix(0.4)))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("{what} {v:.2}"),
            (v + 0.05, 0.08),
            ("sans-serif", 13),
        )))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
