//! Conversions of rationals: from decimal digits and `f64`, to correctly
//! rounded `f64`, and to text.

use super::Rational;
use num_bigint::{BigInt, BigUint};
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use std::fmt;

impl Rational {
    /// The non-negative integer written with the decimal digits `digits`
    /// (`None` if empty or if some character is not a digit).
    pub fn from_digits(digits: &str) -> Option<Rational> {
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        if digits.len() <= 38 {
            return digits.parse::<i128>().ok().map(Rational::int);
        }
        let n = BigInt::parse_bytes(digits.as_bytes(), 10)?;
        Some(Rational::from_big(BigRational::from_integer(n)))
    }

    /// The exact value of a finite `f64` (`None` for infinities and NaN).
    pub fn from_f64(x: f64) -> Option<Rational> {
        BigRational::from_float(x).map(Rational::from_big)
    }

    /// Approximate number of decimal digits of the larger of numerator and
    /// denominator (`log10 max(|num|, den)`; 0 for 0 and ±1).
    pub fn digits(self) -> f64 {
        match self.den {
            0 => self.with_stored(|v| {
                let bits = v.numer().bits().max(v.denom().bits());
                bits as f64 * std::f64::consts::LOG10_2
            }),
            d => (self.num.unsigned_abs().max(d.unsigned_abs()) as f64).log10(),
        }
    }

    /// A short scientific form for messages (`6.0221e23`, `-1.0000e400`).
    pub fn sci(self) -> String {
        let v = self.to_f64();
        if v.is_finite() && v != 0.0 {
            return format!("{v:.4e}");
        }
        // beyond f64 (or underflowing it): from the exact decimal digits
        let b = self.to_big();
        let neg = b.is_negative();
        let a = b.abs();
        let (n, d) = (a.numer(), a.denom());
        // 10^k ≤ a < 10^(k+1): estimate k from bit lengths, then fix it up
        let est = ((n.bits() as f64 - d.bits() as f64) * std::f64::consts::LOG10_2) as i64;
        let mut best = String::new();
        for k in [est - 1, est, est + 1] {
            // floor(a · 10^(4 − k)) has five digits exactly when 10^k ≤ a < 10^(k+1)
            let s = 4 - k;
            let ten = BigInt::from(10u32);
            let m = if s >= 0 {
                (n * num_traits::pow(ten, s as usize)) / d
            } else {
                n / (d * num_traits::pow(ten, (-s) as usize))
            };
            let digits = m.to_string();
            if digits.len() == 5 {
                best = format!(
                    "{}{}.{}e{}",
                    if neg { "-" } else { "" },
                    &digits[..1],
                    &digits[1..],
                    k
                );
                break;
            }
        }
        if best.is_empty() {
            best = self.to_string();
        }
        best
    }

    /// The nearest `f64`, correctly rounded (ties to even) for every value:
    /// beyond `f64::MAX` it is infinite, below the smallest subnormal zero.
    pub fn to_f64(self) -> f64 {
        if self.den != 0 {
            const EXACT: u128 = 1 << 53;
            if self.num.unsigned_abs() <= EXACT && (self.den as u128) <= EXACT {
                // both exact in f64: one correctly rounded division
                return self.num as f64 / self.den as f64;
            }
        }
        let b = self.to_big();
        let v = ratio_to_f64(b.numer().magnitude(), b.denom().magnitude());
        if b.is_negative() { -v } else { v }
    }
}

/// `n / d` (both positive) rounded to the nearest `f64`, ties to even.
fn ratio_to_f64(n: &BigUint, d: &BigUint) -> f64 {
    if n.is_zero() || d.is_zero() {
        return 0.0;
    }
    let (nb, db) = (n.bits() as i64, d.bits() as i64);
    // n/d lies in [2^(nb−db−1), 2^(nb−db+1))
    if nb - db > 1025 {
        return f64::INFINITY;
    }
    if nb - db < -1076 {
        // below 2^−1075, half the smallest subnormal: rounds to zero
        return 0.0;
    }
    // t = floor(n·2^s / d) has 55 or 56 bits; the remainder is the sticky bit
    let s = 55 - (nb - db);
    let (t, rem) = if s >= 0 {
        (n << (s as usize)).div_rem(d)
    } else {
        n.div_rem(&(d << ((-s) as usize)))
    };
    let sticky = !rem.is_zero();
    let t = t.to_u64().unwrap_or(u64::MAX);
    let tb = 64 - i64::from(t.leading_zeros());
    // exponent of the last kept bit: 53 significant bits, or the subnormal grid
    let lsb = (tb - 53 - s).max(-1074);
    let drop = lsb + s; // ≥ 2
    let m = if drop >= 64 {
        0
    } else {
        let m = t >> drop;
        let r = t & ((1u64 << drop) - 1);
        let half = 1u64 << (drop - 1);
        if r > half || (r == half && (sticky || m & 1 == 1)) {
            m + 1
        } else {
            m
        }
    };
    ldexp(m as f64, lsb)
}

/// `x · 2^k`, exact whenever the result is representable.
fn ldexp(mut x: f64, mut k: i64) -> f64 {
    let pow2 = |k: i64| f64::from_bits(((k + 1023) as u64) << 52);
    while k > 1000 {
        x *= pow2(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= pow2(-1000);
        k += 1000;
    }
    x * pow2(k)
}

impl fmt::Display for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.den {
            1 => write!(f, "{}", self.num),
            0 => {
                let b = self.to_big();
                if b.is_integer() {
                    write!(f, "{}", b.numer())
                } else {
                    write!(f, "{}/{}", b.numer(), b.denom())
                }
            }
            d => write!(f, "{}/{}", self.num, d),
        }
    }
}

impl fmt::Debug for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Rational({self})")
    }
}
