//! The report: Markdown tables on standard output, a CSV of every run and
//! one work–precision SVG per problem.

use std::fmt::Write as _;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::analysis::{self, AtError, Row};
use crate::methods::Suite;

/// The target errors of the side-by-side.
pub const TARGETS: [f64; 3] = [1e-6, 1e-8, 1e-10];

/// What the report knows about one problem besides its runs.
pub struct ProblemInfo {
    /// The problem's name.
    pub name: &'static str,
    /// Seconds per right-hand side.
    pub rhs_cost: f64,
    /// Seconds per Jacobian.
    pub jacobian_cost: f64,
    /// How the reference was obtained.
    pub reference_note: String,
}

impl ProblemInfo {
    /// The physical limit at `target`: the fewest right-hand sides any method
    /// needed × the cost of one; with the method that needed them.
    pub fn limit(&self, rows: &[Row], target: f64) -> Option<(&'static str, AtError, f64)> {
        analysis::fewest_rhs(rows, self.name, target).map(|(m, c)| (m, c, c.value * self.rhs_cost))
    }
}

/// `value` formatted with `digits` significant digits in scientific notation,
/// prefixed with `≤` when it is a bound.
fn sci(v: AtError, digits: usize) -> String {
    format!("{}{:.*e}", if v.bound { "≤" } else { "" }, digits, v.value)
}

fn ratio(ours: Option<(&str, AtError)>, theirs: Option<(&str, AtError)>) -> String {
    match (ours, theirs) {
        (Some(o), Some(t)) => format!("{:.2}", o.1.value / t.1.value),
        _ => "—".into(),
    }
}

/// The side-by-side: per problem and target error, our best against each
/// peer's best and against the physical limit.
pub fn side_by_side(rows: &[Row], infos: &[ProblemInfo]) -> String {
    let mut s = String::from(
        "| problem | error | ours: best [s] | ode_solvers: best [s] | diffsol: best [s] | russell_ode: best [s] | limit [s] (fewest RHS × cost) | ours/ode_solvers | ours/diffsol | ours/russell_ode | ours/limit |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for info in infos {
        for target in TARGETS {
            let best = |suite| analysis::suite_best(rows, info.name, suite, target);
            let cell = |b: Option<(&str, AtError)>| {
                b.map_or("—".into(), |(m, t)| format!("{m}: {}", sci(t, 2)))
            };
            let (ours, os, ds, rs) = (
                best(Suite::Ours),
                best(Suite::OdeSolvers),
                best(Suite::Diffsol),
                best(Suite::Russell),
            );
            let limit = info.limit(rows, target);
            let limit_cell = limit.map_or("—".into(), |(m, c, t)| {
                format!("{t:.2e} ({} RHS, {m})", sci(c, 2))
            });
            let limit_ratio = match (ours, limit) {
                (Some(o), Some(l)) => format!("{:.2}", o.1.value / l.2),
                _ => "—".into(),
            };
            let _ = writeln!(
                s,
                "| {} | {target:.0e} | {} | {} | {} | {} | {limit_cell} | {} | {} | {} | {limit_ratio} |",
                info.name,
                cell(ours),
                cell(os),
                cell(ds),
                cell(rs),
                ratio(ours, os),
                ratio(ours, ds),
                ratio(ours, rs),
            );
        }
    }
    s
}

/// Every method's time, right-hand sides and Jacobians at each target error.
pub fn per_method(rows: &[Row], infos: &[ProblemInfo]) -> String {
    let mut s = String::from("| problem | method |");
    for t in TARGETS {
        let _ = write!(s, " s at {t:.0e} | RHS at {t:.0e} |");
    }
    s.push('\n');
    s.push_str(&"|---".repeat(2 + 2 * TARGETS.len()));
    s.push_str("|\n");
    for info in infos {
        for (_, m) in analysis::methods(rows, info.name) {
            let _ = write!(s, "| {} | {m} |", info.name);
            for t in TARGETS {
                let time = analysis::seconds_at(rows, info.name, m, t);
                let calls = analysis::rhs_at(rows, info.name, m, t);
                let _ = write!(
                    s,
                    " {} | {} |",
                    time.map_or("—".into(), |v| sci(v, 2)),
                    calls.map_or("—".into(), |v| format!(
                        "{}{:.0}",
                        if v.bound { "≤" } else { "" },
                        v.value
                    ))
                );
            }
            s.push('\n');
        }
    }
    s
}

