//! Double-double arithmetic (about 32 significant digits): a value is the
//! unevaluated sum `hi + lo` of two `f64`s. Used to decide, at random points,
//! whether an expression the canonical form cannot simplify vanishes: a
//! cancellation that leaves 1e-16 of the terms in `f64` leaves 1e-32 here.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dd {
    /// The leading part.
    pub hi: f64,
    /// The trailing part, |lo| ≤ ulp(hi)/2.
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    /// Zero.
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    /// One.
    pub const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };
    /// π to double-double precision.
    pub const PI: Dd = Dd {
        hi: std::f64::consts::PI,
        lo: 1.224_646_799_147_353_2e-16,
    };
    const LN2: Dd = Dd {
        hi: std::f64::consts::LN_2,
        lo: 2.319_046_813_846_299_6e-17,
    };

    /// An `f64` as a double-double.
    pub fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// `n / d` correctly rounded to double-double.
    pub fn ratio(n: i128, d: i128) -> Dd {
        if d == 1 {
            // exactly nn / 1, without the division
            return Dd::from_i128(n);
        }
        let nn = Dd::from_i128(n);
        let dd = Dd::from_i128(d);
        nn / dd
    }

    /// An exact rational as a double-double: `ratio` for the small form,
    /// otherwise the nearest `f64` plus the nearest `f64` of the exact
    /// remainder (infinite beyond the range of `f64`).
    pub fn from_rational(q: super::Rational) -> Dd {
        if let Some((n, d)) = q.to_i128_parts() {
            return Dd::ratio(n, d);
        }
        let hi = q.to_f64();
        let lo = super::Rational::from_f64(hi)
            .and_then(|h| q.checked_sub(h))
            .map_or(0.0, |r| r.to_f64());
        Dd { hi, lo }
    }

    fn from_i128(n: i128) -> Dd {
        let hi = n as f64;
        let rest = n - hi as i128;
        let (h, l) = quick_two_sum(hi, rest as f64);
        Dd { hi: h, lo: l }
    }

    /// The nearest `f64`.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// |x|.
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 { -self } else { self }
    }

    /// Is this finite?
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// x^k for an integer k.
    pub fn powi(self, k: i64) -> Dd {
        let mut e = k.unsigned_abs();
        let mut b = self;
        let mut acc = Dd::ONE;
        while e > 0 {
            if e & 1 == 1 {
                acc = acc * b;
            }
            e >>= 1;
            if e > 0 {
                b = b * b;
            }
        }
        if k < 0 { Dd::ONE / acc } else { acc }
    }

    /// √x (one Newton step on the `f64` root).
    pub fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::from_f64(self.hi.sqrt());
        }
        let r = Dd::from_f64(self.hi.sqrt());
        r + (self - r * r) / (r * Dd::from_f64(2.0))
    }

    /// eˣ: reduced by multiples of ln 2, then a Taylor series.
    pub fn exp(self) -> Dd {
        if !self.is_finite() || self.hi.abs() > 700.0 {
            return Dd::from_f64(self.hi.exp());
        }
        let k = (self.hi / std::f64::consts::LN_2).round();
        let r = self - Dd::LN2 * Dd::from_f64(k);
        // e^r with |r| ≤ ln2/2, as (e^(r/16))^16
        let r = r * Dd::from_f64(1.0 / 16.0);
        let mut term = Dd::ONE;
        let mut sum = Dd::ONE;
        for i in 1..24 {
            term = term * r / Dd::from_f64(i as f64);
            sum = sum + term;
        }
        let mut y = sum;
        for _ in 0..4 {
            y = y * y;
        }
        y * Dd::from_f64(2f64.powi(k as i32))
    }

    /// ln x: Newton's method on eʸ = x from the `f64` logarithm.
    pub fn ln(self) -> Dd {
        if self.hi <= 0.0 || !self.is_finite() {
            return Dd::from_f64(self.hi.ln());
        }
        let mut y = Dd::from_f64(self.hi.ln());
        for _ in 0..2 {
            y = y + self * (-y).exp() - Dd::ONE;
        }
        y
    }

    /// sinh x: its Taylor series for |x| < 1/2 (where (eˣ − e⁻ˣ)/2 would
    /// cancel), (eˣ − e⁻ˣ)/2 beyond.
    pub fn sinh(self) -> Dd {
        if !self.is_finite() || self.hi.abs() > 700.0 {
            return Dd::from_f64(self.hi.sinh());
        }
        if self.hi.abs() < 0.5 {
            let x2 = self * self;
            let (mut term, mut sum) = (self, self);
            for i in 1..16 {
                let i = i as f64;
                term = term * x2 / Dd::from_f64((2.0 * i) * (2.0 * i + 1.0));
                sum = sum + term;
            }
            return sum;
        }
        let e = self.exp();
        (e - Dd::ONE / e) * Dd::from_f64(0.5)
    }

    /// cosh x = (eˣ + e⁻ˣ)/2.
    pub fn cosh(self) -> Dd {
        if !self.is_finite() || self.hi.abs() > 700.0 {
            return Dd::from_f64(self.hi.cosh());
        }
        let e = self.exp();
        (e + Dd::ONE / e) * Dd::from_f64(0.5)
    }

    /// tanh x = sinh x / cosh x (±1 to double-double precision beyond |x| = 40).
    pub fn tanh(self) -> Dd {
        if !self.is_finite() || self.hi.abs() > 40.0 {
            return Dd::from_f64(self.hi.tanh());
        }
        self.sinh() / self.cosh()
    }

    /// atan2(y, x) with `self` = y: the angle of the point (x, y) in
    /// (−π, π], by Newton's method from the `f64` angle θ: at the angle,
    /// y cos θ − x sin θ = 0 and x cos θ + y sin θ = r. 0 at the origin.
    pub fn atan2(self, x: Dd) -> Dd {
        let y = self;
        if !y.is_finite() || !x.is_finite() || (y.hi == 0.0 && x.hi == 0.0) {
            return Dd::from_f64(y.hi.atan2(x.hi));
        }
        let mut t = Dd::from_f64(y.hi.atan2(x.hi));
        for _ in 0..2 {
            let (s, c) = t.sin_cos();
            t = t + (y * c - x * s) / (x * c + y * s);
        }
        t
    }

    /// asin x = atan2(x, √(1 − x²)) (NaN beyond |x| = 1).
    pub fn asin(self) -> Dd {
        let root = ((Dd::ONE - self) * (Dd::ONE + self)).sqrt();
        self.atan2(root)
    }

    /// acos x = atan2(√(1 − x²), x) (NaN beyond |x| = 1).
    pub fn acos(self) -> Dd {
        let root = ((Dd::ONE - self) * (Dd::ONE + self)).sqrt();
        root.atan2(self)
    }

    /// (sin x, cos x): reduced by multiples of π/2, then Taylor series.
    pub fn sin_cos(self) -> (Dd, Dd) {
        if !self.is_finite() || self.hi.abs() > 1e6 {
            return (Dd::from_f64(self.hi.sin()), Dd::from_f64(self.hi.cos()));
        }
        let half_pi = Dd::PI * Dd::from_f64(0.5);
        let k = (self.hi / half_pi.hi).round();
        let r = self - half_pi * Dd::from_f64(k);
        let r2 = r * r;
        let (mut s, mut c) = (r, Dd::ONE);
        let (mut ts, mut tc) = (r, Dd::ONE);
        for i in 1..16 {
            let i = i as f64;
            ts = -ts * r2 / Dd::from_f64((2.0 * i) * (2.0 * i + 1.0));
            tc = -tc * r2 / Dd::from_f64((2.0 * i - 1.0) * (2.0 * i));
            s = s + ts;
            c = c + tc;
        }
        match (k as i64).rem_euclid(4) {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    fn add(self, o: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, o: Dd) -> Dd {
        self + (-o)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, o: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self - o * Dd::from_f64(q1);
        let q2 = r.hi / o.hi;
        let r = r - o * Dd::from_f64(q2);
        let q3 = r.hi / o.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo } + Dd::from_f64(q3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Dd, b: Dd, tol: f64) -> bool {
        (a - b).abs().to_f64() <= tol * b.abs().to_f64().max(1.0)
    }

    #[test]
    fn identities_hold_to_double_double_precision() {
        for &x in &[0.3, 1.7, -2.9, 10.1, 123.456] {
            let x = Dd::from_f64(x) + Dd::from_f64(1e-20);
            let (s, c) = x.sin_cos();
            assert!(close(s * s + c * c, Dd::ONE, 1e-30), "sin² + cos² at {x:?}");
            let e = x.exp();
            let err = (e.ln() - x).abs().to_f64() / x.abs().to_f64();
            assert!(err <= 1e-29, "ln exp at {x:?}: {err:e}");
            let r = e.sqrt();
            assert!(close(r * r, e, 1e-30));
            // sin 2x = 2 sin x cos x
            let (s2, _) = (x * Dd::from_f64(2.0)).sin_cos();
            assert!(close(s2, Dd::from_f64(2.0) * s * c, 1e-29));
        }
        assert!(close(Dd::ratio(1, 3) * Dd::from_f64(3.0), Dd::ONE, 1e-31));
    }

    #[test]
    fn inverse_and_hyperbolic_functions_hold_to_double_double_precision() {
        for &x in &[0.3, 0.97, -0.61, 1e-3, -0.2] {
            let x = Dd::from_f64(x) + Dd::from_f64(1e-20);
            // sin(asin x) = x, cos(acos x) = x, tan(atan x) = x
            assert!(close(x.asin().sin_cos().0, x, 1e-30), "asin at {x:?}");
            assert!(close(x.acos().sin_cos().1, x, 1e-30), "acos at {x:?}");
            let (s, c) = x.atan2(Dd::ONE).sin_cos();
            assert!(close(s / c, x, 1e-30), "atan at {x:?}");
            // cosh² − sinh² = 1, tanh = sinh/cosh, sinh from its series and exp agree
            let (sh, ch) = (x.sinh(), x.cosh());
            assert!(
                close(ch * ch - sh * sh, Dd::ONE, 1e-30),
                "cosh² − sinh² at {x:?}"
            );
            let e = x.exp();
            let sh_exp = (e - Dd::ONE / e) * Dd::from_f64(0.5);
            assert!((sh - sh_exp).abs().to_f64() < 1e-30, "sinh at {x:?}");
        }
        // the four quadrants of atan2 and the π/4 multiples
        let quarter = Dd::PI * Dd::from_f64(0.25);
        for (y, x, k) in [
            (1.0, 1.0, 1.0),
            (1.0, -1.0, 3.0),
            (-1.0, -1.0, -3.0),
            (0.0, -1.0, 4.0),
        ] {
            let t = Dd::from_f64(y).atan2(Dd::from_f64(x));
            assert!(
                close(t, quarter * Dd::from_f64(k), 1e-31),
                "atan2({y}, {x})"
            );
        }
    }
}
