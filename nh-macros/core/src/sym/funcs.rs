//! The functions beyond `sin`, `cos`, `tan`, `exp` and `ln` in the
//! canonical form: `cot`, `sec` and `csc` as powers of `sin` and `cos`; the
//! odd functions (`sinh`, `tanh`, `asin`, `atan`, `sign`) with the sign of
//! their argument pulled out and the even ones (`cosh`, `abs`) with it
//! dropped; `abs` distributed over the factors of a monomial (`|x²y| = x²|y|`);
//! `atan2`; and the exact values at constant arguments ([`exact_value`]).

use super::normal::is_even;
use super::{Atom, AtomId, Engine, ExprId, Fun, ONE, Rational, ZERO};

/// The exact value of `f(c)` at a rational `c`, as `(r, k)` meaning
/// `r + k·π`, where it is a rational or a rational multiple of π (`acos(0)`
/// is `(0, 1/2)`); `None` where it is neither or `c` is outside the domain.
/// Only functions of the language beyond `sin`, `cos`, `tan`, `exp` and `ln`.
pub fn exact_value(f: Fun, c: Rational) -> Option<(Rational, Rational)> {
    let q = |n, d| Rational::new(n, d);
    let rational = |r: Rational| Some((r, Rational::ZERO));
    let pi = |n, d| Some((Rational::ZERO, q(n, d)?));
    let sign = match c.cmp(&Rational::ZERO) {
        std::cmp::Ordering::Less => -1,
        std::cmp::Ordering::Equal => 0,
        std::cmp::Ordering::Greater => 1,
    };
    let half = q(1, 2)?;
    match f {
        Fun::Abs => rational(c.abs()),
        Fun::Sign => rational(Rational::int(sign)),
        Fun::Sinh | Fun::Tanh | Fun::Asin | Fun::Atan if c.is_zero() => rational(Rational::ZERO),
        Fun::Cosh if c.is_zero() => rational(Rational::ONE),
        Fun::Asin if c.abs().is_one() => pi(sign, 2),
        Fun::Asin if c.abs() == half => pi(sign, 6),
        Fun::Acos if c.is_zero() => pi(1, 2),
        Fun::Acos if c.is_one() => rational(Rational::ZERO),
        Fun::Acos if c == Rational::MINUS_ONE => pi(1, 1),
        Fun::Acos if c == half => pi(1, 3),
        Fun::Acos if c.checked_neg() == Some(half) => pi(2, 3),
        Fun::Atan if c.abs().is_one() => pi(sign, 4),
        _ => None,
    }
}

/// The exact value of `atan2(y, x)` at rationals, as `(r, k)` meaning
/// `r + k·π` (see [`exact_value`]), where the angle is a multiple of π/4;
/// `None` otherwise and at the origin, where it is undefined.
pub fn exact_atan2(y: Rational, x: Rational) -> Option<(Rational, Rational)> {
    use std::cmp::Ordering::{Equal, Greater, Less};
    let quarters: i128 = match (y.cmp(&Rational::ZERO), x.cmp(&Rational::ZERO)) {
        (Equal, Equal) => return None,
        (Equal, Greater) => 0,
        (Equal, Less) => 4,
        (Greater, Equal) => 2,
        (Less, Equal) => -2,
        _ if y.abs() != x.abs() => return None,
        (Greater, Greater) => 1,
        (Greater, Less) => 3,
        (Less, Less) => -3,
        (Less, Greater) => -1,
    };
    Some((Rational::ZERO, Rational::new(quarters, 4)?))
}

/// Is the function odd (`f(−u) = −f(u)`)?
fn is_odd(f: Fun) -> bool {
    matches!(f, Fun::Sinh | Fun::Tanh | Fun::Asin | Fun::Atan | Fun::Sign)
}

