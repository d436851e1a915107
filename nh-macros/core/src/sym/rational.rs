//! Exact rational numbers of any size.
//!
//! Coefficients in mechanics are mostly small (halves, quarters, products of
//! a few such), but a physicist's literals are not (`6.62607015e-34`, `1e300`,
//! a forty-digit integer), and sums of many distinct fractions grow their
//! denominators without bound. A [`Rational`] therefore has two
//! representations behind one `Copy` value:
//!
//! * **small**: numerator and denominator inline as `i128`, with the checked
//!   128-bit arithmetic of the fast path;
//! * **big**: an index into a per-thread interner of arbitrary-precision
//!   rationals (`num_rational::BigRational`), used only when a value does not
//!   fit the small form.
//!
//! The representation is canonical — a value that fits the small form is
//! always small, and the interner stores each big value once — so equality
//! and hashing compare values exactly, while [`Ord`] compares by value.
//! Arithmetic never overflows: a small result that does not fit is promoted.
//! Only powers are bounded ([`Rational::MAX_DIGITS`]), so that a constant
//! power such as `2^(10^9)` is refused before it is computed.
//!
//! A big value belongs to the thread that created it (the macro runs on one
//! thread); on another thread it reads as zero instead of panicking.

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use std::cell::RefCell;
use std::cmp::Ordering;
use std::collections::HashMap;

mod convert;

/// An exact rational number in lowest terms with a positive denominator.
///
/// `Copy`, compared and hashed by value; see the [module docs](self).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rational {
    /// small: the numerator (never `i128::MIN`); big: the interner index
    num: i128,
    /// small: the denominator (> 0); big: 0
    den: i128,
}

/// The per-thread store of values that do not fit the small form.
#[derive(Default)]
struct Interner {
    vals: Vec<BigRational>,
    ix: HashMap<BigRational, usize>,
}

thread_local! {
    static BIG: RefCell<Interner> = RefCell::new(Interner::default());
}

/// Greatest common divisor of |a| and |b| (never overflows: magnitudes are
/// taken as unsigned; the result fits an i128 because small values exclude
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

