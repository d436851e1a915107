//! The normal form of a monomial: constant bases folded into the
//! coefficient, integer powers of monomial bases distributed, small integer
//! powers of sums expanded, and trigonometric powers reduced modulo
//! `sin² + cos² = 1`; even powers of `|u|` become powers of `u`.

use super::{Atom, AtomId, Engine, ExprId, Factors, Fun, MonoId, ONE, Rational};

/// A normalised factor list: still one monomial (with a coefficient), or an
/// expression (the monomial expanded into a sum).
pub(super) enum Normal {
    Mono(MonoId, Rational),
    Expr(ExprId),
}

/// A monomial under normalisation: the factors it keeps, its coefficient and
/// the expressions it is multiplied by.
struct Parts {
    kept: Factors,
    coef: Rational,
    multiplicands: Vec<ExprId>,
}

impl Engine {
    /// Normalises a merged factor list: folds constant bases into the
    /// coefficient, expands integer powers of sums, distributes integer powers
    /// of monomial bases and reduces `cos²`.
    pub(super) fn normal_mono(&mut self, f: Factors) -> Normal {
        let needs =
            f.iter().any(|&(a, e)| self.factor_needs_work(a, e)) || self.sin_over_cos(&f).is_some();
        if !needs {
            let m = self.intern_mono(f);
            return Normal::Mono(m, Rational::ONE);
        }
        if let Some((si, u)) = self.sin_over_cos(&f) {
            return Normal::Expr(self.split_sin_over_cos(f, si, u));
        }
        let mut parts = Parts {
            kept: Vec::new(),
            coef: Rational::ONE,
            multiplicands: Vec::new(),
        };
        for (a, e) in f {
            if e.is_zero() {
                continue;
            }
            match self.atoms[a.index()].clone() {
                Atom::Func(Fun::Cos, u) if e.is_integer() && e >= Rational::int(2) => {
                    let k = e.to_integer().unwrap_or(0);
                    if k % 2 == 1 {
                        parts.kept.push((a, Rational::ONE));
                    }
                    // (1 - sin(u)^2)^(k div 2)
                    let s = self.func(Fun::Sin, u);
                    let s2 = self.mul(s, s);
                    let one_minus = self.sub(ONE, s2);
                    let half = self.exponent_count(k / 2);
                    let p = self.pow_int(one_minus, half);
                    parts.multiplicands.push(p);
                }
                Atom::Base(b) => self.normal_base_power(a, b, e, &mut parts),
                Atom::Func(Fun::Abs, u) if is_even(e) => {
                    // |u|^(2k) = u^(2k)
                    let p = self.pow(u, e);
                    parts.multiplicands.push(p);
                }
                _ => parts.kept.push((a, e)),
            }
        }
        let m = self.intern_mono(parts.kept);
        let base = self.intern_expr(vec![(m, Rational::ONE)]);
        let mut r = self.scale(base, parts.coef);
        for p in parts.multiplicands {
            r = self.mul(r, p);
        }
        Normal::Expr(r)
    }

    /// `sin(u)^a cos(u)^b` with `a ≥ 2` and `b < 0` (the `sin(u)` at `si` of
    /// `f`): sin² = 1 − cos² (this keeps the Laurent part in the basis
    /// {cos^b, sin·cos^b}, so that, e.g., tan² + 1 becomes cos⁻²). Split into
    /// the two monomials directly: multiplying by 1 − cos² would
    /// canonicalise back to sin².
    fn split_sin_over_cos(&mut self, f: Factors, si: usize, u: ExprId) -> ExprId {
        let mut f1 = f;
        f1[si].1 = f1[si]
            .1
            .checked_sub(Rational::int(2))
            .unwrap_or(Rational::ZERO);
        let mut f2 = f1.clone();
        if let Some(&c) = self.atom_ix.get(&Atom::Func(Fun::Cos, u))
            && let Some(slot) = f2.iter_mut().find(|x| x.0 == c)
        {
            slot.1 = slot
                .1
                .checked_add(Rational::int(2))
                .unwrap_or(Rational::ZERO);
        }
        let e1 = self.normal_expr(f1);
        let e2 = self.normal_expr(f2);
        self.sub(e1, e2)
    }

