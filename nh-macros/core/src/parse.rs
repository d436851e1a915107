//! Parsing of the `nonholonomic_system!` input language (DESIGN §2) into a
//! surface syntax tree that keeps every token's span.
//!
//! The body of the struct is split into items before any item is parsed, and
//! each item (and each statement of a block) is parsed on its own, so a
//! syntax error in one item does not hide the errors in the others.

mod items;

use crate::ctxt::{Ctxt, SpanRange};
use crate::names;
use crate::sym::Rational;
use items::{Item, split_items};
use proc_macro2::{Delimiter, Ident, Span, TokenStream, TokenTree};
use syn::ext::IdentExt;
use syn::parse::{ParseStream, Parser};
use syn::{Token, Visibility};

/// Deepest expression nesting accepted; deeper input is a clear error rather
/// than a stack overflow.
pub const MAX_DEPTH: usize = 256;

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
    pub fn call1(&self, func: &str) -> Option<&Expr> {
        match self {
            Expr::Call { func: f, args, .. } if f == func && args.len() == 1 => Some(&args[0]),
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
    /// its value
    pub value: Expr,
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

/// A `rolls(BODY, radius: .., axle: ..);` line of `constraints`.
#[derive(Clone, Debug)]
pub struct RollingDef {
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
    /// `constraints { .. }`
    pub constraints: Option<(Ident, Vec<Constraint>)>,
    /// `outputs { .. }`
    pub outputs: Option<(Ident, Vec<Ident>)>,
    /// The outputs of `outputs { .. }` written with a list of names,
    /// `sensitivities(m, k)`: (the output, the names), in order
    pub output_arguments: Vec<(Ident, Vec<Ident>)>,
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
    /// What the rejected items were meant to declare, for the stand-in
    /// emitted next to the errors (lowering does not see it).
    pub rejected: Rejected,
    /// The path of the `nonholonomic` facade in the generated code: the
    /// facade's `macro_rules!` wrapper passes its `$crate` as `@crate($crate)`
    /// before the system, so a renamed dependency works; `::nonholonomic`
    /// when the engine is called without it (its own tests).
    pub krate: TokenStream,
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
    /// a placeholder.
    pub names: Vec<(&'static str, Vec<Ident>)>,
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
    pub fn names_of(&self, which: &str) -> Option<&[Ident]> {
        self.names
            .iter()
            .find(|(w, _)| *w == which)
            .map(|(_, n)| n.as_slice())
    }
}

/// The names a block of names that failed to parse was meant to declare:
/// each identifier, and a placeholder for each comma-separated entry with
/// none (`parameters { m, 2 }` meant two parameters).
fn names_meant(group: &proc_macro2::Group) -> Vec<Ident> {
    let mut names = Vec::new();
    let mut entry_named = false;
    let mut entry_empty = true;
    let close_entry = |named: bool, empty: bool, names: &mut Vec<Ident>| {
        if !named && !empty {
            let i = names.len();
            names.push(quote::format_ident!("__nh_unnamed_{}", i));
        }
    };
    for tt in group.stream() {
        match tt {
            TokenTree::Punct(p) if p.as_char() == ',' => {
                close_entry(entry_named, entry_empty, &mut names);
                (entry_named, entry_empty) = (false, true);
            }
            TokenTree::Ident(id) => {
                names.push(names::canonical(id));
                (entry_named, entry_empty) = (true, false);
            }
            _ => entry_empty = false,
        }
    }
    close_entry(entry_named, entry_empty, &mut names);
    names
}

/// Splits off the `@crate(path)` prefix the facade's wrapper puts before the
/// system: the path, and the rest of the input.
fn crate_prefix(input: TokenStream) -> (TokenStream, TokenStream) {
    let tokens: Vec<TokenTree> = input.into_iter().collect();
    if let [
        TokenTree::Punct(at),
        TokenTree::Ident(kw),
        TokenTree::Group(path),
        ..,
    ] = tokens.as_slice()
        && at.as_char() == '@'
        && kw == "crate"
        && path.delimiter() == Delimiter::Parenthesis
    {
        return (path.stream(), tokens[3..].iter().cloned().collect());
    }
    (quote::quote!(::nonholonomic), tokens.into_iter().collect())
}

/// Parses the macro input. Returns the definition as far as it could be
/// parsed; errors are recorded in `cx`. `None` if not even the struct header
/// could be read.
pub fn parse_system(input: TokenStream, cx: &mut Ctxt) -> Option<SystemDef> {
    let (krate, input) = crate_prefix(input);
    let header = |stream: ParseStream| -> syn::Result<(Vec<TokenStream>, Visibility, Ident, proc_macro2::Group)> {
        // outer attributes are kept as tokens: their contents are rustc's business
        let mut attrs = Vec::new();
        while stream.peek(Token![#]) {
            let pound: TokenTree = stream.parse()?;
            let group: TokenTree = match stream.parse::<TokenTree>()? {
                TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket => TokenTree::Group(g),
                other => {
                    return Err(syn::Error::new(other.span(), "expected `[` after `#`: an attribute is written `#[..]`"));
                }
            };
            attrs.push(TokenStream::from_iter([pound, group]));
        }
        let vis: Visibility = stream.parse()?;
        let _: Token![struct] = stream.parse().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected `struct Name { .. }`: a system is written as `pub struct Name { parameters { .. } coordinates { .. } lagrangian = ..; }`",
            )
        })?;
        let name: Ident = stream.parse()?;
        let body: proc_macro2::Group = match stream.parse::<TokenTree>()? {
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => g,
            other => {
                return Err(syn::Error::new(
                    other.span(),
                    "expected `{` after the struct name (generics are added by the macro: the struct is generic over its scalar type)",
                ));
            }
        };
        // the sentinel `;` appended below
        if stream.peek(Token![;]) {
            let _: Token![;] = stream.parse()?;
        }
        if !stream.is_empty() {
            return Err(stream.error("unexpected tokens after the system's closing brace: one `nonholonomic_system!` defines one struct"));
        }
        Ok((attrs, vis, name, body))
    };
    // Huge input gets a clear error instead of minutes of work.
    if let Some(e) = too_large(&input) {
        cx.syn_error(e);
        return None;
    }
    // A sentinel `;` at the last token: an input that ends too early gets an
    // error at its end rather than at the whole macro call.
    let mut input: Vec<TokenTree> = input.into_iter().collect();
    if let Some(last) = input.last() {
        let mut semi = proc_macro2::Punct::new(';', proc_macro2::Spacing::Alone);
        semi.set_span(last.span());
        input.push(TokenTree::Punct(semi));
    }
    let input: TokenStream = input.into_iter().collect();
    let (attrs, vis, name, body) = match header.parse2(input) {
        Ok(h) => h,
        Err(e) => {
            cx.syn_error(e);
            return None;
        }
    };
    let mut def = SystemDef {
        attrs,
        vis,
        name,
        parameters: None,
        coordinates: None,
        inputs: None,
        lets: Vec::new(),
        bodies: Vec::new(),
        rolling: Vec::new(),
        lagrangians: Vec::new(),
        forces: None,
        constraints: None,
        outputs: None,
        output_arguments: Vec::new(),
        dependent: None,
        speeds: None,
        kinematics: None,
        poisoned: Vec::new(),
        lagrangian_written: false,
        rejected: Rejected::default(),
        krate,
    };
    let mut failed = false;
    for item in split_items(body.stream(), cx) {
        if failed && headless(&item) {
            continue;
        }
        let before = cx.len();
        parse_item(item, &mut def, cx);
        failed = cx.len() > before;
    }
    let has_parameters = def.parameters.as_ref().is_some_and(|p| !p.1.is_empty());
    def.attrs = crate::attrs::check_derives(std::mem::take(&mut def.attrs), has_parameters, cx);
    Some(def)
}

/// Most tokens accepted in one system (counting the tokens inside groups).
pub const MAX_TOKENS: usize = 200_000;

fn too_large(input: &TokenStream) -> Option<syn::Error> {
    let mut count = 0usize;
    let mut stack: Vec<TokenStream> = vec![input.clone()];
    let mut first: Option<Span> = None;
    while let Some(ts) = stack.pop() {
        for tt in ts {
            count += 1;
            first.get_or_insert(tt.span());
            if let TokenTree::Group(g) = tt {
                stack.push(g.stream());
            }
        }
        if count > MAX_TOKENS {
            return Some(syn::Error::new(
                first.unwrap_or_else(Span::call_site),
                format!(
                    "this system has more than {MAX_TOKENS} tokens: split the expressions into `let` items or generate the system in parts"
                ),
            ));
        }
    }
    None
}

/// Parses an item.
fn parse_item(item: Item, def: &mut SystemDef, cx: &mut Ctxt) {
    match item {
        Item::Block(kw, group) => parse_block(kw, &group, def, cx),
        Item::Body(name, group) => {
            let (fields, rejected_fields) = parse_fields(&group, cx);
            def.bodies.push(BodyDef {
                name,
                fields,
                rejected_fields,
            });
        }
        Item::Statement(toks) => {
            parse_statement_item(toks, def, cx);
        }
        Item::Unterminated(toks) => {
            // the last token before the sentinel `;`
            let last = toks.len().checked_sub(2).map(|k| toks[k].span());
            if parse_statement_item(toks, def, cx)
                && let Some(last) = last
            {
                cx.error_at(
                    last,
                    "expected `;` after this: an item ends with `;` before the next one",
                );
            }
        }
    }
}

/// Whether a statement cannot start an item (`let NAME = ..;`,
/// `lagrangian = ..;`): right after an item with an error, it is taken as
/// the rest of that item, whose error covers it.
fn headless(item: &Item) -> bool {
    let toks = match item {
        Item::Statement(t) | Item::Unterminated(t) => t,
        _ => return false,
    };
    !matches!(toks.first(), Some(TokenTree::Ident(id)) if id == "let" || id == "lagrangian")
}

/// The blocks of a definition, in the order messages list them.
pub(crate) const BLOCKS: [&str; 9] = [
    "parameters",
    "coordinates",
    "inputs",
    "forces",
    "constraints",
    "dependent",
    "speeds",
    "kinematics",
    "outputs",
];

/// A block `kw { .. }`.
fn parse_block(kw: Ident, group: &proc_macro2::Group, def: &mut SystemDef, cx: &mut Ctxt) {
    let which = kw.to_string();
    match which.as_str() {
        "parameters" | "coordinates" | "inputs" | "speeds" | "outputs" | "dependent" => {
            parse_name_block(kw, group, def, cx)
        }
        "kinematics" => {
            let list = parse_each(group, parse_kinematics_line, headless_equation, cx);
            def.rejected.kinematics_lines += split_statements(group).len() - list.len();
            set_once(&mut def.kinematics, kw, list, cx, |_| {
                "duplicate `kinematics` block: write one line per coordinate in one block"
                    .to_string()
            });
        }
        "constraints" => {
            let mut list = Vec::new();
            let mut rolling = Vec::new();
            let lines = parse_each(group, parse_constraint_line, headless_equation, cx);
            def.rejected.constraint_lines += split_statements(group).len() - lines.len();
            // the rejected lines that were rolling contacts (two rows each)
            let rolling_written = split_statements(group)
                .iter()
                .filter(|(toks, _)| mentions_rolls(toks))
                .count();
            let rolling_parsed = lines
                .iter()
                .filter(|l| matches!(l, Line::Rolling(_)))
                .count();
            def.rejected.rolling_lines += rolling_written.saturating_sub(rolling_parsed);
            for line in lines {
                match line {
                    Line::Equation(c) => list.push(c),
                    Line::Rolling(mut r) => {
                        r.position = list.len();
                        rolling.push(r);
                    }
                }
            }
            if def.constraints.is_none() {
                def.rolling = rolling;
            }
            set_once(&mut def.constraints, kw, list, cx, |_| {
                "duplicate `constraints` block: write all constraints in one block".to_string()
            });
        }
        "forces" => {
            let list = parse_each(group, parse_force, headless_force, cx);
            set_once(&mut def.forces, kw, list, cx, |_| {
                "duplicate `forces` block: write all forces in one block".to_string()
            });
        }
        _ => {
            let hint = crate::names::suggest(&which, &BLOCKS);
            reject_misspelled_block(&which, group, def);
            cx.error_at(
                kw.span(),
                format!(
                    "unknown block `{which}`{hint}; the blocks are `parameters`, `coordinates`, `inputs`, `forces`, `constraints`, `dependent`, `speeds`, `kinematics` and `outputs`"
                ),
            );
        }
    }
}

/// What a misspelled block (`constraint { .. }`) was meant to declare, for
/// the stand-in: the names of a block of names, or the number of lines of
/// `constraints`.
fn reject_misspelled_block(which: &str, group: &proc_macro2::Group, def: &mut SystemDef) {
    match crate::names::closest(which, BLOCKS) {
        Some("constraints") => {
            def.rejected.constraint_lines += split_statements(group).len();
        }
        Some(block @ ("parameters" | "coordinates" | "inputs" | "speeds" | "outputs")) => {
            def.rejected.names.push((block, names_meant(group)));
        }
        _ => {}
    }
}

/// A block of names: `parameters`, `coordinates`, `inputs` or `outputs`.
fn parse_name_block(kw: Ident, group: &proc_macro2::Group, def: &mut SystemDef, cx: &mut Ctxt) {
    let which = kw.to_string();
    let parsed = if which == "outputs" {
        parse_output_list
            .parse2(group.stream())
            .map(|(names, arguments)| {
                if def.outputs.is_none() {
                    def.output_arguments = arguments;
                }
                names
            })
    } else {
        parse_name_list.parse2(group.stream())
    };
    let list = match parsed {
        Ok(n) => n,
        Err(e) => {
            cx.syn_error(e);
            // the names it meant to declare must not cause follow-up errors
            for tt in group.stream() {
                if let TokenTree::Ident(id) = tt {
                    def.poisoned.push(names::canonical(id));
                }
            }
            if let Some(block) = BLOCKS.into_iter().find(|b| *b == which) {
                def.rejected.names.push((block, names_meant(group)));
            }
            return;
        }
    };
    // a keyword is reported here, once, at the name; it stays
    // declared, so its uses raise no follow-up errors
    let kind = match which.as_str() {
        "parameters" => Some("a parameter"),
        "coordinates" => Some("a coordinate"),
        "inputs" => Some("an input"),
        "speeds" => Some("a speed"),
        _ => None,
    };
    for id in &list {
        if let Some(msg) = kind.and_then(|k| names::keyword_problem(id, k)) {
            cx.error_at(id.span(), msg);
        }
    }
    let slot = match which.as_str() {
        "parameters" => &mut def.parameters,
        "coordinates" => &mut def.coordinates,
        "inputs" => &mut def.inputs,
        "speeds" => &mut def.speeds,
        "dependent" => &mut def.dependent,
        _ => &mut def.outputs,
    };
    set_once(slot, kw, list, cx, |prev| {
        format!("duplicate `{which}` block: list all names in the first `{prev}` block")
    });
}

/// Each `;`-separated statement of a block parsed by `parser`; the errors
/// into `cx`. One token moved across the `;` between two statements (the
/// last of one to the start of the next, or back) is put back, with the
/// first statement's error only; a statement that cannot start a line
/// (`headless`) right after one with an error is taken as its rest, whose
/// error covers it.
fn parse_each<T>(
    group: &proc_macro2::Group,
    parser: fn(ParseStream) -> syn::Result<T>,
    headless: fn(&[TokenTree]) -> bool,
    cx: &mut Ctxt,
) -> Vec<T> {
    let statements: Vec<Vec<TokenTree>> = split_statements(group)
        .into_iter()
        .map(|(toks, _)| toks)
        .collect();
    let parse = |toks: &[TokenTree]| parser.parse2(toks.iter().cloned().collect());
    let mut list = Vec::new();
    let mut failed = false;
    let mut k = 0;
    while k < statements.len() {
        let here = &statements[k];
        k += 1;
        let e = match parse(here) {
            Ok(c) => {
                list.push(c);
                failed = false;
                continue;
            }
            Err(e) => e,
        };
        if let Some(next) = statements.get(k)
            && let Some(both) = moved_across(here, next, parse)
        {
            cx.syn_error(e);
            list.extend(both);
            failed = false;
            k += 1;
            continue;
        }
        if !(failed && headless(here)) {
            cx.syn_error(e);
        }
        failed = true;
    }
    list
}

/// Two statements (each ending in its `;`) parsed with one token moved
/// back across the `;` between them, if that makes both parse: the last
/// token of the first to the start of the second, or the first token of the
/// second to the end of the first (a second left empty is none).
fn moved_across<T>(
    first: &[TokenTree],
    second: &[TokenTree],
    parse: impl Fn(&[TokenTree]) -> syn::Result<T>,
) -> Option<Vec<T>> {
    let (Some((semi, body)), Some((head, rest))) = (first.split_last(), second.split_first())
    else {
        return None;
    };
    // the last token of the first statement to the start of the second
    if let Some((last, body_rest)) = body.split_last()
        && !body_rest.is_empty()
    {
        let a: Vec<TokenTree> = body_rest.iter().chain([semi]).cloned().collect();
        let b: Vec<TokenTree> = [last].into_iter().chain(second).cloned().collect();
        if let (Ok(x), Ok(y)) = (parse(&a), parse(&b)) {
            return Some(vec![x, y]);
        }
    }
    // the first token of the second statement to the end of the first
    let a: Vec<TokenTree> = body.iter().chain([head, semi]).cloned().collect();
    let x = parse(&a).ok()?;
    let rest_is_empty = rest
        .iter()
        .all(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ';'));
    if rest_is_empty {
        return Some(vec![x]);
    }
    let y = parse(rest).ok()?;
    Some(vec![x, y])
}

