//! Numeric evaluation of expressions, in any [`Scalar`] number type: `f64`
//! for the numeric checks of the derivation, double-double ([`Dd`]) where
//! cancellation to zero has to be judged beyond `f64` precision.

use super::dd::Dd;
use super::{Atom, AtomId, Engine, ExprId, Fun, MonoId, Rational};
use rustc_hash::FxHashMap as HashMap;
use std::ops::{Add, Div, Mul, Sub};

/// A number type expressions can be evaluated in.
pub trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// Zero.
    const ZERO: Self;
    /// The nearest value to an exact rational.
    fn from_rational(q: Rational) -> Self;
    /// The absolute value.
    fn abs(self) -> Self;
    /// `self^k` for an integer `k` with `|k| < i32::MAX`.
    fn powi(self, k: i64) -> Self;
    /// `self^q` for a rational exponent that is not a small integer.
    fn powq(self, q: Rational) -> Self;
    /// The sine.
    fn sin(self) -> Self;
    /// The cosine.
    fn cos(self) -> Self;
    /// The tangent.
    fn tan(self) -> Self;
    /// The exponential.
    fn exp(self) -> Self;
    /// The natural logarithm.
    fn ln(self) -> Self;
    /// The hyperbolic sine.
    fn sinh(self) -> Self;
    /// The hyperbolic cosine.
    fn cosh(self) -> Self;
    /// The hyperbolic tangent.
    fn tanh(self) -> Self;
    /// The inverse sine.
    fn asin(self) -> Self;
    /// The inverse cosine.
    fn acos(self) -> Self;
    /// The inverse tangent.
    fn atan(self) -> Self;
    /// The angle of the point `(x, self)`, in (−π, π] (0 at the origin).
    fn atan2(self, x: Self) -> Self;
    /// −1, 0 or 1 by the sign (0 at ±0; NaN stays NaN).
    fn sign(self) -> Self;
}

impl Scalar for f64 {
    const ZERO: f64 = 0.0;
    fn from_rational(q: Rational) -> f64 {
        q.to_f64()
    }
    fn abs(self) -> f64 {
        f64::abs(self)
    }
    fn powi(self, k: i64) -> f64 {
        f64::powi(self, k as i32)
    }
    fn powq(self, q: Rational) -> f64 {
        f64::powf(self, q.to_f64())
    }
    fn sin(self) -> f64 {
        f64::sin(self)
    }
    fn cos(self) -> f64 {
        f64::cos(self)
    }
    fn tan(self) -> f64 {
        f64::tan(self)
    }
    fn exp(self) -> f64 {
        f64::exp(self)
    }
    fn ln(self) -> f64 {
        f64::ln(self)
    }
    fn sinh(self) -> f64 {
        f64::sinh(self)
    }
    fn cosh(self) -> f64 {
        f64::cosh(self)
    }
    fn tanh(self) -> f64 {
        f64::tanh(self)
    }
    fn asin(self) -> f64 {
        f64::asin(self)
    }
    fn acos(self) -> f64 {
        f64::acos(self)
    }
    fn atan(self) -> f64 {
        f64::atan(self)
    }
    fn atan2(self, x: f64) -> f64 {
        f64::atan2(self, x)
    }
    fn sign(self) -> f64 {
        if self > 0.0 {
            1.0
        } else if self < 0.0 {
            -1.0
        } else {
            self
        }
    }
}

impl Scalar for Dd {
    const ZERO: Dd = Dd::ZERO;
    fn from_rational(q: Rational) -> Dd {
        Dd::from_rational(q)
    }
    fn abs(self) -> Dd {
        Dd::abs(self)
    }
    fn powi(self, k: i64) -> Dd {
        Dd::powi(self, k)
    }
    fn powq(self, q: Rational) -> Dd {
        (Dd::ln(self) * Dd::from_rational(q)).exp()
    }
    fn sin(self) -> Dd {
        self.sin_cos().0
    }
    fn cos(self) -> Dd {
        self.sin_cos().1
    }
    fn tan(self) -> Dd {
        let (s, c) = self.sin_cos();
        s / c
    }
    fn exp(self) -> Dd {
        Dd::exp(self)
    }
    fn ln(self) -> Dd {
        Dd::ln(self)
    }
    fn sinh(self) -> Dd {
        Dd::sinh(self)
    }
    fn cosh(self) -> Dd {
        Dd::cosh(self)
    }
    fn tanh(self) -> Dd {
        Dd::tanh(self)
    }
    fn asin(self) -> Dd {
        Dd::asin(self)
    }
    fn acos(self) -> Dd {
        Dd::acos(self)
    }
    fn atan(self) -> Dd {
        Dd::atan2(self, Dd::ONE)
    }
    fn atan2(self, x: Dd) -> Dd {
        Dd::atan2(self, x)
    }
    fn sign(self) -> Dd {
        Dd::from_f64(self.hi.sign())
    }
}

