//! Work–precision reports: every integrator's error against its run time.
//!
//! A report is a list of [`Run`]s — one integration of one scene by one
//! integrator at one tolerance (or step size) — written as a Markdown table
//! ([`markdown_table`]), a CSV file ([`write_csv`]) and one log–log SVG
//! diagram per scene ([`svg_work_precision`], drawn with `plotters`): error
//! against seconds, one line per integrator, in the manner of DiffEqDevTools'
//! `WorkPrecisionSet`. [`progress_bar`] shows the progress of a long run.
//! `cargo run --release -p nh-lab --example work_precision` produces the project's.

use std::fmt::Write as _;
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One integration of one scene by one integrator at one setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The scene (system and initial state).
    pub scene: String,
    /// The integrator.
    pub integrator: String,
    /// Relative tolerance, or the step size for fixed-step methods.
    pub tolerance: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Right-hand-side evaluations (finite-difference Jacobians included).
    pub rhs_evals: usize,
    /// Median wall time of the repeats, in seconds.
    pub seconds: f64,
    /// Error at the final time: max abs over the state against the reference.
    pub error: f64,
    /// |E(t1) − E(t0)| / |E(t0)| where energy is conserved.
    pub energy_error: Option<f64>,
}

/// Runs `f` `repeats` times (at least once) and returns the median wall time
/// in seconds with the last result.
pub fn median_time<R>(repeats: usize, mut f: impl FnMut() -> R) -> (f64, R) {
    let repeats = repeats.max(1);
    let mut times = Vec::with_capacity(repeats);
    let start = Instant::now();
    let mut last = f();
    times.push(start.elapsed().as_secs_f64());
    for _ in 1..repeats {
        let start = Instant::now();
        last = f();
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[repeats / 2], last)
}

/// The runs as a Markdown table.
pub fn markdown_table(runs: &[Run]) -> String {
    let mut s = String::from(
        "| scene | integrator | tolerance / h | steps | rhs evals | seconds | error | energy error |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in runs {
        let energy = r
            .energy_error
            .map(|e| format!("{e:.2e}"))
            .unwrap_or_else(|| "—".into());
        let _ = writeln!(
            s,
            "| {} | {} | {:e} | {} | {} | {:.3e} | {:.2e} | {} |",
            r.scene, r.integrator, r.tolerance, r.steps, r.rhs_evals, r.seconds, r.error, energy
        );
    }
    s
}

/// Writes the runs as CSV with the columns
/// `scene,integrator,tolerance,steps,rhs_evals,seconds,error,energy_error`
/// (an empty energy error where energy is not conserved).
pub fn write_csv(path: &Path, runs: &[Run]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut s =
        String::from("scene,integrator,tolerance,steps,rhs_evals,seconds,error,energy_error\n");
    for r in runs {
        let energy = r.energy_error.map(|e| format!("{e:e}")).unwrap_or_default();
        let _ = writeln!(
            s,
            "{},{},{:e},{},{},{:e},{:e},{}",
            r.scene, r.integrator, r.tolerance, r.steps, r.rhs_evals, r.seconds, r.error, energy
        );
    }
    std::fs::write(path, s)
}

/// The series colours (ColorBrewer's Dark2, then grey), in order of first
/// appearance of an integrator.
const COLOURS: [RGBColor; 8] = [
    RGBColor(0x1b, 0x9e, 0x77),
    RGBColor(0xd9, 0x5f, 0x02),
    RGBColor(0x75, 0x70, 0xb3),
    RGBColor(0xe7, 0x29, 0x8a),
    RGBColor(0x66, 0xa6, 0x1e),
    RGBColor(0xe6, 0xab, 0x02),
    RGBColor(0xa6, 0x76, 0x1d),
    RGBColor(0x66, 0x66, 0x66),
];

/// The whole decades covering the positive finite `values`, at least one
/// decade wide, as powers of ten; `None` if there are none.
fn log_bounds(values: impl Iterator<Item = f64>) -> Option<Range<f64>> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return None;
    }
    Some(10f64.powf(lo.floor())..10f64.powf(hi.ceil().max(lo.floor() + 1.0)))
}

/// A log–log work–precision diagram of one scene's runs as an SVG document:
/// error (vertical) against seconds (horizontal), one line with markers per
/// integrator, axes labelled, with a legend. Runs with a zero, negative or
/// non-finite error or time are left out (they cannot be drawn on log axes).
///
/// Drawn with `plotters`' SVG backend; text is left to the viewer's fonts
/// (`<text>` elements), so no font library is needed to draw.
pub fn svg_work_precision(scene: &str, runs: &[Run]) -> String {
    let runs: Vec<&Run> = runs
        .iter()
        .filter(|r| {
            r.scene == scene
                && r.error > 0.0
                && r.error.is_finite()
                && r.seconds > 0.0
                && r.seconds.is_finite()
        })
        .collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 480)).into_drawing_area();
        // Drawing into a String cannot fail for want of I/O; an error here
        // would be a plotting bug, and the partial document is still returned.
        if let Err(e) = draw_work_precision(&root, scene, &runs) {
            eprintln!("work–precision chart of {scene}: {e}");
        }
    }
    svg
}

