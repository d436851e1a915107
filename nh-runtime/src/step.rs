//! One accepted step and its continuous extension ("dense output").

use core::fmt;

use nalgebra::{RealField, SVector};

/// Maximal number of polynomial coefficients (degree ≤ 7).
pub(crate) const MAX_COEFFS: usize = 8;

/// The "nested" basis `1, s, s(1−s), s²(1−s), s²(1−s)², s³(1−s)², s³(1−s)³,
/// s⁴(1−s)³` of Hairer's `CONTD5`/`CONTD8`/`CONTRO` routines, as monomial
/// coefficients (row `k` holds the coefficients of basis polynomial `k`).
const NESTED: [[f64; MAX_COEFFS]; MAX_COEFFS] = [
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, -2.0, 1.0, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 1.0, -2.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, 1.0, -3.0, 3.0, -1.0, 0.0],
    [0.0, 0.0, 0.0, 0.0, 1.0, -3.0, 3.0, -1.0],
];

/// The first four terms of Hairer's nested dense output for a step
/// `(x, f) → (x_new, f_new)` of size `h`: `x`, `Δ = x_new − x`,
/// `r3 = h f − Δ`, `r4 = Δ − h f_new − r3` (alone, the cubic Hermite
/// interpolant; `CONTD5` and `CONTD8` add higher terms).
pub(crate) fn hermite_terms<T: RealField + Copy, const D: usize>(
    x: &SVector<T, D>,
    f: &SVector<T, D>,
    x_new: &SVector<T, D>,
    f_new: &SVector<T, D>,
    h: T,
) -> [SVector<T, D>; 4] {
    let ydiff = x_new - x;
    let bspl = f * h - ydiff;
    [*x, ydiff, bspl, ydiff - f_new * h - bspl]
}

/// A vector polynomial `x(θ) = Σ_j c_j θ^j` in the normalised step time
/// `θ = (t − t_prev)/h`, of degree `< MAX_COEFFS`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Poly<T, const D: usize> {
    c: [SVector<T, D>; MAX_COEFFS],
    n: usize,
}

impl<T: RealField + Copy, const D: usize> Poly<T, D> {
    /// The polynomial with the given monomial coefficients (lowest first).
    pub(crate) fn from_monomial(coeffs: &[SVector<T, D>]) -> Self {
        debug_assert!(coeffs.len() <= MAX_COEFFS);
        let mut c = [SVector::<T, D>::zeros(); MAX_COEFFS];
        c[..coeffs.len()].copy_from_slice(coeffs);
        Self { c, n: coeffs.len() }
    }

    /// The polynomial `Σ_k r_k p_k(θ)` in Hairer's nested basis, i.e.
    /// `r0 + θ(r1 + (1−θ)(r2 + θ(r3 + (1−θ)(r4 + …))))`.
    pub(crate) fn from_nested(r: &[SVector<T, D>]) -> Self {
        debug_assert!(r.len() <= MAX_COEFFS);
        let mut c = [SVector::<T, D>::zeros(); MAX_COEFFS];
        for (k, rk) in r.iter().enumerate() {
            for (j, &w) in NESTED[k].iter().enumerate().take(k + 1) {
                if w != 0.0 {
                    c[j] += rk * nalgebra::convert::<f64, T>(w);
                }
            }
        }
        Self { c, n: r.len() }
    }

    /// Whether every coefficient is finite.
    pub(crate) fn is_finite(&self) -> bool {
        crate::numeric::all_finite_in(&self.c[..self.n])
    }

    /// Horner evaluation at `θ`.
    pub(crate) fn eval(&self, theta: T) -> SVector<T, D> {
        if self.n == 0 {
            return SVector::zeros();
        }
        let mut x = self.c[self.n - 1];
        for j in (0..self.n - 1).rev() {
            x = x * theta + self.c[j];
        }
        x
    }
}

