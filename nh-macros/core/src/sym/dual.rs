//! Dual numbers over double-double: a value and its derivative along one
//! direction, carried through an evaluation (forward differentiation). Used
//! to see at random points that a quantity built from derivatives, such as a
//! curvature entry, does not vanish, without differentiating symbolically.

use super::Rational;
use super::dd::Dd;
use super::eval::Scalar;
use std::ops::{Add, Div, Mul, Sub};

/// `value + derivative·ε` with ε² = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    /// The value.
    pub value: Dd,
    /// The derivative along the chosen direction.
    pub derivative: Dd,
}

impl Dual {
    /// A constant (derivative zero).
    pub fn constant(value: Dd) -> Dual {
        Dual {
            value,
            derivative: Dd::ZERO,
        }
    }

    /// The variable differentiated along (derivative one).
    pub fn variable(value: Dd) -> Dual {
        Dual {
            value,
            derivative: Dd::ONE,
        }
    }

    /// `f(self)` for `f` with value `f(v)` and slope `f'(v)`.
    fn chain(self, value: Dd, slope: Dd) -> Dual {
        Dual {
            value,
            derivative: slope * self.derivative,
        }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            value: self.value + o.value,
            derivative: self.derivative + o.derivative,
        }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            value: self.value - o.value,
            derivative: self.derivative - o.derivative,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            value: self.value * o.value,
            derivative: self.derivative * o.value + self.value * o.derivative,
        }
    }
}

impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        let value = self.value / o.value;
        Dual {
            value,
            derivative: (self.derivative - value * o.derivative) / o.value,
        }
    }
}

impl Scalar for Dual {
    const ZERO: Dual = Dual {
        value: Dd::ZERO,
        derivative: Dd::ZERO,
    };
    fn from_rational(q: Rational) -> Dual {
        Dual::constant(Dd::from_rational(q))
    }
    fn abs(self) -> Dual {
        let s = Scalar::sign(self.value);
        self.chain(self.value.abs(), s)
    }
    fn powi(self, k: i64) -> Dual {
        if k == 0 {
            return Dual::constant(Dd::ONE);
        }
        let below = self.value.powi(k - 1);
        self.chain(below * self.value, Dd::from_f64(k as f64) * below)
    }
    fn powq(self, q: Rational) -> Dual {
        let value = Scalar::powq(self.value, q);
        self.chain(value, Dd::from_rational(q) * value / self.value)
    }
    fn sin(self) -> Dual {
        let (s, c) = self.value.sin_cos();
        self.chain(s, c)
    }
    fn cos(self) -> Dual {
        let (s, c) = self.value.sin_cos();
        self.chain(c, Dd::ZERO - s)
    }
    fn tan(self) -> Dual {
        let (s, c) = self.value.sin_cos();
        self.chain(s / c, Dd::ONE / (c * c))
    }
    fn exp(self) -> Dual {
        let e = self.value.exp();
        self.chain(e, e)
    }
    fn ln(self) -> Dual {
        self.chain(self.value.ln(), Dd::ONE / self.value)
    }
    fn sinh(self) -> Dual {
        self.chain(self.value.sinh(), self.value.cosh())
    }
    fn cosh(self) -> Dual {
        self.chain(self.value.cosh(), self.value.sinh())
    }
    fn tanh(self) -> Dual {
        let t = self.value.tanh();
        self.chain(t, Dd::ONE - t * t)
    }
    fn asin(self) -> Dual {
        let root = (Dd::ONE - self.value * self.value).sqrt();
        self.chain(self.value.asin(), Dd::ONE / root)
    }
    fn acos(self) -> Dual {
        let root = (Dd::ONE - self.value * self.value).sqrt();
        self.chain(self.value.acos(), Dd::ZERO - Dd::ONE / root)
    }
    fn atan(self) -> Dual {
        let slope = Dd::ONE / (Dd::ONE + self.value * self.value);
        self.chain(Scalar::atan(self.value), slope)
    }
    fn atan2(self, x: Dual) -> Dual {
        // d atan2(y, x) = (x dy − y dx)/(x² + y²)
        let (y, r2) = (self.value, self.value * self.value + x.value * x.value);
        Dual {
            value: y.atan2(x.value),
            derivative: (x.value * self.derivative - y * x.derivative) / r2,
        }
    }
    fn sign(self) -> Dual {
        Dual::constant(Scalar::sign(self.value))
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
                (f.derivative.to_f64() - want).abs() < 1e-14,
                "case {k}: {} against {want}",
                f.derivative.to_f64()
            );
        }
        let q = (x * x - Dual::constant(d(1.0))) / (x + Dual::constant(d(2.0)));
        let want = (2.0 * v * (v + 2.0) - (v * v - 1.0)) / ((v + 2.0) * (v + 2.0));
        assert!((q.derivative.to_f64() - want).abs() < 1e-15);
    }
}