impl Engine {
    /// `f(a)` for the functions beyond `sin`, `cos`, `tan`, `exp` and `ln`
    /// (see the module documentation).
    pub(super) fn func_beyond(&mut self, f: Fun, a: ExprId) -> ExprId {
        match f {
            Fun::Cot => {
                let c = self.func(Fun::Cos, a);
                let s = self.func(Fun::Sin, a);
                let si = self.pow(s, Rational::MINUS_ONE);
                return self.mul(c, si);
            }
            Fun::Sec | Fun::Csc => {
                let g = if f == Fun::Sec { Fun::Cos } else { Fun::Sin };
                let x = self.func(g, a);
                return self.pow(x, Rational::MINUS_ONE);
            }
            Fun::Abs => return self.abs(a),
            _ => {}
        }
        if let Some(c) = self.as_constant(a)
            && let Some((r, k)) = exact_value(f, c)
            && k.is_zero()
        {
            return self.constant(r);
        }
        if self.leading_negative(a) && (is_odd(f) || f == Fun::Cosh) {
            let na = self.neg(a);
            let inner = self.func(f, na);
            return if f == Fun::Cosh {
                inner
            } else {
                self.neg(inner)
            };
        }
        if f == Fun::Sign
            && let [(m, c)] = self.exprs[a.index()].as_slice()
            && !c.is_one()
        {
            // sign(c·m) = sign(m) for c > 0 (the negative case is odd, above)
            let m = *m;
            let unit = self.intern_expr(vec![(m, Rational::ONE)]);
            return self.func(Fun::Sign, unit);
        }
        self.func_atom(f, a)
    }

    /// The atom `f(a)` to the first power, as an expression.
    pub(super) fn func_atom(&mut self, f: Fun, a: ExprId) -> ExprId {
        let at = self.intern_atom(Atom::Func(f, a));
        self.atom_power(at, Rational::ONE)
    }

    /// Is the leading coefficient of `a` negative?
    pub(super) fn leading_negative(&self, a: ExprId) -> bool {
        self.exprs[a.index()]
            .first()
            .is_some_and(|(_, c)| c.is_negative())
    }

    /// `|a|`: a constant folded; a monomial `c·Π xᵢ^eᵢ` as `|c|·Π |xᵢ|^eᵢ`
    /// with `|x|^e = x^e` where `x^e` is never negative (an even power, a
    /// fractional power, `exp`, `cosh`, `abs`); a sum as the atom `|±a|`
    /// with a positive leading coefficient.
    fn abs(&mut self, a: ExprId) -> ExprId {
        if let Some(c) = self.as_constant(a) {
            return self.constant(c.abs());
        }
        let terms = self.exprs[a.index()].clone();
        let [(m, c)] = terms.as_slice() else {
            let a = if self.leading_negative(a) {
                self.neg(a)
            } else {
                a
            };
            return self.func_atom(Fun::Abs, a);
        };
        let mut r = self.constant(c.abs());
        for (at, e) in self.monos[m.index()].clone() {
            let factor = if self.nonnegative_power(at, e) {
                self.normal_expr(vec![(at, e)])
            } else {
                let x = self.atom_abs(at);
                self.pow(x, e)
            };
            r = self.mul(r, factor);
        }
        r
    }

    /// Is `x^e` (atom `x`) never negative where it is defined?
    fn nonnegative_power(&self, x: AtomId, e: Rational) -> bool {
        is_even(e)
            || !e.is_integer()
            || matches!(
                self.atoms[x.index()],
                Atom::Func(Fun::Exp | Fun::Cosh | Fun::Abs, _)
            )
    }

    /// `|x|` of one atom `x`: `x` itself if it is never negative (`exp`,
    /// `cosh`, `abs`), else as [`atom_abs`](Self::atom_abs).
    pub(super) fn abs_of_atom(&mut self, x: AtomId) -> ExprId {
        if self.nonnegative_power(x, Rational::ONE) {
            return self.atom_power(x, Rational::ONE);
        }
        self.atom_abs(x)
    }

