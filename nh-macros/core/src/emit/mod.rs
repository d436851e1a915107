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
//!
//! The graph and its nodes are defined here; `fold` holds the folded
//! arithmetic on nodes, `from_sym` the nodes of engine expressions (the
//! linear solves on nodes are in `crate::algebra`), `live` what outputs need and cost, `text` the
//! emission as text and `chunk` the blocks of large functions.

mod chunk;
mod fold;
mod from_sym;
mod live;
mod tangent;
mod text;
#[cfg(test)]
mod value;

use crate::sym::{AtomId, ExprId, Fun, Rational, SymId};
use proc_macro2::TokenStream;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

pub use text::{parse_text, take_unrepresentable, with_text_parser};

crate::sym::id_type! {
    /// A node of the dataflow graph.
    Node
}

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
    /// atan2(y, x), the angle of the point (x, y)
    Atan2(Node, Node),
    /// √a
    Sqrt(Node),
    /// a^k for a small integer k ≥ 2 (emitted as multiplications)
    Powi(Node, u32),
    /// a^b
    Powf(Node, Node),
    /// a itself, as a value the folds do not look into: a dependent
    /// velocity, which the rates along the motion hold (`Dag::rates`'s
    /// frozen nodes). Folded into its users, a dependent velocity −b would
    /// vanish into their subtractions (a + (−b) → a − b) and be
    /// differentiated as the expression of the coordinates it is; wrapped,
    /// it stays one node. Emitted as `a` (no operation, no statement).
    Opaque(Node),
}

/// The dataflow graph under construction.
#[derive(Clone)]
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
    /// The [`Op::Opaque`] nodes, ascending: they are never named, and the
    /// names of the others skip them (a wrapped value leaves the names of
    /// the code around it as they were).
    opaque_nodes: Vec<Node>,
}

/// Operation count of a node kind, as SymPy's `count_ops` counts: every
/// +, −, ×, ÷, power and function call is one (integer powers as the
/// multiplications they are emitted as).
fn cost(op: &Op) -> usize {
    match op {
        Op::Const(_) | Op::Pi | Op::Leaf(_) | Op::Opaque(_) => 0,
        Op::Powi(_, k) => powi_muls(*k),
        _ => 1,
    }
}

fn powi_muls(k: u32) -> usize {
    // square-and-multiply
    let bits = 32 - k.leading_zeros() as usize;
    bits - 1 + k.count_ones() as usize - 1
}

/// The zero node (always node 0).
pub const ZERO_NODE: Node = Node::from_index(0);
/// The one node (always node 1).
pub const ONE_NODE: Node = Node::from_index(1);

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
            opaque_nodes: Vec::new(),
        };
        d.intern(Op::Const(Rational::ZERO));
        d.intern(Op::Const(Rational::ONE));
        d
    }

    fn intern(&mut self, op: Op) -> Node {
        if let Some(&n) = self.ix.get(&op) {
            return n;
        }
        let n = Node::from_index(self.ops.len());
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

    /// The operands of `n`, each seen through [`Op::Opaque`] (emission and
    /// the operation counts see a wrapped value as the value itself).
    fn children(&self, n: Node) -> [Option<Node>; 2] {
        let r = |a: &Node| Some(self.resolved(*a));
        match &self.ops[n.index()] {
            Op::Add(a, b)
            | Op::Sub(a, b)
            | Op::Mul(a, b)
            | Op::Div(a, b)
            | Op::Powf(a, b)
            | Op::Atan2(a, b) => [r(a), r(b)],
            Op::Neg(a) | Op::Call(_, a) | Op::Sqrt(a) | Op::Powi(a, _) | Op::Opaque(a) => {
                [r(a), None]
            }
            Op::Const(_) | Op::Pi | Op::Leaf(_) => [None, None],
        }
    }

    /// `n` seen through [`Op::Opaque`].
    pub(crate) fn resolved(&self, mut n: Node) -> Node {
        while let Op::Opaque(a) = self.ops[n.index()] {
            n = a;
        }
        n
    }

    /// `a` as a value the folds do not look into ([`Op::Opaque`]); a leaf
    /// or a constant is already one.
    pub fn opaque(&mut self, a: Node) -> Node {
        match self.ops[a.index()] {
            Op::Leaf(_) | Op::Const(_) | Op::Pi | Op::Opaque(_) => a,
            _ => {
                let before = self.ops.len();
                let o = self.intern(Op::Opaque(a));
                if o.index() == before {
                    self.opaque_nodes.push(o);
                }
                o
            }
        }
    }

    /// The number in the name of `n`: its index less the opaque nodes
    /// before it.
    fn number(&self, n: Node) -> usize {
        n.index() - self.opaque_nodes.partition_point(|&o| o < n)
    }

    /// Attaches a comment to a node; emitted as a doc comment on its `let`
    /// (shown by `cargo expand`). The first label of a node wins.
    pub fn label(&mut self, n: Node, text: impl Into<String>) {
        if !matches!(self.ops[n.index()], Op::Const(_) | Op::Pi) {
            self.labels.entry(n).or_insert_with(|| text.into());
        }
    }

    /// Binds a symbol to a node (a leaf, or a computed value such as a
    /// dependent velocity).
    pub fn bind(&mut self, s: SymId, n: Node) {
        self.sym_nodes.insert(s, n);
    }

    /// The node bound to symbol `s`, if any.
    pub fn bound(&self, s: SymId) -> Option<Node> {
        self.sym_nodes.get(&s).copied()
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
        match self.ops[n.index()] {
            Op::Const(q) => Some(q),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
