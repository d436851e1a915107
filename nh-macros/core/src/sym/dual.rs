//! Dual numbers over double-double: a value and its derivatives along one
//! or several directions, carried through an evaluation (forward
//! differentiation). Used to see at random points that a quantity built
//! from derivatives, such as a curvature entry, does not vanish, without
//! differentiating symbolically.

use super::Rational;
use super::dd::Dd;
use super::eval::Scalar;
use std::ops::{Add, Div, Mul, Sub};

/// `value + Σ_i derivatives[i]·ε_i` with ε_i ε_j = 0: the derivatives along
/// `N` directions at once, each computed exactly as a single direction's
/// would be (the same operations in the same order), so that one evaluation
/// of a shared expression serves `N` directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Duals<const N: usize> {
    /// The value.
    pub value: Dd,
    /// The derivatives along the chosen directions.
    pub derivatives: [Dd; N],
}

/// One direction: `value + derivative·ε` with ε² = 0.
pub type Dual = Duals<1>;

impl<const N: usize> Duals<N> {
    /// A constant (derivatives zero).
    pub fn constant(value: Dd) -> Self {
        Duals {
            value,
            derivatives: [Dd::ZERO; N],
        }
    }

    /// The variable differentiated along every direction (derivatives one).
    pub fn variable(value: Dd) -> Self {
        Duals {
            value,
            derivatives: [Dd::ONE; N],
        }
    }

    /// The derivative along the first direction.
    pub fn derivative(&self) -> Dd {
        self.derivatives[0]
    }

    /// `f(self)` for `f` with value `f(v)` and slope `f'(v)`.
    fn chain(self, value: Dd, slope: Dd) -> Self {
        Duals {
            value,
            derivatives: self.derivatives.map(|d| slope * d),
        }
    }

    /// Combines the derivatives of `self` and `o` pairwise.
    fn zip(self, o: Self, value: Dd, f: impl Fn(Dd, Dd) -> Dd) -> Self {
        let mut derivatives = self.derivatives;
        for (d, &e) in derivatives.iter_mut().zip(&o.derivatives) {
            *d = f(*d, e);
        }
        Duals { value, derivatives }
    }
}

impl<const N: usize> Add for Duals<N> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        self.zip(o, self.value + o.value, |a, b| a + b)
    }
}

impl<const N: usize> Sub for Duals<N> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self.zip(o, self.value - o.value, |a, b| a - b)
    }
}

impl<const N: usize> Mul for Duals<N> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)] // the product rule
    fn mul(self, o: Self) -> Self {
        let (v, w) = (self.value, o.value);
        self.zip(o, v * w, |a, b| a * w + v * b)
    }
}

impl<const N: usize> Div for Duals<N> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)] // the quotient rule
    fn div(self, o: Self) -> Self {
        let value = self.value / o.value;
        let w = o.value;
        self.zip(o, value, |a, b| (a - value * b) / w)
    }
}