/// Whether a line of `constraints` was meant as `rolls(..)`: `rolls` among
/// its first tokens (or first in its first parentheses).
fn mentions_rolls(toks: &[TokenTree]) -> bool {
    toks.iter().take(3).any(|t| match t {
        TokenTree::Ident(id) => id == "rolls",
        TokenTree::Group(g) => g
            .stream()
            .into_iter()
            .next()
            .is_some_and(|f| matches!(f, TokenTree::Ident(id) if id == "rolls")),
        _ => false,
    })
}

/// A line of `constraints` or `kinematics` that cannot start one: it starts
/// with a punctuation other than `-`.
fn headless_equation(toks: &[TokenTree]) -> bool {
    matches!(toks.first(), Some(TokenTree::Punct(p)) if p.as_char() != '-')
}

/// A line of `forces` that cannot start one: not `name:`.
fn headless_force(toks: &[TokenTree]) -> bool {
    !matches!(
        (toks.first(), toks.get(1)),
        (Some(TokenTree::Ident(_)), Some(TokenTree::Punct(p))) if p.as_char() == ':'
    )
}

/// Fills the slot of a block, or reports a second block of its kind at its
/// keyword with `duplicate(first keyword)`.
fn set_once<T>(
    slot: &mut Option<(Ident, Vec<T>)>,
    kw: Ident,
    list: Vec<T>,
    cx: &mut Ctxt,
    duplicate: impl FnOnce(&Ident) -> String,
) {
    match slot {
        Some((prev, _)) => cx.error_at(kw.span(), duplicate(prev)),
        None => *slot = Some((kw, list)),
    }
}

