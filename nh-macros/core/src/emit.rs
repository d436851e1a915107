//! Code emission: symbolic expressions become straight-line Rust over a
//! generic `T: RealField + Copy`.
//!
//! Expressions are lowered into a hash-consed dataflow graph of scalar
//! operations (so every shared subexpression is one node: common-subexpression
//! elimination), with sums factored greedily in the multivariate Horner way,
//! constants folded and zeros pruned. Numeric linear algebra (the projections
//! of the multiplier route, the reduced solve) is built in the same graph, so
//! structural zeros of the matrices remove operations rather than multiply by
//! zero. The graph is emitted as `let` statements in topological order; `sin`
//! and `cos` of one angle become one `sin_cos` call.

use crate::sym::{Atom, AtomId, Engine, ExprId, Fun, Rational, SymId};
use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};
use std::collections::{HashMap, HashSet};

/// A node of the dataflow graph.
pub type Node = u32;

/// One scalar operation.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Op {
    /// A rational constant.
    Const(Rational),
    /// π.
    Pi,
    /// A value supplied by the caller (a coordinate, parameter, ...), by index into the leaf table.
    Leaf(usize),
    /// a + b
    Add(Node, Node),
    /// a − b
    Sub(Node, Node),
    /// a · b
    Mul(Node, Node),
    /// a / b
    Div(Node, Node),
    /// −a
    Neg(Node),
    /// f(a)
    Call(Fun, Node),
    /// √a
    Sqrt(Node),
    /// a^k for a small integer k ≥ 2 (emitted as multiplications)
    Powi(Node, u32),
    /// a^b
    Powf(Node, Node),
}

/// The dataflow graph under construction.
pub struct Dag {
    ops: Vec<Op>,
    ix: HashMap<Op, Node>,
    leaves: Vec<(TokenStream, Option<String>)>,
    leaf_ix: HashMap<String, Node>,
    labels: HashMap<Node, String>,
    param_leaves: HashSet<Node>,
    expr_memo: HashMap<ExprId, Node>,
    atom_memo: HashMap<AtomId, Node>,
    sym_nodes: HashMap<SymId, Node>,
}

/// Operation count of a node kind, as SymPy's `count_ops` counts: every
/// +, −, ×, ÷, power and function call is one (integer powers as the
/// multiplications they are emitted as).
fn cost(op: &Op) -> usize {
    match op {
        Op::Const(_) | Op::Pi | Op::Leaf(_) => 0,
        Op::Powi(_, k) => powi_muls(*k),
        _ => 1,
    }
}

fn powi_muls(k: u32) -> usize {
    // square-and-multiply
    let bits = 32 - k.leading_zeros() as usize;
    bits - 1 + k.count_ones() as usize - 1
}

/// An LDLᵀ factorisation held as graph nodes.
pub struct Ldlt {
    l: Vec<Vec<Node>>,
    /// The pivots D.
    pub d: Vec<Node>,
    dinv: Vec<Node>,
}

/// The zero node (always node 0).
pub const ZERO_NODE: Node = 0;
/// The one node (always node 1).
pub const ONE_NODE: Node = 1;

impl Default for Dag {
    fn default() -> Self {
        Dag::new()
    }
}

impl Dag {
    /// An empty graph with the constants 0 and 1.
    pub fn new() -> Dag {
        let mut d = Dag {
            ops: Vec::new(),
            ix: HashMap::new(),
            leaves: Vec::new(),
            leaf_ix: HashMap::new(),
            labels: HashMap::new(),
            param_leaves: HashSet::new(),
            expr_memo: HashMap::new(),
            atom_memo: HashMap::new(),
            sym_nodes: HashMap::new(),
        };
        d.intern(Op::Const(Rational::ZERO));
        d.intern(Op::Const(Rational::ONE));
        d
    }

    fn intern(&mut self, op: Op) -> Node {
        if let Some(&n) = self.ix.get(&op) {
            return n;
        }
        let n = self.ops.len() as Node;
        self.ops.push(op.clone());
        self.ix.insert(op, n);
        n
    }

