//! Parsing of the `nonholonomic_system!` input language (DESIGN §2) into a
//! surface syntax tree that keeps every token's span.
//!
//! The body of the struct is split into items before any item is parsed, and
//! each item (and each statement of a block) is parsed on its own, so a
//! syntax error in one item does not hide the errors in the others.

mod ast;
mod blocks;
mod expr;
mod items;

pub use ast::*;
pub use expr::MAX_DEPTH;

use crate::ctxt::Ctxt;
use crate::names;
use crate::words::{Block, Keyword};
use blocks::{parse_block, parse_fields};
use expr::parse_expr_all;
use items::{Item, split_items};
use proc_macro2::{Delimiter, Ident, Span, TokenStream, TokenTree};
use syn::ext::IdentExt;
use syn::parse::{ParseStream, Parser};
use syn::{Token, Visibility};

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
        symmetries: None,
        momenta: None,
        constraints: None,
        outputs: None,
        output_arguments: Vec::new(),
        dependent: None,
        speeds: None,
        kinematics: None,
        poisoned: Vec::new(),
        lagrangian_written: false,
        one_chart: false,
        euler_chart: false,
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
    let word = match toks.first() {
        Some(TokenTree::Ident(id)) => Keyword::of(id),
        _ => None,
    };
    !matches!(word, Some(Keyword::Let | Keyword::Lagrangian))
}

/// A statement: `lagrangian = ..;` or `let name = ..;`; whether it parsed.
fn parse_statement_item(toks: Vec<TokenTree>, def: &mut SystemDef, cx: &mut Ctxt) -> bool {
    if toks.is_empty() {
        return true;
    }
    match (&toks[0], toks.get(1)) {
        (TokenTree::Ident(kw), _) if *kw == Keyword::Lagrangian => def.lagrangian_written = true,
        (TokenTree::Ident(kw), Some(TokenTree::Ident(name))) if *kw == Keyword::Let => {
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
    if kw == Keyword::Lagrangian {
        let _: Token![=] = input
            .parse()
            .map_err(|e| syn::Error::new(e.span(), "expected `=` after `lagrangian`"))?;
        let value = parse_expr_all(input)?;
        return Ok(Statement::Lagrangian(kw, value));
    }
    let hint = names::suggest(&kw.to_string(), &[Keyword::Lagrangian.name()]);
    // every block but `dependent`, which only chooses the coordinates the
    // constraints are solved for
    let blocks: Vec<String> = Block::ALL
        .into_iter()
        .filter(|b| *b != Block::Dependent)
        .map(|b| format!("`{b} {{ .. }}`"))
        .collect();
    Err(syn::Error::new(
        kw.span(),
        format!(
            "unexpected `{kw}`{hint}: an item is `let NAME = ..;`, `lagrangian = ..;` or a block {}",
            blocks.join(", ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

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