/// A statement: `lagrangian = ..;` or `let name = ..;`; whether it parsed.
fn parse_statement_item(toks: Vec<TokenTree>, def: &mut SystemDef, cx: &mut Ctxt) -> bool {
    if toks.is_empty() {
        return true;
    }
    match (&toks[0], toks.get(1)) {
        (TokenTree::Ident(kw), _) if kw == "lagrangian" => def.lagrangian_written = true,
        (TokenTree::Ident(kw), Some(TokenTree::Ident(name))) if kw == "let" => {
            def.poisoned.push(names::canonical(name.clone()))
        }
        _ => {}
    }
    let stream: TokenStream = toks.into_iter().collect();
    match parse_statement.parse2(stream) {
        Ok(Statement::Let(l)) => {
            if let Some(msg) = names::keyword_problem(&l.name, "a `let`") {
                cx.error_at(l.name.span(), msg);
            }
            def.poisoned.retain(|p| p != &l.name);
            def.lets.push(l)
        }
        Ok(Statement::Lagrangian(kw, e)) => def.lagrangians.push((kw, e)),
        Err(e) => {
            cx.syn_error(e);
            return false;
        }
    }
    true
}

/// The `;`-separated statements of a block, each ending in its `;` (the last
/// one, which may omit it, gets one at the closing brace) so that an error
/// at the end of a statement points into the source, not at the macro call.
fn split_statements(group: &proc_macro2::Group) -> Vec<(Vec<TokenTree>, Span)> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for tt in group.stream() {
        match &tt {
            TokenTree::Punct(p) if p.as_char() == ';' => {
                if !cur.is_empty() {
                    let span = p.span();
                    cur.push(tt);
                    out.push((std::mem::take(&mut cur), span));
                }
            }
            _ => cur.push(tt),
        }
    }
    if !cur.is_empty() {
        let close = group.span_close();
        let mut semi = proc_macro2::Punct::new(';', proc_macro2::Spacing::Alone);
        semi.set_span(close);
        cur.push(TokenTree::Punct(semi));
        out.push((cur, close));
    }
    out
}