/// `num / den` in the small form, or `None` if it does not fit (or `den == 0`).
fn small_new(num: i128, den: i128) -> Option<Rational> {
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

impl Rational {
    /// Zero.
    pub const ZERO: Rational = Rational { num: 0, den: 1 };
    /// One.
    pub const ONE: Rational = Rational { num: 1, den: 1 };
    /// Minus one.
    pub const MINUS_ONE: Rational = Rational { num: -1, den: 1 };

    /// Largest number of decimal digits (of numerator or denominator) that a
    /// power [`Rational::checked_powi`] computes; beyond it the power is
    /// refused before any work is done. Literals' exponents are bounded by
    /// the same figure.
    pub const MAX_DIGITS: u32 = 10_000;

    /// The integer `n`.
    pub fn int(n: i128) -> Rational {
        if n == i128::MIN {
            // the one i128 outside the (symmetric) small range
            return Rational::from_big(BigRational::from_integer(BigInt::from(n)));
        }
        Rational { num: n, den: 1 }
    }

    /// `num / den` reduced to lowest terms; `None` if `den == 0`.
    pub fn new(num: i128, den: i128) -> Option<Rational> {
        if den == 0 {
            return None;
        }
        small_new(num, den).or_else(|| {
            Some(Rational::from_big(BigRational::new(
                BigInt::from(num),
                BigInt::from(den),
            )))
        })
    }

    // ------------------------------------------------------------ representation

    /// The value as an arbitrary-precision rational.
    fn to_big(self) -> BigRational {
        if self.den != 0 {
            return BigRational::new_raw(BigInt::from(self.num), BigInt::from(self.den));
        }
        self.stored()
    }

    /// The stored big value (zero if this thread does not hold it).
    fn stored(self) -> BigRational {
        self.with_stored(|v| v.clone())
    }

    /// `f` of the stored big value, without copying it (`f` of zero if this
    /// thread does not hold it).
    fn with_stored<R: Default>(self, f: impl FnOnce(&BigRational) -> R) -> R {
        let idx = usize::try_from(self.num).unwrap_or(usize::MAX);
        let mut f = Some(f);
        let r = BIG
            .try_with(|b| {
                let b = b.try_borrow().ok()?;
                let v = b.vals.get(idx)?;
                f.take().map(|f| f(v))
            })
            .ok()
            .flatten();
        match (r, f.take()) {
            (Some(r), _) => r,
            (None, Some(f)) => f(&BigRational::zero()),
            // not reached: `f` is taken only to produce `r`
            (None, None) => R::default(),
        }
    }

    /// `f` of the values of `a` and `b` as big rationals, borrowing the
    /// interned ones (`R::default()` if this thread does not hold them).
    fn with_pair<R: Default>(
        a: Rational,
        b: Rational,
        f: impl FnOnce(&BigRational, &BigRational) -> R,
    ) -> R {
        let temp = |x: Rational| {
            x.to_i128_parts()
                .map(|(n, d)| BigRational::new_raw(BigInt::from(n), BigInt::from(d)))
        };
        let (ta, tb) = (temp(a), temp(b));
        BIG.try_with(|cell| {
            let st = cell.try_borrow().ok()?;
            fn pick<'v>(
                x: Rational,
                t: &'v Option<BigRational>,
                vals: &'v [BigRational],
            ) -> Option<&'v BigRational> {
                match t {
                    Some(v) => Some(v),
                    None => vals.get(usize::try_from(x.num).unwrap_or(usize::MAX)),
                }
            }
            let (x, y) = (pick(a, &ta, &st.vals)?, pick(b, &tb, &st.vals)?);
            Some(f(x, y))
        })
        .ok()
        .flatten()
        .unwrap_or_default()
    }

    /// A measure of the cost of arithmetic on this value: 0 for the small
    /// form, otherwise the number of 64-bit words of numerator and
    /// denominator.
    pub fn size_words(self) -> u64 {
        match self.den {
            0 => self.with_stored(|v| (v.numer().bits() + v.denom().bits()).div_ceil(64)),
            _ => 0,
        }
    }

    /// The canonical `Rational` of a big value: small if it fits, otherwise
    /// its interned index.
    fn from_big(v: BigRational) -> Rational {
        if let (Some(n), Some(d)) = (v.numer().to_i128(), v.denom().to_i128())
            && n != i128::MIN
            && d > 0
        {
            return Rational { num: n, den: d };
        }
        let idx = BIG
            .try_with(|b| {
                let mut b = b.try_borrow_mut().ok()?;
                if let Some(&i) = b.ix.get(&v) {
                    return Some(i);
                }
                let i = b.vals.len();
                b.vals.push(v.clone());
                b.ix.insert(v, i);
                Some(i)
            })
            .ok()
            .flatten();
        match idx.and_then(|i| i128::try_from(i).ok()) {
            Some(i) => Rational { num: i, den: 0 },
            None => Rational::ZERO,
        }
    }

    /// Numerator and denominator if both fit an `i128` (the small form).
    pub fn to_i128_parts(self) -> Option<(i128, i128)> {
        (self.den != 0).then_some((self.num, self.den))
    }

    /// Numerator (carries the sign).
    pub fn numer(self) -> BigInt {
        if self.den != 0 {
            return BigInt::from(self.num);
        }
        self.with_stored(|v| v.numer().clone())
    }

    /// Denominator (always positive).
    pub fn denom(self) -> BigInt {
        if self.den != 0 {
            return BigInt::from(self.den);
        }
        self.with_stored(|v| v.denom().clone())
    }

    // ------------------------------------------------------------ predicates

    /// Is this zero?
    pub fn is_zero(self) -> bool {
        self.den != 0 && self.num == 0
    }

    /// Is this one?
    pub fn is_one(self) -> bool {
        self.num == 1 && self.den == 1
    }

    /// Is this an integer?
    pub fn is_integer(self) -> bool {
        match self.den {
            0 => self.with_stored(|v| v.is_integer()),
            d => d == 1,
        }
    }

    /// Is this strictly negative?
    pub fn is_negative(self) -> bool {
        match self.den {
            0 => self.with_stored(|v| v.is_negative()),
            _ => self.num < 0,
        }
    }

    /// The integer value if this is an integer that fits an `i64`.
    pub fn to_integer(self) -> Option<i64> {
        if self.den == 1 {
            i64::try_from(self.num).ok()
        } else {
            None
        }
    }

    /// The largest integer not above this.
    pub fn floor(self) -> Rational {
        match self.den {
            0 => Rational::from_big(self.stored().floor()),
            d => Rational::int(self.num.div_euclid(d)),
        }
    }

    // ------------------------------------------------------------ arithmetic

    /// `-self`.
    pub fn checked_neg(self) -> Option<Rational> {
        match self.den {
            // the small range is symmetric (i128::MIN is excluded)
            0 => Some(Rational::from_big(-self.to_big())),
            _ => Some(Rational {
                num: -self.num,
                den: self.den,
            }),
        }
    }

    /// `|self|`.
    pub fn abs(self) -> Rational {
        if self.is_negative() {
            self.checked_neg().unwrap_or(self)
        } else {
            self
        }
    }

    /// `self + o` (always `Some`: arithmetic is exact at any size).
    pub fn checked_add(self, o: Rational) -> Option<Rational> {
        if self.den != 0 && o.den != 0 {
            if self.den == 1 && o.den == 1 {
                if let Some(s) = self.num.checked_add(o.num)
                    && s != i128::MIN
                {
                    return Some(Rational { num: s, den: 1 });
                }
            } else if let Some(r) = self.small_add(o) {
                return Some(r);
            }
        }
        Some(Rational::from_big(Rational::with_pair(self, o, |x, y| {
            x + y
        })))
    }

    fn small_add(self, o: Rational) -> Option<Rational> {
        let g = gcd(self.den, o.den);
        let a = self.num.checked_mul(o.den / g)?;
        let b = o.num.checked_mul(self.den / g)?;
        let d = (self.den / g).checked_mul(o.den)?;
        small_new(a.checked_add(b)?, d)
    }

    /// `self - o` (always `Some`).
    pub fn checked_sub(self, o: Rational) -> Option<Rational> {
        self.checked_add(o.checked_neg()?)
    }

    /// `self * o` (always `Some`).
    pub fn checked_mul(self, o: Rational) -> Option<Rational> {
        if self.den != 0
            && o.den != 0
            && let Some(r) = self.small_mul(o)
        {
            return Some(r);
        }
        // integers multiply as integers: the product of rationals reduces
        // by gcds, which for a denominator of 1 take time quadratic in the
        // length of the other number (binary gcd)
        Some(Rational::from_big(Rational::with_pair(self, o, |x, y| {
            if x.is_integer() && y.is_integer() {
                BigRational::from_integer(x.numer() * y.numer())
            } else {
                x * y
            }
        })))
    }

    fn small_mul(self, o: Rational) -> Option<Rational> {
        if self.den == 1 && o.den == 1 {
            let n = self.num.checked_mul(o.num)?;
            return (n != i128::MIN).then_some(Rational { num: n, den: 1 });
        }
        let g1 = gcd(self.num, o.den).max(1);
        let g2 = gcd(o.num, self.den).max(1);
        let n = (self.num / g1).checked_mul(o.num / g2)?;
        let d = (self.den / g2).checked_mul(o.den / g1)?;
        small_new(n, d)
    }

    /// `1 / self`; `None` for zero.
    pub fn checked_recip(self) -> Option<Rational> {
        if self.is_zero() {
            return None;
        }
        match self.den {
            0 => Some(Rational::from_big(self.to_big().recip())),
            _ => small_new(self.den, self.num),
        }
    }

    /// `self / o`; `None` for division by zero.
    pub fn checked_div(self, o: Rational) -> Option<Rational> {
        self.checked_mul(o.checked_recip()?)
    }

    /// Approximate decimal digits of `self^e` (of its larger part), as
    /// `|e| · digits(self)`; what [`Rational::checked_powi`] bounds.
    pub fn pow_digits(self, e: Rational) -> f64 {
        let d = self.digits();
        if d == 0.0 {
            return 0.0;
        }
        e.abs().to_f64() * d
    }

    /// `self ^ e` for an integer exponent; `None` for `0^negative` or when
    /// the result would have more than [`Rational::MAX_DIGITS`] digits
    /// (decided before computing it).
    pub fn checked_powi(self, e: i64) -> Option<Rational> {
        if e == 0 {
            return Some(Rational::ONE);
        }
        if self.is_zero() {
            return if e > 0 { Some(Rational::ZERO) } else { None };
        }
        if self.is_one() {
            return Some(Rational::ONE);
        }
        if self == Rational::MINUS_ONE {
            return Some(if e % 2 == 0 {
                Rational::ONE
            } else {
                Rational::MINUS_ONE
            });
        }
        if self.pow_digits(Rational::int(e as i128)) > f64::from(Rational::MAX_DIGITS) {
            return None;
        }
        let base = if e < 0 { self.checked_recip()? } else { self };
        let k = e.unsigned_abs();
        // fast path: repeated squaring in the small form
        if base.den != 0
            && let Some(r) = small_powi(base, k)
        {
            return Some(r);
        }
        // numerator and denominator stay coprime under powers
        let k32 = u32::try_from(k).ok()?;
        let b = base.to_big();
        let n = num_traits::Pow::pow(b.numer(), k32);
        let d = num_traits::Pow::pow(b.denom(), k32);
        Some(Rational::from_big(BigRational::new_raw(n, d)))
    }

    /// Greatest common divisor of two rationals (of numerators over lcm of
    /// denominators), always non-negative; used to factor out content.
    /// Always `Some`.
    pub fn gcd(self, o: Rational) -> Option<Rational> {
        if self.den != 0 && o.den != 0 {
            let n = gcd(self.num, o.num);
            let g = gcd(self.den, o.den);
            if let Some(l) = (self.den / g).checked_mul(o.den)
                && let Some(r) = small_new(n, l)
            {
                return Some(r);
            }
        }
        // gcd(n1, n2) and lcm(d1, d2) are coprime (each n_i is coprime to
        // its d_i), so the quotient needs no further reduction
        let g = Rational::with_pair(self, o, |a, b| {
            let n = a.numer().gcd(b.numer());
            let d = a.denom().lcm(b.denom());
            BigRational::new_raw(n, d)
        });
        Some(Rational::from_big(g))
    }
}

fn small_powi(base: Rational, mut k: u64) -> Option<Rational> {
    let mut acc = Rational::ONE;
    let mut b = base;
    while k > 0 {
        if k & 1 == 1 {
            acc = acc.small_mul(b)?;
        }
        k >>= 1;
        if k > 0 {
            b = b.small_mul(b)?;
        }
    }
    Some(acc)
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> Ordering {
        if self.den != 0 && other.den != 0 {
            if self.den == other.den {
                return self.num.cmp(&other.num);
            }
            // a/b against c/d as a·d against c·b
            if let (Some(l), Some(r)) = (
                self.num.checked_mul(other.den),
                other.num.checked_mul(self.den),
            ) {
                return l.cmp(&r);
            }
        }
        if other.is_zero() {
            return if self.is_negative() {
                Ordering::Less
            } else {
                Ordering::Greater
            };
        }
        if self.is_zero() {
            return if other.is_negative() {
                Ordering::Greater
            } else {
                Ordering::Less
            };
        }
        Rational::with_pair(*self, *other, |x, y| Some(x.cmp(y))).unwrap_or(Ordering::Equal)
    }
}

#[cfg(test)]
mod tests;
