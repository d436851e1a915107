//! Test problems shared by the integration tests.
#![allow(dead_code)]

use nalgebra::{SVector, Vector1, Vector2};
use nh_runtime::OdeSystem;

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