enum Statement {
    Let(Let),
    Lagrangian(Ident, Expr),
}

fn parse_statement(input: ParseStream) -> syn::Result<Statement> {
    if input.peek(Token![let]) {
        let _: Token![let] = input.parse()?;
        let name: Ident = input
            .call(IdentExt::parse_any)
            .map_err(|e| syn::Error::new(e.span(), "expected a name after `let`"))?;
        let name = names::canonical(name);
        let _: Token![=] = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), format!("expected `=` after `let {name}`")))?;
        let value = parse_expr_all(input)?;
        return Ok(Statement::Let(Let { name, value }));
    }
    let kw: Ident = input.parse().map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected an item: `let NAME = ..;`, `lagrangian = ..;` or a block such as `constraints { .. }`",
        )
    })?;
    if kw == "lagrangian" {
        let _: Token![=] = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected `=` after `lagrangian`"))?;
        let value = parse_expr_all(input)?;
        return Ok(Statement::Lagrangian(kw, value));
    }
    let hint = crate::names::suggest(&kw.to_string(), &["lagrangian"]);
    Err(syn::Error::new(
        kw.span(),
        format!(
            "unexpected `{kw}`{hint}: an item is `let NAME = ..;`, `lagrangian = ..;` or a block `parameters {{ .. }}`, `coordinates {{ .. }}`, `inputs {{ .. }}`, `forces {{ .. }}`, `constraints {{ .. }}`, `speeds {{ .. }}`, `kinematics {{ .. }}`, `outputs {{ .. }}`"
        ),
    ))
}

fn parse_name_list(input: ParseStream) -> syn::Result<Vec<Ident>> {
    let mut names = Vec::new();
    while !input.is_empty() {
        // keywords are read as names, and reported at the name (`declared_names`)
        let id: Ident = input.call(IdentExt::parse_any).map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected a name: this block is a comma-separated list of names",
            )
        })?;
        names.push(names::canonical(id));
        if input.is_empty() {
            break;
        }
        let _: Token![,] = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected `,` between names"))?;
    }
    Ok(names)
}

