//! The bounds of an adaptive step: the smallest step the clock resolves
//! (`min_step`) and the first trial step (`initial_step`, Hairer's `hinit`).

use nalgebra::{RealField, SVector};

use crate::numeric::c;
use crate::tolerance::{Tolerance, scaled};
use crate::{OdeSystem, Stats};

/// The smallest step magnitude an adaptive method may take at `t`:
/// `10·eps·|t|` (the resolution of `t`, as in Hairer's codes), floored at
/// `10·eps²·|t1|` so that it stays positive near `t = 0` without stopping
/// short initial transients of long integrations, and at
/// `1 / (eps·T::MAX)` (about 2.5e-293 in `f64`) so that it never underflows
/// and `1/h` stays finite. A span below it is covered in one Euler step.
pub(crate) fn min_step<T: RealField + Copy>(eps: T, t: T, t1: T) -> T {
    let floor = T::max_value().map_or(T::zero(), |max| T::one() / (max * eps));
    (c::<T>(10.0) * eps * t.abs().max(eps * t1.abs())).max(floor)
}

/// Hairer's `hinit`: a first step magnitude for a method of order `order`
/// from `f0 = f(t, x)` and one explicit Euler probe step (one evaluation of
/// the right-hand side, counted in `stats`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<T, S, const D: usize>(
    sys: &S,
    stats: &mut Stats,
    t: T,
    x: &SVector<T, D>,
    f0: &SVector<T, D>,
    dir: T,
    hmax: T,
    tol: &Tolerance<T, D>,
    order: u32,
) -> T
where
    T: RealField + Copy,
    S: OdeSystem<T, D> + ?Sized,
{
    let sk = tol.weights_at(x);
    let ratio = |v: &SVector<T, D>| v.zip_map(&sk, scaled).norm_squared();
    let (dnf, dny) = (ratio(f0), ratio(x));
    let tiny = c::<T>(1e-10);
    let mut h = if dnf <= tiny || dny <= tiny || !(dnf / dny).is_finite() {
        c::<T>(1e-6)
    } else {
        (dny / dnf).sqrt() * c::<T>(0.01)
    };
    h = h.min(hmax);
    // One explicit Euler step to estimate the second derivative.
    let x1 = x + f0 * (h * dir);
    let f1 = sys.rhs(t + h * dir, &x1);
    stats.rhs_evals += 1;
    let der2 = ratio(&(f1 - f0)).sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if !(der2.is_finite() && der12.is_finite()) {
        // The probe step produced garbage: stay cautious.
        h * c::<T>(1e-3)
    } else if der12 <= c::<T>(1e-15) {
        c::<T>(1e-6).max(h * c::<T>(1e-3))
    } else {
        (c::<T>(0.01) / der12).powf(T::one() / c::<T>(f64::from(order)))
    };
    (h * c::<T>(100.0)).min(h1).min(hmax)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector1;

    #[test]
    fn min_step_resolves_t_and_never_underflows() {
        let eps = f64::EPSILON;
        assert_eq!(min_step(eps, 1.0, 2.0), 10.0 * eps);
        assert_eq!(min_step(eps, -4.0, 0.0), 10.0 * eps * 4.0);
        // Near t = 0 the floor comes from the end of the span.
        assert_eq!(min_step(eps, 0.0, 1e6), 10.0 * eps * (eps * 1e6));
        // With t = t1 = 0 only the floor `1/(eps·MAX)` is left.
        let floor = min_step(eps, 0.0, 0.0);
        assert_eq!(floor, 1.0 / (f64::MAX * eps));
        assert!(floor > 0.0 && (1.0 / floor).is_finite());
    }

    #[test]
    fn initial_step_follows_hairers_hinit() {
        // x' = −x at x = 1 with sk = 2e-6: ‖f0‖ = ‖x‖, so h = 0.01; the Euler
        // probe gives ‖f1 − f0‖/h = ‖f0‖ = 5e5, so h1 = (0.01/5e5)^(1/5).
        let decay = |_t: f64, x: &Vector1<f64>| -x;
        let tol = Tolerance::uniform(1e-6, 1e-6);
        let (x, f0) = (Vector1::new(1.0), Vector1::new(-1.0));
        let mut stats = Stats::default();
        let h = initial_step(&decay, &mut stats, 0.0, &x, &f0, 1.0, 10.0, &tol, 5);
        assert!((h - 2e-8f64.powf(0.2)).abs() < 1e-12, "{h}");
        assert_eq!(stats.rhs_evals, 1);
        // Capped at the largest step.
        let h = initial_step(&decay, &mut stats, 0.0, &x, &f0, 1.0, 1e-3, &tol, 5);
        assert_eq!(h, 1e-3);
        assert_eq!(stats.rhs_evals, 2);
    }

    #[test]
    fn initial_step_is_cautious_without_a_derivative() {
        // f = 0 everywhere: no scale to go by, Hairer's 1e-6.
        let rest = |_t: f64, _x: &Vector1<f64>| Vector1::zeros();
        let tol = Tolerance::uniform(1e-6, 1e-6);
        let (x, f0) = (Vector1::new(1.0), Vector1::zeros());
        let mut stats = Stats::default();
        let h = initial_step(&rest, &mut stats, 0.0, &x, &f0, -1.0, 10.0, &tol, 4);
        assert_eq!(h, 1e-6);
        // A probe that turns non-finite shrinks the step a thousandfold.
        let blow_up = |_t: f64, _x: &Vector1<f64>| Vector1::new(f64::NAN);
        let f0 = Vector1::new(-1.0);
        let h = initial_step(&blow_up, &mut stats, 0.0, &x, &f0, 1.0, 10.0, &tol, 4);
        assert_eq!(h, 0.01 * 1e-3);
    }
}