impl<const N: usize> Scalar for Duals<N> {
    const ZERO: Self = Duals {
        value: Dd::ZERO,
        derivatives: [Dd::ZERO; N],
    };
    fn from_rational(q: Rational) -> Self {
        Self::constant(Dd::from_rational(q))
    }
    fn abs(self) -> Self {
        let s = Scalar::sign(self.value);
        self.chain(self.value.abs(), s)
    }
    fn powi(self, k: i64) -> Self {
        if k == 0 {
            return Self::constant(Dd::ONE);
        }
        let below = self.value.powi(k - 1);
        self.chain(below * self.value, Dd::from_f64(k as f64) * below)
    }
    fn powq(self, q: Rational) -> Self {
        let value = Scalar::powq(self.value, q);
        self.chain(value, Dd::from_rational(q) * value / self.value)
    }
    fn sin(self) -> Self {
        let (s, c) = self.value.sin_cos();
        self.chain(s, c)
    }
    fn cos(self) -> Self {
        let (s, c) = self.value.sin_cos();
        self.chain(c, Dd::ZERO - s)
    }
    fn tan(self) -> Self {
        let (s, c) = self.value.sin_cos();
        self.chain(s / c, Dd::ONE / (c * c))
    }
    fn exp(self) -> Self {
        let e = self.value.exp();
        self.chain(e, e)
    }
    fn ln(self) -> Self {
        self.chain(self.value.ln(), Dd::ONE / self.value)
    }
    fn sinh(self) -> Self {
        self.chain(self.value.sinh(), self.value.cosh())
    }
    fn cosh(self) -> Self {
        self.chain(self.value.cosh(), self.value.sinh())
    }
    fn tanh(self) -> Self {
        let t = self.value.tanh();
        self.chain(t, Dd::ONE - t * t)
    }
    fn asin(self) -> Self {
        let root = (Dd::ONE - self.value * self.value).sqrt();
        self.chain(self.value.asin(), Dd::ONE / root)
    }
    fn acos(self) -> Self {
        let root = (Dd::ONE - self.value * self.value).sqrt();
        self.chain(self.value.acos(), Dd::ZERO - Dd::ONE / root)
    }
    fn atan(self) -> Self {
        let slope = Dd::ONE / (Dd::ONE + self.value * self.value);
        self.chain(Scalar::atan(self.value), slope)
    }
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy − y dx)/(x² + y²)
        let (y, r2) = (self.value, self.value * self.value + x.value * x.value);
        let xv = x.value;
        self.zip(x, y.atan2(x.value), |dy, dx| (xv * dy - y * dx) / r2)
    }
    fn sign(self) -> Self {
        Self::constant(Scalar::sign(self.value))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(x: f64) -> Dd {
        Dd::from_f64(x)
    }

    /// Each function's derivative against its closed form at x = 0.7.
    #[test]
    fn derivatives_match_closed_forms() {
        let x = Dual::variable(d(0.7));
        let v = 0.7_f64;
        let cases: [(Dual, f64); 12] = [
            (x.sin(), v.cos()),
            (x.cos(), -v.sin()),
            (x.tan(), 1.0 / (v.cos() * v.cos())),
            (x.exp(), v.exp()),
            (x.ln(), 1.0 / v),
            (x.tanh(), 1.0 - v.tanh() * v.tanh()),
            (x.asin(), 1.0 / (1.0 - v * v).sqrt()),
            (x.acos(), -1.0 / (1.0 - v * v).sqrt()),
            (Scalar::atan(x), 1.0 / (1.0 + v * v)),
            (x.powi(3), 3.0 * v * v),
            (x.powq(Rational::new(1, 2).unwrap()), 0.5 / v.sqrt()),
            (x.atan2(Dual::constant(d(0.3))), 0.3 / (0.09 + v * v)),
        ];
        for (k, (f, want)) in cases.iter().enumerate() {
            assert!(
                (f.derivative().to_f64() - want).abs() < 1e-14,
                "case {k}: {} against {want}",
                f.derivative().to_f64()
            );
        }
        let q = (x * x - Dual::constant(d(1.0))) / (x + Dual::constant(d(2.0)));
        let want = (2.0 * v * (v + 2.0) - (v * v - 1.0)) / ((v + 2.0) * (v + 2.0));
        assert!((q.derivative().to_f64() - want).abs() < 1e-15);
    }

    /// Several directions at once give, bit for bit, each direction's
    /// derivative as one direction alone does: f(x, y) = sin(x y)/(x + y)
    /// + atan2(y, x) + x^3 along (1, 0), (0, 1) and (0.3, −2).
    #[test]
    fn several_directions_are_each_direction_alone() {
        fn f<S: Scalar>(x: S, y: S) -> S {
            (x * y).sin() / (x + y) + y.atan2(x) + x.powi(3)
        }
        let seeds = [(1.0, 0.0), (0.0, 1.0), (0.3, -2.0)];
        let (x0, y0) = (d(0.7), d(-0.4));
        let mut x = Duals::<3>::constant(x0);
        let mut y = Duals::<3>::constant(y0);
        for (i, &(sx, sy)) in seeds.iter().enumerate() {
            x.derivatives[i] = d(sx);
            y.derivatives[i] = d(sy);
        }
        let all = f(x, y);
        for (i, &(sx, sy)) in seeds.iter().enumerate() {
            let one = f(
                Dual {
                    value: x0,
                    derivatives: [d(sx)],
                },
                Dual {
                    value: y0,
                    derivatives: [d(sy)],
                },
            );
            assert_eq!(all.value, one.value);
            assert_eq!(all.derivatives[i], one.derivative(), "direction {i}");
        }
    }
}