/// The list of `outputs { .. }`: names, each optionally with a
/// parenthesised list of names (`sensitivities(m, k)`); returns the names
/// and those lists.
#[allow(clippy::type_complexity)]
fn parse_output_list(input: ParseStream) -> syn::Result<(Vec<Ident>, Vec<(Ident, Vec<Ident>)>)> {
    let mut names = Vec::new();
    let mut arguments = Vec::new();
    while !input.is_empty() {
        let id: Ident = input.call(IdentExt::parse_any).map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected the name of an output: this block is a comma-separated list of outputs, such as `energy, jacobian` or `sensitivities(m, k)`",
            )
        })?;
        let id = names::canonical(id);
        if input.peek(syn::token::Paren) {
            let content;
            syn::parenthesized!(content in input);
            let list = parse_name_list(&content).map_err(|e| {
                syn::Error::new(
                    e.span(),
                    format!("expected names in `{id}(..)`: a comma-separated list of parameters"),
                )
            })?;
            arguments.push((id.clone(), list));
        }
        names.push(id);
        if input.is_empty() {
            break;
        }
        let _: Token![,] = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected `,` between outputs"))?;
    }
    Ok((names, arguments))
}

/// A line of `constraints`: an equation or a rolling contact.
enum Line {
    Equation(Constraint),
    Rolling(RollingDef),
}

fn parse_constraint_line(input: ParseStream) -> syn::Result<Line> {
    let fork = input.fork();
    let is_rolling =
        fork.call(Ident::parse_any).is_ok_and(|id| id == "rolls") && fork.peek(syn::token::Paren);
    if is_rolling {
        return parse_rolling(input).map(Line::Rolling);
    }
    parse_constraint(input).map(Line::Equation)
}

/// `rolls(BODY, name: expr, ..);`
fn parse_rolling(input: ParseStream) -> syn::Result<RollingDef> {
    let kw: Ident = input.call(IdentExt::parse_any)?;
    let content;
    let paren = syn::parenthesized!(content in input);
    let body: Ident = content.call(IdentExt::parse_any).map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected the rolling body's name: `rolls(wheel, radius: r, axle: [0, 1, 0]);`",
        )
    })?;
    let mut fields = Vec::new();
    while !content.is_empty() {
        let _: Token![,] = content.parse().map_err(|e| {
            syn::Error::new(e.span(), "expected `,` between the arguments of `rolls`")
        })?;
        if content.is_empty() {
            break;
        }
        fields.push(parse_field(&content)?);
    }
    if input.peek(Token![;]) {
        let _: Token![;] = input.parse()?;
    }
    if !input.is_empty() {
        return Err(input.error("unexpected tokens after `rolls(..)`: end the line with `;`"));
    }
    Ok(RollingDef {
        range: SpanRange {
            first: kw.span(),
            last: paren.span.close(),
        },
        body: names::canonical(body),
        fields,
        position: 0,
    })
}

/// `name: expr`
fn parse_field(input: ParseStream) -> syn::Result<Field> {
    let name: Ident = input
        .call(IdentExt::parse_any)
        .map_err(|e| syn::Error::new(e.span(), "expected a field: `name: value`"))?;
    let _: Token![:] = input.parse().map_err(|e| {
        syn::Error::new(
            e.span(),
            format!("expected `:` after `{name}`: a field is written `{name}: value`"),
        )
    })?;
    let value = parse_expr(input, 0)?;
    Ok(Field { name, value })
}

/// The comma-separated `name: expr` fields of a `body` item, each parsed on
/// its own so that one error does not hide the others; and whether one did
/// not parse.
fn parse_fields(group: &proc_macro2::Group, cx: &mut Ctxt) -> (Vec<Field>, bool) {
    let mut out = Vec::new();
    let mut rejected = false;
    let mut failed = false;
    // each piece ends in its `,` (the last in one at the closing brace), so
    // that an error at the end of a field points into the source
    let mut pieces: Vec<Vec<TokenTree>> = vec![Vec::new()];
    for tt in group.stream() {
        match &tt {
            TokenTree::Punct(p) if p.as_char() == ',' => {
                if let Some(v) = pieces.last_mut() {
                    v.push(tt.clone());
                }
                pieces.push(Vec::new());
            }
            _ => {
                if let Some(v) = pieces.last_mut() {
                    v.push(tt);
                }
            }
        }
    }
    if let Some(last) = pieces.last_mut()
        && !last.is_empty()
    {
        let mut comma = proc_macro2::Punct::new(',', proc_macro2::Spacing::Alone);
        comma.set_span(group.span_close());
        last.push(TokenTree::Punct(comma));
    }
    let is_comma = |t: &TokenTree| matches!(t, TokenTree::Punct(p) if p.as_char() == ',');
    for piece in pieces.into_iter().filter(|p| !p.iter().all(is_comma)) {
        let parser = |input: ParseStream| {
            let f = parse_field(input)?;
            if input.peek(Token![,]) {
                let _: Token![,] = input.parse()?;
            }
            if !input.is_empty() {
                let tt: TokenTree = input.parse()?;
                return Err(syn::Error::new(
                    tt.span(),
                    format!("unexpected `{tt}`: separate the fields of a body with `,`"),
                ));
            }
            Ok(f)
        };
        // a piece that cannot start a field (`name:`) right after one with
        // an error is its rest: that error covers it
        let headless = !matches!(
            (piece.first(), piece.get(1)),
            (Some(TokenTree::Ident(_)), Some(TokenTree::Punct(p))) if p.as_char() == ':'
        );
        match parser.parse2(piece.into_iter().collect()) {
            Ok(f) => {
                out.push(f);
                failed = false;
            }
            Err(e) => {
                if !(failed && headless) {
                    cx.syn_error(e);
                }
                rejected = true;
                failed = true;
            }
        }
    }
    (out, rejected)
}

