//! Products kept unexpanded: past the expansion limits, a product of sums
//! keeps its primitive factors as atoms (after taking out their contents),
//! so that shared factors stay shared and `let` chains grow additively.

use super::{Atom, Engine, ExprId, Factors, ONE, Rational};

impl Engine {
    /// `a · b` for two sums whose expansion would not pay (more than
    /// [`EXPAND_LIMIT`](super::EXPAND_LIMIT) products of terms): each sum is
    /// split into its content (a rational times a monomial) and its primitive
    /// rest, and the rests stay unexpanded, as atoms of one monomial. The rest
    /// of a sum is one atom wherever it occurs, so shared factors stay shared
    /// (in the graph and in the emitted code), and a `let` chain or a product
    /// of long sums grows additively instead of multiplicatively.
    pub(super) fn kept_product(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let (ga, ra) = self.content(a).unwrap_or((ONE, a));
        let (gb, rb) = self.content(b).unwrap_or((ONE, b));
        let xa = self.kept_factor(ra);
        let xb = self.kept_factor(rb);
        let g = self.mul(ga, gb);
        let x = self.mul(xa, xb);
        self.mul(g, x)
    }

    /// A primitive sum as a factor of a kept product: one atom if it is longer
    /// than [`ATOM_MIN`](super::ATOM_MIN) terms, else the sum itself
    /// (distributed over the other factor, which is then an atom).
    pub(super) fn kept_factor(&mut self, s: ExprId) -> ExprId {
        if self.exprs[s.index()].len() <= self.atom_min {
            return s;
        }
        let x = self.intern_atom(Atom::Base(s));
        self.atom_power(x, Rational::ONE)
    }

    /// Is `s^k` (a sum to a positive integer power) kept unexpanded? A sum of
    /// more than [`ATOM_MIN`](super::ATOM_MIN) terms always is; a shorter one
    /// when the expansion would exceed [`EXPAND_LIMIT`](super::EXPAND_LIMIT)
    /// products of terms.
    pub(super) fn power_is_kept(&self, s: ExprId, k: i64) -> bool {
        let len = self.exprs[s.index()].len();
        if len > self.atom_min {
            return true;
        }
        let mut size: usize = 1;
        for _ in 0..k.clamp(0, 64) {
            size = size.saturating_mul(len);
            if size > self.expand_limit {
                return true;
            }
        }
        k > 64 && len >= 2
    }

    /// The content of a sum — `g` (a monomial times a rational, positive
    /// leading coefficient of the rest) and the primitive rest with `e = g·rest`
    /// — or `None` if the content is 1.
    pub(super) fn content(&mut self, e: ExprId) -> Option<(ExprId, ExprId)> {
        let terms = self.exprs[e.index()].clone();
        if terms.len() < 2 {
            return None;
        }
        // rational part
        let mut c = terms[0].1.abs();
        for t in &terms[1..] {
            c = c.gcd(t.1)?;
        }
        if terms[0].1.is_negative() {
            c = c.checked_neg()?;
        }
        // monomial part: atoms in every term, at their least exponent
        let mut common: Factors = self.monos[terms[0].0.index()].clone();
        for (m, _) in &terms[1..] {
            let f = &self.monos[m.index()];
            common.retain_mut(|(a, e)| match f.iter().find(|(b, _)| b == a) {
                Some((_, e2)) => {
                    if *e2 < *e {
                        *e = *e2;
                    }
                    true
                }
                None => false,
            });
        }
        // only whole powers of plain atoms are taken out (exact division)
        common.retain(|(a, e)| e.is_integer() && !matches!(self.atoms[a.index()], Atom::Base(_)));
        if c.is_one() && common.is_empty() {
            return None;
        }
        let cm = self.intern_mono(common.clone());
        let g_mono = self.intern_expr(vec![(cm, Rational::ONE)]);
        let g = self.scale(g_mono, c);
        let inv: Factors = common
            .iter()
            .map(|&(a, e)| (a, e.checked_neg().unwrap_or(e)))
            .collect();
        let ginv_mono = self.normal_expr(inv);
        let cinv = c.checked_recip()?;
        let ginv = self.scale(ginv_mono, cinv);
        // distributed, never kept: the rest of a kept product is taken here
        let rest = self.expanded_product(e, ginv);
        Some((g, rest))
    }
}
