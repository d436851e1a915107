//! The body of the struct split into items, before any item is parsed.
//!
//! An item starts at `let`, at `lagrangian =`, at `body NAME { .. }` and at
//! a block keyword followed by its braces (or any name followed by braces
//! where an item is expected), and a statement ends at its `;` or where the
//! next item starts: a missing `;` costs one error, not the next item.
//!
//! One misplaced token at an item's header (the mistake of swapping two
//! neighbouring tokens) is put back where it belongs, with one error at it,
//! so that the item is still read and nothing it declares is reported again
//! at its uses: a block's name inside its braces (`{ parameters m, g }`) or
//! a token between the name and the braces (`parameters m { , g }`), the
//! next item's first word inside the braces before it (`{ .., y let } X =`),
//! a name left after the braces of a list (`{ m, } g`), a `;` after the word
//! that starts the next item (`.. let ; X =`), and the name and `=` of `let`,
//! `lagrangian` and `body` in the wrong order.

use crate::ctxt::Ctxt;
use crate::names;
use crate::words::{Block, Keyword};
use proc_macro2::{Delimiter, Group, Ident, Punct, Spacing, Span, TokenStream, TokenTree};

/// One top-level item of the body.
pub(super) enum Item {
    /// `keyword { .. }`
    Block(Ident, Group),
    /// `body NAME { .. }`
    Body(Ident, Group),
    /// tokens up to and with their `;`
    Statement(Vec<TokenTree>),
    /// tokens of a statement cut where the next item starts: its `;` is
    /// missing (a sentinel `;` at its last token is appended)
    Unterminated(Vec<TokenTree>),
}

/// The most misplaced tokens put back in one system.
const MAX_REPAIRS: usize = 32;

fn is_block_keyword(t: &TokenTree) -> bool {
    matches!(t, TokenTree::Ident(id) if Block::of(id).is_some())
}

fn is_word(t: Option<&TokenTree>, word: Keyword) -> bool {
    matches!(t, Some(TokenTree::Ident(id)) if *id == word)
}

fn is_punct(t: Option<&TokenTree>, c: char) -> bool {
    matches!(t, Some(TokenTree::Punct(p)) if p.as_char() == c)
}

fn is_ident(t: Option<&TokenTree>) -> bool {
    matches!(t, Some(TokenTree::Ident(_)))
}

fn brace(t: Option<&TokenTree>) -> Option<&Group> {
    match t {
        Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => Some(g),
        _ => None,
    }
}

/// A group with other contents, keeping the original's span.
fn regroup(g: &Group, tokens: Vec<TokenTree>) -> Group {
    let mut out = Group::new(g.delimiter(), tokens.into_iter().collect());
    out.set_span(g.span());
    out
}

/// A `;` at `span`.
fn semicolon(span: Span) -> TokenTree {
    let mut semi = Punct::new(';', Spacing::Alone);
    semi.set_span(span);
    TokenTree::Punct(semi)
}

/// Whether the tokens at `i` start an item: `let`, `lagrangian =`,
/// `body NAME { .. }`, or a block keyword followed by its braces (any name
/// followed by braces, `at_start` of an item).
fn starts_item(toks: &[TokenTree], i: usize, at_start: bool) -> bool {
    let t = &toks[i];
    let next = toks.get(i + 1);
    match t {
        TokenTree::Ident(id) if *id == Keyword::Let => true,
        TokenTree::Ident(id) if *id == Keyword::Lagrangian => is_punct(next, '='),
        TokenTree::Ident(id) if *id == Keyword::Body && is_ident(next) => {
            brace(toks.get(i + 2)).is_some()
        }
        TokenTree::Ident(_) => brace(next).is_some() && (at_start || is_block_keyword(t)),
        _ => false,
    }
}

/// Whether `toks[at..]` can follow an item's first word: the word after
/// `let` is a name, `lagrangian` takes `=`, a block keyword its braces,
/// `body` a name (not a word of the language) and braces.
fn fits_after(word: &TokenTree, toks: &[TokenTree], at: usize) -> bool {
    let next = toks.get(at);
    match word {
        TokenTree::Ident(id) if *id == Keyword::Let => is_ident(next),
        TokenTree::Ident(id) if *id == Keyword::Lagrangian => is_punct(next, '='),
        TokenTree::Ident(id) if *id == Keyword::Body => {
            next.is_some_and(|n| is_ident(Some(n)) && !is_item_word(n))
                && brace(toks.get(at + 1)).is_some()
        }
        t if is_block_keyword(t) => brace(next).is_some(),
        _ => false,
    }
}