fn parse_constraint(input: ParseStream) -> syn::Result<Constraint> {
    parse_equation(
        input,
        "expected `=`: a constraint is written `dot(s) = a(q)*dot(r) + ..;`, `c1(q)*dot(q1) + .. = b(q, t);` or `f(q, t) = 0;`",
    )
}

/// `lhs = rhs`, with `missing_eq` as the error when there is no `=`.
fn parse_equation(input: ParseStream, missing_eq: &str) -> syn::Result<Constraint> {
    let lhs = parse_expr(input, 0)?;
    if !input.peek(Token![=]) {
        return Err(input.error(missing_eq));
    }
    let _: Token![=] = input.parse()?;
    let rhs = parse_expr_all(input)?;
    Ok(Constraint { lhs, rhs })
}

fn parse_kinematics_line(input: ParseStream) -> syn::Result<Constraint> {
    parse_equation(
        input,
        "expected `=`: a line of `kinematics` is written `dot(q) = s1(q)*u1 + s2(q)*u2 + ..;`",
    )
}

fn parse_force(input: ParseStream) -> syn::Result<Force> {
    let coordinate: Ident = input.call(IdentExt::parse_any).map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected a coordinate name: a force is written `q: expr;`",
        )
    })?;
    let coordinate = names::canonical(coordinate);
    let _: Token![:] = input.parse().map_err(|e| {
        syn::Error::new(
            e.span(),
            format!("expected `:` after `{coordinate}`: a force is written `{coordinate}: expr;`"),
        )
    })?;
    let value = parse_expr_all(input)?;
    Ok(Force { coordinate, value })
}

/// Parses an expression that must use up the whole stream.
fn parse_expr_all(input: ParseStream) -> syn::Result<Expr> {
    if input.is_empty() || input.peek(Token![;]) {
        return Err(input.error("expected an expression"));
    }
    let e = parse_expr(input, 0)?;
    if input.peek(Token![;]) {
        let _: Token![;] = input.parse()?;
    }
    if !input.is_empty() {
        let tt: TokenTree = input.parse()?;
        let msg = match &tt {
            TokenTree::Punct(p) if p.as_char() == ';' => "unexpected `;`".to_string(),
            _ => format!(
                "unexpected `{tt}` after a complete expression: is an operator (`+ - * / ^`) missing, or a `;`?"
            ),
        };
        return Err(syn::Error::new(tt.span(), msg));
    }
    Ok(e)
}

/// An error past [`MAX_DEPTH`] levels of nesting (`why`: a guess at the
/// cause, for the message).
fn not_too_deep(input: ParseStream, depth: usize, why: &str) -> syn::Result<()> {
    if depth > MAX_DEPTH {
        return Err(input.error(format!(
            "expression nested more than {MAX_DEPTH} levels deep{why}: split it into `let` items"
        )));
    }
    Ok(())
}

/// expr := term (('+' | '-') term)*
fn parse_expr(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    not_too_deep(input, depth, "")?;
    parse_chain(input, depth, parse_term, additive_op)
}

/// A binary operator with its span.
type Operator = (BinOp, Span);

/// `operand (op operand)*` as one chain, with `op` parsed by `next_op`.
fn parse_chain(
    input: ParseStream,
    depth: usize,
    operand: fn(ParseStream, usize) -> syn::Result<Expr>,
    next_op: fn(ParseStream) -> syn::Result<Option<Operator>>,
) -> syn::Result<Expr> {
    let first = operand(input, depth)?;
    let mut rest = Vec::new();
    while let Some((op, span)) = next_op(input)? {
        check_chain_length(&rest, span)?;
        let rhs = operand(input, depth)?;
        rest.push((op, span, rhs));
    }
    Ok(chain(first, rest))
}

/// `+` or `-` (not `-=`), if next.
fn additive_op(input: ParseStream) -> syn::Result<Option<Operator>> {
    Ok(if input.peek(Token![+]) {
        let t: Token![+] = input.parse()?;
        Some((BinOp::Add, t.span))
    } else if input.peek(Token![-]) && !input.peek(Token![-=]) {
        let t: Token![-] = input.parse()?;
        Some((BinOp::Sub, t.span))
    } else {
        None
    })
}

/// `*` (not `*=` or `**`) or `/` (not `/=`), if next.
fn multiplicative_op(input: ParseStream) -> syn::Result<Option<Operator>> {
    Ok(if input.peek(Token![*]) && !input.peek(Token![*=]) {
        let t: Token![*] = input.parse()?;
        if input.peek(Token![*]) {
            return Err(syn::Error::new(
                t.span,
                "`**` is not an operator here: write powers with `^`, as in `x^2`",
            ));
        }
        Some((BinOp::Mul, t.span))
    } else if input.peek(Token![/]) && !input.peek(Token![/=]) {
        let t: Token![/] = input.parse()?;
        Some((BinOp::Div, t.span))
    } else {
        None
    })
}

/// Longest chain of operands accepted in one sum or product.
pub const MAX_CHAIN: usize = 100_000;

fn check_chain_length(rest: &[(BinOp, Span, Expr)], span: Span) -> syn::Result<()> {
    if rest.len() >= MAX_CHAIN {
        return Err(syn::Error::new(
            span,
            format!(
                "more than {MAX_CHAIN} operands in one sum or product: split it into `let` items"
            ),
        ));
    }
    Ok(())
}

fn chain(first: Expr, rest: Vec<(BinOp, Span, Expr)>) -> Expr {
    if rest.is_empty() {
        first
    } else {
        Expr::Chain {
            first: Box::new(first),
            rest,
            parens: None,
        }
    }
}

/// term := unary (('*' | '/') unary)*
fn parse_term(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    parse_chain(input, depth, parse_unary, multiplicative_op)
}

