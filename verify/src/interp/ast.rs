//! The parsed form of the generated methods: types, expressions and
//! statements of the subset of Rust the engine emits.

use super::lex::Tok;

/// A value's type, with its dimensions.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Ty {
    /// `T`.
    Scalar,
    /// `bool` (held as 1 or 0).
    Bool,
    /// `()`.
    Unit,
    /// A string literal (`let _ = "label";`): no value.
    Str,
    /// `SMatrix<T, r, c>` (`SVector<T, n>` is n × 1), stored column-major.
    Mat(usize, usize),
    /// `[elem; n]`.
    Array(usize, Box<Ty>),
    /// A tuple.
    Tuple(Vec<Ty>),
    /// A type the interpreter does not model (named for the error).
    Other(String),
}

/// The most scalars a value, and registers a frame, may hold (far beyond
/// what the engine generates; it bounds what a malformed expansion costs).
pub(super) const MAX_SIZE: usize = 1 << 22;

impl Ty {
    /// The number of scalars a value of the type holds (saturating).
    pub(super) fn size(&self) -> usize {
        match self {
            Ty::Scalar | Ty::Bool => 1,
            Ty::Unit | Ty::Str | Ty::Other(_) => 0,
            Ty::Mat(r, c) => r.saturating_mul(*c),
            Ty::Array(n, e) => n.saturating_mul(e.size()),
            Ty::Tuple(ts) => ts.iter().fold(0, |a, t| a.saturating_add(t.size())),
        }
    }

    /// Whether a value of the type may be held (at most [`MAX_SIZE`]).
    pub(super) fn fits(&self) -> bool {
        self.size() <= MAX_SIZE
    }
}

/// A generic argument: a type or a constant (`T`, `3usize`).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum GenArg {
    Ty(Ty),
    Num(usize),
    Life,
}

/// A path segment with its generic arguments (`SVector::<T, 2usize>`).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Seg {
    pub name: String,
    pub args: Vec<GenArg>,
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    BitAnd,
    BitOr,
    BitXor,
}

/// A unary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum UnOp {
    Neg,
    Not,
    Ref,
    Deref,
}

/// An expression.
#[derive(Clone, Debug)]
pub(super) enum Expr<'t> {
    Path(Vec<Seg>),
    Lit(String),
    Bool(bool),
    Unary(UnOp, Box<Expr<'t>>),
    Binary(BinOp, Box<Expr<'t>>, Box<Expr<'t>>),
    Call(Box<Expr<'t>>, Vec<Expr<'t>>),
    Method(Box<Expr<'t>>, String, Vec<GenArg>, Vec<Expr<'t>>),
    Field(Box<Expr<'t>>, String),
    Index(Box<Expr<'t>>, Box<Expr<'t>>),
    Tuple(Vec<Expr<'t>>),
    Paren(Box<Expr<'t>>),
    Array(Vec<Expr<'t>>),
    Repeat(Box<Expr<'t>>, Box<Expr<'t>>),
    Block(Block<'t>),
    If(Box<Expr<'t>>, Block<'t>, Option<Box<Expr<'t>>>),
}

/// A `let` pattern.
#[derive(Clone, Debug)]
pub(super) enum Pat {
    Wild,
    /// A name, and whether it is `mut`.
    Bind(String, bool),
    Tuple(Vec<Pat>),
}

/// A statement, with its tokens (for errors).
#[derive(Clone, Debug)]
pub(super) struct Stmt<'t> {
    pub kind: StmtKind<'t>,
    pub src: &'t [Tok],
}

/// The kinds of statement.
#[derive(Clone, Debug)]
pub(super) enum StmtKind<'t> {
    /// `let PAT[: TY][ = EXPR];`
    Let(Pat, Option<Ty>, Option<Expr<'t>>),
    /// An expression whose value is dropped.
    Expr(Expr<'t>),
    /// `PLACE = EXPR;` or `PLACE op= EXPR;`
    Assign(Expr<'t>, Option<BinOp>, Expr<'t>),
    /// `for PAT in EXPR { .. }`
    For(Pat, Expr<'t>, Block<'t>),
}

/// A block: statements and the value of its last expression.
#[derive(Clone, Debug)]
pub(super) struct Block<'t> {
    pub stmts: Vec<Stmt<'t>>,
    pub tail: Option<Box<Expr<'t>>>,
}

/// A method's signature: its parameters after `self` and its result.
#[derive(Clone, Debug)]
pub(super) struct Sig {
    pub has_self: bool,
    pub params: Vec<(String, Ty)>,
    pub ret: Ty,
}