/// Whether a token is a word that starts an item (`let`, `lagrangian`,
/// `body` or a block keyword).
fn is_item_word(t: &TokenTree) -> bool {
    matches!(t, TokenTree::Ident(id) if Keyword::of(id).is_some_and(Keyword::starts_item))
        || is_block_keyword(t)
}

/// Splits the body into items, putting one misplaced token at an item's
/// header back where it belongs (with one error at it).
pub(super) fn split_items(stream: TokenStream, cx: &mut Ctxt) -> Vec<Item> {
    let mut toks: Vec<TokenTree> = stream.into_iter().collect();
    let mut items = Vec::new();
    let mut cur: Vec<TokenTree> = Vec::new();
    let mut i = 0;
    // every repair reports an error; a bound on them bounds the work on any
    // input (a repair never undoes another, but the bound does not rely on it)
    let mut repairs = 0;
    while i < toks.len() {
        if repairs < MAX_REPAIRS && repair(&mut toks, i, &mut cur, &mut items, cx) {
            repairs += 1;
            continue;
        }
        let at_start = cur.is_empty();
        if starts_item(&toks, i, at_start) {
            if !cur.is_empty() {
                items.push(unterminated(std::mem::take(&mut cur)));
            }
            let t = toks[i].clone();
            match (&t, toks.get(i + 1).cloned(), toks.get(i + 2).cloned()) {
                (TokenTree::Ident(kw), Some(TokenTree::Ident(name)), Some(TokenTree::Group(g)))
                    if *kw == Keyword::Body =>
                {
                    items.push(Item::Body(names::canonical(name), g));
                    i += 3;
                }
                (TokenTree::Ident(kw), Some(TokenTree::Group(g)), _)
                    if *kw != Keyword::Let && *kw != Keyword::Lagrangian =>
                {
                    items.push(Item::Block(kw.clone(), g));
                    i += 2;
                }
                _ => {
                    cur.push(t);
                    i += 1;
                    continue;
                }
            }
            // a stray `;` after a block is harmless
            if is_punct(toks.get(i), ';') {
                i += 1;
            }
            continue;
        }
        let t = toks[i].clone();
        i += 1;
        match &t {
            TokenTree::Punct(p) if p.as_char() == ';' => {
                if !cur.is_empty() {
                    // the `;` stays in the statement: an error at its end points at it
                    cur.push(t);
                    items.push(Item::Statement(std::mem::take(&mut cur)));
                }
            }
            _ => cur.push(t),
        }
    }
    if !cur.is_empty() {
        items.push(unterminated(cur));
    }
    items
}

/// A statement cut where the next item starts, with a sentinel `;` at its
/// last token (an error at its end points into the source).
fn unterminated(mut cur: Vec<TokenTree>) -> Item {
    if let Some(last) = cur.last() {
        let span = last.span();
        cur.push(semicolon(span));
    }
    Item::Unterminated(cur)
}

/// Where a misplaced token may be put back: the tokens, the position, the
/// statement read so far and the items before it.
struct Site<'a> {
    toks: &'a mut Vec<TokenTree>,
    i: usize,
    cur: &'a mut Vec<TokenTree>,
    items: &'a mut Vec<Item>,
    cx: &'a mut Ctxt,
}

/// Puts one misplaced token at position `i` back (rewriting `toks`) with an
/// error at it; whether it did. `cur` holds the statement read so far, and
/// `items` the items before. The repairs are tried in order; the first that
/// applies is made.
fn repair(
    toks: &mut Vec<TokenTree>,
    i: usize,
    cur: &mut Vec<TokenTree>,
    items: &mut Vec<Item>,
    cx: &mut Ctxt,
) -> bool {
    let mut site = Site {
        toks,
        i,
        cur,
        items,
        cx,
    };
    let t = site.toks[i].clone();
    let next = site.toks.get(i + 1).cloned();
    REPAIRS
        .iter()
        .any(|rule| rule(&mut site, &t, next.as_ref()))
}

/// A repair: at the site, with its token `t` and the one after, `next`.
type Rule = fn(&mut Site, &TokenTree, Option<&TokenTree>) -> bool;

