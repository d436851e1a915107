//! Draws the operations of the chains of bodies against their links
//! (`docs/chains_scaling.svg`) from the CSV of the scaling benchmark:
//!
//! ```text
//! cargo run --release -p nh-core --example chains -- --family planar --family spatial --csv chains.csv
//! cargo run --release -p nh-lab --example chains_plot -- chains.csv docs/chains_scaling.svg
//! ```
//!
//! Per family (planar, spatial), log–log: the operations of `accelerations`
//! and of its Cᵀ M C with right side (the composite inertias' part, DESIGN
//! §10), with guides of slope 2 and 3 through the first point of each
//! family's projection, so that the quadratic growth of the projection and
//! the cubic part the k × k solve adds are read off the slopes.
use plotters::prelude::*;

/// (family, links, ops of `accelerations`, ops of Cᵀ M C and right side) of
/// the rows without outputs that the multiplier route derived.
fn rows(csv: &str) -> Vec<(String, f64, f64, f64)> {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| head.iter().position(|&h| h == name);
    let (Some(f), Some(l), Some(o), Some(p), Some(out)) = (
        col("family"),
        col("links"),
        col("ops"),
        col("projection_ops"),
        col("outputs"),
    ) else {
        return Vec::new();
    };
    lines
        .filter_map(|line| {
            let x: Vec<&str> = line.split(',').collect();
            let num = |i: usize| x.get(i)?.parse::<f64>().ok();
            let (links, ops, projection) = (num(l)?, num(o)?, num(p)?);
            let none = x.get(out)?.trim_matches('"').is_empty();
            let family = x.get(f)?.to_string();
            (none && projection > 0.0).then_some((family, links, ops, projection))
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
        return Err("no rows of the multiplier route without outputs in the CSV".into());
    }
    let root = SVGBackend::new(output, (760, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let x = 2.0..30.0;
    let top = rows.iter().map(|r| r.2).fold(1.0, f64::max) * 2.0;
    let mut chart = nh_lab::report::log_log_chart(
        &root,
        "Chains of bodies: operations of `accelerations` against links",
        (x, 50.0..top),
        (
            "links n (grey: slopes 2 and 3 from each projection's first point)",
            "operations after CSE",
        ),
    )?;
    let families = [("planar", BLUE), ("spatial", RED)];
    for (family, colour) in families {
        let mine: Vec<_> = rows.iter().filter(|r| r.0 == family).collect();
        let Some(first) = mine.first() else {
            continue;
        };
        let all: Vec<(f64, f64)> = mine.iter().map(|r| (r.1, r.2)).collect();
        let projection: Vec<(f64, f64)> = mine.iter().map(|r| (r.1, r.3)).collect();
        chart
            .draw_series(LineSeries::new(all.clone(), colour.stroke_width(2)))?
            .label(format!("{family}: accelerations"))
            .legend(move |(x, y)| Rectangle::new([(x, y - 2), (x + 20, y + 2)], colour.filled()));
        chart.draw_series(all.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        let light = colour.mix(0.5);
        chart
            .draw_series(LineSeries::new(projection.clone(), light.stroke_width(2)))?
            .label(format!("{family}: Cᵀ M C and right side"))
            .legend(move |(x, y)| Rectangle::new([(x, y - 1), (x + 20, y + 1)], light.filled()));
        chart.draw_series(
            projection
                .iter()
                .map(|&p| TriangleMarker::new(p, 4, light.filled())),
        )?;
        // guides of slope 2 and 3 through the projection's first point
        let (n0, p0) = (first.1, first.3);
        for slope in [2.0, 3.0] {
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
