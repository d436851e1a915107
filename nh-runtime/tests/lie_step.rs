//! The Lie-group step of a free rotation (DESIGN §9.4), on a body turning
//! at a constant angular velocity, written by hand in yaw, pitch and roll
//! with the three other sequences as charts: the one-step integrators
//! advance the rotation in canonical coordinates, in which this motion is
//! linear, so that they reproduce it to rounding error over many turns
//! with steps as long as the canonical coordinates allow, through gimbal
//! lock; `Bdf` switches sequences.

use nalgebra::{Matrix3, SVector, Vector3};
use nh_runtime::{
    Bdf, Dop853, Dopri5, EulerSequence, FreeRotation, GaussLegendre4, Integrator, OdeSystem, Rk4,
    Rodas4,
};

/// A body turning at a constant angular velocity, its state the angles of
/// `SEQUENCES[0]` and their rates; `world`: which components the
/// canonical coordinates carry.
struct Spinning {
    world: bool,
}

/// Yaw-pitch-roll and the three sequences the macro gives it.
const SEQUENCES: [EulerSequence; 4] = [
    EulerSequence::ZYX,
    EulerSequence::ZXY,
    EulerSequence::XYZ,
    EulerSequence::YXZ,
];

fn split(x: &SVector<f64, 6>) -> ([f64; 3], [f64; 3]) {
    ([x[0], x[1], x[2]], [x[3], x[4], x[5]])
}

impl OdeSystem<f64, 6> for Spinning {
    fn rhs(&self, t: f64, x: &SVector<f64, 6>) -> SVector<f64, 6> {
        self.rhs_in_chart(0, t, x)
    }
    fn chart_regularity(&self, t: f64, x: &SVector<f64, 6>) -> Option<f64> {
        self.chart_regularity_in(0, t, x)
    }
    fn charts(&self) -> usize {
        4
    }
    fn rhs_in_chart(&self, chart: usize, _t: f64, x: &SVector<f64, 6>) -> SVector<f64, 6> {
        // ω_b constant: W q̈ = −Σ q̇_i q̇_j (u_i × u_j)
        let seq = SEQUENCES[chart];
        let (q, v) = split(x);
        let bias = seq.body_accelerations(&q, &v, &[0.0; 3]);
        let a = seq.rates(&q, &-bias);
        SVector::from([v[0], v[1], v[2], a[0], a[1], a[2]])
    }
    fn chart_regularity_in(&self, chart: usize, _t: f64, x: &SVector<f64, 6>) -> Option<f64> {
        Some(SEQUENCES[chart].regularity(&split(x).0))
    }
    fn change_chart(
        &self,
        from: usize,
        to: usize,
        _t: f64,
        x: &SVector<f64, 6>,
    ) -> SVector<f64, 6> {
        let (q, v) = split(x);
        let (a, r) = EulerSequence::change(SEQUENCES[from], SEQUENCES[to], &q, &v, None);
        SVector::from([a[0], a[1], a[2], r[0], r[1], r[2]])
    }
    fn change_chart_near(
        &self,
        from: usize,
        to: usize,
        _t: f64,
        x: &SVector<f64, 6>,
        near: &SVector<f64, 6>,
    ) -> SVector<f64, 6> {
        let (q, v) = split(x);
        let n = split(near).0;
        let (a, r) = EulerSequence::change(SEQUENCES[from], SEQUENCES[to], &q, &v, Some(&n));
        SVector::from([a[0], a[1], a[2], r[0], r[1], r[2]])
    }
    fn chart_switch_below(&self, _chart: usize) -> f64 {
        0.4
    }
    fn free_rotation(&self, chart: usize) -> Option<FreeRotation> {
        Some(FreeRotation {
            sequence: SEQUENCES[chart],
            angles: [0, 1, 2],
            rates: [3, 4, 5],
            world: self.world,
        })
    }
}

/// World angular velocity (rad/s): a turn every 0.8 s about a tilted axis.
const OMEGA: [f64; 3] = [3.0, -2.0, 6.5];

/// The state at the orientation `angles` turning at `OMEGA`.
fn start(angles: [f64; 3]) -> SVector<f64, 6> {
    let seq = SEQUENCES[0];
    let r = seq.matrix(&angles);
    let v = seq.rates(&angles, &(r.transpose() * Vector3::from(OMEGA)));
    SVector::from([angles[0], angles[1], angles[2], v[0], v[1], v[2]])
}

