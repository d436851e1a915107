//! Derivatives, memoised per expression and symbol, with long inner
//! derivatives of the chain rule kept as atoms.

use super::{Atom, AtomId, Engine, ExprId, Fun, Limit, MonoId, ONE, Rational, SymId, ZERO};

impl Engine {
    /// `∂e/∂s`, memoised.
    pub fn diff(&mut self, e: ExprId, s: SymId) -> ExprId {
        if !self.depends_on(e, s) {
            return ZERO;
        }
        if let Some(&r) = self.memo_diff.get(&(e, s)) {
            return r;
        }
        if self.abandoned() {
            return ZERO;
        }
        self.counters.derivatives += 1;
        let terms = self.exprs[e.index()].clone();
        let mut parts = Vec::new();
        for (m, c) in terms {
            let dm = self.diff_mono(m, s);
            let t = self.scale(dm, c);
            parts.push(t);
        }
        let r = self.sum(&parts);
        if !self.abandoned() {
            self.memo_diff.insert((e, s), r);
        }
        r
    }

    fn diff_mono(&mut self, m: MonoId, s: SymId) -> ExprId {
        let factors = self.monos[m.index()].clone();
        let mut parts = Vec::new();
        for (i, &(a, e)) in factors.iter().enumerate() {
            if self.atom_syms[a.index()].binary_search(&s).is_err() {
                continue;
            }
            let da = self.diff_atom(a, s);
            if da == ZERO {
                continue;
            }
            let mut f = factors.clone();
            let ne = e.checked_sub(Rational::ONE).unwrap_or_else(|| {
                self.exceed(Limit::Digits);
                Rational::ZERO
            });
            f[i].1 = ne;
            let rest = self.normal_expr(f);
            let t = self.chain_rule_product(rest, da);
            let t = self.scale(t, e);
            parts.push(t);
        }
        self.sum(&parts)
    }

    /// `outer · inner` in a chain rule: an inner derivative longer than
    /// [`ATOM_MIN`](super::ATOM_MIN) terms is kept as one atom instead of being
    /// distributed, so that nested derivatives (`let` chains, functions of
    /// functions) grow additively: d/dx of a_(n+1) = a_n + sin(a_n)/2 is then
    /// a_n' + cos(a_n)/2 · [a_n'] with [a_n'] one atom, not 2ⁿ terms.
    fn chain_rule_product(&mut self, outer: ExprId, inner: ExprId) -> ExprId {
        if self.abandoned() {
            // the derivation is abandoned: no more work on its pieces
            return ZERO;
        }
        if self.exprs[inner.index()].len() <= self.atom_min || self.as_constant(outer).is_some() {
            return self.mul(outer, inner);
        }
        let (g, rest) = self.content(inner).unwrap_or((ONE, inner));
        let x = self.kept_factor(rest);
        let go = self.mul(outer, g);
        self.mul(go, x)
    }

    /// Derivative of an atom with respect to `s` (for `Base(b)`, the derivative of `b`).
    fn diff_atom(&mut self, a: AtomId, s: SymId) -> ExprId {
        match self.atoms[a.index()].clone() {
            Atom::Sym(x) => {
                if x == s {
                    ONE
                } else {
                    ZERO
                }
            }
            Atom::Base(b) => self.diff(b, s),
            Atom::Func(f, u) => {
                let du = self.diff(u, s);
                if du == ZERO {
                    return ZERO;
                }
                let outer = match f {
                    Fun::Sin => self.func(Fun::Cos, u),
                    Fun::Cos => {
                        let x = self.func(Fun::Sin, u);
                        self.neg(x)
                    }
                    Fun::Tan => {
                        let t = self.func(Fun::Tan, u);
                        let t2 = self.mul(t, t);
                        self.add(ONE, t2)
                    }
                    Fun::Exp => self.func(Fun::Exp, u),
                    Fun::Ln => self.pow(u, Rational::MINUS_ONE),
                    _ => self.outer_derivative_beyond(f, u),
                };
                self.chain_rule_product(outer, du)
            }
            Atom::Atan2(y, x) => {
                let dy = self.diff(y, s);
                let dx = self.diff(x, s);
                let (outer, inner) = self.atan2_derivative(y, x, dy, dx);
                self.chain_rule_product(outer, inner)
            }
        }
    }
}