    /// A leaf: a value the generated function reads (its tokens are emitted
    /// once, as a `let`, if used). Leaves with the same text are one node.
    pub fn leaf(&mut self, tokens: TokenStream) -> Node {
        self.leaf_with_name(tokens, None)
    }

    /// A leaf whose `let` gets a readable name (which must be a fresh
    /// identifier, distinct from `v<number>`).
    pub fn leaf_named(&mut self, tokens: TokenStream, name: &str) -> Node {
        self.leaf_with_name(tokens, Some(name.to_string()))
    }

    /// A leaf holding a parameter: values computed from parameters alone can
    /// be hoisted out of the generated functions ([`Dag::hoistable`]).
    pub fn leaf_param(&mut self, tokens: TokenStream, name: &str) -> Node {
        let n = self.leaf_with_name(tokens, Some(name.to_string()));
        self.param_leaves.insert(n);
        n
    }

    fn children(&self, n: Node) -> [Option<Node>; 2] {
        match &self.ops[n as usize] {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Powf(a, b) => {
                [Some(*a), Some(*b)]
            }
            Op::Neg(a) | Op::Call(_, a) | Op::Sqrt(a) | Op::Powi(a, _) => [Some(*a), None],
            Op::Const(_) | Op::Pi | Op::Leaf(_) => [None, None],
        }
    }

    /// The values among those `outputs` need that depend on parameters alone
    /// and are worth keeping (an operation, not a leaf or constant), maximal:
    /// each is used by a value that is not parameter-only, or is an output.
    pub fn hoistable(&self, outputs: &[Node]) -> Vec<Node> {
        let live = self.live_until(outputs, &HashMap::new());
        let mut param_only: HashMap<Node, bool> = HashMap::new();
        for &n in &live {
            let p = match &self.ops[n as usize] {
                Op::Leaf(_) => self.param_leaves.contains(&n),
                Op::Const(_) | Op::Pi => true,
                _ => self
                    .children(n)
                    .iter()
                    .flatten()
                    .all(|c| param_only.get(c).copied().unwrap_or(false)),
            };
            param_only.insert(n, p);
        }
        let mut used_outside: HashSet<Node> = outputs.iter().copied().collect();
        for &n in &live {
            if !param_only[&n] {
                used_outside.extend(self.children(n).iter().flatten());
            }
        }
        live.into_iter()
            .filter(|n| {
                param_only[n] && used_outside.contains(n) && cost(&self.ops[*n as usize]) > 0
            })
            .collect()
    }

    fn leaf_with_name(&mut self, tokens: TokenStream, name: Option<String>) -> Node {
        let key = tokens.to_string();
        if let Some(&n) = self.leaf_ix.get(&key) {
            return n;
        }
        self.leaves.push((tokens, name));
        let n = self.intern(Op::Leaf(self.leaves.len() - 1));
        self.leaf_ix.insert(key, n);
        n
    }

    /// Attaches a comment to a node; emitted as a doc comment on its `let`
    /// (shown by `cargo expand`). The first label of a node wins.
    pub fn label(&mut self, n: Node, text: impl Into<String>) {
        if !matches!(self.ops[n as usize], Op::Const(_) | Op::Pi) {
            self.labels.entry(n).or_insert_with(|| text.into());
        }
    }

    /// Binds a symbol to a node (a leaf, or a computed value such as a
    /// dependent velocity).
    pub fn bind(&mut self, s: SymId, n: Node) {
        self.sym_nodes.insert(s, n);
    }

    /// The node of π.
    pub fn pi(&mut self) -> Node {
        self.intern(Op::Pi)
    }

    /// The constant node for `q`.
    pub fn constant(&mut self, q: Rational) -> Node {
        self.intern(Op::Const(q))
    }

    fn as_const(&self, n: Node) -> Option<Rational> {
        match self.ops[n as usize] {
            Op::Const(q) => Some(q),
            _ => None,
        }
    }

