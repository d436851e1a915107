//! Arithmetic on graph nodes with constants folded, zeros and ones pruned and
//! negations pulled out (so that they become subtractions).

use super::{Dag, Node, ONE_NODE, Op, ZERO_NODE};
use crate::sym::{Fun, Rational};

impl Dag {
    /// The constant `op(a, b)` if `a` and `b` are constants and `op` gives a
    /// value.
    fn folded(
        &mut self,
        a: Node,
        b: Node,
        op: fn(Rational, Rational) -> Option<Rational>,
    ) -> Option<Node> {
        let v = op(self.as_const(a)?, self.as_const(b)?)?;
        Some(self.constant(v))
    }

    /// a + b, folded.
    pub fn add(&mut self, a: Node, b: Node) -> Node {
        if a == ZERO_NODE {
            return b;
        }
        if b == ZERO_NODE {
            return a;
        }
        if let Some(s) = self.folded(a, b, Rational::checked_add) {
            return s;
        }
        if let Op::Neg(bb) = self.ops[b.index()] {
            return self.sub(a, bb);
        }
        if let Op::Neg(aa) = self.ops[a.index()] {
            return self.sub(b, aa);
        }
        let (x, y) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Op::Add(x, y))
    }

    /// a − b, folded.
    pub fn sub(&mut self, a: Node, b: Node) -> Node {
        if b == ZERO_NODE {
            return a;
        }
        if a == ZERO_NODE {
            return self.neg(b);
        }
        if a == b {
            return ZERO_NODE;
        }
        if let Some(s) = self.folded(a, b, Rational::checked_sub) {
            return s;
        }
        if let Op::Neg(bb) = self.ops[b.index()] {
            return self.add(a, bb);
        }
        self.intern(Op::Sub(a, b))
    }

    /// −a, folded.
    pub fn neg(&mut self, a: Node) -> Node {
        if a == ZERO_NODE {
            return a;
        }
        if let Some(x) = self.as_const(a)
            && let Some(s) = x.checked_neg()
        {
            return self.constant(s);
        }
        match self.ops[a.index()] {
            Op::Neg(x) => x,
            Op::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Op::Neg(a)),
        }
    }

    /// a · b, folded.
    pub fn mul(&mut self, a: Node, b: Node) -> Node {
        if a == ZERO_NODE || b == ZERO_NODE {
            return ZERO_NODE;
        }
        if a == ONE_NODE {
            return b;
        }
        if b == ONE_NODE {
            return a;
        }
        if let Some(p) = self.folded(a, b, Rational::checked_mul) {
            return p;
        }
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), None) if x == Rational::MINUS_ONE => return self.neg(b),
            (None, Some(y)) if y == Rational::MINUS_ONE => return self.neg(a),
            _ => {}
        }
        // pull negations out so they can become subtractions
        if let Op::Neg(x) = self.ops[a.index()] {
            let p = self.mul(x, b);
            return self.neg(p);
        }
        if let Op::Neg(y) = self.ops[b.index()] {
            let p = self.mul(a, y);
            return self.neg(p);
        }
        if a == b {
            return self.intern(Op::Powi(a, 2));
        }
        let (x, y) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Op::Mul(x, y))
    }

    /// a / b, folded (a division by a constant becomes a multiplication).
    pub fn div(&mut self, a: Node, b: Node) -> Node {
        if a == ZERO_NODE {
            return ZERO_NODE;
        }
        if b == ONE_NODE {
            return a;
        }
        if let Some(y) = self.as_const(b)
            && let Some(r) = y.checked_recip()
        {
            let c = self.constant(r);
            return self.mul(a, c);
        }
        if let Op::Neg(x) = self.ops[a.index()] {
            let p = self.div(x, b);
            return self.neg(p);
        }
        self.intern(Op::Div(a, b))
    }

    /// f(a).
    pub fn call(&mut self, f: Fun, a: Node) -> Node {
        self.intern(Op::Call(f, a))
    }

    /// atan2(y, x).
    pub fn atan2(&mut self, y: Node, x: Node) -> Node {
        self.intern(Op::Atan2(y, x))
    }

    /// a^q for a rational exponent.
    pub fn pow(&mut self, a: Node, q: Rational) -> Node {
        if q.is_zero() {
            return ONE_NODE;
        }
        if q.is_one() {
            return a;
        }
        if q.is_negative() {
            let nq = q.checked_neg().unwrap_or(q);
            let p = self.pow(a, nq);
            return self.div(ONE_NODE, p);
        }
        if let Some(k) = q.to_integer()
            && k <= 64
        {
            return self.intern(Op::Powi(a, k as u32));
        }
        if let Some((k, 2)) = q.to_i128_parts() {
            let s = self.intern(Op::Sqrt(a));
            if k == 1 {
                return s;
            }
            let rest = self.pow(a, Rational::int((k - 1) / 2));
            return self.mul(rest, s);
        }
        let c = self.constant(q);
        self.intern(Op::Powf(a, c))
    }
}
