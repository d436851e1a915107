//! The Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina and Schwab
//! 2007) derived at compile time from its bodies and rolling contacts
//! (`model.rs`): the eigenvalues of the linearised roll and steer motion
//! against speed, read off the generated nonlinear system's Jacobian, the
//! weave and capsize speeds, a plot of the eigenvalues as the paper's
//! Figure 3 draws them (`target/whipple_eigenvalues.svg`), and nonlinear runs
//! inside and outside the self-stable speed range.
//!
//! Run with `cargo run --release --example whipple_bicycle`.
mod model;

use nonholonomic::prelude::*;
use plotters::prelude::*;

fn main() {
    let bike = model::benchmark();
    println!(
        "Eigenvalues of the linearised Whipple bicycle (roll, steer) from the generated Jacobian:"
    );
    println!("{:>5}  {:>40}", "v m/s", "eigenvalues (re ± im i)");
    for v in 0..=10 {
        let ev = model::eigenvalues(&bike, f64::from(v));
        let text: Vec<String> = ev
            .iter()
            .map(|(re, im)| {
                if *im == 0.0 {
                    format!("{re:.8}")
                } else {
                    format!("{re:.8}{im:+.8}i")
                }
            })
            .collect();
        println!("{v:>5}  {}", text.join("  "));
    }
    let weave = model::stability_boundary(&bike, 3.0, 5.0);
    let capsize = model::stability_boundary(&bike, 5.0, 7.0);
    println!(
        "weave speed {weave:.12} m/s (published 4.29238253634111), capsize speed {capsize:.12} m/s (published 6.02426201538837)"
    );
    match plot(&bike, "target/whipple_eigenvalues.svg") {
        Ok(()) => println!("wrote target/whipple_eigenvalues.svg"),
        Err(e) => println!("could not write the plot: {e}"),
    }
    println!(
        "\nNonlinear runs from upright, straight ahead, with a roll rate of 0.5 rad/s (Dormand–Prince, rtol 1e-10):"
    );
    for v in [3.0, 5.0, 7.0, 1.0] {
        run(&bike, v);
    }
}

/// Real parts (solid) and imaginary parts (dashed) of the eigenvalues
/// against speed, v = 0..10 m/s.
fn plot(bike: &model::Whipple, path: &str) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all("target")?;
    let root = SVGBackend::new(path, (800, 560)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Whipple bicycle: eigenvalues against speed",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..10.0, -10.0..10.0)?;
    chart
        .configure_mesh()
        .x_desc("forward speed v [m/s]")
        .y_desc("eigenvalue [1/s]")
        .draw()?;
    let speeds: Vec<f64> = (0..=400).map(|i| f64::from(i) / 40.0).collect();
    let spectra: Vec<Vec<(f64, f64)>> = speeds
        .iter()
        .map(|&v| model::eigenvalues(bike, v))
        .collect();
    // the real parts, sorted, are four continuous curves
    for k in 0..4 {
        let re = speeds.iter().zip(&spectra).map(|(&v, ev)| (v, ev[k].0));
        chart.draw_series(LineSeries::new(re, BLUE.stroke_width(2)))?;
    }
    // the imaginary part of the oscillating (weave) pair, where there is one
    let im = speeds
        .iter()
        .zip(&spectra)
        .map(|(&v, ev)| (v, ev.iter().map(|e| e.1.abs()).fold(0.0, f64::max)));
    chart
        .draw_series(LineSeries::new(im, RED.stroke_width(2)))?
        .label("|imaginary part|")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED));
    chart
        .draw_series(std::iter::once(PathElement::new([(0.0, 0.0)], BLUE)))?
        .label("real parts")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE));
    for (v, what) in [
        (model::stability_boundary(bike, 3.0, 5.0), "weave"),
        (model::stability_boundary(bike, 5.0, 7.0), "capsize"),
    ] {
        chart.draw_series(LineSeries::new([(v, -10.0), (v, 10.0)], BLACK.mix(0.4)))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("{what} {v:.3}"),
            (v + 0.05, 9.0),
            ("sans-serif", 13),
        )))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE)
        .border_style(BLACK)
        .draw()?;
    chart.draw_series(LineSeries::new([(0.0, 0.0), (10.0, 0.0)], BLACK))?;
    root.present()?;
    Ok(())
}

/// A run at speed `v` for 10 s: the roll angle every second, the energy's
/// relative drift, the largest holonomic residual and how the run ended.
fn run(bike: &model::Whipple, v: f64) {
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[8] = 0.5; // roll rate
    x0[10] = v / bike.rR; // rear wheel rate
    let energy = |x: &SVector<f64, 11>| {
        let (q, r) = (
            x.fixed_rows::<8>(0).into_owned(),
            x.fixed_rows::<3>(8).into_owned(),
        );
        bike.energy(&q, &r)
    };
    let e0 = energy(&x0);
    let (mut drift, mut next, mut rolls) = (0.0_f64, 1.0, Vec::new());
    let out = Dopri5::new(1e-10, 1e-12).integrate_with_observer(bike, 0.0, x0, 10.0, |t, x| {
        drift = drift.max(((energy(x) - e0) / e0).abs());
        if t >= next {
            rolls.push(format!("{:+.4}", x[0]));
            next += 1.0;
        }
    });
    let ending = match &out {
        Ok(o) => format!(
            "reached t = {:.1} s, {} steps, holonomic residual ≤ {:.1e}",
            o.t,
            o.stats.steps,
            o.max_residual.unwrap_or(0.0)
        ),
        Err(SimError::Singular { t, x, .. }) => format!(
            "fell: the run ends at t = {t:.3} s with a singular chart at roll {:.3} rad, steer {:.3} rad (the yaw rate, a dependent velocity here, is not defined by the front wheel turned across the frame)",
            x[0], x[1]
        ),
        Err(e) => format!("ended: {e}"),
    };
    println!("v = {v} m/s: roll at t = 1, 2, .. s: {}", rolls.join(" "));
    println!("    energy drift {drift:.1e}; {ending}");
}