/// `f(x)`.
fn call<S: Scalar>(f: Fun, x: S) -> S {
    match f {
        Fun::Sin => x.sin(),
        Fun::Cos => x.cos(),
        Fun::Tan => x.tan(),
        Fun::Exp => x.exp(),
        Fun::Ln => x.ln(),
        Fun::Abs => x.abs(),
        Fun::Sign => x.sign(),
        Fun::Cot => x.cos() / x.sin(),
        Fun::Sec => S::from_rational(Rational::ONE) / x.cos(),
        Fun::Csc => S::from_rational(Rational::ONE) / x.sin(),
        Fun::Sinh => x.sinh(),
        Fun::Cosh => x.cosh(),
        Fun::Tanh => x.tanh(),
        Fun::Asin => x.asin(),
        Fun::Acos => x.acos(),
        Fun::Atan => x.atan(),
    }
}

/// The values of expressions and of function atoms already evaluated at one
/// point (a function such as `sin(roll)` occurs in many monomials).
pub struct EvalMemo<S> {
    exprs: HashMap<ExprId, S>,
    atoms: HashMap<AtomId, S>,
}

impl<S> Default for EvalMemo<S> {
    fn default() -> Self {
        EvalMemo {
            exprs: HashMap::default(),
            atoms: HashMap::default(),
        }
    }
}

impl Engine {
    /// Evaluates `e` with `vals[s]` the value of symbol `s`.
    pub fn eval<S: Scalar>(&self, e: ExprId, vals: &[S]) -> S {
        let mut memo = EvalMemo::default();
        self.eval_memo(e, vals, &mut memo)
    }

    /// Evaluates with a caller-held memo (for many expressions at one point).
    pub fn eval_memo<S: Scalar>(&self, e: ExprId, vals: &[S], memo: &mut EvalMemo<S>) -> S {
        if let Some(&v) = memo.exprs.get(&e) {
            return v;
        }
        let mut acc = S::ZERO;
        for &(m, c) in &self.exprs[e.index()] {
            acc = acc + self.eval_term(m, c, vals, memo);
        }
        memo.exprs.insert(e, acc);
        acc
    }

    /// The value of atom `a` (memoised unless it is a symbol).
    fn eval_atom<S: Scalar>(&self, a: AtomId, vals: &[S], memo: &mut EvalMemo<S>) -> S {
        if let Atom::Sym(s) = &self.atoms[a.index()] {
            return vals[s.index()];
        }
        if let Some(&v) = memo.atoms.get(&a) {
            return v;
        }
        let v = match &self.atoms[a.index()] {
            Atom::Sym(s) => vals[s.index()],
            Atom::Func(f, u) => call(*f, self.eval_memo(*u, vals, memo)),
            Atom::Base(b) => self.eval_memo(*b, vals, memo),
            Atom::Atan2(y, x) => {
                let y = self.eval_memo(*y, vals, memo);
                y.atan2(self.eval_memo(*x, vals, memo))
            }
        };
        memo.atoms.insert(a, v);
        v
    }

    /// Evaluates `e` and the sum of the absolute values of its terms (the
    /// scale against which cancellation to zero is judged).
    pub fn eval_with_scale<S: Scalar>(&self, e: ExprId, vals: &[S]) -> (S, S) {
        let mut memo = EvalMemo::default();
        let mut value = S::ZERO;
        let mut scale = S::ZERO;
        for &(m, c) in &self.exprs[e.index()] {
            let t = self.eval_term(m, c, vals, &mut memo);
            value = value + t;
            scale = scale + t.abs();
        }
        (value, scale)
    }

    /// The value of the term `c·m`.
    fn eval_term<S: Scalar>(
        &self,
        m: MonoId,
        c: Rational,
        vals: &[S],
        memo: &mut EvalMemo<S>,
    ) -> S {
        let mut t = S::from_rational(c);
        for &(a, ex) in &self.monos[m.index()] {
            let b = self.eval_atom(a, vals, memo);
            t = t * match ex.to_integer() {
                Some(1) => b,
                Some(k) if k.abs() < i32::MAX as i64 => b.powi(k),
                _ => b.powq(ex),
            };
        }
        t
    }
}