/// The exact orientation at t: exp(t [ω]×) R0, Rodrigues' formula.
fn exact(angles: [f64; 3], t: f64) -> Matrix3<f64> {
    let w = Vector3::from(OMEGA);
    let a = w.norm() * t;
    let n = w.normalize();
    let k = Matrix3::new(0.0, -n.z, n.y, n.z, 0.0, -n.x, -n.y, n.x, 0.0);
    let turn = Matrix3::identity() + k * a.sin() + k * k * (1.0 - a.cos());
    turn * SEQUENCES[0].matrix(&angles)
}

/// The largest gap of the orientation at `x` (chart 0's angles) from the
/// exact one at t, and of its world angular velocity from `OMEGA`.
fn gaps(x: &SVector<f64, 6>, angles: [f64; 3], t: f64) -> (f64, f64) {
    let seq = SEQUENCES[0];
    let (q, v) = split(x);
    let r = seq.matrix(&q);
    let w = r * seq.body_rates(&q, &v);
    (
        (r - exact(angles, t)).amax(),
        (w - Vector3::from(OMEGA)).amax(),
    )
}

#[test]
fn one_step_methods_turn_the_body_exactly_through_gimbal_lock() {
    // 20 s, 25 turns, from 0.05 short of the pole
    let angles = [0.3, std::f64::consts::FRAC_PI_2 - 0.05, -0.2];
    let x0 = start(angles);
    for world in [true, false] {
        let sys = Spinning { world };
        let runs = [
            (
                "Dopri5",
                Dopri5::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 20.0),
            ),
            (
                "Dop853",
                Dop853::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 20.0),
            ),
            (
                "Rodas4",
                Rodas4::new(1e-8, 1e-10).integrate(&sys, 0.0, x0, 20.0),
            ),
            ("Rk4", Rk4::new(0.05).integrate(&sys, 0.0, x0, 20.0)),
            (
                "GaussLegendre4",
                GaussLegendre4::new(0.05).integrate(&sys, 0.0, x0, 20.0),
            ),
        ];
        for (name, out) in runs {
            let out = out.unwrap();
            let (rot, spin) = gaps(&out.x, angles, 20.0);
            println!(
                "world {world}, {name}: {} steps + {} rejected, {} switches; orientation {rot:.1e}, ω {spin:.1e}",
                out.stats.steps, out.stats.rejected, out.stats.chart_switches
            );
            assert_eq!(out.stats.chart_switches, 0, "{name}");
            if name == "Rodas4" {
                // its Jacobian, by finite differences, is not exact, and
                // neither is a Rosenbrock step then
                assert!(rot < 1e-6 && spin < 1e-6, "{name}: {rot:e} {spin:e}");
                continue;
            }
            assert!(rot < 1e-11, "{name}: {rot:e}");
            assert!(spin < 1e-11, "{name}: {spin:e}");
            // each adaptive step turns the body by half a turn
            if name.starts_with("Dop") {
                assert!(out.stats.steps <= 60, "{name}: {}", out.stats.steps);
            }
        }
    }
}

#[test]
fn bdf_switches_sequences_instead() {
    let angles = [0.3, std::f64::consts::FRAC_PI_2 - 0.05, -0.2];
    let x0 = start(angles);
    let out = Bdf::new(1e-9, 1e-11)
        .integrate(&Spinning { world: true }, 0.0, x0, 5.0)
        .unwrap();
    let (rot, spin) = gaps(&out.x, angles, 5.0);
    println!(
        "Bdf: {} steps, {} switches; orientation {rot:.1e}, ω {spin:.1e}",
        out.stats.steps, out.stats.chart_switches
    );
    assert!(out.stats.chart_switches >= 1);
    assert!(rot < 1e-5 && spin < 1e-5, "{rot:e} {spin:e}");
}

#[test]
fn the_angles_handed_out_are_continuous_and_chart_0_s() {
    // outputs every 1 ms: the angles change by less than the spin allows
    // where chart 0 is regular, and reproduce the exact rotation
    let angles = [0.3, 1.2, -0.2];
    let x0 = start(angles);
    let times: Vec<f64> = (1..=4000).map(|i| 1e-3 * i as f64).collect();
    let mut worst = (0.0f64, 0.0f64);
    let mut last = x0;
    Dop853::new(1e-10, 1e-12)
        .integrate_with_outputs(&Spinning { world: false }, 0.0, x0, 4.0, &times, |t, x| {
            let (rot, _) = gaps(x, angles, t);
            worst.0 = worst.0.max(rot);
            if x[1].cos().abs() > 0.3 && last[1].cos().abs() > 0.3 {
                worst.1 = (0..3)
                    .map(|i| (x[i] - last[i]).abs())
                    .fold(worst.1, f64::max);
            }
            last = *x;
        })
        .unwrap();
    println!(
        "orientation {:.1e}, largest angle step {:.3}",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-10, "{}", worst.0);
    assert!(worst.1 < 0.5, "{}", worst.1);
}