/// unary := '-' unary | power
fn parse_unary(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    let mut minus_spans = Vec::new();
    while input.peek(Token![-]) {
        let t: Token![-] = input.parse()?;
        minus_spans.push(t.span);
        if minus_spans.len() > MAX_DEPTH {
            return Err(syn::Error::new(t.span, "too many consecutive minus signs"));
        }
    }
    if input.peek(Token![+]) {
        let t: Token![+] = input.parse()?;
        return Err(syn::Error::new(
            t.span,
            "unary `+` is not supported: remove it",
        ));
    }
    let mut e = parse_power(input, depth)?;
    for s in minus_spans.into_iter().rev() {
        let r = SpanRange::single(s).to(e.range());
        e = Expr::Neg(Box::new(e), r);
    }
    Ok(e)
}

/// power := primary ('^' unary)?
fn parse_power(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    not_too_deep(input, depth, " (a tower of powers?)")?;
    let base = parse_postfix(input, depth)?;
    if input.peek(Token![^]) && !input.peek(Token![^=]) {
        let _: Token![^] = input.parse()?;
        let exp = parse_unary(input, depth + 1)?;
        return Ok(Expr::Pow {
            base: Box::new(base),
            exp: Box::new(exp),
            parens: None,
        });
    }
    Ok(base)
}

/// postfix := primary ('.' name | '.' name '(' args ')')*: a component
/// `v.x`, or a method call `a.cross(b)` (the call `cross(a, b)`).
fn parse_postfix(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    let mut e = parse_primary(input, depth)?;
    while input.peek(Token![.]) && !input.peek(Token![..]) {
        let _: Token![.] = input.parse()?;
        let field: Ident = input.call(IdentExt::parse_any).map_err(|err| {
            syn::Error::new(
                err.span(),
                "expected a component `.x`, `.y`, `.z` or a method such as `.cross(b)` after `.`",
            )
        })?;
        if input.peek(syn::token::Paren) {
            let content;
            let paren = syn::parenthesized!(content in input);
            let mut args = vec![e];
            args.extend(parse_args(&content, depth + 1)?);
            let range = args[0].range().to(SpanRange::single(paren.span.close()));
            e = Expr::Call {
                func: names::canonical(field),
                args,
                range,
            };
        } else {
            e = Expr::Component {
                base: Box::new(e),
                field,
            };
        }
    }
    Ok(e)
}

/// args := expr (',' expr)* ','?
fn parse_args(content: ParseStream, depth: usize) -> syn::Result<Vec<Expr>> {
    let mut args = Vec::new();
    while !content.is_empty() {
        args.push(parse_expr(content, depth)?);
        if content.is_empty() {
            break;
        }
        if !content.peek(Token![,]) {
            let t: TokenTree = content.parse()?;
            return Err(syn::Error::new(
                t.span(),
                format!("unexpected `{t}`: separate arguments with `,`"),
            ));
        }
        let _: Token![,] = content.parse()?;
    }
    Ok(args)
}

/// primary := number | name | name '(' args ')' | '(' expr ')' | '[' args ']'
fn parse_primary(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    if input.is_empty() {
        return Err(input.error("expected an operand (a number, a name, `dot(q)`, a function call or a parenthesised expression)"));
    }
    let tt: TokenTree = input.fork().parse()?;
    match tt {
        TokenTree::Literal(_) => parse_number(input),
        TokenTree::Ident(_) => parse_name_or_call(input, depth),
        TokenTree::Group(g) if g.delimiter() == Delimiter::Parenthesis => {
            parse_parenthesised(input, depth)
        }
        TokenTree::Group(g) if g.delimiter() == Delimiter::Bracket => {
            let content;
            let bracket = syn::bracketed!(content in input);
            let items = parse_args(&content, depth + 1)?;
            if items.is_empty() {
                return Err(syn::Error::new(
                    g.span(),
                    "empty brackets: a vector is written `[x, y, z]`",
                ));
            }
            Ok(Expr::Vector {
                items,
                range: SpanRange {
                    first: bracket.span.open(),
                    last: bracket.span.close(),
                },
            })
        }
        TokenTree::Group(g) => {
            let what = match g.delimiter() {
                Delimiter::Brace => "braces `{..}`",
                _ => "this group",
            };
            Err(syn::Error::new(
                g.span(),
                format!("{what} cannot be used in an expression: group with parentheses `(..)`"),
            ))
        }
        TokenTree::Punct(p) => {
            let c = p.as_char();
            let msg = match c {
                '*' | '/' | '^' => format!("`{c}` is missing its left operand"),
                ';' => "expected an expression before `;`".to_string(),
                _ => format!("unexpected `{c}`: expected a number, a name, `dot(q)` or `(`"),
            };
            Err(syn::Error::new(p.span(), msg))
        }
    }
}

/// number := an integer or decimal literal without a type suffix
fn parse_number(input: ParseStream) -> syn::Result<Expr> {
    let lit: syn::Lit = input.parse()?;
    let span = lit.span();
    let (suffix, digits) = match &lit {
        syn::Lit::Int(i) => (i.suffix(), i.base10_digits()),
        syn::Lit::Float(f) => (f.suffix(), f.base10_digits()),
        _ => {
            return Err(syn::Error::new(
                span,
                "expected a number; string and character literals have no meaning here",
            ));
        }
    };
    if !suffix.is_empty() {
        return Err(syn::Error::new(
            span,
            format!("remove the type suffix `{suffix}`: numbers are exact rationals here"),
        ));
    }
    match decimal_to_rational(digits) {
        Some(q) => Ok(Expr::Num(q, SpanRange::single(span))),
        None => Err(syn::Error::new(
            span,
            format!(
                "this number's decimal exponent is out of range: exponents up to ±{} are supported",
                Rational::MAX_DIGITS
            ),
        )),
    }
}