/// The repairs of [`repair`], in the order they are tried.
const REPAIRS: [Rule; 10] = [
    semicolon_after_next_word,
    block_name_inside_braces,
    token_before_braces,
    next_word_inside_braces,
    name_after_braces,
    name_before_let,
    equals_before_name,
    equals_before_lagrangian,
    body_name_before_body,
    body_name_inside_braces,
];

/// `.. x let ; Y = ..`: the `;` of the item before went after the next
/// item's first word
fn semicolon_after_next_word(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if !cur.is_empty() && is_item_word(t) && is_punct(next, ';') && fits_after(t, toks, i + 2) {
        let span = toks[i + 1].span();
        cx.error_at(
            span,
            format!("this `;` ends the item before `{t}`: write it before `{t}`"),
        );
        toks.swap(i, i + 1);
        return true;
    }
    false
}

/// `{ parameters m, g }`: the block's name inside its braces
fn block_name_inside_braces(site: &mut Site, t: &TokenTree, _next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if cur.is_empty()
        && let Some(g) = brace(Some(t))
    {
        let inner: Vec<TokenTree> = g.stream().into_iter().collect();
        if let Some(kw) = inner.first().filter(|k| is_block_keyword(k)) {
            cx.error_at(
                kw.span(),
                format!("the name of a block comes before its braces: write `{kw} {{ .. }}`"),
            );
            let group = regroup(g, inner[1..].to_vec());
            toks.splice(i..=i, [kw.clone(), TokenTree::Group(group)]);
            return true;
        }
    }
    false
}

/// `parameters m { , g }`: a token between a block's name and its braces
/// (`body wheel m { ass: .. }` alike: a token between the body's name
/// and its braces)
fn token_before_braces(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    let (head, at) = if is_word(Some(t), Keyword::Body) && is_ident(next) {
        (i + 1, i + 2)
    } else {
        (i, i + 1)
    };
    if cur.is_empty()
        && (is_block_keyword(t) || head == i + 1)
        && let Some(stray) = toks.get(at).cloned()
        && !is_item_word(&stray)
        && !matches!(stray, TokenTree::Group(_))
        && let Some(g) = brace(toks.get(at + 1)).cloned()
    {
        let t = toks[head].clone();
        let i = head;
        if is_punct(Some(&stray), ';') {
            cx.error_at(
                stray.span(),
                format!("this `;` ends the item before `{t}`: write it before `{t}`"),
            );
            toks.remove(i + 1);
            return true;
        }
        cx.error_at(
            stray.span(),
            format!("`{stray}` stands between `{t}` and its `{{`: move it inside the braces"),
        );
        let mut inner = vec![stray];
        inner.extend(g.stream());
        toks.splice(i + 1..=i + 2, [TokenTree::Group(regroup(&g, inner))]);
        return true;
    }
    false
}

/// a block whose braces end with the next item's first word:
/// `coordinates { x, y let } X = ..`
fn next_word_inside_braces(site: &mut Site, t: &TokenTree, _next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    let at = if is_word(Some(t), Keyword::Body) {
        i + 2
    } else {
        i + 1
    };
    if starts_item(toks, i, cur.is_empty())
        && let TokenTree::Ident(_) = &t
        && let Some(g) = brace(toks.get(at)).cloned()
    {
        let inner: Vec<TokenTree> = g.stream().into_iter().collect();
        if let Some(word) = inner.last().filter(|w| is_item_word(w))
            && fits_after(word, toks, at + 1)
        {
            let owner = if at == i + 2 {
                format!("body {}", toks[i + 1])
            } else {
                t.to_string()
            };
            cx.error_at(
                word.span(),
                format!(
                    "`{word}` is inside the braces of `{owner} {{ .. }}`: close them before it"
                ),
            );
            let word = word.clone();
            let group = regroup(&g, inner[..inner.len() - 1].to_vec());
            toks.splice(at..=at, [TokenTree::Group(group), word]);
            return true;
        }
    }
    false
}

