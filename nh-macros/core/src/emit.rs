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
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

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
            ix: HashMap::default(),
            leaves: Vec::new(),
            leaf_ix: HashMap::default(),
            labels: HashMap::default(),
            param_leaves: HashSet::default(),
            expr_memo: HashMap::default(),
            atom_memo: HashMap::default(),
            sym_nodes: HashMap::default(),
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
        let live = self.live_until(outputs, &HashMap::default());
        let mut param_only = vec![false; self.ops.len()];
        for &n in &live {
            param_only[n as usize] = match &self.ops[n as usize] {
                Op::Leaf(_) => self.param_leaves.contains(&n),
                Op::Const(_) | Op::Pi => true,
                _ => self
                    .children(n)
                    .iter()
                    .flatten()
                    .all(|c| param_only[*c as usize]),
            };
        }
        let mut used_outside = vec![false; self.ops.len()];
        for &o in outputs {
            used_outside[o as usize] = true;
        }
        for &n in &live {
            if !param_only[n as usize] {
                for c in self.children(n).into_iter().flatten() {
                    used_outside[c as usize] = true;
                }
            }
        }
        live.into_iter()
            .filter(|&n| {
                param_only[n as usize]
                    && used_outside[n as usize]
                    && cost(&self.ops[n as usize]) > 0
            })
            .collect()
    }

    fn leaf_with_name(&mut self, tokens: TokenStream, name: Option<String>) -> Node {
        // a named leaf is known by its name (names are unique in a graph)
        let key = match &name {
            Some(n) => format!("#{n}"),
            None => tokens.to_string(),
        };
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
            // all or nothing: a content that cannot be taken out exactly
            // is left in (a partial division would recurse forever)
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
            let divided: Option<Vec<Rational>> = if !g.is_one() && !g.is_zero() {
                terms.iter().map(|t| t.1.checked_div(g)).collect()
            } else {
                None
            };
            if let Some(divided) = divided {
                for (t, c) in terms.iter_mut().zip(divided) {
                    t.1 = c;
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
    /// of current x86-64 cores, confirmed by `cargo bench -p nh-lab --bench routes`.
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
        self.live_until(outputs, &HashMap::default())
    }

    /// The nodes `outputs` need, not looking behind the nodes in `stop`.
    fn live_until(&self, outputs: &[Node], stop: &HashMap<Node, TokenStream>) -> Vec<Node> {
        // a dense mark per node: the graph's ids are consecutive
        let mut seen = vec![false; self.ops.len()];
        let mut stack: Vec<Node> = outputs.to_vec();
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n as usize], true) || stop.contains_key(&n) {
                continue;
            }
            stack.extend(self.children(n).into_iter().flatten());
        }
        (0..self.ops.len() as Node)
            .filter(|&n| seen[n as usize])
            .collect()
    }

    /// Emits the statements computing `outputs`, and the expression naming
    /// each output. The scalar type is `T`.
    pub fn emit(&self, outputs: &[Node]) -> (TokenStream, Vec<TokenStream>) {
        self.emit_with(outputs, &HashMap::default())
    }

    /// Like [`Dag::emit`], with the nodes of `given` taken from the given
    /// tokens instead of computed (hoisted values read from a cache).
    ///
    /// The statements are written as text and parsed once: building them
    /// token by token costs most of an expansion in an unoptimised proc
    /// macro (users' crates build proc macros without optimisation), while
    /// the compiler's own lexer reads the text at full speed. Every name is
    /// generated (`v12`, leaf names, `__nh_` helpers), so nothing the text
    /// holds needs a span of its own.
    pub fn emit_with(
        &self,
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> (TokenStream, Vec<TokenStream>) {
        let (text, outs) = self.emit_text(outputs, given);
        let stmts = parse_text(&text);
        let outs = outs.iter().map(|t| parse_text(t)).collect();
        (stmts, outs)
    }

    /// The statements of [`Dag::emit_with`] as text, with the names of the
    /// outputs.
    pub fn emit_text(
        &self,
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> (String, Vec<String>) {
        let live = self.live_until(outputs, given);
        let pair_of = self.sin_cos_pairs(&live, given);
        let inline = self.inlined(&live, outputs, given, &pair_of);
        let mut inline_text: HashMap<Node, String> = HashMap::default();
        // one statement per bound value (or sin_cos pair): (values, text)
        let mut stmts: Vec<(Vec<Node>, String)> = Vec::new();
        let mut done: HashSet<Node> = HashSet::default();
        for &n in &live {
            if done.contains(&n) {
                continue;
            }
            if let Some(&(s, c)) = pair_of.get(&n) {
                let Op::Call(_, a) = self.ops[s as usize] else {
                    continue;
                };
                let mut text = String::new();
                self.label_text(s, &mut text);
                self.label_text(c, &mut text);
                let (sv, cv, a) = (self.name(s), self.name(c), self.text_of(a, &inline_text));
                text.push_str(&format!("let ({sv}, {cv}): (T, T) = {a}.sin_cos();\n"));
                stmts.push((vec![s, c], text));
                done.extend([s, c]);
                continue;
            }
            let rhs = match given.get(&n) {
                Some(tokens) => tokens.to_string(),
                None => self.op_text(n, &|c| self.text_of(c, &inline_text)),
            };
            if inline.contains(&n) {
                let atomic = matches!(
                    self.ops[n as usize],
                    Op::Const(_) | Op::Pi | Op::Call(..) | Op::Sqrt(_) | Op::Powf(..)
                ) && !rhs.starts_with('-');
                inline_text.insert(n, if atomic { rhs } else { format!("({rhs})") });
                continue;
            }
            let mut text = String::new();
            self.label_text(n, &mut text);
            text.push_str(&format!("let {}: T = {rhs};\n", self.name(n)));
            stmts.push((vec![n], text));
        }
        let text = if stmts.len() > MAX_LETS {
            self.chunked(&stmts, outputs, &inline)
        } else {
            stmts.iter().map(|(_, t)| t.as_str()).collect()
        };
        let outs = outputs
            .iter()
            .map(|&n| self.text_of(n, &inline_text))
            .collect();
        (text, outs)
    }

    /// The name a bound value is known by. `__nh_`: out of the way of the
    /// user's constants (a `let` pattern naming a constant would match it
    /// instead of binding).
    fn name(&self, n: Node) -> String {
        match &self.ops[n as usize] {
            Op::Leaf(i) if self.leaves[*i].1.is_some() => {
                format!("__nh_{}", self.leaves[*i].1.as_deref().unwrap_or("leaf"))
            }
            _ => format!("__nh_v{n}"),
        }
    }

    /// A value as text: its expression if it is written inline, else its name.
    fn text_of(&self, n: Node, inline_text: &HashMap<Node, String>) -> String {
        match inline_text.get(&n) {
            Some(t) => t.clone(),
            None => self.name(n),
        }
    }

    /// The statements of a large function in blocks of [`CHUNK_LETS`]: each
    /// block hands the values later blocks or the outputs need out as one
    /// tuple. Thousands of `let`s in one scope nest thousands of scopes,
    /// which overflows rustc's stack when it emits debug information (seen
    /// at ~20,000); a stack array instead costs LLVM gigabytes of memory.
    fn chunked(
        &self,
        stmts: &[(Vec<Node>, String)],
        outputs: &[Node],
        inline: &HashSet<Node>,
    ) -> String {
        let chunks: Vec<&[(Vec<Node>, String)]> = stmts.chunks(CHUNK_LETS).collect();
        let mut chunk_of = vec![usize::MAX; self.ops.len()];
        for (c, chunk) in chunks.iter().enumerate() {
            for (ns, _) in chunk.iter() {
                for &n in ns {
                    chunk_of[n as usize] = c;
                }
            }
        }
        // a value is handed out if a later block or an output reads it
        let mut exported = vec![false; self.ops.len()];
        for &o in outputs {
            exported[o as usize] = true;
        }
        for (c, chunk) in chunks.iter().enumerate() {
            for (ns, _) in chunk.iter() {
                for &n in ns {
                    self.each_bound_read(n, inline, &mut |r| {
                        if chunk_of[r as usize] != usize::MAX && chunk_of[r as usize] < c {
                            exported[r as usize] = true;
                        }
                    });
                }
            }
        }
        let mut text = String::new();
        for chunk in &chunks {
            let out: Vec<String> = chunk
                .iter()
                .flat_map(|(ns, _)| ns.iter())
                .filter(|&&n| exported[n as usize])
                .map(|&n| self.name(n))
                .collect();
            let body: String = chunk.iter().map(|(_, t)| t.as_str()).collect();
            let names = out.join(", ");
            let types = vec!["T"; out.len()].join(", ");
            let comma = if out.len() == 1 { "," } else { "" };
            text.push_str(&format!(
                "let ({names}{comma}): ({types}{comma}) = {{\n{body}({names}{comma})\n}};\n"
            ));
        }
        text
    }

    /// Calls `f` with every bound (not inlined) value the statement of `n`
    /// reads, looking through the values written inline.
    fn each_bound_read(&self, n: Node, inline: &HashSet<Node>, f: &mut dyn FnMut(Node)) {
        for c in self.children(n).into_iter().flatten() {
            if inline.contains(&c) {
                self.each_bound_read(c, inline, f);
            } else {
                f(c);
            }
        }
    }

    /// The values written into the expression that uses them instead of a
    /// `let` of their own: used once, not an output, not named (a leaf, a
    /// labelled value, half of a `sin_cos` pair), and small enough that the
    /// statement stays readable (at most [`MAX_INLINE_OPS`] operations).
    fn inlined(
        &self,
        live: &[Node],
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
        pair_of: &HashMap<Node, (Node, Node)>,
    ) -> HashSet<Node> {
        let mut uses = vec![0usize; self.ops.len()];
        for &n in live {
            if given.contains_key(&n) {
                continue;
            }
            // a power is written as repeated products of its base
            let times = if matches!(self.ops[n as usize], Op::Powi(..)) {
                2
            } else {
                1
            };
            for c in self.children(n).into_iter().flatten() {
                uses[c as usize] += times;
            }
        }
        for &o in outputs {
            uses[o as usize] += 2;
        }
        let mut size = vec![0usize; self.ops.len()];
        let mut inline = HashSet::default();
        for &n in live {
            let op = &self.ops[n as usize];
            if given.contains_key(&n) || pair_of.contains_key(&n) || matches!(op, Op::Leaf(_)) {
                continue;
            }
            let own = cost(op).max(1)
                + self
                    .children(n)
                    .into_iter()
                    .flatten()
                    .map(|c| size[c as usize])
                    .sum::<usize>();
            if uses[n as usize] == 1 && !self.labels.contains_key(&n) && own <= MAX_INLINE_OPS {
                inline.insert(n);
                size[n as usize] = own;
            }
        }
        inline
    }

    /// sin and cos of one angle, both live: computed by one `sin_cos` call.
    fn sin_cos_pairs(
        &self,
        live: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> HashMap<Node, (Node, Node)> {
        let live_set: HashSet<Node> = live.iter().copied().collect();
        let mut pair_of: HashMap<Node, (Node, Node)> = HashMap::default();
        for &n in live {
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
        pair_of
    }

    /// A label as a string statement (free at run time, visible under
    /// `cargo expand`).
    fn label_text(&self, n: Node, text: &mut String) {
        if let Some(label) = self.labels.get(&n) {
            let escaped = label.replace('\\', "\\\\").replace('"', "\\\"");
            text.push_str(&format!("let _ = \"{escaped}\";\n"));
        }
    }

    /// The right side computing node `n`, as text.
    fn op_text(&self, n: Node, name: &dyn Fn(Node) -> String) -> String {
        match &self.ops[n as usize] {
            Op::Const(q) => const_text(*q),
            Op::Pi => "T::pi()".into(),
            Op::Leaf(i) => self.leaves[*i].0.to_string(),
            Op::Add(a, b) => format!("{} + {}", name(*a), name(*b)),
            Op::Sub(a, b) => format!("{} - {}", name(*a), name(*b)),
            Op::Mul(a, b) => format!("{} * {}", name(*a), name(*b)),
            Op::Div(a, b) => format!("{} / {}", name(*a), name(*b)),
            Op::Neg(a) => format!("-{}", name(*a)),
            Op::Call(f, a) => format!("{}.{}()", name(*a), f.name()),
            Op::Sqrt(a) => format!("{}.sqrt()", name(*a)),
            Op::Powi(a, k) => powi_text(&name(*a), *k),
            Op::Powf(a, b) => format!("{}.powf({})", name(*a), name(*b)),
        }
    }
}

/// A parser of generated text into tokens, supplied by the proc-macro crate
/// for the duration of one expansion (see [`with_text_parser`]).
pub type TextParser = fn(&str) -> Option<TokenStream>;

thread_local! {
    static TEXT_PARSER: std::cell::Cell<Option<TextParser>> = const { std::cell::Cell::new(None) };
}

/// Runs `f` with generated text parsed by `parser`. Inside the compiler the
/// proc-macro crate passes the compiler's own lexer: `proc_macro2` would
/// first lex the text again with its own lexer to validate it, which in an
/// unoptimised proc macro costs more than the rest of an expansion. The text
/// is generated (names, numbers, operators), so it is valid by construction.
pub fn with_text_parser<R>(parser: TextParser, f: impl FnOnce() -> R) -> R {
    let previous = TEXT_PARSER.with(|p| p.replace(Some(parser)));
    let r = f();
    TEXT_PARSER.with(|p| p.set(previous));
    r
}

/// Parses generated text (with the compiler's lexer when one was supplied).
pub fn parse_text(text: &str) -> TokenStream {
    let parsed = match TEXT_PARSER.with(|p| p.get()) {
        Some(parser) => parser(text),
        None => text.parse().ok(),
    };
    parsed.unwrap_or_else(|| {
        let msg = "nonholonomic_system!: internal error: generated code does not lex";
        quote!(::core::compile_error!(#msg);)
    })
}

/// Most operations written in one statement by inlining values used once.
pub const MAX_INLINE_OPS: usize = 6;

/// Statements in one block of a large function (see `Dag::chunked`).
pub const CHUNK_LETS: usize = 1000;

/// Most statements a generated function holds in one block; beyond, they
/// are split into blocks of [`CHUNK_LETS`] (see `Dag::chunked`).
pub const MAX_LETS: usize = 2000;

fn powi_text(a: &str, k: u32) -> String {
    match k {
        2 => format!("{a} * {a}"),
        3 => format!("{a} * {a} * {a}"),
        4 => format!("{{ let __nh_sq = {a} * {a}; __nh_sq * __nh_sq }}"),
        _ => format!("{a}.powi({})", k as i32),
    }
}

thread_local! {
    /// The largest constant generated code needed but `f64` cannot hold,
    /// since the last [`take_unrepresentable`].
    static UNREPRESENTABLE: std::cell::Cell<Option<Rational>> = const { std::cell::Cell::new(None) };
}

/// The largest constant (in magnitude) that generated code needed but `f64`
/// cannot hold (beyond ±`f64::MAX`) since the last call, and resets it.
pub fn take_unrepresentable() -> Option<Rational> {
    UNREPRESENTABLE.try_with(|c| c.take()).ok().flatten()
}

/// The correctly rounded `f64` of a constant of the generated code, or
/// `None` (recorded for [`take_unrepresentable`]) beyond the range of `f64`.
fn representable(q: Rational) -> Option<f64> {
    let v = q.to_f64();
    if v.is_finite() {
        return Some(v);
    }
    let _ = UNREPRESENTABLE.try_with(|c| {
        if c.get().is_none_or(|old| old.abs() < q.abs()) {
            c.set(Some(q));
        }
    });
    None
}

/// Text converting a rational constant to `T` (through the generated
/// `__nh_c`, which names the facade's nalgebra): the correctly rounded
/// `f64` in its shortest round-trip form, exact for `T = f64`.
fn const_text(q: Rational) -> String {
    if q.is_zero() {
        return "T::zero()".into();
    }
    if q.is_one() {
        return "T::one()".into();
    }
    match representable(q) {
        Some(v) => format!("Self::__nh_c({v:?}f64)"),
        None => "T::zero()".into(),
    }
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
