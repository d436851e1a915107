//! Draws the operations of the chains of bodies against their links
//! (`docs/chains_scaling.svg`) from the CSV of the scaling benchmark:
//!
//! ```text
//! cargo run --release -p nh-core --example chains -- --family planar --family spatial --outputs none --outputs jacobian --csv chains.csv
//! cargo run --release -p nh-lab --example chains_plot -- chains.csv docs/chains_scaling.svg
//! ```
//!
//! Per family (planar, spatial), log–log: the operations of `accelerations`
//! (the multiplier route's, without outputs) and of `jacobian` (where the
//! CSV has them), with guides of slope 1 and 2 through the first point of
//! each family's accelerations, so that the linear growth of the
//! articulated-body recursion (DESIGN §10) and the quadratic one of the
//! Jacobian are read off the slopes.
use plotters::prelude::*;

/// One row of the CSV: family, links, ops of `accelerations`, ops of
/// `jacobian` (if derived).
type Row = (String, f64, f64, Option<f64>);

/// The rows that the multiplier route derived, without outputs or with the
/// Jacobian.
fn rows(csv: &str) -> Vec<Row> {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| head.iter().position(|&h| h == name);
    let (Some(f), Some(l), Some(o), Some(p), Some(j)) = (
        col("family"),
        col("links"),
        col("ops"),
        col("projection_ops"),
        col("jacobian_ops"),
    ) else {
        return Vec::new();
    };
    lines
        .filter_map(|line| {
            let x: Vec<&str> = line.split(',').collect();
            let num = |i: usize| x.get(i)?.parse::<f64>().ok();
            let (links, ops, projection) = (num(l)?, num(o)?, num(p)?);
            let family = x.get(f)?.to_string();
            (projection > 0.0).then_some((family, links, ops, num(j)))
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(input), Some(output)) = (args.first(), args.get(1)) else {
        eprintln!("usage: chains_plot CHAINS.csv OUT.svg");
        std::process::exit(2);
    };
    let rows = rows(&std::fs::read_to_string(input)?);
    if rows.is_empty() {
        return Err("no rows of the multiplier route in the CSV".into());
    }
    let root = SVGBackend::new(output, (760, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let x = 2.0..30.0;
    let top = (rows.iter())
        .map(|r| r.3.unwrap_or(r.2))
        .fold(1.0, f64::max)
        * 2.0;
    let mut chart = nh_lab::report::log_log_chart(
        &root,
        "Chains of bodies: operations of `accelerations` and `jacobian` against links",
        (x, 50.0..top),
        (
            "links n (grey: slopes 1 and 2 from each family's first accelerations)",
            "operations after CSE",
        ),
    )?;
    for (family, colour) in [("planar", BLUE), ("spatial", RED)] {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.0 == family).collect();
        let accelerations: Vec<(f64, f64)> = (mine.iter())
            .filter(|r| r.3.is_none())
            .map(|r| (r.1, r.2))
            .collect();
        let jacobian: Vec<(f64, f64)> = mine.iter().filter_map(|r| Some((r.1, r.3?))).collect();
        let Some(&(n0, p0)) = accelerations.first() else {
            continue;
        };
        chart
            .draw_series(LineSeries::new(
                accelerations.clone(),
                colour.stroke_width(2),
            ))?
            .label(format!("{family}: accelerations"))
            .legend(move |(x, y)| Rectangle::new([(x, y - 2), (x + 20, y + 2)], colour.filled()));
        chart.draw_series(
            accelerations
                .iter()
                .map(|&p| Circle::new(p, 3, colour.filled())),
        )?;
        let light = colour.mix(0.5);
        chart
            .draw_series(LineSeries::new(jacobian.clone(), light.stroke_width(2)))?
            .label(format!("{family}: jacobian"))
            .legend(move |(x, y)| Rectangle::new([(x, y - 1), (x + 20, y + 1)], light.filled()));
        chart.draw_series((jacobian.iter()).map(|&p| TriangleMarker::new(p, 4, light.filled())))?;
        for slope in [1.0, 2.0] {
            // ended at 28 links or at the top of the chart, whichever first
            let end = (n0 * (top / p0).powf(1.0 / slope)).min(28.0);
            let guide = [(n0, p0), (end, p0 * (end / n0).powf(slope))];
            chart.draw_series(LineSeries::new(guide, BLACK.mix(0.25).stroke_width(1)))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()?;
    root.present()?;
    println!("{} rows drawn into {output}", rows.len());
    Ok(())
}