/// The log–log axes of a work–precision chart on `root`: time (`x`, described
/// by `x_desc`) against the error at the final time (`y`), labelled in
/// powers of ten.
#[allow(clippy::type_complexity)]
pub fn log_log_axes<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, Shift>,
    title: &str,
    (x, y): (Range<f64>, Range<f64>),
    x_desc: &str,
) -> Result<
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    DrawingAreaErrorKind<std::io::Error>,
> {
    log_log_chart(
        root,
        title,
        (x, y),
        (x_desc, "error at the final time (max abs)"),
    )
}

/// Log–log axes on `root` with the given descriptions, labelled in powers
/// of ten.
#[allow(clippy::type_complexity)]
pub fn log_log_chart<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, Shift>,
    title: &str,
    (x, y): (Range<f64>, Range<f64>),
    (x_desc, y_desc): (&str, &str),
) -> Result<
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    DrawingAreaErrorKind<std::io::Error>,
> {
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(x.log_scale(), y.log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", 14))
        .light_line_style(WHITE)
        .draw()?;
    Ok(chart)
}

/// Draws the chart of [`svg_work_precision`] on `root`.
fn draw_work_precision(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    scene: &str,
    runs: &[&Run],
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let title = format!("Work–precision: {scene}");
    let (Some(x), Some(y)) = (
        log_bounds(runs.iter().map(|r| r.seconds)),
        log_bounds(runs.iter().map(|r| r.error)),
    ) else {
        let root = root.titled(&title, ("sans-serif", 20))?;
        root.draw_text("no data", &("sans-serif", 16).into(), (340, 200))?;
        return root.present();
    };
    let mut chart = log_log_axes(
        root,
        &title,
        (x, y),
        "wall time per integration [s] (median)",
    )?;
    for (i, name) in integrators(runs).into_iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let mut points: Vec<(f64, f64)> = runs
            .iter()
            .filter(|r| r.integrator == name)
            .map(|r| (r.seconds, r.error))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                colour.stroke_width(2),
            ))?
            .label(name)
            .legend(move |(x, y)| Rectangle::new([(x, y - 2), (x + 20, y + 2)], colour.filled()));
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()?;
    root.present()
}

/// The integrators of `runs`, in order of first appearance.
fn integrators<'a>(runs: &[&'a Run]) -> Vec<&'a str> {
    let mut names: Vec<&str> = Vec::new();
    for r in runs {
        if !names.contains(&r.integrator.as_str()) {
            names.push(&r.integrator);
        }
    }
    names
}

/// A progress bar on standard error for `total` units of work, showing the
/// current unit's label as its message (`bar.set_message(..)`, then
/// `bar.inc(1)`). `indicatif` draws it only when standard error is a
/// terminal, so logs and CI output stay clean.
pub fn progress_bar(total: usize) -> ProgressBar {
    let bar = ProgressBar::new(total as u64);
    if let Ok(style) = ProgressStyle::with_template("[{bar:30}] {pos}/{len} {elapsed} {msg}") {
        bar.set_style(style.progress_chars("#>-"));
    }
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(integrator: &str, tol: f64, seconds: f64, error: f64) -> Run {
        Run {
            scene: "s".into(),
            integrator: integrator.into(),
            tolerance: tol,
            steps: 10,
            rhs_evals: 60,
            seconds,
            error,
            energy_error: None,
        }
    }

    #[test]
    fn svg_has_one_line_per_integrator_and_labelled_axes() {
        let runs = vec![
            run("A", 1e-4, 1e-5, 1e-4),
            run("A", 1e-6, 2e-5, 1e-6),
            run("B", 1e-4, 3e-5, 1e-5),
            run("B", 1e-6, 5e-5, 1e-8),
            run("B", 1e-8, 5e-5, 0.0), // not drawable on log axes
        ];
        let svg = svg_work_precision("s", &runs);
        // the series are the lines of width 2 (the axes and ticks are of width 1)
        assert_eq!(svg.matches(r#"stroke-width="2""#).count(), 2);
        assert_eq!(svg.matches("<circle").count(), 4);
        assert!(svg.contains("wall time") && svg.contains("error at the final time"));
        assert!(
            svg.contains("\nA\n</text>") && svg.contains("\nB\n</text>"),
            "legend"
        );
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    }

    #[test]
    fn csv_and_table_have_a_row_per_run() {
        let runs = vec![run("A", 1e-4, 1e-5, 1e-4), run("B", 0.01, 2e-5, 3e-6)];
        let dir = std::env::temp_dir().join(format!("nh-report-{}", std::process::id()));
        let path = dir.join("wp.csv");
        write_csv(&path, &runs).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 3);
        assert!(
            text.starts_with(
                "scene,integrator,tolerance,steps,rhs_evals,seconds,error,energy_error"
            )
        );
        assert_eq!(markdown_table(&runs).lines().count(), 4);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn median_of_repeats() {
        let mut n = 0;
        let (t, r) = median_time(5, || {
            n += 1;
            n
        });
        assert_eq!(r, 5);
        assert!(t >= 0.0);
    }
}
