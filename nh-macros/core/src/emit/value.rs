//! The value of a graph's node at given leaf values, for the tests of the
//! stages that build graphs (the emitted code is what runs; this evaluates
//! the same operations in `f64`).

use super::{Dag, Node, Op};
use crate::sym::Fun;
use rustc_hash::FxHashMap as HashMap;

impl Dag {
    /// The value of `n` with the leaves at `x` (by leaf index).
    pub fn value_of_leaves(&self, n: Node, x: &[f64]) -> f64 {
        self.value_with(n, &|i| x[i], &mut HashMap::default())
    }

    /// The value of `n` with each leaf's value given by its name (`q_x`,
    /// `dot_x`, `p_m`, `u_F`, `time`); a leaf not given is NaN.
    pub fn value_at(&self, n: Node, at: &[(&str, f64)]) -> f64 {
        let leaf = |i: usize| {
            let name = self.leaves[i].1.as_deref();
            at.iter()
                .find(|(k, _)| Some(*k) == name)
                .map_or(f64::NAN, |&(_, v)| v)
        };
        self.value_with(n, &leaf, &mut HashMap::default())
    }

    fn value_with(
        &self,
        n: Node,
        leaf: &dyn Fn(usize) -> f64,
        memo: &mut HashMap<Node, f64>,
    ) -> f64 {
        if let Some(&v) = memo.get(&n) {
            return v;
        }
        let mut v = |m: Node| self.value_with(m, leaf, memo);
        let x = match self.ops[n.index()].clone() {
            Op::Const(q) => {
                let (n, m) = q.to_i128_parts().expect("small constants");
                n as f64 / m as f64
            }
            Op::Pi => core::f64::consts::PI,
            Op::Leaf(i) => leaf(i),
            Op::Add(a, b) => v(a) + v(b),
            Op::Sub(a, b) => v(a) - v(b),
            Op::Mul(a, b) => v(a) * v(b),
            Op::Div(a, b) => v(a) / v(b),
            Op::Neg(a) => -v(a),
            Op::Sqrt(a) => v(a).sqrt(),
            Op::Powi(a, k) => v(a).powi(k as i32),
            Op::Powf(a, b) => v(a).powf(v(b)),
            Op::Opaque(a) => v(a),
            Op::Atan2(a, b) => v(a).atan2(v(b)),
            Op::Call(f, a) => call(f, v(a)),
        };
        memo.insert(n, x);
        x
    }
}

fn call(f: Fun, a: f64) -> f64 {
    match f {
        Fun::Sin => a.sin(),
        Fun::Cos => a.cos(),
        Fun::Tan => a.tan(),
        Fun::Cot => 1.0 / a.tan(),
        Fun::Sec => 1.0 / a.cos(),
        Fun::Csc => 1.0 / a.sin(),
        Fun::Exp => a.exp(),
        Fun::Ln => a.ln(),
        Fun::Abs => a.abs(),
        Fun::Sign => a.signum(),
        Fun::Sinh => a.sinh(),
        Fun::Cosh => a.cosh(),
        Fun::Tanh => a.tanh(),
        Fun::Asin => a.asin(),
        Fun::Acos => a.acos(),
        Fun::Atan => a.atan(),
    }
}
