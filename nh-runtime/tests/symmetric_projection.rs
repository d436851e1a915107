//! GaussLegendre4's projection onto holonomic constraints is symmetric
//! (Hairer's symmetric projection), so that a run forward and back returns
//! to its start. The system: an oscillator u'' = −u − w/2 with a third
//! coordinate w tied to it by the cubic constraint w = u³/3, which the flow
//! keeps (w' = u² u') but a Runge–Kutta step does not (only quadratic
//! invariants are kept), so that every step's end is projected: w moved to
//! u³/3, a fixed direction, as a generated system moves its dependent
//! coordinates. Its energy (u² + v²)/2 + u⁴/24 is conserved.
use nalgebra::SVector;
use nh_runtime::{GaussLegendre4, Integrator, OdeSystem, ProjectionFailure};

struct Tied;

impl OdeSystem<f64, 3> for Tied {
    fn rhs(&self, _t: f64, x: &SVector<f64, 3>) -> SVector<f64, 3> {
        SVector::from([x[1], -x[0] - 0.5 * x[2], x[0] * x[0] * x[1]])
    }
    fn constraint_residual(&self, _t: f64, x: &SVector<f64, 3>) -> Option<f64> {
        Some((x[2] - x[0].powi(3) / 3.0).abs())
    }
    fn project(&self, _t: f64, x: &mut SVector<f64, 3>) -> Result<bool, ProjectionFailure<f64>> {
        let w = x[0].powi(3) / 3.0;
        let moved = w != x[2];
        x[2] = w;
        Ok(moved)
    }
}

#[test]
fn forward_and_back_returns_to_the_start() {
    // 100 steps of h = 0.3 (about 5 periods) forward, then back
    let x0 = SVector::<f64, 3>::from([1.2, 0.0, 1.2f64.powi(3) / 3.0]);
    let mut gl = GaussLegendre4::new(0.3);
    let there = gl.integrate(&Tied, 0.0, x0, 30.0).unwrap();
    let back = gl.integrate(&Tied, 30.0, there.x, 0.0).unwrap();
    let gap = (back.x - x0).amax();
    println!(
        "h = 0.3 over 30 and back: {gap:.1e} from the start; largest residual {:.1e}",
        there.max_residual.unwrap_or(f64::NAN)
    );
    assert!(gap < 1e-12, "{gap:e}");
}

#[test]
fn the_oscillators_energy_stays_bounded() {
    // (u² + v²)/2 + u⁴/24 over 10⁴ steps, its largest error in the second
    // half no larger than in the first
    let x0 = SVector::<f64, 3>::from([1.2, 0.0, 1.2f64.powi(3) / 3.0]);
    let times: Vec<f64> = (1..=3000).map(f64::from).collect();
    let (mut first, mut second) = (0.0f64, 0.0f64);
    GaussLegendre4::new(0.3)
        .integrate_with_outputs(&Tied, 0.0, x0, 3000.0, &times, |t, x| {
            let energy =
                |x: &SVector<f64, 3>| (x[0] * x[0] + x[1] * x[1]) / 2.0 + x[0].powi(4) / 24.0;
            let e = (energy(x) - energy(&x0)).abs();
            if t <= 1500.0 {
                first = first.max(e);
            } else {
                second = second.max(e);
            }
        })
        .unwrap();
    println!("energy: error {first:.2e} up to t = 1500, {second:.2e} after");
    assert!(second <= 1.5 * first + 1e-15, "{first:e} {second:e}");
}
