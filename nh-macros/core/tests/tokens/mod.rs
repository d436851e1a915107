//! Token helpers shared by the fuzz test, the one-swapped-token test and
//! the `expand` and `swaps` tools (`#[path]`-included by the examples).
#![allow(dead_code)]

use proc_macro2::{Delimiter, TokenStream, TokenTree};

/// Every `nonholonomic_system! { .. }` body in a token stream, at any depth.
pub fn find_invocations(ts: TokenStream, out: &mut Vec<TokenStream>) {
    let tokens: Vec<TokenTree> = ts.into_iter().collect();
    for (i, tt) in tokens.iter().enumerate() {
        if let TokenTree::Ident(id) = tt
            && id == "nonholonomic_system"
            && let Some(TokenTree::Punct(p)) = tokens.get(i + 1)
            && p.as_char() == '!'
            && let Some(TokenTree::Group(g)) = tokens.get(i + 2)
        {
            out.push(g.stream());
            continue;
        }
        if let TokenTree::Group(g) = tt {
            find_invocations(g.stream(), out);
        }
    }
}

/// The input as a flat list of token texts, groups as separate delimiters.
pub fn flatten(ts: TokenStream, out: &mut Vec<String>) {
    for tt in ts {
        match tt {
            TokenTree::Group(g) => {
                let (o, c) = match g.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Brace => ("{", "}"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::None => ("", ""),
                };
                out.push(o.to_string());
                flatten(g.stream(), out);
                out.push(c.to_string());
            }
            TokenTree::Punct(p) => out.push(p.as_char().to_string()),
            other => out.push(other.to_string()),
        }
    }
}

/// Byte range covered by the input's tokens.
pub fn extent(ts: &TokenStream) -> (usize, usize) {
    let mut lo = usize::MAX;
    let mut hi = 0;
    let mut stack: Vec<TokenTree> = ts.clone().into_iter().collect();
    while let Some(tt) = stack.pop() {
        let r = tt.span().byte_range();
        lo = lo.min(r.start);
        hi = hi.max(r.end);
        if let TokenTree::Group(g) = tt {
            stack.extend(g.stream());
        }
    }
    (lo, hi)
}
