//! The surface syntax tree of a system definition: expressions, items and
//! blocks as written, with every token's span.

use crate::ctxt::SpanRange;
use crate::sym::Rational;
use crate::words::{Block, Function, Output, Spelled};
use proc_macro2::{Ident, Span, TokenStream};
use syn::Visibility;

/// A binary operator of the input language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
}

/// A surface expression. Chains of `+ -` and of `* /` are flat lists, so a
/// long sum costs no recursion depth anywhere (parsing, lowering, dropping).
#[derive(Clone, Debug)]
pub enum Expr {
    /// A numeric literal, as an exact rational.
    Num(Rational, SpanRange),
    /// A name.
    Name(Ident),
    /// `f(a, ..)`: a function call, `dot(arg)`, or a method call
    /// `a.f(..)` (whose receiver is the first argument).
    Call {
        /// the function name
        func: Ident,
        /// the arguments
        args: Vec<Expr>,
        /// the whole call
        range: SpanRange,
    },
    /// `[a, b, c]`: a vector from its components (or, nested, a matrix by rows).
    Vector {
        /// the components
        items: Vec<Expr>,
        /// the whole bracket
        range: SpanRange,
    },
    /// `v.x`, `v.y`, `v.z`: a component of a vector.
    Component {
        /// the vector
        base: Box<Expr>,
        /// the component's name
        field: Ident,
    },
    /// `-e`.
    Neg(Box<Expr>, SpanRange),
    /// `first op e1 op e2 ...` with all operators `+`/`-` (a sum) or all `*`/`/` (a product).
    Chain {
        /// the first operand
        first: Box<Expr>,
        /// the operators (with their spans) and the following operands
        rest: Vec<(BinOp, Span, Expr)>,
        /// the parentheses around it, if it was written in them
        parens: Option<SpanRange>,
    },
    /// `base ^ exp`.
    Pow {
        /// the base
        base: Box<Expr>,
        /// the exponent
        exp: Box<Expr>,
        /// the parentheses around it, if it was written in them
        parens: Option<SpanRange>,
    },
}

impl Expr {
    /// Calls `f` on this expression and on each of its subexpressions,
    /// parents before children, left to right.
    pub fn visit<'e>(&'e self, f: &mut impl FnMut(&'e Expr)) {
        f(self);
        match self {
            Expr::Num(..) | Expr::Name(_) => {}
            Expr::Call { args: items, .. } | Expr::Vector { items, .. } => {
                items.iter().for_each(|a| a.visit(f));
            }
            Expr::Component { base, .. } | Expr::Neg(base, _) => base.visit(f),
            Expr::Chain { first, rest, .. } => {
                first.visit(f);
                rest.iter().for_each(|r| r.2.visit(f));
            }
            Expr::Pow { base, exp, .. } => {
                base.visit(f);
                exp.visit(f);
            }
        }
    }

    /// The source range of the whole expression.
    pub fn range(&self) -> SpanRange {
        match self {
            Expr::Num(_, r) | Expr::Neg(_, r) => *r,
            Expr::Name(i) => SpanRange::single(i.span()),
            Expr::Call { range, .. } | Expr::Vector { range, .. } => *range,
            Expr::Component { base, field } => base.range().to(SpanRange::single(field.span())),
            Expr::Chain {
                parens: Some(r), ..
            }
            | Expr::Pow {
                parens: Some(r), ..
            } => *r,
            Expr::Chain { first, rest, .. } => match rest.last() {
                Some((_, _, last)) => first.range().to(last.range()),
                None => first.range(),
            },
            Expr::Pow { base, exp, .. } => base.range().to(exp.range()),
        }
    }

    /// The expression as source text, with the parentheses it needs
    /// (for messages: "`dot(theta)^2` is ...").
    pub fn to_source(&self) -> String {
        fn atomic(e: &Expr) -> bool {
            matches!(
                e,
                Expr::Num(..)
                    | Expr::Name(_)
                    | Expr::Call { .. }
                    | Expr::Vector { .. }
                    | Expr::Component { .. }
            )
        }
        fn paren(e: &Expr, need: bool) -> String {
            if need {
                format!("({})", e.to_source())
            } else {
                e.to_source()
            }
        }
        match self {
            Expr::Num(q, _) => q.to_string(),
            Expr::Name(i) => i.to_string(),
            Expr::Call { func, args, .. } => format!("{func}({})", list_source(args)),
            Expr::Vector { items, .. } => format!("[{}]", list_source(items)),
            Expr::Component { base, field } => format!("{}.{field}", paren(base, !atomic(base))),
            Expr::Neg(inner, _) => format!("-{}", paren(inner, inner.is_sum())),
            Expr::Chain { first, rest, .. } => {
                let sum = self.is_sum();
                let mut out = paren(first, !sum && first.is_sum());
                for (op, _, e) in rest {
                    let sym = match op {
                        BinOp::Add => " + ",
                        BinOp::Sub => " - ",
                        BinOp::Mul => "*",
                        BinOp::Div => "/",
                    };
                    out.push_str(sym);
                    let need = if sum {
                        *op == BinOp::Sub && e.is_sum()
                    } else {
                        matches!(e, Expr::Chain { .. } | Expr::Neg(..))
                    };
                    out.push_str(&paren(e, need));
                }
                out
            }
            Expr::Pow { base, exp, .. } => {
                format!(
                    "{}^{}",
                    paren(base, !atomic(base)),
                    paren(exp, !atomic(exp) && !matches!(**exp, Expr::Pow { .. }))
                )
            }
        }
    }

