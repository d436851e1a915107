//! Long-time behaviour of what is conserved: energy and the conserved
//! momenta (`outputs { momenta }`, DESIGN §4.1) over 10⁵ characteristic
//! periods, by GaussLegendre4 (symmetric) and by the explicit methods at
//! about the same number of right-hand sides:
//!
//! * the Chaplygin sleigh (`nh_lab::systems::ChaplyginSled`, its centre of
//!   mass ahead of the blade): energy;
//! * a disc rolling upright: energy, the rolling and heading momenta;
//! * the thesis's disc on a nutating motion: energy;
//! * a homogeneous ball rolling on the plane in yaw, pitch and roll:
//!   energy, the yaw momentum (the vertical angular momentum about the
//!   contact point) and the horizontal components of that angular
//!   momentum (`momenta { K_x(..); K_y(..); }`);
//! * the Suslov problem in speeds: energy;
//! * Modin and Verdier's non-reversible contact oscillator: energy. Its
//!   perturbation is a null Lagrangian in the velocities (the generated
//!   equations are the reversible oscillator's, `tests/momenta.rs`), so in
//!   this form it is reversible.
//!
//! ```text
//! cargo run --release -p nh-lab --example long_time
//! ```
//!
//! Prints, per system and method, the largest error so far at 10², 10³,
//! 10⁴ and 10⁵ periods, the slope of log error against log time over the
//! last three decades, and the cost; writes `target/reports/long_time.svg`
//! (error against time, log–log, one panel per system), of which
//! `docs/long_time.svg` is a copy.
use nh_lab::report;
use nh_lab::systems::{ChaplyginSled, ThesisDisc};
use nonholonomic::prelude::*;
use plotters::prelude::*;
use std::ops::Range;
use std::time::Instant;

nonholonomic_system! {
    /// A disc rolling upright.
    pub struct VerticalDisc {
        parameters { m, R, I, J }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + I/2*dot(theta)^2 + J/2*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { energy, momenta }
    }
}

nonholonomic_system! {
    /// A homogeneous ball rolling on the plane.
    pub struct RollingBall {
        parameters { m, R }
        coordinates { x, y, yaw, pitch, roll }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        let w = omega(Q);
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/5*(w.x^2 + w.y^2 + w.z^2);
        constraints {
            dot(x) = R*w.y;
            dot(y) = -R*w.x;
        }
        momenta {
            K_x(Q: [1, 0, 0], y: -R);
            K_y(Q: [0, 1, 0], x: R);
        }
        outputs { energy, momenta }
    }
}