/// name | name '(' args ')'
fn parse_name_or_call(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    let id: Ident = names::canonical(input.call(IdentExt::parse_any)?);
    if !input.peek(syn::token::Paren) {
        return Ok(Expr::Name(id));
    }
    let content;
    let paren = syn::parenthesized!(content in input);
    if content.is_empty() {
        return Err(syn::Error::new(
            paren.span.join(),
            format!("`{id}()` needs an argument"),
        ));
    }
    let args = parse_args(&content, depth + 1)?;
    let range = SpanRange {
        first: id.span(),
        last: paren.span.close(),
    };
    Ok(Expr::Call {
        func: id,
        args,
        range,
    })
}

/// '(' expr ')'
fn parse_parenthesised(input: ParseStream, depth: usize) -> syn::Result<Expr> {
    let content;
    let paren = syn::parenthesized!(content in input);
    if content.is_empty() {
        return Err(syn::Error::new(
            paren.span.join(),
            "empty parentheses: expected an expression inside",
        ));
    }
    let e = parse_expr(&content, depth + 1)?;
    if !content.is_empty() {
        let t: TokenTree = content.parse()?;
        return Err(syn::Error::new(
            t.span(),
            format!("unexpected `{t}` inside parentheses"),
        ));
    }
    // keep the parentheses in the range so errors cover them
    let outer = SpanRange {
        first: paren.span.open(),
        last: paren.span.close(),
    };
    Ok(match e {
        Expr::Num(q, _) => Expr::Num(q, outer),
        Expr::Neg(inner, _) => Expr::Neg(inner, outer),
        Expr::Chain { first, rest, .. } => Expr::Chain {
            first,
            rest,
            parens: Some(outer),
        },
        Expr::Pow { base, exp, .. } => Expr::Pow {
            base,
            exp,
            parens: Some(outer),
        },
        other => other,
    })
}

/// Converts decimal literal digits (`12`, `0.25`, `1e-3`, `6.62607015e-34`,
/// forty-digit integers) to an exact rational; `None` if the decimal exponent
/// (after the point is moved) exceeds ±[`Rational::MAX_DIGITS`].
pub fn decimal_to_rational(text: &str) -> Option<Rational> {
    let text = text.replace('_', "");
    let (mantissa, exp) = match text.find(['e', 'E']) {
        Some(i) => (&text[..i], text[i + 1..].parse::<i64>().ok()?),
        None => (text.as_str(), 0),
    };
    let (int_part, frac_part) = match mantissa.find('.') {
        Some(i) => (&mantissa[..i], &mantissa[i + 1..]),
        None => (mantissa, ""),
    };
    let digits = format!("{int_part}{frac_part}");
    let digits = digits.trim_start_matches('0');
    if digits.is_empty() {
        return Some(Rational::ZERO);
    }
    let num = Rational::from_digits(digits)?;
    let scale = exp.checked_sub(i64::try_from(frac_part.len()).ok()?)?;
    if scale.unsigned_abs() > u64::from(Rational::MAX_DIGITS) {
        return None;
    }
    num.checked_mul(Rational::int(10).checked_powi(scale)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    #[test]
    fn decimals_are_exact() {
        assert_eq!(decimal_to_rational("0.25"), Rational::new(1, 4));
        assert_eq!(decimal_to_rational("1e-3"), Rational::new(1, 1000));
        assert_eq!(decimal_to_rational("2.5E2"), Rational::new(250, 1));
        assert_eq!(decimal_to_rational("007"), Rational::new(7, 1));
    }

    #[test]
    fn a_physicists_literals_are_exact() {
        let pow10 = |k: i64| Rational::int(10).checked_powi(k).unwrap();
        let planck = Rational::int(662607015).checked_div(pow10(42));
        assert_eq!(decimal_to_rational("6.62607015e-34"), planck);
        let avogadro = Rational::int(602214076).checked_mul(pow10(15));
        assert_eq!(decimal_to_rational("6.02214076e23"), avogadro);
        assert_eq!(decimal_to_rational("1e300"), Some(pow10(300)));
        assert_eq!(decimal_to_rational("1E-400"), Some(pow10(-400)));
        let forty = "1234567890123456789012345678901234567890";
        assert_eq!(decimal_to_rational(forty).unwrap().to_string(), forty);
        assert_eq!(
            decimal_to_rational("1_000.000_000_000_000_000_000_000_000_000_000_000_1")
                .unwrap()
                .to_string(),
            format!("1{}1/1{}", "0".repeat(36), "0".repeat(34))
        );
        assert_eq!(decimal_to_rational("0e99999999"), Some(Rational::ZERO));
        // decimal exponents are bounded (the value would have 10^5 digits)
        assert_eq!(decimal_to_rational("1e10000"), Some(pow10(10000)));
        assert_eq!(decimal_to_rational("1e10001"), None);
        assert_eq!(decimal_to_rational("1e-99999999999999999999"), None);
    }

    #[test]
    fn precedence_of_power_and_minus() {
        let e = parse_expr_all.parse2(quote!(-x ^ 2)).unwrap();
        assert!(matches!(e, Expr::Neg(..)));
        let e = parse_expr_all.parse2(quote!(a ^ b ^ c)).unwrap();
        match e {
            Expr::Pow { exp, .. } => assert!(matches!(*exp, Expr::Pow { .. })),
            _ => panic!("expected a power"),
        }
        let e = parse_expr_all.parse2(quote!(m * x ^ 2)).unwrap();
        match e {
            Expr::Chain { first, rest, .. } => {
                assert!(matches!(*first, Expr::Name(_)));
                assert!(matches!(rest[0], (BinOp::Mul, _, Expr::Pow { .. })));
            }
            _ => panic!("expected a product"),
        }
    }

    #[test]
    fn all_item_errors_are_collected() {
        let mut cx = Ctxt::new();
        let def = parse_system(
            quote!(struct S { parameters { m, } coordinates { x y } lagrangian = m * ; let a = 1 + ; }),
            &mut cx,
        );
        assert!(def.is_some());
        assert_eq!(cx.len(), 3, "{:?}", cx.errors());
    }
}