    /// The argument of a one-argument call of `func` (`dot(x)`: `x`).
    pub fn call1(&self, func: Function) -> Option<&Expr> {
        match self {
            Expr::Call { func: f, args, .. } if *f == func && args.len() == 1 => Some(&args[0]),
            _ => None,
        }
    }

    /// Is this a sum (a chain of `+`/`-`)?
    pub fn is_sum(&self) -> bool {
        matches!(self, Expr::Chain { rest, .. }
            if rest.first().is_some_and(|r| matches!(r.0, BinOp::Add | BinOp::Sub)))
    }
}

/// Comma-separated source of a list of expressions.
fn list_source(items: &[Expr]) -> String {
    items
        .iter()
        .map(Expr::to_source)
        .collect::<Vec<_>>()
        .join(", ")
}

/// A `name: expr` field of a `body` item or a `rolls(..)` line.
#[derive(Clone, Debug)]
pub struct Field {
    /// the field's name
    pub name: Ident,
    /// its value; for a field written as an equation, `on: z = h(x, y)`,
    /// its left side
    pub value: Expr,
    /// the right side of a field written as an equation
    pub equals: Option<Expr>,
}

/// A `body NAME { mass: .., centre: .., orientation: .., inertia: .. }` item.
#[derive(Clone, Debug)]
pub struct BodyDef {
    /// the body's name
    pub name: Ident,
    /// the fields as written
    pub fields: Vec<Field>,
    /// whether a field did not parse (then a missing field is no news, and
    /// the body is not lowered further)
    pub rejected_fields: bool,
}

/// What a contact line of `constraints` says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactKind {
    /// `rolls(..)`: rolling without slipping (a contact point, two rows
    /// of no slip, and its height where that is not identically zero)
    Rolls,
    /// `skates(..)`: no velocity of a body point across a direction (one row)
    Skates,
    /// `slides(..)`: a body point kept on a surface (one holonomic row)
    Slides,
}

/// A `rolls(BODY, radius: .., axle: ..);` line of `constraints`, a
/// `skates(BODY, across: ..);` line or a `slides(BODY, at: ..);` line.
#[derive(Clone, Debug)]
pub struct RollingDef {
    /// which contact the line is
    pub kind: ContactKind,
    /// the rolling body
    pub body: Ident,
    /// the named arguments as written
    pub fields: Vec<Field>,
    /// the whole line
    pub range: SpanRange,
    /// how many equations of the block come before it
    pub position: usize,
}

/// A `let NAME = expr;` item.
#[derive(Clone, Debug)]
pub struct Let {
    /// the name
    pub name: Ident,
    /// the value
    pub value: Expr,
}

/// One `dot(s) = rhs;` constraint.
#[derive(Clone, Debug)]
pub struct Constraint {
    /// left side as written
    pub lhs: Expr,
    /// right side
    pub rhs: Expr,
}

/// One `q: expr;` generalized force.
#[derive(Clone, Debug)]
pub struct Force {
    /// the coordinate the force acts on
    pub coordinate: Ident,
    /// Q_j
    pub value: Expr,
}

/// A declared one-parameter symmetry group, `NAME(q: ξ_q, ..)`: its
/// generator, the rate at which each coordinate it moves changes along the
/// group (the others stay); the angles of a rotation `R` may be given
/// together as the fixed axis it turns about, `R: [a, b, c]`. A declared
/// momentum's direction (`momenta { .. }`) is written the same way.
#[derive(Clone, Debug)]
pub struct Symmetry {
    /// the group's name
    pub name: Ident,
    /// the coordinates it moves and their rates ξ_q
    pub generator: Vec<(Ident, Expr)>,
}