nonholonomic_system! {
    /// Modin and Verdier's non-reversible member of the contact-oscillator
    /// family (McLachlan and Perlmutter's §5.2 with the Hamiltonian
    /// ½(|q|² + |p + ∇S|²), S = cos z): in the velocities its perturbation
    /// is the null Lagrangian −dS/dt.
    pub struct ShiftedOscillator {
        parameters { eps }
        coordinates { x, y, z }
        lagrangian = (dot(x)^2 + dot(y)^2 + dot(z)^2)/2 - (x^2 + y^2 + z^2 + eps*x^2*z^2)/2
                   + sin(z)*dot(z);
        constraints { dot(x) = -y*dot(z); }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// The Suslov problem in the speeds ω₁, ω₂ (ω₃ = 0 by construction),
    /// its orientation in yaw, pitch and roll.
    pub struct SuslovSpeeds {
        parameters { A, B, C, D, E }
        coordinates { psi, theta, phi }
        let Q = rot_z(psi) * rot_y(theta) * rot_x(phi);
        let w = omega_body(Q);
        lagrangian = (A*w.x^2 + B*w.y^2 + C*w.z^2)/2 + D*w.x*w.z + E*w.y*w.z;
        speeds { w1, w2 }
        kinematics {
            dot(psi) = w2*sin(phi)/cos(theta);
            dot(theta) = w2*cos(phi);
            dot(phi) = w1 + w2*sin(phi)*tan(theta);
        }
        outputs { energy }
    }
}

/// Periods the runs cover.
const PERIODS: f64 = 1e5;
/// GaussLegendre4's steps per period.
const STEPS_PER_PERIOD: f64 = 32.0;
/// Output samples per decade of time.
const PER_DECADE: usize = 10;

/// One run's record: the largest error so far of each quantity at the
/// sample times, and the cost.
struct Record {
    method: String,
    times: Vec<f64>,
    /// per quantity, the largest error up to each sample time
    errors: Vec<Vec<f64>>,
    rhs_evals: usize,
    seconds: f64,
}

/// A quantity watched along a run, of the system and its state.
type Quantity<S, const D: usize> = Box<dyn Fn(&S, &SVector<f64, D>) -> f64>;

/// A scene: a system, its state, its period, and the quantities watched.
struct Scene<S, const D: usize> {
    name: &'static str,
    sys: S,
    x0: SVector<f64, D>,
    period: f64,
    quantities: Vec<(&'static str, Quantity<S, D>)>,
}

/// The sample times: PER_DECADE per decade from one period to the end.
fn sample_times(period: f64) -> Vec<f64> {
    let decades = PERIODS.log10();
    let n = (decades * PER_DECADE as f64) as usize;
    (0..=n)
        .map(|i| period * 10f64.powf(i as f64 / PER_DECADE as f64))
        .collect()
}

impl<S: OdeSystem<f64, D>, const D: usize> Scene<S, D> {
    /// The quantities' names.
    fn names(&self) -> Vec<&'static str> {
        self.quantities.iter().map(|q| q.0).collect()
    }

    /// Runs `integrate(sys, x0, t1, times, observer)` and records the
    /// quantities' largest errors so far at the sample times.
    fn record(
        &self,
        method: &str,
        mut run: impl FnMut(
            &S,
            SVector<f64, D>,
            f64,
            &[f64],
            &mut dyn FnMut(f64, &SVector<f64, D>),
        ) -> usize,
    ) -> Record {
        let times = sample_times(self.period);
        let t1 = *times.last().unwrap_or(&self.period);
        let start: Vec<f64> = self
            .quantities
            .iter()
            .map(|(_, q)| q(&self.sys, &self.x0))
            .collect();
        let mut worst = vec![0.0f64; self.quantities.len()];
        let mut errors = vec![Vec::new(); self.quantities.len()];
        let clock = Instant::now();
        let evals = run(&self.sys, self.x0, t1, &times, &mut |_, x| {
            for (k, (_, q)) in self.quantities.iter().enumerate() {
                let e = (q(&self.sys, x) - start[k]).abs() / start[k].abs().max(1e-300);
                worst[k] = worst[k].max(e);
                errors[k].push(worst[k]);
            }
        });
        Record {
            method: method.to_string(),
            times,
            errors,
            rhs_evals: evals,
            seconds: clock.elapsed().as_secs_f64(),
        }
    }

    /// The runs of the scene: GaussLegendre4 at `STEPS_PER_PERIOD`, Rk4
    /// at the same right sides per period, Dop853 at the tolerance whose
    /// right sides over 100 periods come closest.
    fn runs(&self) -> Vec<Record> {
        let h = self.period / STEPS_PER_PERIOD;
        let t100 = 100.0 * self.period;
        let probe = GaussLegendre4::new(h).integrate(&self.sys, 0.0, self.x0, t100);
        let gl_evals = probe.map(|o| o.stats.rhs_evals as f64).unwrap_or(f64::NAN);
        let rk4_h = (4.0 * t100 / gl_evals).min(self.period / 4.0);
        let rtol = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
            .into_iter()
            .min_by(|&a, &b| {
                let cost = |r: f64| {
                    Dop853::new(r, r * 1e-2)
                        .integrate(&self.sys, 0.0, self.x0, t100)
                        .map_or(f64::INFINITY, |o| {
                            (o.stats.rhs_evals as f64 / gl_evals).ln().abs()
                        })
                };
                cost(a).total_cmp(&cost(b))
            })
            .unwrap_or(1e-8);
        let outputs = |out: Result<Outcome<f64, D>, SimError<f64, D>>| match out {
            Ok(o) => o.stats.rhs_evals,
            Err(e) => {
                eprintln!("{}: {e}", self.name);
                0
            }
        };
        vec![
            self.record(
                &format!("GaussLegendre4 h = T/{STEPS_PER_PERIOD}"),
                |s, x0, t1, times, obs| {
                    outputs(
                        GaussLegendre4::new(h)
                            .with_max_steps(usize::MAX)
                            .integrate_with_outputs(s, 0.0, x0, t1, times, obs),
                    )
                },
            ),
            self.record(
                &format!("Rk4 h = T/{:.0}", self.period / rk4_h),
                |s, x0, t1, times, obs| {
                    outputs(
                        Rk4::new(rk4_h)
                            .with_max_steps(usize::MAX)
                            .integrate_with_outputs(s, 0.0, x0, t1, times, obs),
                    )
                },
            ),
            self.record(
                &format!("Dop853 rtol {rtol:.0e}"),
                |s, x0, t1, times, obs| {
                    outputs(
                        Dop853::new(rtol, rtol * 1e-2)
                            .with_max_steps(usize::MAX)
                            .integrate_with_outputs(s, 0.0, x0, t1, times, obs),
                    )
                },
            ),
        ]
    }
}

/// The slope of log error against log time over the last three decades.
fn slope(times: &[f64], errors: &[f64]) -> f64 {
    let len = times.len().min(errors.len());
    let start = len.saturating_sub(3 * PER_DECADE + 1);
    let pts: Vec<(f64, f64)> = (start..len)
        .filter(|&i| errors[i] > 0.0)
        .map(|i| (times[i].ln(), errors[i].ln()))
        .collect();
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx).powi(2))
    });
    num / den
}

