//! Work–precision reports: every integrator's error against its run time.
//!
//! A report is a list of [`Run`]s — one integration of one scene by one
//! integrator at one tolerance (or step size) — written as a Markdown table
//! ([`markdown_table`]), a CSV file ([`write_csv`]) and one log–log SVG
//! diagram per scene ([`svg_work_precision`]): error against seconds, one line
//! per integrator, in the manner of DiffEqDevTools' `WorkPrecisionSet`.
//! `cargo run --release -p nh-lab --example work_precision` produces the project's.

use std::fmt::Write as _;
use std::io::{IsTerminal, Write as _};
use std::path::Path;
use std::time::Instant;

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

const COLOURS: [&str; 8] = [
    "#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666",
];

fn log_bounds(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return None;
    }
    Some((lo.floor(), hi.ceil().max(lo.floor() + 1.0)))
}

/// A log–log work–precision diagram of one scene's runs: error (vertical)
/// against seconds (horizontal), one line per integrator, axes labelled, with
/// a legend. Runs with a zero, negative or non-finite error or time are left
/// out (they cannot be drawn on log axes).
pub fn svg_work_precision(scene: &str, runs: &[Run]) -> String {
    let runs: Vec<&Run> = runs
        .iter()
        .filter(|r| r.scene == scene && r.error > 0.0 && r.error.is_finite() && r.seconds > 0.0)
        .collect();
    let (w, h) = (720.0, 480.0);
    let (left, right, top, bottom) = (80.0, 190.0, 40.0, 60.0);
    let (pw, ph) = (w - left - right, h - top - bottom);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Arial, Helvetica, sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="15">Work–precision: {}</text>"#,
        left + pw / 2.0,
        xml_escape(scene)
    );
    let (Some((x0, x1)), Some((y0, y1))) = (
        log_bounds(runs.iter().map(|r| r.seconds)),
        log_bounds(runs.iter().map(|r| r.error)),
    ) else {
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">no data</text></svg>"#,
            w / 2.0,
            h / 2.0
        );
        return s;
    };
    let px = |v: f64| left + (v.log10() - x0) / (x1 - x0) * pw;
    let py = |v: f64| top + (y1 - v.log10()) / (y1 - y0) * ph;
    // grid and decade ticks
    for d in (x0 as i32)..=(x1 as i32) {
        let x = left + (d as f64 - x0) / (x1 - x0) * pw;
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{top}" x2="{x:.1}" y2="{}" stroke="#ddd"/>"##,
            top + ph
        );
        let _ = writeln!(
            s,
            r#"<text x="{x:.1}" y="{}" text-anchor="middle">1e{d}</text>"#,
            top + ph + 18.0
        );
    }
    for d in (y0 as i32)..=(y1 as i32) {
        let y = top + (y1 - d as f64) / (y1 - y0) * ph;
        let _ = writeln!(
            s,
            r##"<line x1="{left}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/>"##,
            left + pw
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{:.1}" text-anchor="end">1e{d}</text>"#,
            left - 6.0,
            y + 4.0
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="black"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">wall time per integration [s] (median)</text>"#,
        left + pw / 2.0,
        h - 14.0
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(22 {}) rotate(-90)" text-anchor="middle">error at the final time (max abs)</text>"#,
        top + ph / 2.0
    );
    // one line per integrator, in order of first appearance
    let mut names: Vec<&str> = Vec::new();
    for r in &runs {
        if !names.contains(&r.integrator.as_str()) {
            names.push(&r.integrator);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let mut pts: Vec<(f64, f64)> = runs
            .iter()
            .filter(|r| r.integrator == *name)
            .map(|r| (px(r.seconds), py(r.error)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let path: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.1},{y:.1}")).collect();
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="2"/>"#,
            path.join(" ")
        );
        for (x, y) in &pts {
            let _ = writeln!(
                s,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="{colour}"/>"#
            );
        }
        let ly = top + 10.0 + 20.0 * i as f64;
        let lx = left + pw + 15.0;
        let _ = writeln!(
            s,
            r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{colour}" stroke-width="2"/><text x="{}" y="{}">{}</text>"#,
            lx + 24.0,
            lx + 30.0,
            ly + 4.0,
            xml_escape(name)
        );
    }
    s.push_str("</svg>\n");
    s
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A progress bar on standard error, drawn only when standard error is a
/// terminal (so logs and CI output stay clean).
pub struct Progress {
    total: usize,
    done: usize,
    enabled: bool,
}

impl Progress {
    /// A bar for `total` units of work.
    pub fn new(total: usize) -> Progress {
        Progress {
            total: total.max(1),
            done: 0,
            enabled: std::io::stderr().is_terminal(),
        }
    }

    /// Advances by one unit, labelled `what`.
    pub fn tick(&mut self, what: &str) {
        self.done += 1;
        if self.enabled {
            let width = 30;
            let filled = width * self.done.min(self.total) / self.total;
            let mut err = std::io::stderr();
            let _ = write!(
                err,
                "\r[{}{}] {}/{} {:<40}",
                "#".repeat(filled),
                " ".repeat(width - filled),
                self.done,
                self.total,
                what
            );
            let _ = err.flush();
        }
    }

    /// Ends the bar (a newline, if drawn).
    pub fn finish(&mut self) {
        if self.enabled {
            let _ = writeln!(std::io::stderr());
        }
    }
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
        assert_eq!(svg.matches("<polyline").count(), 2);
        assert_eq!(svg.matches("<circle").count(), 4);
        assert!(svg.contains("wall time") && svg.contains("error at the final time"));
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