    /// a + b, folded.
    pub fn add(&mut self, a: Node, b: Node) -> Node {
        if a == ZERO_NODE {
            return b;
        }
        if b == ZERO_NODE {
            return a;
        }
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b))
            && let Some(s) = x.checked_add(y)
        {
            return self.constant(s);
        }
        if let Op::Neg(bb) = self.ops[b as usize] {
            return self.sub(a, bb);
        }
        if let Op::Neg(aa) = self.ops[a as usize] {
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
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b))
            && let Some(s) = x.checked_sub(y)
        {
            return self.constant(s);
        }
        if let Op::Neg(bb) = self.ops[b as usize] {
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
        match self.ops[a as usize] {
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
        match (self.as_const(a), self.as_const(b)) {
            (Some(x), Some(y)) => {
                if let Some(p) = x.checked_mul(y) {
                    return self.constant(p);
                }
            }
            (Some(x), None) if x == Rational::MINUS_ONE => return self.neg(b),
            (None, Some(y)) if y == Rational::MINUS_ONE => return self.neg(a),
            _ => {}
        }
        // pull negations out so they can become subtractions
        if let Op::Neg(x) = self.ops[a as usize] {
            let p = self.mul(x, b);
            return self.neg(p);
        }
        if let Op::Neg(y) = self.ops[b as usize] {
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
        if let Op::Neg(x) = self.ops[a as usize] {
            let p = self.div(x, b);
            return self.neg(p);
        }
        self.intern(Op::Div(a, b))
    }

    /// f(a).
    pub fn call(&mut self, f: Fun, a: Node) -> Node {
        self.intern(Op::Call(f, a))
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

    // ------------------------------------------------------------ from symbolic

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
                    let name = format_ident!("__unbound_{}", s);
                    self.leaf(quote!(#name))
                }
            },
            Atom::Func(f, u) => {
                let un = self.expr(eng, u);
                self.call(f, un)
            }
            Atom::Base(b) => self.expr(eng, b),
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
        if terms.len() >= 2 {
            // content: factor out the common rational factor
            let mut g = terms[0].1.abs();
            for t in &terms[1..] {
                g = g.gcd(t.1).unwrap_or(Rational::ONE);
                if g.to_i128_parts().is_none() {
                    // a content past 128 bits (many distinct big denominators)
                    // only makes every quotient bigger: leave it in the terms
                    g = Rational::ONE;
                    break;
                }
            }
            if terms.iter().all(|t| t.1.is_negative()) {
                g = g.checked_neg().unwrap_or(g);
            }
            if !g.is_one() && !g.is_zero() {
                for t in terms.iter_mut() {
                    t.1 = t.1.checked_div(g).unwrap_or(t.1);
                }
                let inner = self.poly(eng, terms);
                let gc = self.constant(g);
                return self.mul(gc, inner);
            }
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
            let mut count: HashMap<AtomId, (usize, Rational)> = HashMap::new();
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

    // ------------------------------------------------------------ linear algebra

    /// Solves the symmetric system `m x = f` by an LDLᵀ factorisation without
    /// pivoting, built in the graph so structural zeros cost nothing. Returns
    /// x and the pivots D (for singularity checks: a constant-zero pivot means
    /// the matrix is structurally singular).
    pub fn solve_symmetric(&mut self, m: &[Vec<Node>], f: &[Node]) -> (Vec<Node>, Vec<Node>) {
        let fac = self.factor_symmetric(m);
        let x = self.solve_factored(&fac, f);
        (x, fac.d)
    }

    /// The LDLᵀ factorisation of a symmetric matrix, in the graph.
    pub fn factor_symmetric(&mut self, m: &[Vec<Node>]) -> Ldlt {
        let k = m.len();
        let mut l = vec![vec![ZERO_NODE; k]; k]; // unit lower triangular
        let mut ld = vec![vec![ZERO_NODE; k]; k]; // L·D below the diagonal
        let mut d = vec![ZERO_NODE; k];
        let mut dinv = vec![ZERO_NODE; k];
        for j in 0..k {
            let mut dj = m[j][j];
            for r in 0..j {
                let t = self.mul(l[j][r], ld[j][r]);
                dj = self.sub(dj, t);
            }
            d[j] = dj;
            dinv[j] = self.div(ONE_NODE, dj);
            for i in (j + 1)..k {
                let mut v = m[i][j];
                for r in 0..j {
                    let t = self.mul(l[i][r], ld[j][r]);
                    v = self.sub(v, t);
                }
                ld[i][j] = v;
                l[i][j] = self.mul(v, dinv[j]);
            }
        }
        Ldlt { l, d, dinv }
    }

    /// Solves with a factorisation from [`Dag::factor_symmetric`] (one more
    /// right side costs only the substitutions).
    pub fn solve_factored(&mut self, fac: &Ldlt, f: &[Node]) -> Vec<Node> {
        let k = f.len();
        // forward substitution L y = f
        let mut y = vec![ZERO_NODE; k];
        for i in 0..k {
            let mut v = f[i];
            for r in 0..i {
                let t = self.mul(fac.l[i][r], y[r]);
                v = self.sub(v, t);
            }
            y[i] = v;
        }
        // D z = y, Lᵀ x = z
        let mut x = vec![ZERO_NODE; k];
        for i in (0..k).rev() {
            let mut v = self.mul(y[i], fac.dinv[i]);
            for r in (i + 1)..k {
                let t = self.mul(fac.l[r][i], x[r]);
                v = self.sub(v, t);
            }
            x[i] = v;
        }
        x
    }

    // ------------------------------------------------------------ emission

    /// Number of operations needed to compute `outputs` (each shared node once).
    pub fn op_count(&self, outputs: &[Node]) -> usize {
        let live = self.live(outputs);
        live.iter().map(|&n| cost(&self.ops[n as usize])).sum()
    }

    /// Estimated run time of computing `outputs`, in units of one addition:
    /// divisions and square roots about 4, elementary functions about 15
    /// (sin and cos of one angle together about 20, as one `sin_cos`). Used to
    /// choose between the derivation routes; the figures are rough latencies
    /// of current x86-64 cores, confirmed by `cargo bench --bench routes`.
    pub fn cost_estimate(&self, outputs: &[Node]) -> usize {
        let live = self.live(outputs);
        let live_set: HashSet<Node> = live.iter().copied().collect();
        let mut total = 0;
        for &n in &live {
            total += match &self.ops[n as usize] {
                Op::Div(..) | Op::Sqrt(_) => 4,
                Op::Powf(..) => 40,
                Op::Call(Fun::Cos, a) => {
                    if live_set.contains(
                        &self
                            .ix
                            .get(&Op::Call(Fun::Sin, *a))
                            .copied()
                            .unwrap_or(u32::MAX),
                    ) {
                        5
                    } else {
                        15
                    }
                }
                Op::Call(..) => 15,
                op => cost(op),
            };
        }
        total
    }

    fn live(&self, outputs: &[Node]) -> Vec<Node> {
        self.live_until(outputs, &HashMap::new())
    }

    /// The nodes `outputs` need, not looking behind the nodes in `stop`.
    fn live_until(&self, outputs: &[Node], stop: &HashMap<Node, TokenStream>) -> Vec<Node> {
        let mut seen = HashSet::new();
        let mut stack: Vec<Node> = outputs.to_vec();
        while let Some(n) = stack.pop() {
            if !seen.insert(n) {
                continue;
            }
            if stop.contains_key(&n) {
                continue;
            }
            match &self.ops[n as usize] {
                Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Powf(a, b) => {
                    stack.push(*a);
                    stack.push(*b)
                }
                Op::Neg(a) | Op::Call(_, a) | Op::Sqrt(a) | Op::Powi(a, _) => stack.push(*a),
                Op::Const(_) | Op::Pi | Op::Leaf(_) => {}
            }
        }
        let mut v: Vec<Node> = seen.into_iter().collect();
        v.sort_unstable();
        v
    }

    /// Emits the statements computing `outputs`, and the expression naming
    /// each output. The scalar type is `T`.
    pub fn emit(&self, outputs: &[Node]) -> (TokenStream, Vec<TokenStream>) {
        self.emit_with(outputs, &HashMap::new())
    }

    /// Like [`Dag::emit`], with the nodes of `given` taken from the given
    /// tokens instead of computed (hoisted values read from a cache).
    pub fn emit_with(
        &self,
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> (TokenStream, Vec<TokenStream>) {
        let live = self.live_until(outputs, given);
        let live_set: HashSet<Node> = live.iter().copied().collect();
        // sin and cos of one angle: one sin_cos call
        let mut pair_of: HashMap<Node, (Node, Node)> = HashMap::new();
        for &n in &live {
            if let Op::Call(Fun::Sin, a) = self.ops[n as usize]
                && let Some(&c) = self.ix.get(&Op::Call(Fun::Cos, a))
                && live_set.contains(&c)
                && !given.contains_key(&n)
                && !given.contains_key(&c)
            {
                pair_of.insert(n, (n, c));
                pair_of.insert(c, (n, c));
            }
        }
        // Small functions: one `let` per value. Large ones: one stack array,
        // since thousands of nested `let` scopes overflow rustc's stack when
        // it emits debug information (seen at ~3,000).
        let array = live.len() > MAX_LETS;
        let slot: HashMap<Node, usize> = live.iter().enumerate().map(|(i, &n)| (n, i)).collect();
        let name = |n: Node| -> TokenStream {
            if array {
                let i = slot.get(&n).copied().unwrap_or(0);
                return quote!(vals[#i]);
            }
            let id = match &self.ops[n as usize] {
                Op::Leaf(i) if self.leaves[*i].1.is_some() => Ident::new(
                    self.leaves[*i].1.as_deref().unwrap_or("leaf"),
                    Span::call_site(),
                ),
                _ => Ident::new(&format!("v{n}"), Span::call_site()),
            };
            quote!(#id)
        };
        // Labels become string statements (free at run time, visible under
        // `cargo expand`).
        let doc = |n: Node| -> TokenStream {
            match self.labels.get(&n) {
                Some(text) if !array => quote!(let _ = #text;),
                _ => quote!(),
            }
        };
        let mut stmts = TokenStream::new();
        if array {
            let len = live.len();
            stmts.extend(quote!(let mut vals: [T; #len] = [T::zero(); #len];));
        }
        let mut done: HashSet<Node> = HashSet::new();
        for &n in &live {
            if done.contains(&n) {
                continue;
            }
            let v = name(n);
            if let Some(&(s, c)) = pair_of.get(&n) {
                let (sv, cv) = (name(s), name(c));
                let a = match self.ops[s as usize] {
                    Op::Call(_, a) => name(a),
                    _ => continue,
                };
                let (ds, dc) = (doc(s), doc(c));
                if array {
                    stmts.extend(quote!({ let (s, c): (T, T) = #a.sin_cos(); #sv = s; #cv = c; }));
                } else {
                    stmts.extend(quote!(#ds #dc let (#sv, #cv): (T, T) = #a.sin_cos();));
                }
                done.insert(s);
                done.insert(c);
                continue;
            }
            let bin = |a: &Node, b: &Node| (name(*a), name(*b));
            let rhs = match &self.ops[n as usize] {
                _ if given.contains_key(&n) => given[&n].clone(),
                Op::Const(q) => const_tokens(*q),
                Op::Pi => quote!(T::pi()),
                Op::Leaf(i) => self.leaves[*i].0.clone(),
                Op::Add(a, b) => {
                    let (a, b) = bin(a, b);
                    quote!(#a + #b)
                }
                Op::Sub(a, b) => {
                    let (a, b) = bin(a, b);
                    quote!(#a - #b)
                }
                Op::Mul(a, b) => {
                    let (a, b) = bin(a, b);
                    quote!(#a * #b)
                }
                Op::Div(a, b) => {
                    let (a, b) = bin(a, b);
                    quote!(#a / #b)
                }
                Op::Neg(a) => {
                    let a = name(*a);
                    quote!(-#a)
                }
                Op::Call(f, a) => {
                    let a = name(*a);
                    let m = format_ident!("{}", f.name());
                    quote!(#a.#m())
                }
                Op::Sqrt(a) => {
                    let a = name(*a);
                    quote!(#a.sqrt())
                }
                Op::Powi(a, k) => powi_tokens(&name(*a), *k),
                Op::Powf(a, b) => {
                    let (a, b) = bin(a, b);
                    quote!(#a.powf(#b))
                }
            };
            if array {
                stmts.extend(quote!(#v = #rhs;));
            } else {
                let d = doc(n);
                stmts.extend(quote!(#d let #v: T = #rhs;));
            }
        }
        let outs = outputs.iter().map(|&n| name(n)).collect();
        (stmts, outs)
    }
}

/// Most values a generated function holds in separate `let`s; beyond, they
/// live in one array.
pub const MAX_LETS: usize = 1500;

fn powi_tokens(a: &TokenStream, k: u32) -> TokenStream {
    match k {
        2 => quote!(#a * #a),
        3 => quote!(#a * #a * #a),
        4 => quote!({ let sq = #a * #a; sq * sq }),
        _ => {
            let k = k as i32;
            quote!(#a.powi(#k))
        }
    }
}

thread_local! {
    /// The largest constant [`const_tokens`] could not represent in `f64`
    /// since the last [`take_unrepresentable`].
    static UNREPRESENTABLE: std::cell::Cell<Option<Rational>> = const { std::cell::Cell::new(None) };
}

/// The largest constant (in magnitude) that generated code needed but `f64`
/// cannot hold (beyond ±`f64::MAX`) since the last call, and resets it.
pub fn take_unrepresentable() -> Option<Rational> {
    UNREPRESENTABLE.try_with(|c| c.take()).ok().flatten()
}

/// Tokens converting a rational constant to `T`: the correctly rounded
/// `f64` literal (exact for `T = f64`: the literal is printed in its
/// shortest round-trip form). A constant beyond the range of `f64` is
/// recorded for [`take_unrepresentable`] and emitted as zero.
pub fn const_tokens(q: Rational) -> TokenStream {
    if q.is_zero() {
        return quote!(T::zero());
    }
    if q.is_one() {
        return quote!(T::one());
    }
    let v = q.to_f64();
    if !v.is_finite() {
        let _ = UNREPRESENTABLE.try_with(|c| {
            let keep = match c.get() {
                Some(old) => old.abs() >= q.abs(),
                None => false,
            };
            if !keep {
                c.set(Some(q));
            }
        });
        return quote!(T::zero());
    }
    let lit = proc_macro2::Literal::f64_suffixed(v);
    quote!(::nonholonomic::__private::nalgebra::convert::<f64, T>(#lit))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structural_zeros_cost_nothing() {
        let mut d = Dag::new();
        let a = d.leaf(quote!(a));
        let b = d.leaf(quote!(b));
        let m = vec![vec![a, ZERO_NODE], vec![ZERO_NODE, b]];
        let f = vec![a, b];
        let (x, _) = d.solve_symmetric(&m, &f);
        // a diagonal system: two reciprocals and two products
        assert_eq!(d.op_count(&x), 4);
    }

    #[test]
    fn horner_factoring_shares_atoms() {
        let mut e = Engine::new();
        let xs = e.symbol("x");
        let ys = e.symbol("y");
        let x = e.sym(xs);
        let y = e.sym(ys);
        // x*y + x*y^2 + x: factored as x*(1 + y*(1 + y)) -> 4 ops
        let xy = e.mul(x, y);
        let y2 = e.mul(y, y);
        let xy2 = e.mul(x, y2);
        let p = e.sum(&[xy, xy2, x]);
        let mut d = Dag::new();
        let lx = d.leaf(quote!(x));
        let ly = d.leaf(quote!(y));
        d.bind(xs, lx);
        d.bind(ys, ly);
        let n = d.expr(&e, p);
        assert_eq!(d.op_count(&[n]), 4);
    }
}
