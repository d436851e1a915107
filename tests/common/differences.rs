//! Central differences, to check a generated Jacobian against.
use nonholonomic::prelude::*;

/// Max deviation of `jac` from central differences of `f` at `x`,
/// relative to max(1, |column entry|), with steps 1e-6 max(1, |x_c|).
#[allow(dead_code)]
pub fn jacobian_deviation<const D: usize>(
    f: impl Fn(&SVector<f64, D>) -> SVector<f64, D>,
    jac: &SMatrix<f64, D, D>,
    x: &SVector<f64, D>,
) -> f64 {
    jacobian_deviation_with_step(f, jac, x, 1e-6)
}

/// [`jacobian_deviation`] with steps `step` max(1, |x_c|).
#[allow(dead_code)]
pub fn jacobian_deviation_with_step<const D: usize>(
    f: impl Fn(&SVector<f64, D>) -> SVector<f64, D>,
    jac: &SMatrix<f64, D, D>,
    x: &SVector<f64, D>,
    step: f64,
) -> f64 {
    let mut worst = 0.0f64;
    for c in 0..D {
        let h = step * x[c].abs().max(1.0);
        let (mut xp, mut xm) = (*x, *x);
        xp[c] += h;
        xm[c] -= h;
        let col = (f(&xp) - f(&xm)) / (2.0 * h);
        for r in 0..D {
            worst = worst.max((jac[(r, c)] - col[r]).abs() / col[r].abs().max(1.0));
        }
    }
    worst
}
