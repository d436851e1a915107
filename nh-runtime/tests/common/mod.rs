//! Test problems shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{Matrix2, Matrix3, SVector, Vector1, Vector2, Vector3};
use nh_runtime::{OdeJacobian, OdeSystem};

/// `x' = -x`.
pub struct Decay;

impl OdeSystem<f64, 1> for Decay {
    fn rhs(&self, _t: f64, x: &Vector1<f64>) -> Vector1<f64> {
        -x
    }
}

/// Harmonic oscillator `q'' = -q` as `(q, p)' = (p, -q)`; generic over the scalar.
pub struct Oscillator;

impl<T: nalgebra::RealField + Copy> OdeSystem<T, 2> for Oscillator {
    fn rhs(&self, _t: T, x: &Vector2<T>) -> Vector2<T> {
        Vector2::new(x[1], -x[0])
    }
}

/// Exact oscillator state at `t` from `(1, 0)` at 0.
pub fn oscillator_exact(t: f64) -> Vector2<f64> {
    Vector2::new(t.cos(), -t.sin())
}

/// `x' = x^2`, blows up at `t = 1/x0`.
pub struct BlowUp;

impl OdeSystem<f64, 1> for BlowUp {
    fn rhs(&self, _t: f64, x: &Vector1<f64>) -> Vector1<f64> {
        x.component_mul(x)
    }
}

/// Prothero–Robinson-like stiff problem `x' = -1e6 (x - cos t)`.
pub struct Stiff;

impl OdeSystem<f64, 1> for Stiff {
    fn rhs(&self, t: f64, x: &Vector1<f64>) -> Vector1<f64> {
        Vector1::new(-1e6 * (x[0] - t.cos()))
    }
}

/// Three uncoupled oscillators with frequencies 1, 2, 3 (D = 6).
pub struct Oscillators3;

impl OdeSystem<f64, 6> for Oscillators3 {
    fn rhs(&self, _t: f64, x: &SVector<f64, 6>) -> SVector<f64, 6> {
        SVector::<f64, 6>::from([x[1], -x[0], x[3], -4.0 * x[2], x[5], -9.0 * x[4]])
    }
}

/// Max-norm difference.
pub fn max_err<const D: usize>(a: &SVector<f64, D>, b: &SVector<f64, D>) -> f64 {
    (a - b).amax()
}

/// Van der Pol in the scaling of the Test Set for IVP Solvers (problem
/// VDPOL): `y1' = y2`, `y2' = ((1 − y1²) y2 − y1)/ε`, `ε` = [`VDPOL_EPS`],
/// which is `μ = 1000` with time measured in units of `μ`.
pub struct VanDerPolTestSet;

/// ε of [`VanDerPolTestSet`].
pub const VDPOL_EPS: f64 = 1e-6;

impl OdeSystem<f64, 2> for VanDerPolTestSet {
    fn rhs(&self, _t: f64, y: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(y[1], ((1.0 - y[0] * y[0]) * y[1] - y[0]) / VDPOL_EPS)
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

impl OdeJacobian<f64, 2> for VanDerPolTestSet {
    fn jacobian(&self, _t: f64, y: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(
            0.0,
            1.0,
            (-2.0 * y[0] * y[1] - 1.0) / VDPOL_EPS,
            (1.0 - y[0] * y[0]) / VDPOL_EPS,
        )
    }
}

/// The state of VDPOL at `t = 2` from `y(0) = (2, 0)`, from the Test Set
/// for IVP Solvers (Mazzia & Magherini, University of Bari, `vdpol.f`,
/// `solut`): RADAU in extended precision, `rtol = atol = h0 = 1.1e-18`.
pub const VDPOL_AT_2: [f64; 2] = [1.706167732170483, -0.8928097010247975];

/// Robertson's chemical kinetics (Hairer & Wanner's ROBER).
pub struct Robertson;

impl OdeSystem<f64, 3> for Robertson {
    fn rhs(&self, _t: f64, y: &Vector3<f64>) -> Vector3<f64> {
        let r1 = 0.04 * y[0];
        let r2 = 1e4 * y[1] * y[2];
        let r3 = 3e7 * y[1] * y[1];
        Vector3::new(-r1 + r2, r1 - r2 - r3, r3)
    }
}

impl OdeJacobian<f64, 3> for Robertson {
    fn jacobian(&self, _t: f64, y: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::new(
            -0.04,
            1e4 * y[2],
            1e4 * y[1],
            0.04,
            -1e4 * y[2] - 6e7 * y[1],
            -1e4 * y[1],
            0.0,
            6e7 * y[1],
            0.0,
        )
    }
}

/// ROBER at t = 40 (Hairer & Wanner, *Solving ODEs II*, IV.10, 7 digits).
pub const ROBER_AT_40: [f64; 3] = [0.7158271, 9.185535e-6, 0.2841637];
