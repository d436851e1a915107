//! Arithmetic in the canonical form: constants, sums, scaling, products
//! (expanded, or kept unexpanded past the expansion limits), quotients and
//! the elementary functions, with constants folded. Rational coefficient
//! arithmetic is counted as work and flags overflow instead of panicking.

use super::graph::merge_factors;
use super::normal::Normal;
use super::{
    Atom, AtomId, Engine, ExprId, Fun, Limit, MAX_NESTING, MAX_TERMS, MONO_ONE, MonoId, ONE,
    Rational, SymId, Terms, ZERO,
};

impl Engine {
    /// Counts arithmetic on big coefficients as work (see
    /// [`MAX_WORK`](super::MAX_WORK)): a product of two values of `a` and
    /// `b` words costs about `a·b` word operations plus the reduction.
    /// True if the derivation is abandoned (then the product is not
    /// computed).
    fn big_work(&mut self, a: Rational, b: Rational) -> bool {
        if a.to_i128_parts().is_none() || b.to_i128_parts().is_none() {
            let (wa, wb) = (a.size_words(), b.size_words());
            self.count_big_work(8u64.saturating_mul(wa + 1).saturating_mul(wb + 1));
            return self.abandoned();
        }
        false
    }

    /// Adds `cost` units of arithmetic on big coefficients to the work;
    /// past the limit, the derivation is abandoned there
    /// ([`Limit::Constants`]).
    fn count_big_work(&mut self, cost: u64) {
        let cost = usize::try_from(cost).unwrap_or(usize::MAX);
        self.work = self.work.saturating_add(cost);
        if self.work > self.max_work {
            self.exceed(Limit::Constants);
        }
    }

    pub(super) fn qmul(&mut self, a: Rational, b: Rational) -> Rational {
        if self.big_work(a, b) {
            return Rational::ZERO;
        }
        a.checked_mul(b).unwrap_or_else(|| {
            self.exceed(Limit::Digits);
            Rational::ZERO
        })
    }

    pub(super) fn qpowi(&mut self, a: Rational, e: i64) -> Rational {
        a.checked_powi(e).unwrap_or_else(|| {
            self.exceed(Limit::Digits);
            Rational::ZERO
        })
    }

    /// The rational constant `c`.
    pub fn constant(&mut self, c: Rational) -> ExprId {
        if c.is_zero() {
            ZERO
        } else {
            self.intern_expr(vec![(MONO_ONE, c)])
        }
    }

    /// The integer constant `n`.
    pub fn int(&mut self, n: i128) -> ExprId {
        self.constant(Rational::int(n))
    }

    /// The expression consisting of symbol `s`.
    pub fn sym(&mut self, s: SymId) -> ExprId {
        let a = self.intern_atom(Atom::Sym(s));
        self.atom_power(a, Rational::ONE)
    }

    /// `a^e` for an atom `a`.
    pub fn atom_power(&mut self, a: AtomId, e: Rational) -> ExprId {
        let m = self.intern_mono(vec![(a, e)]);
        self.intern_expr(vec![(m, Rational::ONE)])
    }

    /// Builds an expression from unsorted terms, collecting like monomials.
    fn collect(&mut self, mut acc: Vec<(MonoId, Rational)>) -> ExprId {
        acc.sort_unstable_by_key(|t| t.0);
        let mut out: Terms = Vec::with_capacity(acc.len());
        for (m, c) in acc {
            match out.last_mut() {
                Some((lm, lc)) if *lm == m => {
                    if lc.to_i128_parts().is_none() || c.to_i128_parts().is_none() {
                        let w = lc.size_words() + c.size_words() + 1;
                        self.count_big_work(8u64.saturating_mul(w).saturating_mul(w));
                    }
                    *lc = lc.checked_add(c).unwrap_or_else(|| {
                        self.exceed(Limit::Digits);
                        Rational::ZERO
                    })
                }
                _ => out.push((m, c)),
            }
        }
        out.retain(|(_, c)| !c.is_zero());
        self.intern_expr(out)
    }

    /// `a + b`.
    pub fn add(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if a == ZERO {
            return b;
        }
        if b == ZERO {
            return a;
        }
        let mut acc = self.exprs[a.index()].clone();
        acc.extend_from_slice(&self.exprs[b.index()]);
        self.collect(acc)
    }

    /// Sum of many expressions.
    pub fn sum(&mut self, items: &[ExprId]) -> ExprId {
        let mut acc = Vec::new();
        for &i in items {
            acc.extend_from_slice(&self.exprs[i.index()]);
        }
        self.collect(acc)
    }

    /// `c * a` for a rational `c`.
    pub fn scale(&mut self, a: ExprId, c: Rational) -> ExprId {
        if c.is_zero() {
            return ZERO;
        }
        if c.is_one() {
            return a;
        }
        let t: Terms = self.exprs[a.index()].clone();
        let t = t.into_iter().map(|(m, k)| (m, self.qmul(k, c))).collect();
        self.collect(t)
    }

    /// `-a`.
    pub fn neg(&mut self, a: ExprId) -> ExprId {
        self.scale(a, Rational::MINUS_ONE)
    }

    /// `a - b`.
    pub fn sub(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let nb = self.neg(b);
        self.add(a, nb)
    }