/// The table rows of a scene's records.
fn table(name: &str, period: f64, quantities: &[&str], records: &[Record]) {
    for r in records {
        for (k, q) in quantities.iter().enumerate() {
            let at = |periods: f64| {
                let i = r
                    .times
                    .iter()
                    .position(|&t| t >= periods * period * 0.999)
                    .unwrap_or(0);
                r.errors[k].get(i).copied().unwrap_or(f64::NAN)
            };
            println!(
                "| {name} | {} | {q} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {:.2} | {} | {:.2} |",
                r.method,
                at(1e2),
                at(1e3),
                at(1e4),
                at(1e5),
                slope(&r.times, &r.errors[k]),
                r.rhs_evals,
                r.seconds,
            );
        }
    }
}

/// The log–log panels: the relative errors of the watched quantities
/// against time, one panel per system, one colour per method; the energy
/// solid, each momentum dashed (its own dash length, named in the legend).
fn svg(panels: &[(&str, Vec<Record>, Vec<&str>)]) -> String {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (960, 1080)).into_drawing_area();
        let _ = root.fill(&WHITE);
        let areas = root.split_evenly((3, 2));
        // six panels for at most six systems
        for ((name, records, names), area) in panels.iter().zip(&areas) {
            let title = match names.len() {
                1 => format!("{name}: energy"),
                _ => format!("{name}: {}", names.join(", ")),
            };
            let Some(ranges) = panel_ranges(records) else {
                continue;
            };
            let Ok(mut chart) = report::log_log_axes(area, &title, ranges, "time") else {
                continue;
            };
            for (r, c) in records.iter().zip([RED, BLUE, GREEN]) {
                for (k, errors) in r.errors.iter().enumerate() {
                    let pts: Vec<(f64, f64)> = (r.times.iter().zip(errors))
                        .filter(|(_, e)| **e > 0.0)
                        .map(|(&t, &e)| (t, e))
                        .collect();
                    let label = match k {
                        0 => r.method.clone(),
                        _ => format!("{}: {}", r.method, names[k]),
                    };
                    let drawn = if k == 0 {
                        chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))
                    } else {
                        let dash = 2 + 4 * k as i32;
                        chart.draw_series(DashedLineSeries::new(pts, dash, 3, c.stroke_width(1)))
                    };
                    if let Ok(series) = drawn {
                        series
                            .label(label)
                            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
                    }
                }
            }
            let _ = chart
                .configure_series_labels()
                .background_style(WHITE)
                .border_style(BLACK)
                .label_font(("sans-serif", 10))
                .draw();
        }
        let _ = root.present();
    }
    out
}