    /// `|x|` of one atom: the atom `abs(x)` (for a sum base, `|±b|`).
    fn atom_abs(&mut self, x: AtomId) -> ExprId {
        match self.atoms[x.index()] {
            Atom::Base(b) if self.exprs[b.index()].len() > 1 => self.abs(b),
            _ => {
                let u = self.atom_power(x, Rational::ONE);
                self.func_atom(Fun::Abs, u)
            }
        }
    }

    /// `atan2(y, x)`, the angle of the point `(x, y)`: exact at constant
    /// points where it is a multiple of π/4 with no π (`atan2(0, c) = 0`
    /// for `c > 0`), otherwise an atom. At the origin it is undefined; a
    /// constant origin is kept as an atom (the language rejects it first).
    pub fn atan2(&mut self, y: ExprId, x: ExprId) -> ExprId {
        if let (Some(cy), Some(cx)) = (self.as_constant(y), self.as_constant(x))
            && let Some((r, k)) = exact_atan2(cy, cx)
            && k.is_zero()
        {
            return self.constant(r);
        }
        let at = self.intern_atom(Atom::Atan2(y, x));
        self.atom_power(at, Rational::ONE)
    }

    /// `(x·∂y − y·∂x) / (x² + y²)`, the derivative of `atan2(y, x)` given
    /// the derivatives `dy` and `dx` of its arguments.
    pub(super) fn atan2_derivative(
        &mut self,
        y: ExprId,
        x: ExprId,
        dy: ExprId,
        dx: ExprId,
    ) -> (ExprId, ExprId) {
        let xdy = self.mul(x, dy);
        let ydx = self.mul(y, dx);
        let num = self.sub(xdy, ydx);
        let x2 = self.mul(x, x);
        let y2 = self.mul(y, y);
        let r2 = self.add(x2, y2);
        let inv = self.pow(r2, Rational::MINUS_ONE);
        (inv, num)
    }

    /// The derivative `f'(u)` of a function beyond `sin`, `cos`, `tan`, `exp`
    /// and `ln` (that of `sign` taken as 0, also at 0).
    pub(super) fn outer_derivative_beyond(&mut self, f: Fun, u: ExprId) -> ExprId {
        let half = Rational::new(1, 2).unwrap_or(Rational::ONE);
        let minus_half = half.checked_neg().unwrap_or(Rational::MINUS_ONE);
        match f {
            Fun::Abs => self.func(Fun::Sign, u),
            Fun::Sinh => self.func(Fun::Cosh, u),
            Fun::Cosh => self.func(Fun::Sinh, u),
            Fun::Tanh => {
                let t = self.func(Fun::Tanh, u);
                let t2 = self.mul(t, t);
                self.sub(ONE, t2)
            }
            Fun::Asin | Fun::Acos => {
                let u2 = self.mul(u, u);
                let one_minus = self.sub(ONE, u2);
                let d = self.pow(one_minus, minus_half);
                if f == Fun::Acos { self.neg(d) } else { d }
            }
            Fun::Atan => {
                let u2 = self.mul(u, u);
                let one_plus = self.add(ONE, u2);
                self.pow(one_plus, Rational::MINUS_ONE)
            }
            Fun::Cot | Fun::Csc => {
                // cot' = −1/sin², csc' = −cos/sin²
                let s = self.func(Fun::Sin, u);
                let s2 = self.pow(s, Rational::int(-2));
                let top = if f == Fun::Csc {
                    self.func(Fun::Cos, u)
                } else {
                    ONE
                };
                let d = self.mul(top, s2);
                self.neg(d)
            }
            Fun::Sec => {
                // sec' = sin/cos²
                let s = self.func(Fun::Sin, u);
                let c = self.func(Fun::Cos, u);
                let c2 = self.pow(c, Rational::int(-2));
                self.mul(s, c2)
            }
            Fun::Sign | Fun::Sin | Fun::Cos | Fun::Tan | Fun::Exp | Fun::Ln => ZERO,
        }
    }
}