/// The implicit methods' own work per step (time per step less its
/// right-hand sides and Jacobians at their measured costs), at each target.
pub fn overheads(rows: &[Row], infos: &[ProblemInfo], methods: &[&str]) -> String {
    let mut s = String::from("| problem | method |");
    for t in TARGETS {
        let _ = write!(s, " µs/step at {t:.0e} |");
    }
    s.push_str(" RHS/step | Jacobians/step |\n");
    s.push_str(&"|---".repeat(4 + TARGETS.len()));
    s.push_str("|\n");
    for info in infos {
        for &m in methods {
            let ladder = analysis::ladder(rows, info.name, m);
            if ladder.is_empty() {
                continue;
            }
            let _ = write!(s, "| {} | {m} |", info.name);
            for t in TARGETS {
                let v = analysis::overhead_at(rows, info.name, m, t);
                let _ = write!(
                    s,
                    " {} |",
                    v.map_or("—".into(), |v| format!(
                        "{}{:.2}",
                        if v.bound { "≤" } else { "" },
                        v.value * 1e6
                    ))
                );
            }
            let steps: usize = ladder.iter().map(|r| r.steps).sum();
            let rhs: usize = ladder.iter().map(|r| r.rhs).sum();
            let jac: usize = ladder.iter().map(|r| r.jacobian).sum();
            let per = |n: usize| n as f64 / steps.max(1) as f64;
            let _ = writeln!(s, " {:.2} | {:.2} |", per(rhs), per(jac));
        }
    }
    s
}

/// Writes every run as CSV.
pub fn write_csv(path: &Path, rows: &[Row]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut s = String::from(
        "problem,suite,method,setting,steps,rhs_calls,jacobian_calls,cpu_seconds,wall_seconds,error,overhead_per_step_seconds\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{:e},{},{},{},{:e},{:e},{:e},{:e}",
            r.problem,
            r.suite.label(),
            r.method,
            r.setting,
            r.steps,
            r.rhs,
            r.jacobian,
            r.seconds,
            r.wall_seconds,
            r.error,
            r.overhead_per_step
        );
    }
    std::fs::write(path, s)
}

/// Sixteen distinguishable colours (Tableau 10, then darker variants).
const COLOURS: [RGBColor; 16] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0xe3, 0x77, 0xc2),
    RGBColor(0x7f, 0x7f, 0x7f),
    RGBColor(0xbc, 0xbd, 0x22),
    RGBColor(0x17, 0xbe, 0xcf),
    RGBColor(0x0b, 0x3c, 0x5d),
    RGBColor(0x6b, 0x0f, 0x1a),
    RGBColor(0x14, 0x52, 0x14),
    RGBColor(0x4a, 0x2c, 0x6b),
    RGBColor(0x8a, 0x45, 0x00),
    RGBColor(0x00, 0x5f, 0x6b),
];

/// The work–precision diagram of one problem as an SVG document: error
/// against median wall time, log–log; our methods solid and thick, the
/// peers' thin, the physical limit black and dashed.
pub fn svg(rows: &[Row], info: &ProblemInfo) -> String {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 600)).into_drawing_area();
        if let Err(e) = draw(&root, rows, info) {
            eprintln!("work–precision chart of {}: {e}", info.name);
        }
    }
    out
}

fn decades(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v.log10());
        hi = hi.max(v.log10());
    }
    if lo > hi {
        return 1e-6..1.0;
    }
    10f64.powf(lo.floor())..10f64.powf(hi.ceil().max(lo.floor() + 1.0))
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    rows: &[Row],
    info: &ProblemInfo,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let all = rows;
    let rows: Vec<&Row> = all
        .iter()
        .filter(|r| r.problem == info.name && r.error > 0.0 && r.error.is_finite())
        .collect();
    let limit: Vec<(f64, f64)> = (0..=16)
        .map(|k| 10f64.powf(-3.0 - 0.5 * k as f64))
        .filter_map(|e| info.limit(all, e).filter(|l| !l.1.bound).map(|l| (l.2, e)))
        .collect();
    let x = decades(
        rows.iter()
            .map(|r| r.seconds)
            .chain(limit.iter().map(|p| p.0)),
    );
    let y = decades(rows.iter().map(|r| r.error));
    let mut chart = nh_lab::report::log_log_axes(
        root,
        &format!("Work–precision: {} (ours vs peers)", info.name),
        (x, y),
        "CPU time per integration [s] (median)",
    )?;
    for (i, (suite, name)) in analysis::methods(all, info.name).into_iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let ours = suite == Suite::Ours;
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.method == name)
            .map(|r| (r.seconds, r.error))
            .collect();
        let style = colour.stroke_width(if ours { 3 } else { 1 });
        let label = if ours {
            format!("{name} (ours)")
        } else {
            name.to_string()
        };
        chart
            .draw_series(LineSeries::new(points.iter().copied(), style))?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 2), (x + 20, y + 2)], colour.filled()));
        if ours {
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))?;
        } else {
            chart.draw_series(points.iter().map(|&p| TriangleMarker::new(p, 4, colour)))?;
        }
    }
    chart
        .draw_series(DashedLineSeries::new(
            limit.iter().copied(),
            6,
            4,
            BLACK.stroke_width(2),
        ))?
        .label("physical limit (fewest RHS × cost)")
        .legend(|(x, y)| Rectangle::new([(x, y - 1), (x + 20, y + 1)], BLACK.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()?;
    root.present()
}