/// One accepted step `[t_prev, t]` with its dense output (continuous
/// extension).
///
/// Handed to the callback of
/// [`Integrator::integrate_with_steps`](crate::Integrator::integrate_with_steps)
/// after every accepted step. [`Step::interpolate`] evaluates the
/// integrator's own continuous extension, whose accuracy depends on the
/// method:
///
/// | integrator | dense output |
/// |---|---|
/// | [`Rk4`](crate::Rk4) | the standard 3rd-order extension of classical RK4 |
/// | [`Dopri5`](crate::Dopri5) | Hairer's 4th-order `CONTD5` (Shampine's coefficients) |
/// | [`Dop853`](crate::Dop853) | Hairer's 7th-order `CONTD8` (three extra stages, computed only for steps that are interpolated) |
/// | [`Rodas4`](crate::Rodas4) | the 3rd-order formula of Hairer's `RODAS` |
/// | [`Rodas5P`](crate::Rodas5P) | Steinebach's 4th-order formula (the same form, one term more) |
/// | [`Bdf`](crate::Bdf) | the interpolating polynomial of the step's order `q` (1–5) through the new state and the `q` grid points before it |
/// | [`GaussLegendre4`](crate::GaussLegendre4) | cubic Hermite from `(x_prev, f_prev, x, f)` (3rd order, C¹) |
///
/// All of them are continuous across steps and reproduce `x_prev` and `x`
/// exactly at the ends of the step. The dense output is built, and checked
/// to be finite, before the step is accepted; asking for it never changes
/// the steps: where it is not finite (`Dop853`'s extra stages outside the
/// domain of the right-hand side, or an overflow near the largest float)
/// the step stands and is interpolated on a lower-order extension instead,
/// `Dop853`'s cubic Hermite interpolant of the step's ends or, for the
/// other methods, the chord from `x_prev` to `x`. An interpolated sample
/// is never NaN.
///
/// For a system with several charts ([`OdeSystem::charts`](crate::OdeSystem::charts))
/// the steps are reported in chart 0's layout wherever the run is: in
/// another chart the ends are mapped by
/// [`OdeSystem::change_chart`](crate::OdeSystem::change_chart) and so is
/// every interpolated point (the polynomial is the chart's; the chord
/// fallback joins the mapped ends).
///
/// # Example
///
/// ```rust
/// use nalgebra::Vector2;
/// use nh_runtime::{Dopri5, Integrator};
///
/// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
/// let mut worst: f64 = 0.0;
/// Dopri5::new(1e-9, 1e-12)
///     .integrate_with_steps(&oscillator, 0.0, Vector2::new(1.0, 0.0), 5.0, |step| {
///         // Check the interpolant in the middle of every step.
///         let tm = 0.5 * (step.t_prev() + step.t());
///         worst = worst.max((step.interpolate(tm)[0] - tm.cos()).abs());
///     })
///     .unwrap();
/// assert!(worst < 1e-7, "{worst:e}");
/// ```
pub struct Step<'a, T, const D: usize> {
    t_prev: T,
    t: T,
    x_prev: &'a SVector<T, D>,
    x: &'a SVector<T, D>,
    dense: Option<&'a Poly<T, D>>,
    /// The length of time the dense output's `θ ∈ [0, 1]` spans: `t −
    /// t_prev`, or the whole step's for a [`Step::truncated`] one.
    span: T,
    /// The map from the chart the dense output is in to the layout the
    /// step is reported in (chart 0), for a step of a run in another
    /// chart ([`Step::mapped`]); the ends are already mapped.
    map: Option<&'a ChartMap<'a, T, D>>,
}

/// A map of states `(t, x) ↦ x'` between the charts of a system.
pub(crate) type ChartMap<'a, T, const D: usize> = dyn Fn(T, &SVector<T, D>) -> SVector<T, D> + 'a;

impl<'a, T: RealField + Copy, const D: usize> Step<'a, T, D> {
    pub(crate) fn new(
        t_prev: T,
        x_prev: &'a SVector<T, D>,
        t: T,
        x: &'a SVector<T, D>,
        dense: Option<&'a Poly<T, D>>,
    ) -> Self {
        Self {
            t_prev,
            t,
            x_prev,
            x,
            dense,
            span: t - t_prev,
            map: None,
        }
    }

