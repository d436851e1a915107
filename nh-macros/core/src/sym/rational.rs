//! Exact rational numbers with checked 128-bit arithmetic.
//!
//! Coefficients in mechanics stay small (halves, quarters, products of a few
//! such), so a fixed-width representation suffices; every operation is checked
//! and reports overflow as `None` instead of wrapping or panicking.

use std::cmp::Ordering;
use std::fmt;

/// An exact rational number `num / den` in lowest terms with `den > 0`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Rational {
    num: i128,
    den: i128,
}

/// Greatest common divisor of |a| and |b| (never overflows: magnitudes are
/// taken as unsigned; the result fits an i128 because `Rational` excludes
/// `i128::MIN`).
fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.unsigned_abs(), b.unsigned_abs());
    while b != 0 {
        let r = a % b;
        a = b;
        b = r;
    }
    i128::try_from(a).unwrap_or(i128::MAX)
}

impl Rational {
    /// Zero.
    pub const ZERO: Rational = Rational { num: 0, den: 1 };
    /// One.
    pub const ONE: Rational = Rational { num: 1, den: 1 };
    /// Minus one.
    pub const MINUS_ONE: Rational = Rational { num: -1, den: 1 };

    /// The integer `n`.
    pub const fn int(n: i128) -> Rational {
        Rational { num: n, den: 1 }
    }

    /// `num / den` reduced to lowest terms; `None` if `den == 0` or on overflow.
    pub fn new(num: i128, den: i128) -> Option<Rational> {
        // i128::MIN has no positive counterpart: treat it as overflow
        if den == 0 || num == i128::MIN || den == i128::MIN {
            return None;
        }
        let g = gcd(num, den);
        let (mut n, mut d) = (num / g, den / g);
        if d < 0 {
            n = n.checked_neg()?;
            d = d.checked_neg()?;
        }
        Some(Rational { num: n, den: d })
    }

    /// Numerator (carries the sign).
    pub fn numer(self) -> i128 {
        self.num
    }

    /// Denominator (always positive).
    pub fn denom(self) -> i128 {
        self.den
    }

    /// Is this zero?
    pub fn is_zero(self) -> bool {
        self.num == 0
    }

    /// Is this one?
    pub fn is_one(self) -> bool {
        self.num == 1 && self.den == 1
    }

    /// Is this an integer?
    pub fn is_integer(self) -> bool {
        self.den == 1
    }

    /// Is this strictly negative?
    pub fn is_negative(self) -> bool {
        self.num < 0
    }

    /// The integer value if this is an integer that fits an `i64`.
    pub fn to_integer(self) -> Option<i64> {
        if self.den == 1 {
            i64::try_from(self.num).ok()
        } else {
            None
        }
    }

    /// Nearest `f64` (correctly rounded when both parts fit 53 bits).
    pub fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }

    /// `-self`.
    pub fn checked_neg(self) -> Option<Rational> {
        Some(Rational {
            num: self.num.checked_neg()?,
            den: self.den,
        })
    }

    /// `|self|`.
    pub fn abs(self) -> Rational {
        Rational {
            num: self.num.saturating_abs(),
            den: self.den,
        }
    }

    /// `self + o`.
    pub fn checked_add(self, o: Rational) -> Option<Rational> {
        let g = gcd(self.den, o.den);
        let a = self.num.checked_mul(o.den / g)?;
        let b = o.num.checked_mul(self.den / g)?;
        let d = (self.den / g).checked_mul(o.den)?;
        Rational::new(a.checked_add(b)?, d)
    }

    /// `self - o`.
    pub fn checked_sub(self, o: Rational) -> Option<Rational> {
        self.checked_add(o.checked_neg()?)
    }

    /// `self * o`.
    pub fn checked_mul(self, o: Rational) -> Option<Rational> {
        let g1 = gcd(self.num, o.den).max(1);
        let g2 = gcd(o.num, self.den).max(1);
        let n = (self.num / g1).checked_mul(o.num / g2)?;
        let d = (self.den / g2).checked_mul(o.den / g1)?;
        Rational::new(n, d)
    }

    /// `1 / self`; `None` for zero.
    pub fn checked_recip(self) -> Option<Rational> {
        Rational::new(self.den, self.num)
    }

    /// `self / o`.
    pub fn checked_div(self, o: Rational) -> Option<Rational> {
        self.checked_mul(o.checked_recip()?)
    }

    /// `self ^ e` for an integer exponent; `None` on overflow or `0^negative`.
    pub fn checked_powi(self, e: i64) -> Option<Rational> {
        let base = if e < 0 { self.checked_recip()? } else { self };
        let mut e = e.unsigned_abs();
        let mut acc = Rational::ONE;
        let mut b = base;
        while e > 0 {
            if e & 1 == 1 {
                acc = acc.checked_mul(b)?;
            }
            e >>= 1;
            if e > 0 {
                b = b.checked_mul(b)?;
            }
        }
        Some(acc)
    }

    /// Greatest common divisor of two rationals (of numerators over lcm of
    /// denominators), always positive; used to factor out content.
    pub fn gcd(self, o: Rational) -> Option<Rational> {
        let n = gcd(self.num, o.num);
        let g = gcd(self.den, o.den);
        let l = (self.den / g).checked_mul(o.den)?;
        Rational::new(n, l)
    }
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> Ordering {
        // Compare a/b with c/d as a*d with c*b, widening through f64 on overflow.
        match (
            self.num.checked_mul(other.den),
            other.num.checked_mul(self.den),
        ) {
            (Some(l), Some(r)) => l.cmp(&r),
            _ => self
                .to_f64()
                .partial_cmp(&other.to_f64())
                .unwrap_or(Ordering::Equal),
        }
    }
}

impl fmt::Display for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i128, d: i128) -> Rational {
        Rational::new(n, d).unwrap()
    }

    #[test]
    fn arithmetic_is_exact() {
        assert_eq!(q(1, 3).checked_add(q(1, 6)), Some(q(1, 2)));
        assert_eq!(q(2, 4), q(1, 2));
        assert_eq!(q(3, -6), q(-1, 2));
        assert_eq!(q(2, 3).checked_mul(q(9, 4)), Some(q(3, 2)));
        assert_eq!(q(2, 3).checked_powi(-2), Some(q(9, 4)));
        assert_eq!(q(6, 5).gcd(q(9, 10)), Some(q(3, 10)));
        assert!(q(1, 3) < q(1, 2));
        assert_eq!(Rational::new(1, 0), None);
    }

    #[test]
    fn the_most_negative_integer_is_overflow_not_a_panic() {
        assert_eq!(Rational::new(i128::MIN, 1), None);
        let big = Rational::int(-(1i128 << 126));
        assert_eq!(big.checked_mul(Rational::int(2)), None);
        assert_eq!(big.checked_add(big), None);
    }

    #[test]
    fn overflow_is_reported() {
        let big = Rational::int(i128::MAX / 2);
        assert_eq!(big.checked_mul(Rational::int(4)), None);
        assert_eq!(Rational::int(10).checked_powi(60), None);
    }
}
