//! The nodes of engine expressions: sums factored in the multivariate Horner
//! way, monomials as quotients of products of powers.

use super::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::sym::{Atom, AtomId, Engine, ExprId, Fun, Rational};
use quote::{format_ident, quote};
use rustc_hash::FxHashMap as HashMap;

impl Dag {
    /// The node of an engine expression, factored and memoised.
    pub fn expr(&mut self, eng: &Engine, e: ExprId) -> Node {
        if let Some(&n) = self.expr_memo.get(&e) {
            return n;
        }
        let terms: Vec<(Vec<(AtomId, Rational)>, Rational)> = eng
            .terms(e)
            .iter()
            .map(|&(m, c)| (eng.factors(m).to_vec(), c))
            .collect();
        let n = self.poly(eng, terms);
        self.expr_memo.insert(e, n);
        n
    }

    fn atom(&mut self, eng: &Engine, a: AtomId) -> Node {
        if let Some(&n) = self.atom_memo.get(&a) {
            return n;
        }
        let n = match eng.atom(a).clone() {
            Atom::Sym(s) => match self.sym_nodes.get(&s) {
                Some(&n) => n,
                None => {
                    let name = format_ident!("__unbound_{}", s.index());
                    self.leaf(quote!(#name))
                }
            },
            Atom::Func(f, u) => {
                let un = self.expr(eng, u);
                self.call(f, un)
            }
            Atom::Base(b) => self.expr(eng, b),
            Atom::Atan2(y, x) => {
                let yn = self.expr(eng, y);
                let xn = self.expr(eng, x);
                self.atan2(yn, xn)
            }
        };
        self.atom_memo.insert(a, n);
        n
    }

    /// A sum of monomials, factored greedily: the atom that occurs in the
    /// most terms is factored out, recursively (multivariate Horner). The
    /// remainder is processed in a loop, so the recursion depth is bounded by
    /// the degree of the monomials, not by the number of terms.
    fn poly(&mut self, eng: &Engine, terms: Vec<(Vec<(AtomId, Rational)>, Rational)>) -> Node {
        let mut terms: Vec<_> = terms.into_iter().filter(|t| !t.1.is_zero()).collect();
        if let Some((g, divided)) = content(&terms) {
            for (t, c) in terms.iter_mut().zip(divided) {
                t.1 = c;
            }
            let inner = self.poly(eng, terms);
            let gc = self.constant(g);
            return self.mul(gc, inner);
        }
        let mut acc = ZERO_NODE;
        loop {
            match terms.len() {
                0 => return acc,
                1 => {
                    let (f, c) = terms.pop().unwrap_or((Vec::new(), Rational::ZERO));
                    let m = self.monomial(eng, &f, c);
                    return self.add(acc, m);
                }
                _ => {}
            }
            // the most frequent atom with a positive exponent
            let mut count: HashMap<AtomId, (usize, Rational)> = HashMap::default();
            for (f, _) in &terms {
                for &(a, e) in f {
                    if e > Rational::ZERO {
                        let ent = count.entry(a).or_insert((0, e));
                        ent.0 += 1;
                        if e < ent.1 {
                            ent.1 = e;
                        }
                    }
                }
            }
            let best = count
                .iter()
                .filter(|(_, (c, _))| *c >= 2)
                .max_by_key(|(a, (c, _))| (*c, std::cmp::Reverse(**a)))
                .map(|(a, (_, e))| (*a, *e));
            let Some((a, emin)) = best else {
                // plain sum: positive terms first, then subtract the negative ones
                let mut neg = Vec::new();
                for (f, c) in &terms {
                    if c.is_negative() {
                        let m = self.monomial(eng, f, c.abs());
                        neg.push(m);
                    } else {
                        let m = self.monomial(eng, f, *c);
                        acc = self.add(acc, m);
                    }
                }
                for m in neg {
                    acc = self.sub(acc, m);
                }
                return acc;
            };
            let mut with = Vec::new();
            let mut without = Vec::new();
            for (f, c) in terms {
                if let Some(pos) = f.iter().position(|&(x, e)| x == a && e > Rational::ZERO) {
                    let mut f2 = f;
                    let ne = f2[pos].1.checked_sub(emin).unwrap_or(Rational::ZERO);
                    if ne.is_zero() {
                        f2.remove(pos);
                    } else {
                        f2[pos].1 = ne;
                    }
                    with.push((f2, c));
                } else {
                    without.push((f, c));
                }
            }
            let an = self.atom(eng, a);
            let ap = self.pow(an, emin);
            let inner = self.poly(eng, with);
            let prod = self.mul(ap, inner);
            acc = self.add(acc, prod);
            terms = without;
        }
    }

    fn monomial(&mut self, eng: &Engine, f: &[(AtomId, Rational)], c: Rational) -> Node {
        let mut num = ONE_NODE;
        let mut den = ONE_NODE;
        for &(a, e) in f {
            if let Atom::Func(Fun::Exp, u) = eng.atom(a) {
                // exp(u)^e is emitted as exp(e·u): one call, no power
                let un = self.expr(eng, *u);
                let ec = self.constant(e);
                let arg = self.mul(ec, un);
                let x = self.call(Fun::Exp, arg);
                num = self.mul(num, x);
                continue;
            }
            let an = self.atom(eng, a);
            if e.is_negative() {
                let p = self.pow(an, e.abs());
                den = self.mul(den, p);
            } else {
                let p = self.pow(an, e);
                num = self.mul(num, p);
            }
        }
        let mut v = if den == ONE_NODE {
            num
        } else {
            self.div(num, den)
        };
        if !c.is_one() {
            let cn = self.constant(c);
            v = self.mul(cn, v);
        }
        v
    }
}

/// The common rational factor of the coefficients of a sum of at least two
/// terms (negative if all are) with the coefficients divided by it, or
/// `None` if it is 1. All or nothing: a content that cannot be taken out
/// exactly is left in (a partial division would recurse forever).
fn content(terms: &[(Vec<(AtomId, Rational)>, Rational)]) -> Option<(Rational, Vec<Rational>)> {
    if terms.len() < 2 {
        return None;
    }
    let mut g = Some(terms[0].1.abs());
    for t in &terms[1..] {
        g = g.and_then(|g| g.gcd(t.1));
        if g.is_some_and(|g| g.to_i128_parts().is_none()) {
            // a content past 128 bits (many distinct big denominators)
            // only makes every quotient bigger: leave it in the terms
            g = None;
            break;
        }
    }
    let mut g = g.unwrap_or(Rational::ONE);
    if terms.iter().all(|t| t.1.is_negative()) {
        g = g.checked_neg().unwrap_or(g);
    }
    if g.is_one() || g.is_zero() {
        return None;
    }
    let divided: Option<Vec<Rational>> = terms.iter().map(|t| t.1.checked_div(g)).collect();
    Some((g, divided?))
}