    /// `a * b`, distributed and normalised.
    pub fn mul(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if a == ZERO || b == ZERO {
            return ZERO;
        }
        if a == ONE {
            return b;
        }
        if b == ONE {
            return a;
        }
        let key = if a <= b { (a, b) } else { (b, a) };
        if let Some(&r) = self.memo_mul.get(&key) {
            return r;
        }
        if self.abandoned() {
            return ZERO;
        }
        let (la, lb) = (self.exprs[a.index()].len(), self.exprs[b.index()].len());
        // kept: at least one factor becomes an atom (longer than `atom_min`), so
        // the product of the parts is a monomial times a sum
        let keep = (la >= 2
            && lb >= 2
            && la.max(lb) > self.atom_min
            && la.saturating_mul(lb) > self.expand_limit)
            || (la.min(lb) == 1 && la.max(lb) > super::SCALED_MIN);
        // products nest (a kept product takes contents, a normalised monomial
        // multiplies its expansions): past MAX_NESTING the input is swell
        // beyond reason, reported as such rather than overflowing the stack
        if self.nesting >= MAX_NESTING {
            self.exceed(Limit::Nesting);
            return ZERO;
        }
        self.nesting += 1;
        let r = if keep {
            self.kept_product(a, b)
        } else {
            self.expanded_product(a, b)
        };
        self.nesting -= 1;
        if !self.abandoned() {
            self.memo_mul.insert(key, r);
        }
        r
    }

    /// `a · b` distributed over the terms of both factors and normalised.
    pub(super) fn expanded_product(&mut self, a: ExprId, b: ExprId) -> ExprId {
        self.counters.products += 1;
        let ta = self.exprs[a.index()].clone();
        let tb = self.exprs[b.index()].clone();
        self.work = self.work.saturating_add(ta.len().saturating_mul(tb.len()));
        if self.work > self.max_work {
            self.exceed(Limit::Work);
            return ZERO;
        }
        let mut acc: Vec<(MonoId, Rational)> = Vec::with_capacity(ta.len() * tb.len());
        let mut extra: Vec<ExprId> = Vec::new();
        for &(ma, ca) in &ta {
            for &(mb, cb) in &tb {
                let c = self.qmul(ca, cb);
                let f = merge_factors(&self.monos[ma.index()], &self.monos[mb.index()]);
                match self.normal_mono(f) {
                    Normal::Mono(m, k) => {
                        let c2 = self.qmul(c, k);
                        acc.push((m, c2))
                    }
                    Normal::Expr(e) => {
                        let e2 = self.scale(e, c);
                        extra.push(e2)
                    }
                }
                if acc.len() > MAX_TERMS {
                    self.exceed(Limit::Terms);
                    return ZERO;
                }
            }
        }
        for e in extra {
            acc.extend_from_slice(&self.exprs[e.index()]);
        }
        self.collect(acc)
    }

    /// `a / b`.
    pub fn div(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let r = self.pow(b, Rational::MINUS_ONE);
        self.mul(a, r)
    }

    /// `f(a)`, with sign symmetries and values at zero folded (for the
    /// functions beyond `sin`, `cos`, `tan`, `exp` and `ln`, see `funcs`).
    pub fn func(&mut self, f: Fun, a: ExprId) -> ExprId {
        if !matches!(f, Fun::Sin | Fun::Cos | Fun::Tan | Fun::Exp | Fun::Ln) {
            return self.func_beyond(f, a);
        }
        if a == ZERO {
            return match f {
                Fun::Sin | Fun::Tan => ZERO,
                Fun::Cos | Fun::Exp => ONE,
                _ => self.func_atom(f, a),
            };
        }
        if f == Fun::Ln && a == ONE {
            return ZERO;
        }
        let leading_negative = self.exprs[a.index()]
            .first()
            .is_some_and(|(_, c)| c.is_negative());
        if leading_negative && matches!(f, Fun::Sin | Fun::Tan | Fun::Cos) {
            let na = self.neg(a);
            let inner = self.func(f, na);
            return if f == Fun::Cos {
                inner
            } else {
                self.neg(inner)
            };
        }
        if f == Fun::Exp {
            return self.exp(a);
        }
        if f == Fun::Ln
            && let [(m, c)] = self.exprs[a.index()].as_slice()
            && c.is_one()
            && let [(at, e)] = self.monos[m.index()].as_slice()
            && let Atom::Func(Fun::Exp, u) = self.atoms[at.index()]
        {
            // ln(exp(u)^e) = e·u
            let e = *e;
            return self.scale(u, e);
        }
        if f == Fun::Tan {
            // tan = sin / cos, so that identities between tan, sin and cos cancel
            let s = self.func(Fun::Sin, a);
            let c = self.func(Fun::Cos, a);
            let ci = self.pow(c, Rational::MINUS_ONE);
            return self.mul(s, ci);
        }
        let at = self.intern_atom(Atom::Func(f, a));
        self.atom_power(at, Rational::ONE)
    }

    /// `exp(a)` in canonical form: exp(Σ c_i m_i) = Π exp(m_i)^c_i, so that
    /// exp(x)·exp(y) and exp(x + y) are one expression; exp(c·ln u) = u^c.
    fn exp(&mut self, a: ExprId) -> ExprId {
        let terms = self.exprs[a.index()].clone();
        let mut r = ONE;
        for (m, c) in terms {
            if let [(at, e)] = self.monos[m.index()].as_slice()
                && e.is_one()
                && let Atom::Func(Fun::Ln, u) = self.atoms[at.index()]
            {
                let p = self.pow(u, c);
                r = self.mul(r, p);
                continue;
            }
            let arg = self.intern_expr(vec![(m, Rational::ONE)]);
            let at = self.intern_atom(Atom::Func(Fun::Exp, arg));
            let p = self.atom_power_normal(at, c);
            r = self.mul(r, p);
        }
        r
    }
}
