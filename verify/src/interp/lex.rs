//! The expansion's tokens as a tree of plain tokens: identifiers without
//! their `r#`, multi-character operators joined, lifetimes as one token.

use proc_macro2::{Delimiter, Spacing, TokenStream, TokenTree};

/// A token.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Tok {
    /// An identifier or keyword (`r#` removed).
    Ident(String),
    /// An operator or punctuation (`::`, `+=`, `<`, ...).
    Punct(String),
    /// A literal as written (`0.5f64`, `3usize`, `"x"`).
    Lit(String),
    /// A lifetime (`'static`).
    Life(String),
    /// A delimited group (an invisible group becomes parentheses).
    Group(Delim, Vec<Tok>),
}

/// The delimiter of a group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Delim {
    Paren,
    Bracket,
    Brace,
}

/// The operators of more than one character, longest first. `>>` and `<<`
/// are left apart: generic argument lists close with them.
const OPS: &[&str] = &[
    "..=", "::", "->", "=>", "==", "!=", "<=", ">=", "&&", "||", "+=", "-=", "*=", "/=", "..",
];

/// The tokens of a stream.
pub(super) fn lex(ts: TokenStream) -> Vec<Tok> {
    let mut out = Vec::new();
    let mut run = String::new();
    let mut it = ts.into_iter().peekable();
    while let Some(tt) = it.next() {
        match tt {
            TokenTree::Punct(p) => {
                if p.as_char() == '\''
                    && let Some(TokenTree::Ident(id)) = it.peek()
                {
                    out.push(Tok::Life(format!("'{id}")));
                    it.next();
                    continue;
                }
                run.push(p.as_char());
                let joint = p.spacing() == Spacing::Joint;
                if !(joint && matches!(it.peek(), Some(TokenTree::Punct(_)))) {
                    split_ops(&run, &mut out);
                    run.clear();
                }
            }
            TokenTree::Ident(id) => out.push(Tok::Ident(unraw(&id.to_string()))),
            TokenTree::Literal(l) => out.push(Tok::Lit(l.to_string())),
            TokenTree::Group(g) => {
                let delim = match g.delimiter() {
                    Delimiter::Bracket => Delim::Bracket,
                    Delimiter::Brace => Delim::Brace,
                    Delimiter::Parenthesis | Delimiter::None => Delim::Paren,
                };
                out.push(Tok::Group(delim, lex(g.stream())));
            }
        }
    }
    out
}

/// A name without its raw prefix (`r#type` is `type`).
pub(super) fn unraw(s: &str) -> String {
    s.strip_prefix("r#").unwrap_or(s).to_string()
}

/// A run of joint punctuation split into operators, longest first.
fn split_ops(run: &str, out: &mut Vec<Tok>) {
    let mut rest = run;
    while let Some(c) = rest.chars().next() {
        let op = OPS
            .iter()
            .find(|op| rest.starts_with(**op))
            .map_or_else(|| c.to_string(), |op| (*op).to_string());
        rest = &rest[op.len()..];
        out.push(Tok::Punct(op));
    }
}

/// Tokens as text, cut after about `limit` characters.
pub(super) fn show(toks: &[Tok], limit: usize) -> String {
    let mut s = String::new();
    write_toks(toks, &mut s, limit);
    if s.len() > limit {
        let mut cut = limit;
        while !s.is_char_boundary(cut) {
            cut -= 1;
        }
        s.truncate(cut);
        s.push_str(" …");
    }
    s
}

fn write_toks(toks: &[Tok], s: &mut String, limit: usize) {
    for (i, t) in toks.iter().enumerate() {
        if s.len() > limit {
            return;
        }
        if i > 0 {
            s.push(' ');
        }
        match t {
            Tok::Ident(x) | Tok::Punct(x) | Tok::Lit(x) | Tok::Life(x) => s.push_str(x),
            Tok::Group(d, inner) => {
                let (open, close) = match d {
                    Delim::Paren => ('(', ')'),
                    Delim::Bracket => ('[', ']'),
                    Delim::Brace => ('{', '}'),
                };
                s.push(open);
                write_toks(inner, s, limit);
                s.push(close);
            }
        }
    }
}

/// An error with the statement it arose in (unless it names one already).
pub(super) fn in_stmt(e: String, stmt: &[Tok]) -> String {
    if e.contains("\n    in `") {
        e
    } else {
        format!("{e}\n    in `{}`", show(stmt, 300))
    }
}

/// An integer literal's value (`3usize`, `0`, `12i32`).
pub(super) fn lit_int(s: &str) -> Option<i64> {
    let digits = strip_suffix(
        s,
        &[
            "usize", "isize", "u32", "i32", "u64", "i64", "u8", "i8", "u16", "i16",
        ],
    );
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit() || c == '_') {
        return None;
    }
    digits.replace('_', "").parse().ok()
}

/// A floating-point literal's value (`0.5f64`, `4.0`, `1e-300f64`, `2f64`).
pub(super) fn lit_float(s: &str) -> Option<f64> {
    let body = strip_suffix(s, &["f64", "f32"]);
    let plain = body.replace('_', "");
    let is_float = plain.contains(['.', 'e', 'E']) || body.len() < s.len();
    if !is_float || plain.starts_with("0x") || plain.starts_with("0b") || plain.starts_with("0o") {
        return None;
    }
    plain.parse().ok()
}

/// A string literal's value (plain or raw; escapes of `\\`, `\"`, `\n`).
pub(super) fn lit_str(s: &str) -> Option<String> {
    if let Some(raw) = s.strip_prefix('r') {
        let hashes = raw.len() - raw.trim_start_matches('#').len();
        let inner = raw.get(hashes + 1..raw.len().checked_sub(hashes + 1)?)?;
        return Some(inner.to_string());
    }
    let inner = s.strip_prefix('"')?.strip_suffix('"')?;
    let mut out = String::new();
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next()? {
                'n' => out.push('\n'),
                't' => out.push('\t'),
                other => out.push(other),
            }
        } else {
            out.push(c);
        }
    }
    Some(out)
}

fn strip_suffix<'a>(s: &'a str, suffixes: &[&str]) -> &'a str {
    suffixes.iter().find_map(|x| s.strip_suffix(x)).unwrap_or(s)
}