/// A panel's ranges of time and error over every error of its records (a
/// nominal error range where the motion is exact and no error is nonzero).
fn panel_ranges(records: &[Record]) -> Option<(Range<f64>, Range<f64>)> {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for e in records.iter().flat_map(|r| r.errors.iter().flatten()) {
        if *e > 0.0 {
            lo = lo.min(*e);
            hi = hi.max(*e);
        }
    }
    let t = &records.first()?.times;
    let x = t[0]..*t.last().unwrap_or(&1.0);
    let (lo, hi) = if lo.is_finite() {
        (lo, hi.max(lo * 10.0))
    } else {
        (1e-17, 1e-15)
    };
    Some((x, lo..hi))
}

fn main() {
    // the Chaplygin sled, its centre of mass 0.2 ahead of the blade: it
    // spirals out to a straight line; the charts switch at θ = π/2
    let sleigh = Scene {
        name: "sleigh",
        sys: ChaplyginSled::new(2.0, 0.3, 0.2),
        x0: SVector::<f64, 5>::from([0.0, 0.4, 0.0, 0.7, 1.3]),
        period: 2.0 * std::f64::consts::PI / 1.3,
        quantities: vec![(
            "energy",
            Box::new(|s: &ChaplyginSled<f64>, x: &SVector<f64, 5>| {
                let q = SVector::<f64, 3>::from([x[0], x[1], x[2]]);
                s.energy(&q, &SVector::<f64, 2>::from([x[3], x[4]]))
            }),
        )],
    };
    let vertical = Scene {
        name: "vertical disc",
        sys: VerticalDisc::new(1.0, 0.3, 0.05, 0.02),
        x0: SVector::<f64, 6>::from([0.0, 0.0, 0.0, 0.0, 2.0, 1.0]),
        period: 2.0 * std::f64::consts::PI,
        quantities: {
            let split = |x: &SVector<f64, 6>| {
                (
                    SVector::<f64, 4>::from([x[0], x[1], x[2], x[3]]),
                    SVector::<f64, 2>::from([x[4], x[5]]),
                )
            };
            vec![
                (
                    "energy",
                    Box::new(move |s: &VerticalDisc<f64>, x: &SVector<f64, 6>| {
                        let (q, v) = split(x);
                        s.energy(&q, &v)
                    }),
                ),
                (
                    "p_theta",
                    Box::new(move |s: &VerticalDisc<f64>, x: &SVector<f64, 6>| {
                        let (q, v) = split(x);
                        s.momenta(0.0, &q, &v)[0]
                    }),
                ),
                (
                    "p_phi",
                    Box::new(move |s: &VerticalDisc<f64>, x: &SVector<f64, 6>| {
                        let (q, v) = split(x);
                        s.momenta(0.0, &q, &v)[1]
                    }),
                ),
            ]
        },
    };
    let thesis = Scene {
        name: "thesis disc",
        sys: ThesisDisc::new(1.0, 0.3, 9.81),
        // rolling at 6 rad/s with a lean of 0.3 and a nutation
        x0: SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 1.0, 0.5]),
        period: 0.25,
        quantities: vec![(
            "energy",
            Box::new(|s: &ThesisDisc<f64>, x: &SVector<f64, 8>| {
                let q = SVector::<f64, 5>::from([x[0], x[1], x[2], x[3], x[4]]);
                s.energy(&q, &SVector::<f64, 3>::from([x[5], x[6], x[7]]))
            }),
        )],
    };
    let ball = Scene {
        name: "rolling ball",
        sys: RollingBall::new(1.0, 0.3),
        x0: SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.5, -0.2, 0.7, -1.1, 2.0]),
        period: 2.0 * std::f64::consts::PI / 2.4,
        quantities: {
            let split = |x: &SVector<f64, 8>| {
                (
                    SVector::<f64, 5>::from_column_slice(&x.as_slice()[..5]),
                    SVector::<f64, 3>::from_column_slice(&x.as_slice()[5..]),
                )
            };
            vec![
                (
                    "energy",
                    Box::new(move |s: &RollingBall<f64>, x: &SVector<f64, 8>| {
                        let (q, v) = split(x);
                        s.energy(&q, &v)
                    }),
                ),
                (
                    "p_yaw",
                    Box::new(move |s: &RollingBall<f64>, x: &SVector<f64, 8>| {
                        let (q, v) = split(x);
                        s.momenta(0.0, &q, &v)[0]
                    }),
                ),
                (
                    "K_x",
                    Box::new(move |s: &RollingBall<f64>, x: &SVector<f64, 8>| {
                        let (q, v) = split(x);
                        s.declared_momenta(0.0, &q, &v)[0]
                    }),
                ),
                (
                    "K_y",
                    Box::new(move |s: &RollingBall<f64>, x: &SVector<f64, 8>| {
                        let (q, v) = split(x);
                        s.declared_momenta(0.0, &q, &v)[1]
                    }),
                ),
            ]
        },
    };
    println!("# Long-time behaviour, {PERIODS:.0e} periods\n");
    println!(
        "Relative error |Q(t) − Q(0)|/|Q(0)|, the largest up to 10², 10³, 10⁴ and 10⁵ periods; slope of log error against log time over the last three decades; right sides; seconds.\n"
    );
    println!("| system | method | quantity | 10² | 10³ | 10⁴ | 10⁵ | slope | rhs | s |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let r1 = sleigh.runs();
    table(sleigh.name, sleigh.period, &sleigh.names(), &r1);
    let r2 = vertical.runs();
    table(vertical.name, vertical.period, &vertical.names(), &r2);
    let r3 = thesis.runs();
    table(thesis.name, thesis.period, &thesis.names(), &r3);
    let r4 = ball.runs();
    table(ball.name, ball.period, &ball.names(), &r4);
    let oscillator = Scene {
        name: "Modin-Verdier oscillator",
        sys: ShiftedOscillator::new(0.1),
        // y(t) = cos t on the level H = 1.5 (as odelab's initial_cos, z0 = 0.3)
        x0: {
            let z0 = 0.3f64;
            let x = ((3.0 - z0 * z0 - 1.0) / (1.0 + 0.1 * z0 * z0)).sqrt();
            SVector::<f64, 5>::from([x, 1.0, z0, 0.0, 0.0])
        },
        period: 2.0 * std::f64::consts::PI,
        quantities: vec![(
            "energy",
            Box::new(|s: &ShiftedOscillator<f64>, x: &SVector<f64, 5>| {
                let q = SVector::<f64, 3>::from([x[0], x[1], x[2]]);
                s.energy(&q, &SVector::<f64, 2>::from([x[3], x[4]]))
            }),
        )],
    };
    let suslov = Scene {
        name: "Suslov (speeds)",
        sys: SuslovSpeeds::new(1.0, 2.0, 3.0, 0.4, 0.3),
        x0: SVector::<f64, 5>::from([0.0, 0.1, 0.3, 0.5, 0.2]),
        period: 2.0 * std::f64::consts::PI / 0.54,
        quantities: vec![(
            "energy",
            Box::new(|s: &SuslovSpeeds<f64>, x: &SVector<f64, 5>| {
                let q = SVector::<f64, 3>::from([x[0], x[1], x[2]]);
                s.energy(&q, &SVector::<f64, 2>::from([x[3], x[4]]))
            }),
        )],
    };
    let r6 = suslov.runs();
    table(suslov.name, suslov.period, &suslov.names(), &r6);
    let r5 = oscillator.runs();
    table(oscillator.name, oscillator.period, &oscillator.names(), &r5);
    let panels = [
        (sleigh.name, r1, sleigh.names()),
        (vertical.name, r2, vertical.names()),
        (thesis.name, r3, thesis.names()),
        (ball.name, r4, ball.names()),
        (oscillator.name, r5, oscillator.names()),
        (suslov.name, r6, suslov.names()),
    ];
    let dir = std::path::Path::new("target/reports");
    let _ = std::fs::create_dir_all(dir);
    if let Err(e) = std::fs::write(dir.join("long_time.svg"), svg(&panels)) {
        eprintln!("long_time.svg: {e}");
    }
    println!("\nWrote target/reports/long_time.svg");
}
