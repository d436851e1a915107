//! Rates along the motion computed on the graph itself (forward-mode
//! differentiation): the rate of a node is built from the rates of its
//! operands, so a rate shares every subexpression with its value and with
//! the other rates of the same pass.

use super::{Dag, Node, ONE_NODE, Op, ZERO_NODE};
use crate::sym::{Fun, Rational};
use rustc_hash::FxHashMap as HashMap;

impl Dag {
    /// The rates of `roots` when each node of `seeds` moves at the given
    /// rate and every other leaf, and every node of `frozen`, is held fixed
    /// (its rate is zero).
    pub fn rates(
        &mut self,
        roots: &[Node],
        seeds: &HashMap<Node, Node>,
        frozen: &[Node],
    ) -> Vec<Node> {
        let mut rate: HashMap<Node, Node> = HashMap::default();
        for &f in frozen {
            rate.insert(f, ZERO_NODE);
        }
        for n in self.reachable(roots, &rate) {
            let r = match seeds.get(&n) {
                Some(&s) => s,
                None => self.rate_of(n, &rate),
            };
            rate.insert(n, r);
        }
        roots.iter().map(|r| rate[r]).collect()
    }

    /// The nodes below `roots` whose rate is not known yet, operands first
    /// (a node is always created after its operands).
    fn reachable(&self, roots: &[Node], known: &HashMap<Node, Node>) -> Vec<Node> {
        let mut seen: rustc_hash::FxHashSet<Node> = Default::default();
        let mut stack: Vec<Node> = roots.to_vec();
        while let Some(n) = stack.pop() {
            if known.contains_key(&n) || !seen.insert(n) {
                continue;
            }
            stack.extend(operands(&self.ops[n.index()]));
        }
        let mut order: Vec<Node> = seen.into_iter().collect();
        order.sort_unstable_by_key(|n| n.index());
        order
    }

    /// The rate of `n` from the rates of its operands.
    fn rate_of(&mut self, n: Node, rate: &HashMap<Node, Node>) -> Node {
        let r = |x: &Node| rate.get(x).copied().unwrap_or(ZERO_NODE);
        match self.ops[n.index()].clone() {
            Op::Const(_) | Op::Pi | Op::Leaf(_) => ZERO_NODE,
            Op::Opaque(a) => r(&a),
            Op::Add(a, b) => self.add(r(&a), r(&b)),
            Op::Sub(a, b) => self.sub(r(&a), r(&b)),
            Op::Neg(a) => self.neg(r(&a)),
            Op::Mul(a, b) => {
                let x = self.mul(r(&a), b);
                let y = self.mul(a, r(&b));
                self.add(x, y)
            }
            Op::Div(a, b) => {
                // (a/b)' = (a' − (a/b) b') / b
                let nb = self.mul(n, r(&b));
                let num = self.sub(r(&a), nb);
                self.div(num, b)
            }
            Op::Call(f, a) => {
                let ra = r(&a);
                if ra == ZERO_NODE {
                    return ZERO_NODE;
                }
                let slope = self.slope(f, a, n);
                self.mul(slope, ra)
            }
            Op::Atan2(y, x) => {
                // (x y' − y x') / (x² + y²)
                let a = self.mul(x, r(&y));
                let b = self.mul(y, r(&x));
                let num = self.sub(a, b);
                let x2 = self.pow(x, Rational::int(2));
                let y2 = self.pow(y, Rational::int(2));
                let den = self.add(x2, y2);
                self.div(num, den)
            }
            Op::Sqrt(a) => {
                let two = self.constant(Rational::int(2));
                let den = self.mul(two, n);
                self.div(r(&a), den)
            }
            Op::Powi(a, k) => {
                let lower = self.pow(a, Rational::int(i128::from(k) - 1));
                let kc = self.constant(Rational::int(i128::from(k)));
                let slope = self.mul(kc, lower);
                self.mul(slope, r(&a))
            }
            Op::Powf(a, b) => {
                // (a^b)′ = a^b (b′ ln a + b a′/a)
                let ln_a = self.call(Fun::Ln, a);
                let x = self.mul(r(&b), ln_a);
                let ratio = self.div(r(&a), a);
                let y = self.mul(b, ratio);
                let sum = self.add(x, y);
                self.mul(n, sum)
            }
        }
    }