    /// The factor `b^e` (atom `a`) of a monomial being normalised: a constant
    /// base folds its integer power into the coefficient, a monomial base
    /// distributes it, a sum expands it unless the power is kept; the
    /// fractional rest of the exponent stays on the atom.
    fn normal_base_power(&mut self, a: AtomId, b: ExprId, e: Rational, parts: &mut Parts) {
        let k = floor(e);
        let frac = e
            .checked_sub(Rational::int(k as i128))
            .unwrap_or(Rational::ZERO);
        if let Some(c) = self.as_constant(b) {
            // c^e = c^floor(e) * c^(e - floor(e))
            let ck = self.qpowi(c, k);
            parts.coef = self.qmul(parts.coef, ck);
        } else if self.exprs[b.index()].len() == 1 {
            // a monomial base: integer part distributes
            let p = self.pow_signed(b, k);
            parts.multiplicands.push(p);
        } else if e >= Rational::ONE && !self.power_is_kept(b, k) {
            let kk = self.exponent_count(k);
            let p = self.pow_int(b, kk);
            parts.multiplicands.push(p);
        } else {
            parts.kept.push((a, e));
            return;
        }
        if !frac.is_zero() {
            parts.kept.push((a, frac));
        }
    }

    /// A factor list as a normalised expression.
    pub(super) fn normal_expr(&mut self, f: Factors) -> ExprId {
        match self.normal_mono(f) {
            Normal::Mono(m, k) => {
                let e = self.intern_expr(vec![(m, Rational::ONE)]);
                self.scale(e, k)
            }
            Normal::Expr(e) => e,
        }
    }

    /// In a factor list, the position of `sin(u)^a` (a ≥ 2) whose `cos(u)`
    /// has a negative exponent, and `u`.
    fn sin_over_cos(&self, f: &[(AtomId, Rational)]) -> Option<(usize, ExprId)> {
        for (i, &(a, e)) in f.iter().enumerate() {
            if let Atom::Func(Fun::Sin, u) = self.atoms[a.index()]
                && e.is_integer()
                && e >= Rational::int(2)
                && let Some(&c) = self.atom_ix.get(&Atom::Func(Fun::Cos, u))
                && f.iter().any(|&(x, ex)| x == c && ex.is_negative())
            {
                return Some((i, u));
            }
        }
        None
    }

    fn factor_needs_work(&self, a: AtomId, e: Rational) -> bool {
        if e.is_zero() {
            return true;
        }
        match &self.atoms[a.index()] {
            Atom::Func(Fun::Cos, _) => e.is_integer() && e >= Rational::int(2),
            Atom::Func(Fun::Abs, _) => is_even(e),
            Atom::Base(b) => {
                // normal exponents: in (0, 1) for constant and monomial bases,
                // below 1 for sums, except a sum whose power is kept
                // unexpanded (see `kept_product`)
                if self.exprs[b.index()].len() <= 1 {
                    !(e > Rational::ZERO && e < Rational::ONE)
                } else {
                    e >= Rational::ONE && !self.power_is_kept(*b, floor(e))
                }
            }
            Atom::Sym(_) | Atom::Func(..) | Atom::Atan2(..) => false,
        }
    }
}

/// Is `e` an even integer?
pub(super) fn is_even(e: Rational) -> bool {
    e.checked_div(Rational::int(2))
        .is_some_and(|h| h.is_integer())
}

pub(super) fn floor(e: Rational) -> i64 {
    let q = e.floor();
    q.to_integer().unwrap_or(if q.is_negative() {
        i64::MIN / 2
    } else {
        i64::MAX / 2
    })
}