/// `parameters { m, } g coordinates { .. }`: a name after the braces of
/// a list of names
fn name_after_braces(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks,
        i,
        cur,
        items,
        cx,
        ..
    } = site;
    let i = *i;
    if cur.is_empty()
        && let TokenTree::Ident(stray) = &t
        && !is_item_word(t)
        && brace(next).is_none()
        && let Some(Item::Block(kw, g)) = items.last()
        && Block::of(kw).is_some_and(Block::lists_names)
    {
        // the names up to the next item
        let mut end = i;
        while end < toks.len()
            && !starts_item(toks, end, false)
            && (is_ident(toks.get(end)) || is_punct(toks.get(end), ','))
        {
            end += 1;
        }
        let ends_here = end == toks.len() || starts_item(toks, end, false);
        // `X let = ..` is the name of the `let`
        let let_name = is_word(toks.get(end), Keyword::Let) && is_punct(toks.get(end + 1), '=');
        if ends_here && !let_name {
            cx.error_at(
                stray.span(),
                format!("`{stray}` is after the braces of `{kw} {{ .. }}`: move it inside them"),
            );
            let mut inner: Vec<TokenTree> = g.stream().into_iter().collect();
            let ends_in_comma = inner.last().is_none_or(|l| is_punct(Some(l), ','));
            if !ends_in_comma && !is_punct(toks.get(i), ',') {
                let mut comma = Punct::new(',', Spacing::Alone);
                comma.set_span(stray.span());
                inner.push(TokenTree::Punct(comma));
            }
            inner.extend(toks[i..end].iter().cloned());
            let group = regroup(g, inner);
            // the block is read again with the names
            let kw = kw.clone();
            items.pop();
            toks.splice(i..end, [TokenTree::Ident(kw), TokenTree::Group(group)]);
            return true;
        }
    }
    false
}

/// `X let = ..`: the name before `let`
fn name_before_let(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if let [name @ TokenTree::Ident(_)] = cur.as_slice()
        && !is_item_word(name)
        && is_word(Some(t), Keyword::Let)
        && is_punct(next, '=')
    {
        cx.error_at(
            name.span(),
            format!("the name comes after `let`: write `let {name} = ..`"),
        );
        let name = cur.remove(0);
        toks.insert(i + 1, name);
        return true;
    }
    false
}

/// `let = X ..`: `=` before the name
fn equals_before_name(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site { toks, i, cx, .. } = site;
    let i = *i;
    if is_word(Some(t), Keyword::Let)
        && is_punct(next, '=')
        && toks
            .get(i + 2)
            .is_some_and(|n| is_ident(Some(n)) && !is_item_word(n))
    {
        let name = toks[i + 2].clone();
        cx.error_at(
            toks[i + 1].span(),
            format!("`=` comes after the name: write `let {name} = ..`"),
        );
        toks.swap(i + 1, i + 2);
        return true;
    }
    false
}

/// `= lagrangian ..`
fn equals_before_lagrangian(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if cur.is_empty() && is_punct(Some(t), '=') && is_word(next, Keyword::Lagrangian) {
        cx.error_at(
            t.span(),
            "`=` comes after `lagrangian`: write `lagrangian = ..`",
        );
        toks.swap(i, i + 1);
        return true;
    }
    false
}

/// `wheel body { .. }`: the body's name before `body`
fn body_name_before_body(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if cur.is_empty()
        && let TokenTree::Ident(name) = &t
        && !is_item_word(t)
        && is_word(next, Keyword::Body)
        && brace(toks.get(i + 2)).is_some()
    {
        cx.error_at(
            name.span(),
            format!("the body's name comes after `body`: write `body {name} {{ .. }}`"),
        );
        toks.swap(i, i + 1);
        return true;
    }
    false
}

/// `body { wheel mass: m, .. }`: the body's name inside its braces
fn body_name_inside_braces(site: &mut Site, t: &TokenTree, next: Option<&TokenTree>) -> bool {
    let Site {
        toks, i, cur, cx, ..
    } = site;
    let i = *i;
    if cur.is_empty()
        && is_word(Some(t), Keyword::Body)
        && let Some(g) = brace(next).cloned()
    {
        let inner: Vec<TokenTree> = g.stream().into_iter().collect();
        if let Some(TokenTree::Ident(name)) = inner.first()
            && !is_item_word(&inner[0])
            && !is_punct(inner.get(1), ':')
        {
            cx.error_at(
                name.span(),
                format!("the body's name comes before its braces: write `body {name} {{ .. }}`"),
            );
            let name = inner[0].clone();
            let group = regroup(&g, inner[1..].to_vec());
            toks.splice(i + 1..=i + 1, [name, TokenTree::Group(group)]);
            return true;
        }
    }
    false
}
