//! Powers: integer powers by repeated squaring, and rational powers with
//! real-valued semantics (exponents multiplied only where that is an
//! identity on the reals), with the content of a sum and `c·cos²` pivots
//! taken out first.

use super::normal::is_even;
use super::{Atom, AtomId, Engine, ExprId, Factors, Fun, Limit, MONO_ONE, ONE, Rational, ZERO};

impl Engine {
    /// An integer exponent to expand by; beyond 2³² it is expression swell
    /// (flagged, and 0 returned).
    pub(super) fn exponent_count(&mut self, k: i64) -> u32 {
        u32::try_from(k).unwrap_or_else(|_| {
            self.exceed(Limit::Exponent);
            0
        })
    }

    /// `a^k` for a non-negative integer `k`, by repeated squaring.
    pub fn pow_int(&mut self, a: ExprId, k: u32) -> ExprId {
        let mut acc = ONE;
        let mut b = a;
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                acc = self.mul(acc, b);
            }
            k >>= 1;
            if k > 0 {
                b = self.mul(b, b);
            }
        }
        acc
    }

    /// `a^k` for an integer `k` of either sign.
    pub(super) fn pow_signed(&mut self, a: ExprId, k: i64) -> ExprId {
        if k >= 0 {
            let kk = self.exponent_count(k);
            return self.pow_int(a, kk);
        }
        self.pow(a, Rational::int(k as i128))
    }

    /// `a^q` for a rational exponent, following real-valued semantics: the
    /// exponents of a power are multiplied only where that is an identity on
    /// the reals, and an even power under a root is a power of the absolute
    /// value (`(x²)^(1/2)` is `|x|`, `(x⁴)^(1/2)` is `x²`).
    pub fn pow(&mut self, a: ExprId, q: Rational) -> ExprId {
        if q.is_zero() {
            return ONE;
        }
        if q.is_one() {
            return a;
        }
        if q.is_integer()
            && a != ZERO
            && let Some(c) = self.as_constant(a)
        {
            let v = self.constant_power(c, q);
            return self.constant(v);
        }
        if q.is_integer() && !q.is_negative() {
            let k = q.to_integer().unwrap_or(i64::MAX);
            let kk = self.exponent_count(k);
            return self.pow_int(a, kk);
        }
        if a == ZERO {
            // 0^q = 0 for q > 0 (sqrt(0) = 0); 0 to a negative power is a
            // division by zero, which the caller reports: keep it symbolic.
            if !q.is_negative() {
                return ZERO;
            }
            let b = self.intern_atom(Atom::Base(ZERO));
            return self.atom_power(b, q);
        }
        if let Some(p) = self.distributed_power(a, q) {
            return p;
        }
        // an integer power of a sum: take its content (the rational gcd and the
        // monomial common to all terms) out first, so that a factor such as
        // m R² of a pivot cancels against the numerator
        if q.is_integer()
            && let Some((g, rest)) = self.content(a)
        {
            let gq = self.pow(g, q);
            let rq = self.pow(rest, q);
            return self.mul(gq, rq);
        }
        // c·(1 − sin²u) is c·cos²u: an integer power of it is a power of cos
        // (the Pythagorean normal form keeps cos² as 1 − sin², so pivots of
        // a reduced mass matrix come out in this shape)
        if q.is_integer()
            && let Some((c, u)) = self.scaled_one_minus_sin2(a)
        {
            let cq = self.pow(c, q);
            let cu = self.func(Fun::Cos, u);
            let k = q.checked_mul(Rational::int(2)).unwrap_or(q);
            let cp = self.atom_power_normal_of(cu, k);
            return self.mul(cq, cp);
        }
        let b = self.intern_atom(Atom::Base(a));
        self.atom_power_normal(b, q)
    }

    /// A constant to an integer power: exact, bounded in size (beyond
    /// [`Rational::MAX_DIGITS`] digits flagged as overflow).
    fn constant_power(&mut self, c: Rational, q: Rational) -> Rational {
        match q.to_integer() {
            Some(k) => self.qpowi(c, k),
            None if c.is_one() => Rational::ONE,
            None if c == Rational::MINUS_ONE => {
                let even = q
                    .checked_div(Rational::int(2))
                    .is_some_and(|h| h.is_integer());
                if even {
                    Rational::ONE
                } else {
                    Rational::MINUS_ONE
                }
            }
            None => {
                self.exceed(Limit::Exponent);
                Rational::ZERO
            }
        }
    }

    /// `a^q` for a monomial `a` whose power distributes over its factors
    /// (an integer power, or a positive coefficient with no integer
    /// exponents other than ±1), else `None`.
    fn distributed_power(&mut self, a: ExprId, q: Rational) -> Option<ExprId> {
        let terms = self.exprs[a.index()].clone();
        let [(m, c)] = terms.as_slice() else {
            return None;
        };
        let factors = self.monos[m.index()].clone();
        let distributable = q.is_integer()
            || (!c.is_negative()
                && factors
                    .iter()
                    .all(|&(_, e)| !e.is_integer() || e.abs().is_one() || is_even(e)));
        if !distributable {
            return None;
        }
        // coefficient part
        let cpart = if c.is_one() {
            ONE
        } else if q.is_integer() {
            let v = self.qpowi(*c, q.to_integer().unwrap_or(0));
            self.constant(v)
        } else {
            let cc = self.constant(*c);
            let b = self.intern_atom(Atom::Base(cc));
            self.atom_power_normal(b, q)
        };
        let mut prod: Factors = Vec::with_capacity(factors.len());
        let mut even_roots = Vec::new();
        for (at, e) in factors {
            let ne = self.qmul(e, q);
            if !q.is_integer() && is_even(e) {
                // (x^(2k))^q = |x|^(2kq): sqrt(x²) is |x|
                even_roots.push((at, ne));
            } else {
                prod.push((at, ne));
            }
        }
        let mut r = self.normal_expr(prod);
        r = self.mul(cpart, r);
        for (at, ne) in even_roots {
            let x = self.abs_of_atom(at);
            let p = self.pow(x, ne);
            r = self.mul(r, p);
        }
        Some(r)
    }

    /// `(c, u)` if `e` is `c·(1 − sin²u)` for a rational `c`: the normal form
    /// of `c·cos²u`, whose square root is `√c·|cos u|`.
    pub fn as_scaled_cos_square(&mut self, e: ExprId) -> Option<(Rational, ExprId)> {
        let (c, u) = self.scaled_one_minus_sin2(e)?;
        Some((self.as_constant(c)?, u))
    }

    /// `(c, u)` if `e` is `c − c·sin(u)²` for a rational `c ≠ 0`.
    fn scaled_one_minus_sin2(&mut self, e: ExprId) -> Option<(ExprId, ExprId)> {
        let terms = self.exprs[e.index()].clone();
        let [(m0, c0), (m1, c1)] = terms.as_slice() else {
            return None;
        };
        let (konst, other, c_other) = if *m0 == MONO_ONE {
            (*c0, *m1, *c1)
        } else if *m1 == MONO_ONE {
            (*c1, *m0, *c0)
        } else {
            return None;
        };
        if c_other.checked_neg() != Some(konst) {
            return None;
        }
        let [(at, ex)] = self.monos[other.index()].as_slice() else {
            return None;
        };
        match self.atoms[at.index()] {
            Atom::Func(Fun::Sin, u) if *ex == Rational::int(2) => Some((self.constant(konst), u)),
            _ => None,
        }
    }

    /// `x^k` for an expression `x` that is a single atom to the first power.
    fn atom_power_normal_of(&mut self, x: ExprId, k: Rational) -> ExprId {
        match self.exprs[x.index()].as_slice() {
            [(m, c)] if c.is_one() => match self.monos[m.index()].as_slice() {
                [(at, e)] if e.is_one() => {
                    let at = *at;
                    self.atom_power_normal(at, k)
                }
                _ => self.pow(x, k),
            },
            _ => self.pow(x, k),
        }
    }

    pub(super) fn atom_power_normal(&mut self, a: AtomId, q: Rational) -> ExprId {
        self.normal_expr(vec![(a, q)])
    }
}
