//! The blocks of a definition (`parameters { .. }`, `constraints { .. }`,
//! ...) and the fields of a `body`, each line or field parsed on its own so
//! that one error does not hide the others.

use super::expr::{parse_expr, parse_expr_all};
use super::{Constraint, ContactKind, Field, Force, RollingDef, Symmetry, SystemDef};
use crate::ctxt::{Ctxt, SpanRange};
use crate::names;
use crate::words::{Block, Keyword, Output, Spelled, and_list};
use proc_macro2::{Group, Ident, Span, TokenTree};
use syn::Token;
use syn::ext::IdentExt;
use syn::parse::{ParseStream, Parser};

/// The names a block of names that failed to parse was meant to declare:
/// each identifier, and a placeholder for each comma-separated entry with
/// none (`parameters { m, 2 }` meant two parameters).
fn names_meant(group: &Group) -> Vec<Ident> {
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

/// A block `kw { .. }`.
pub(super) fn parse_block(kw: Ident, group: &Group, def: &mut SystemDef, cx: &mut Ctxt) {
    let Some(block) = Block::of(&kw) else {
        let which = kw.to_string();
        let hint = Block::suggest(&which);
        reject_misspelled_block(&which, group, def);
        cx.error_at(
            kw.span(),
            format!(
                "unknown block `{which}`{hint}; the blocks are {}",
                and_list(Block::ALL.map(Block::name))
            ),
        );
        return;
    };
    match block {
        Block::Kinematics => {
            let list = parse_each(group, parse_kinematics_line, headless_equation, cx);
            def.rejected.kinematics_lines += split_statements(group).len() - list.len();
            set_once(&mut def.kinematics, kw, list, cx, |_| {
                "duplicate `kinematics` block: write one line per coordinate in one block"
                    .to_string()
            });
        }
        Block::Constraints => parse_constraints(kw, group, def, cx),
        Block::Forces => {
            let list = parse_each(group, parse_force, headless_force, cx);
            set_once(&mut def.forces, kw, list, cx, |_| {
                "duplicate `forces` block: write all forces in one block".to_string()
            });
        }
        Block::Outputs => parse_outputs_block(kw, group, def, cx),
        Block::Symmetries => {
            let list = parse_each(group, parse_symmetry, headless_force, cx);
            set_once(&mut def.symmetries, kw, list, cx, |_| {
                "duplicate `symmetries` block: write all symmetries in one block".to_string()
            });
        }
        Block::Momenta => {
            let list = parse_each(group, parse_momentum, headless_force, cx);
            set_once(&mut def.momenta, kw, list, cx, |_| {
                "duplicate `momenta` block: write all momenta in one block".to_string()
            });
        }
        Block::Parameters
        | Block::Coordinates
        | Block::Inputs
        | Block::Speeds
        | Block::Dependent => parse_name_block(block, kw, group, def, cx),
    }
}

/// `constraints { .. }`: its equations and rolling contacts.
fn parse_constraints(kw: Ident, group: &Group, def: &mut SystemDef, cx: &mut Ctxt) {
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

/// What a misspelled block (`constraint { .. }`) was meant to declare, for
/// the stand-in: the names of a block of names, or the number of lines of
/// `constraints`.
fn reject_misspelled_block(which: &str, group: &Group, def: &mut SystemDef) {
    match Block::closest(which) {
        Some(Block::Constraints) => {
            def.rejected.constraint_lines += split_statements(group).len();
        }
        Some(
            block @ (Block::Parameters
            | Block::Coordinates
            | Block::Inputs
            | Block::Speeds
            | Block::Outputs),
        ) => reject_names(block, group, def),
        _ => {}
    }
}

/// Records what a rejected block of names was meant to declare (the first
/// rejected `outputs` block's outputs).
fn reject_names(block: Block, group: &Group, def: &mut SystemDef) {
    let names = names_meant(group);
    if block == Block::Outputs {
        let outputs = names.into_iter().map(Spelled::new).collect();
        def.rejected.outputs.get_or_insert(outputs);
    } else {
        def.rejected.names.push((block, names));
    }
}

/// A block of names that did not parse: its error, and the names it meant
/// to declare, which must not cause follow-up errors.
fn reject_name_block(
    error: syn::Error,
    block: Block,
    group: &Group,
    def: &mut SystemDef,
    cx: &mut Ctxt,
) {
    cx.syn_error(error);
    for tt in group.stream() {
        if let TokenTree::Ident(id) = tt {
            def.poisoned.push(names::canonical(id));
        }
    }
    reject_names(block, group, def);
}

/// A block of names: `parameters`, `coordinates`, `inputs`, `speeds` or
/// `dependent`.
fn parse_name_block(block: Block, kw: Ident, group: &Group, def: &mut SystemDef, cx: &mut Ctxt) {
    let list = match parse_name_list.parse2(group.stream()) {
        Ok(n) => n,
        Err(e) => return reject_name_block(e, block, group, def, cx),
    };
    // a keyword is reported here, once, at the name; it stays
    // declared, so its uses raise no follow-up errors
    let kind = match block {
        Block::Parameters => Some("a parameter"),
        Block::Coordinates => Some("a coordinate"),
        Block::Inputs => Some("an input"),
        Block::Speeds => Some("a speed"),
        _ => None,
    };
    for id in &list {
        if let Some(msg) = kind.and_then(|k| names::keyword_problem(id, k)) {
            cx.error_at(id.span(), msg);
        }
    }
    if let Some(slot) = def.names_block(block) {
        set_once(slot, kw, list, cx, duplicate_names(block));
    }
}

/// `outputs { .. }`: the outputs, and the lists of names some are written
/// with.
fn parse_outputs_block(kw: Ident, group: &Group, def: &mut SystemDef, cx: &mut Ctxt) {
    let list = match parse_output_list.parse2(group.stream()) {
        Ok((names, arguments)) => {
            if def.outputs.is_none() {
                def.output_arguments = arguments;
            }
            names
        }
        Err(e) => return reject_name_block(e, Block::Outputs, group, def, cx),
    };
    set_once(
        &mut def.outputs,
        kw,
        list,
        cx,
        duplicate_names(Block::Outputs),
    );
}

/// The error at a second block of names of its kind, given the first's
/// keyword.
fn duplicate_names(block: Block) -> impl FnOnce(&Ident) -> String {
    move |prev| format!("duplicate `{block}` block: list all names in the first `{prev}` block")
}

/// Each `;`-separated statement of a block parsed by `parser`; the errors
/// into `cx`. One token moved across the `;` between two statements (the
/// last of one to the start of the next, or back) is put back, with the
/// first statement's error only; a statement that cannot start a line
/// (`headless`) right after one with an error is taken as its rest, whose
/// error covers it.
fn parse_each<T>(
    group: &Group,
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
        TokenTree::Ident(id) => *id == Keyword::Rolls,
        TokenTree::Group(g) => g
            .stream()
            .into_iter()
            .next()
            .is_some_and(|f| matches!(f, TokenTree::Ident(id) if id == Keyword::Rolls)),
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

/// The `;`-separated statements of a block, each ending in its `;` (the last
/// one, which may omit it, gets one at the closing brace) so that an error
/// at the end of a statement points into the source, not at the macro call.
fn split_statements(group: &Group) -> Vec<(Vec<TokenTree>, Span)> {
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
fn parse_output_list(
    input: ParseStream,
) -> syn::Result<(Vec<Spelled<Output>>, Vec<(Spelled<Output>, Vec<Ident>)>)> {
    let mut names = Vec::new();
    let mut arguments = Vec::new();
    while !input.is_empty() {
        let id: Ident = input.call(IdentExt::parse_any).map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected the name of an output: this block is a comma-separated list of outputs, such as `energy, jacobian` or `sensitivities(m, k)`",
            )
        })?;
        let id = Spelled::new(names::canonical(id));
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
    let is_rolling = fork
        .call(Ident::parse_any)
        .is_ok_and(|id| id == Keyword::Rolls || id == Keyword::Skates || id == Keyword::Slides)
        && fork.peek(syn::token::Paren);
    if is_rolling {
        return parse_rolling(input).map(Line::Rolling);
    }
    parse_constraint(input).map(Line::Equation)
}

/// `rolls(BODY, name: expr, ..);`, `skates(BODY, name: expr, ..);` or
/// `slides(BODY, name: expr, ..);`
fn parse_rolling(input: ParseStream) -> syn::Result<RollingDef> {
    let kw: Ident = input.call(IdentExt::parse_any)?;
    let kind = if kw == Keyword::Skates {
        ContactKind::Skates
    } else if kw == Keyword::Slides {
        ContactKind::Slides
    } else {
        ContactKind::Rolls
    };
    let content;
    let paren = syn::parenthesized!(content in input);
    let body: Ident = content.call(IdentExt::parse_any).map_err(|e| {
        let example = match kind {
            ContactKind::Skates => {
                "expected the skating body's name: `skates(sled, across: [0, 1, 0]);`"
            }
            ContactKind::Slides => {
                "expected the sliding body's name: `slides(top, at: [0, 0, -l]);`"
            }
            ContactKind::Rolls => {
                "expected the rolling body's name: `rolls(wheel, radius: r, axle: [0, 1, 0]);`"
            }
        };
        syn::Error::new(e.span(), example)
    })?;
    let mut fields = Vec::new();
    while !content.is_empty() {
        let _: Token![,] = content.parse().map_err(|e| {
            syn::Error::new(
                e.span(),
                format!("expected `,` between the arguments of `{kw}`"),
            )
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
        return Err(input.error(format!(
            "unexpected tokens after `{kw}(..)`: end the line with `;`"
        )));
    }
    Ok(RollingDef {
        kind,
        range: SpanRange {
            first: kw.span(),
            last: paren.span.close(),
        },
        body: names::canonical(body),
        fields,
        position: 0,
    })
}

/// `name: expr`, or `name: lhs = rhs` (a surface's equation)
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
    let equals = if input.peek(Token![=]) && !input.peek(Token![==]) {
        let _: Token![=] = input.parse()?;
        Some(parse_expr(input, 0)?)
    } else {
        None
    };
    Ok(Field {
        name,
        value,
        equals,
    })
}

/// The comma-separated `name: expr` fields of a `body` item, each parsed on
/// its own so that one error does not hide the others; and whether one did
/// not parse.
pub(super) fn parse_fields(group: &Group, cx: &mut Ctxt) -> (Vec<Field>, bool) {
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

/// `NAME(q: ξ_q, ..)`: a one-parameter symmetry group by its generator.
fn parse_symmetry(input: ParseStream) -> syn::Result<Symmetry> {
    parse_generator(
        input,
        (
            "symmetry",
            "a symmetry is written `NAME(q: rate, ..);`, the rate at which each coordinate it moves changes along the group (`turn(x: -y, y: x, phi: 1);`)",
        ),
    )
}

fn parse_momentum(input: ParseStream) -> syn::Result<Symmetry> {
    parse_generator(
        input,
        (
            "momentum",
            "a momentum is written `NAME(q: rate, ..);`, the direction it is the momentum along: the rate of each coordinate the motion moves, or the fixed axis a rotation turns about (`K_x(Q: [1, 0, 0], y: -R);`)",
        ),
    )
}

/// `NAME(q: rate, ..);`, a symmetry's generator or a momentum's direction:
/// `(what, form)` name it in messages.
fn parse_generator(input: ParseStream, (what, form): (&str, &str)) -> syn::Result<Symmetry> {
    let name: Ident = input
        .call(IdentExt::parse_any)
        .map_err(|e| syn::Error::new(e.span(), format!("expected the {what}'s name: {form}")))?;
    let content;
    syn::parenthesized!(content in input);
    let mut generator = Vec::new();
    while !content.is_empty() {
        let q: Ident = content.call(IdentExt::parse_any).map_err(|e| {
            syn::Error::new(e.span(), format!("expected a coordinate name: {form}"))
        })?;
        let _: Token![:] = content
            .parse()
            .map_err(|e| syn::Error::new(e.span(), format!("expected `:` after `{q}`: {form}")))?;
        let value = parse_expr(&content, 0)?;
        generator.push((names::canonical(q), value));
        if content.is_empty() {
            break;
        }
        let _: Token![,] = content.parse()?;
    }
    let _: Token![;] = input
        .parse()
        .map_err(|e| syn::Error::new(e.span(), format!("expected `;` after the {what}: {form}")))?;
    Ok(Symmetry {
        name: names::canonical(name),
        generator,
    })
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