/// A parsed system definition.
#[derive(Clone, Debug)]
pub struct SystemDef {
    /// outer attributes (doc comments) for the struct, as `#[..]` tokens:
    /// passed through unparsed, for rustc to check
    pub attrs: Vec<TokenStream>,
    /// visibility
    pub vis: Visibility,
    /// struct name
    pub name: Ident,
    /// `parameters { .. }` (keyword span, names)
    pub parameters: Option<(Ident, Vec<Ident>)>,
    /// `coordinates { .. }`
    pub coordinates: Option<(Ident, Vec<Ident>)>,
    /// `inputs { .. }`
    pub inputs: Option<(Ident, Vec<Ident>)>,
    /// `let` items in order
    pub lets: Vec<Let>,
    /// `body NAME { .. }` items in order
    pub bodies: Vec<BodyDef>,
    /// `rolls(..)` lines of `constraints`, in order
    pub rolling: Vec<RollingDef>,
    /// `lagrangian = ..;` items (more than one is an error reported later)
    pub lagrangians: Vec<(Ident, Expr)>,
    /// `forces { .. }`
    pub forces: Option<(Ident, Vec<Force>)>,
    /// `symmetries { .. }`
    pub symmetries: Option<(Ident, Vec<Symmetry>)>,
    /// `momenta { .. }`: the directions of declared momenta, written as
    /// generators are
    pub momenta: Option<(Ident, Vec<Symmetry>)>,
    /// `constraints { .. }`
    pub constraints: Option<(Ident, Vec<Constraint>)>,
    /// `outputs { .. }`
    pub outputs: Option<(Ident, Vec<Spelled<Output>>)>,
    /// The outputs of `outputs { .. }` written with a list of names,
    /// `sensitivities(m, k)`: (the output, the names), in order
    pub output_arguments: Vec<(Spelled<Output>, Vec<Ident>)>,
    /// `dependent { .. }`: the coordinates the implicit and holonomic
    /// constraints are solved for, in the order of those constraints
    pub dependent: Option<(Ident, Vec<Ident>)>,
    /// `speeds { .. }`: the generalized speeds u (DESIGN §9)
    pub speeds: Option<(Ident, Vec<Ident>)>,
    /// `kinematics { dot(q) = ..; }`: q̇ = S(q, t) u + σ(q, t), one line per
    /// coordinate (parsed like constraints)
    pub kinematics: Option<(Ident, Vec<Constraint>)>,
    /// Names declared by items that failed to parse: their uses are not
    /// reported again as unknown (no follow-up errors).
    pub poisoned: Vec<Ident>,
    /// Whether a `lagrangian` item was written, even if it failed to parse.
    pub lagrangian_written: bool,
    /// Whether the system keeps one chart: no atlas is derived (a chart of
    /// another system's atlas, DESIGN §9.3).
    pub one_chart: bool,
    /// Whether the system is the chart of another system's atlas in which
    /// a free rotation is read in another sequence (DESIGN §9.4): its
    /// chart regularity includes the rotation's.
    pub euler_chart: bool,
    /// What the rejected items were meant to declare, for the stand-in
    /// emitted next to the errors (lowering does not see it).
    pub rejected: Rejected,
    /// The path of the `nonholonomic` facade in the generated code: the
    /// facade's `macro_rules!` wrapper passes its `$crate` as `@crate($crate)`
    /// before the system, so a renamed dependency works; `::nonholonomic`
    /// when the engine is called without it (its own tests).
    pub krate: TokenStream,
}

impl SystemDef {
    /// The keyword of a block (`def.constraints.as_ref()`, ..) as a range,
    /// or the system's name without the block: where an error about the
    /// block as a whole points.
    pub fn keyword_range<T>(&self, block: Option<&(Ident, T)>) -> SpanRange {
        SpanRange::single(block.map_or(self.name.span(), |b| b.0.span()))
    }

    /// The slot of a block of names other than `outputs` (`parameters`,
    /// `coordinates`, `inputs`, `speeds`, `dependent`); `None` for another
    /// block.
    pub(super) fn names_block(&mut self, block: Block) -> Option<&mut Option<(Ident, Vec<Ident>)>> {
        Some(match block {
            Block::Parameters => &mut self.parameters,
            Block::Coordinates => &mut self.coordinates,
            Block::Inputs => &mut self.inputs,
            Block::Speeds => &mut self.speeds,
            Block::Dependent => &mut self.dependent,
            Block::Forces
            | Block::Constraints
            | Block::Kinematics
            | Block::Outputs
            | Block::Symmetries
            | Block::Momenta => return None,
        })
    }
}

/// What items rejected by the parser were meant to declare: the stand-in
/// emitted next to the errors keeps the dimensions the user meant (a
/// parameter list with a syntax error still gives `new` its arguments, a
/// constraint that does not parse still removes an independent velocity),
/// so the code that uses the system raises no follow-up errors.
#[derive(Clone, Debug, Default)]
pub struct Rejected {
    /// The names of blocks of names that did not parse (or a misspelled
    /// block's, under the block it was taken for), read leniently: every
    /// identifier is a name, and a comma-separated entry without one (`2`)
    /// a placeholder. The outputs of `outputs` are in `outputs`.
    pub names: Vec<(Block, Vec<Ident>)>,
    /// The outputs of the first `outputs` block that did not parse (or a
    /// block misspelled for it), read like `names`.
    pub outputs: Option<Vec<Spelled<Output>>>,
    /// The lines of `constraints` (or of a block misspelled for it) that did
    /// not parse.
    pub constraint_lines: usize,
    /// The lines of `kinematics` that did not parse (a coordinate without
    /// its line is then no news).
    pub kinematics_lines: usize,
    /// Of the rejected lines of `constraints`, those that were `rolls(..)`
    /// (a contact: two rows, and the system has contacts).
    pub rolling_lines: usize,
}

impl Rejected {
    /// The names block `which` was meant to declare, if it was rejected.
    pub fn names_of(&self, which: Block) -> Option<&[Ident]> {
        self.names
            .iter()
            .find(|(w, _)| *w == which)
            .map(|(_, n)| n.as_slice())
    }
}