    /// f′(a) for `n` = f(a).
    fn slope(&mut self, f: Fun, a: Node, n: Node) -> Node {
        let square = |d: &mut Dag, x: Node| d.pow(x, Rational::int(2));
        match f {
            Fun::Sin => self.call(Fun::Cos, a),
            Fun::Cos => {
                let s = self.call(Fun::Sin, a);
                self.neg(s)
            }
            Fun::Tan => {
                let n2 = square(self, n);
                self.add(ONE_NODE, n2)
            }
            Fun::Cot => {
                let n2 = square(self, n);
                let s = self.add(ONE_NODE, n2);
                self.neg(s)
            }
            Fun::Sec => {
                let t = self.call(Fun::Tan, a);
                self.mul(n, t)
            }
            Fun::Csc => {
                let c = self.call(Fun::Cot, a);
                let s = self.mul(n, c);
                self.neg(s)
            }
            Fun::Exp => n,
            Fun::Ln => self.div(ONE_NODE, a),
            Fun::Abs => self.call(Fun::Sign, a),
            Fun::Sign => ZERO_NODE,
            Fun::Sinh => self.call(Fun::Cosh, a),
            Fun::Cosh => self.call(Fun::Sinh, a),
            Fun::Tanh => {
                let n2 = square(self, n);
                self.sub(ONE_NODE, n2)
            }
            Fun::Asin | Fun::Acos => {
                let a2 = square(self, a);
                let rest = self.sub(ONE_NODE, a2);
                let root = self.intern(Op::Sqrt(rest));
                let s = self.div(ONE_NODE, root);
                if f == Fun::Acos { self.neg(s) } else { s }
            }
            Fun::Atan => {
                let a2 = square(self, a);
                let den = self.add(ONE_NODE, a2);
                self.div(ONE_NODE, den)
            }
        }
    }
}

/// The operands of an operation.
fn operands(op: &Op) -> Vec<Node> {
    match *op {
        Op::Const(_) | Op::Pi | Op::Leaf(_) => Vec::new(),
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Atan2(a, b) => {
            vec![a, b]
        }
        Op::Powf(a, b) => vec![a, b],
        Op::Neg(a) | Op::Call(_, a) | Op::Sqrt(a) | Op::Powi(a, _) | Op::Opaque(a) => vec![a],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    /// Every operation's rate against a central difference of its value,
    /// with q moving at rate v and the leaf w held.
    #[test]
    fn rates_match_central_differences() {
        let mut d = Dag::new();
        let (q, v, w) = (d.leaf(quote!(q)), d.leaf(quote!(v)), d.leaf(quote!(w)));
        let leaf_index = |d: &Dag, n: Node| match d.ops[n.index()] {
            Op::Leaf(i) => i,
            _ => unreachable!(),
        };
        let (iq, iv, iw) = (leaf_index(&d, q), leaf_index(&d, v), leaf_index(&d, w));
        let half = d.constant(Rational::new(1, 2).unwrap());
        let small = d.mul(half, q); // keeps asin/acos arguments in (−1, 1)
        let qw = d.mul(q, w);
        let mut roots = vec![
            d.div(qw, small),
            d.atan2(q, w),
            d.intern(Op::Sqrt(qw)),
            d.pow(q, Rational::int(5)),
            d.pow(q, Rational::new(1, 3).unwrap()),
        ];
        use Fun::*;
        for f in [
            Sin, Cos, Tan, Cot, Sec, Csc, Exp, Ln, Abs, Sinh, Cosh, Tanh, Asin, Acos, Atan,
        ] {
            let arg = if matches!(f, Asin | Acos) { small } else { qw };
            roots.push(d.call(f, arg));
        }
        let seeds: HashMap<Node, Node> = [(q, v)].into_iter().collect();
        let rates = d.rates(&roots, &seeds, &[]);
        let mut x = vec![0.0; d.leaves.len()];
        x[iw] = 0.8;
        x[iv] = 1.7;
        let (q0, h) = (0.6, 1e-6);
        for (&root, &rate) in roots.iter().zip(&rates) {
            x[iq] = q0 + h;
            let up = d.value_of_leaves(root, &x);
            x[iq] = q0 - h;
            let down = d.value_of_leaves(root, &x);
            x[iq] = q0;
            let expected = (up - down) / (2.0 * h) * x[iv];
            let got = d.value_of_leaves(rate, &x);
            assert!(
                (got - expected).abs() <= 1e-7 * (1.0 + expected.abs()),
                "{:?}: {got} vs {expected}",
                d.ops[root.index()]
            );
        }
    }

    /// A held node stops the rate: only the seeded coordinate moves.
    #[test]
    fn held_nodes_have_no_rate() {
        let mut d = Dag::new();
        let (q, v) = (d.leaf(quote!(q)), d.leaf(quote!(v)));
        let s = d.call(Fun::Sin, q);
        let held = d.mul(s, v); // a velocity computed from q: held as a whole
        let root = d.mul(held, s);
        let seeds: HashMap<Node, Node> = [(q, v)].into_iter().collect();
        let rate = d.rates(&[root], &seeds, &[held])[0];
        let c = d.call(Fun::Cos, q);
        let cv = d.mul(c, v);
        let expected = d.mul(held, cv);
        assert_eq!(rate, expected);
    }
}
