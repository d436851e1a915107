//! Substitution of expressions for symbols.

use super::{Atom, Engine, ExprId, SymId};
use rustc_hash::FxHashMap as HashMap;

impl Engine {
    /// Substitutes expressions for symbols everywhere in `e`.
    pub fn subst(
        &mut self,
        e: ExprId,
        map: &HashMap<SymId, ExprId>,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> ExprId {
        if self.expr_syms[e.index()]
            .iter()
            .all(|s| !map.contains_key(s))
        {
            return e;
        }
        if let Some(&r) = memo.get(&e) {
            return r;
        }
        let terms = self.exprs[e.index()].clone();
        let parts: Vec<ExprId> = (terms.into_iter())
            .map(|(m, c)| self.subst_term(m, c, map, memo))
            .collect();
        let r = self.sum(&parts);
        memo.insert(e, r);
        r
    }

    /// [`Engine::subst`] abandoned once the substituted terms of `e`'s sum
    /// count more than `limit` terms together: `None` then. (The sum can
    /// only have fewer terms than its parts together, after cancellation.)
    /// A term is not multiplied out when the product of its substituted
    /// symbols' term counts alone (what it expands to before cancelling
    /// within itself) would pass the limit.
    pub fn subst_within(
        &mut self,
        e: ExprId,
        map: &HashMap<SymId, ExprId>,
        limit: usize,
    ) -> Option<ExprId> {
        let mut memo = HashMap::default();
        let terms = self.exprs[e.index()].clone();
        let mut parts = Vec::with_capacity(terms.len());
        let mut count = 0usize;
        for (m, c) in terms {
            if count.saturating_add(self.expanded_terms(m, map)) > limit {
                return None;
            }
            let t = self.subst_term(m, c, map, &mut memo);
            count += self.num_terms(t);
            if count > limit {
                return None;
            }
            parts.push(t);
        }
        Some(self.sum(&parts))
    }

    /// The terms monomial `m` multiplies out to, before cancellation, with
    /// the symbols of `map` substituted (other atoms count one).
    fn expanded_terms(&self, m: super::MonoId, map: &HashMap<SymId, ExprId>) -> usize {
        self.monos[m.index()]
            .iter()
            .fold(1usize, |n, &(a, ex)| match &self.atoms[a.index()] {
                // a positive integer power multiplies out; others stay one atom
                Atom::Sym(s) => match (map.get(s), ex.to_integer().filter(|&k| k > 0)) {
                    (Some(&v), Some(k)) => {
                        let k = u32::try_from(k).unwrap_or(u32::MAX);
                        n.saturating_mul(self.num_terms(v).saturating_pow(k))
                    }
                    _ => n,
                },
                _ => n,
            })
    }

    /// One term c·m of a sum with the map substituted.
    fn subst_term(
        &mut self,
        m: super::MonoId,
        c: super::Rational,
        map: &HashMap<SymId, ExprId>,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> ExprId {
        let mut t = self.constant(c);
        for (a, ex) in self.monos[m.index()].clone() {
            let base = match self.atoms[a.index()].clone() {
                Atom::Sym(s) => match map.get(&s) {
                    Some(&v) => v,
                    None => self.sym(s),
                },
                Atom::Func(f, u) => {
                    let u2 = self.subst(u, map, memo);
                    self.func(f, u2)
                }
                Atom::Base(b) => self.subst(b, map, memo),
                Atom::Atan2(y, x) => {
                    let y2 = self.subst(y, map, memo);
                    let x2 = self.subst(x, map, memo);
                    self.atan2(y2, x2)
                }
            };
            let p = self.pow(base, ex);
            t = self.mul(t, p);
        }
        t
    }
}