    /// This step reported in another chart: the ends `x_prev` and `x`
    /// already mapped, and every interpolated point mapped by `map`.
    pub(crate) fn mapped<'b>(
        &self,
        x_prev: &'b SVector<T, D>,
        x: &'b SVector<T, D>,
        map: &'b ChartMap<'b, T, D>,
    ) -> Step<'b, T, D>
    where
        'a: 'b,
    {
        Step {
            t_prev: self.t_prev,
            t: self.t,
            x_prev,
            x,
            dense: self.dense,
            span: self.span,
            map: Some(map),
        }
    }

    /// The first part of this step, up to `t` inside it where the dense
    /// output is `x` (the same interpolant).
    pub(crate) fn truncated<'b>(&self, t: T, x: &'b SVector<T, D>) -> Step<'b, T, D>
    where
        'a: 'b,
    {
        Step {
            t_prev: self.t_prev,
            t,
            x_prev: self.x_prev,
            x,
            dense: self.dense,
            span: self.span,
            map: self.map,
        }
    }
}

impl<T: RealField + Copy, const D: usize> Step<'_, T, D> {
    /// Time at the end of the step.
    pub fn t(&self) -> T {
        self.t
    }

    /// State at the end of the step, [`Step::t`].
    pub fn x(&self) -> &SVector<T, D> {
        self.x
    }

    /// Time at the start of the step.
    pub fn t_prev(&self) -> T {
        self.t_prev
    }

    /// State at the start of the step, [`Step::t_prev`].
    pub fn x_prev(&self) -> &SVector<T, D> {
        self.x_prev
    }

    /// The signed step size `t − t_prev` (negative when integrating
    /// backwards).
    pub fn h(&self) -> T {
        self.t - self.t_prev
    }

    /// The dense-output approximation of the solution at `t`.
    ///
    /// Meant for `t` between [`Step::t_prev`] and [`Step::t`] (in either
    /// direction of time); exactly `x_prev` at `t_prev` and exactly `x` at
    /// `t`. Outside the step the polynomial is extrapolated, which is
    /// well-defined but quickly inaccurate.
    pub fn interpolate(&self, t: T) -> SVector<T, D> {
        if t == self.t {
            return *self.x;
        }
        if t == self.t_prev {
            return *self.x_prev;
        }
        match self.dense {
            Some(p) => {
                let x = p.eval((t - self.t_prev) / self.span);
                match self.map {
                    Some(map) => map(t, &x),
                    None => x,
                }
            }
            // Steps reported without dense output (to observers, which do
            // not interpolate): the chord.
            None => {
                self.x_prev + (self.x - self.x_prev) * ((t - self.t_prev) / (self.t - self.t_prev))
            }
        }
    }
}

impl<T: fmt::Debug, const D: usize> fmt::Debug for Step<'_, T, D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Step")
            .field("t_prev", &self.t_prev)
            .field("t", &self.t)
            .field("x_prev", self.x_prev)
            .field("x", self.x)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector1;

    #[test]
    fn nested_basis_matches_hairer_horner_form() {
        let r: [Vector1<f64>; 8] =
            core::array::from_fn(|k| Vector1::new(0.3 * k as f64 - 1.0 + (k * k) as f64 * 0.07));
        let p = Poly::from_nested(&r);
        for &s in &[0.0, 0.2, 0.5, 0.9, 1.0, 1.3] {
            let s1 = 1.0 - s;
            let v = |k: usize| r[k][0];
            let hairer = v(0)
                + s * (v(1)
                    + s1 * (v(2) + s * (v(3) + s1 * (v(4) + s * (v(5) + s1 * (v(6) + s * v(7)))))));
            assert!((p.eval(s)[0] - hairer).abs() < 1e-13, "s = {s}");
        }
        // Shorter forms (CONTD5 uses five terms) are prefixes.
        let p5 = Poly::from_nested(&r[..5]);
        let s = 0.37;
        let s1 = 1.0 - s;
        let v = |k: usize| r[k][0];
        let hairer = v(0) + s * (v(1) + s1 * (v(2) + s * (v(3) + s1 * v(4))));
        assert!((p5.eval(s)[0] - hairer).abs() < 1e-14);
    }

    #[test]
    fn monomial_horner() {
        let p = Poly::from_monomial(&[Vector1::new(1.0), Vector1::new(2.0), Vector1::new(3.0)]);
        assert_eq!(p.eval(2.0)[0], 1.0 + 4.0 + 12.0);
    }
}
