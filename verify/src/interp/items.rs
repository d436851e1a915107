//! The items of an expansion: the constants of `impl NAME<f64>` and the
//! methods of `impl<T> NAME<T>` and of the trait impls for `NAME<T>`, found
//! at any depth (they sit inside `const _: () = { .. };`).

use super::lex::{Delim, Tok, lit_str, show};

/// A method's tokens: its name, its signature (after the name, before the
/// body) and its body's contents.
pub(super) struct FnSrc<'t> {
    pub name: String,
    pub sig: &'t [Tok],
    pub body: &'t [Tok],
}

/// What an expansion defines.
#[derive(Default)]
pub(super) struct Items<'t> {
    /// The system's name (from `impl NAME<f64>`).
    pub name: Option<String>,
    /// The constants of `impl NAME<f64>`: name and value tokens.
    pub consts: Vec<(String, &'t [Tok])>,
    /// The methods of the generic inherent impl.
    pub inherent: Vec<FnSrc<'t>>,
    /// The methods of the trait impls, with the first name after `for`.
    pub traits: Vec<(String, FnSrc<'t>)>,
    /// The message of a `compile_error!` in the expansion, if any.
    pub compile_error: Option<String>,
}

/// The items of the token list (searching every brace group).
pub(super) fn scan<'t>(toks: &'t [Tok], out: &mut Items<'t>) {
    let mut i = 0;
    while i < toks.len() {
        match &toks[i] {
            Tok::Ident(w) if w == "impl" => i = impl_block(toks, i + 1, out),
            Tok::Ident(w) if w == "compile_error" => {
                out.compile_error
                    .get_or_insert_with(|| show(&toks[i..], 400));
                i += 1;
            }
            Tok::Group(_, inner) => {
                scan(inner, out);
                i += 1;
            }
            _ => i += 1,
        }
    }
}

/// The impl whose header starts at `i`; returns the index after its body.
fn impl_block<'t>(toks: &'t [Tok], i: usize, out: &mut Items<'t>) -> usize {
    let Some(open) = (i..toks.len()).find(|&j| matches!(toks[j], Tok::Group(Delim::Brace, _)))
    else {
        return toks.len();
    };
    let Tok::Group(_, body) = &toks[open] else {
        return open + 1;
    };
    let header = &toks[i..open];
    if header.iter().any(is_hidden_chart) {
        // another chart of the system's atlas: a system of its own
        return open + 1;
    }
    let is_for = |t: &Tok| matches!(t, Tok::Ident(w) if w == "for");
    if let Some(at) = header.iter().position(is_for) {
        let target = match header.get(at + 1) {
            Some(Tok::Ident(name)) => name.clone(),
            _ => String::new(),
        };
        out.traits
            .extend(methods(body).into_iter().map(|f| (target.clone(), f)));
    } else if header
        .iter()
        .any(|t| matches!(t, Tok::Ident(w) if w == "f64"))
    {
        out.name = self_name(header);
        out.consts.extend(consts(body));
    } else {
        out.inherent.extend(methods(body));
    }
    open + 1
}

/// Whether `t` names one of the hidden systems of an atlas's other charts,
/// `__nh_{Name}_chart{c}`.
fn is_hidden_chart(t: &Tok) -> bool {
    let Tok::Ident(w) = t else { return false };
    w.starts_with("__nh_")
        && w.rsplit_once("_chart")
            .is_some_and(|(_, c)| !c.is_empty() && c.bytes().all(|b| b.is_ascii_digit()))
}

/// `NAME` in `impl NAME<f64>`.
fn self_name(header: &[Tok]) -> Option<String> {
    match header.first() {
        Some(Tok::Ident(name)) => Some(name.clone()),
        _ => None,
    }
}

/// The tokens from `i` up to the next `;` (exclusive) and the index after it.
fn until_semi(toks: &[Tok], i: usize) -> (&[Tok], usize) {
    let end = (i..toks.len())
        .find(|&j| matches!(&toks[j], Tok::Punct(p) if p == ";"))
        .unwrap_or(toks.len());
    (&toks[i..end], end + 1)
}

/// The `const NAME: TY = VALUE;` items of an impl body.
fn consts(body: &[Tok]) -> Vec<(String, &[Tok])> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < body.len() {
        if let (Tok::Ident(k), Some(Tok::Ident(name))) = (&body[i], body.get(i + 1))
            && k == "const"
            && name != "fn"
        {
            let (item, next) = until_semi(body, i + 2);
            let eq = item
                .iter()
                .position(|t| matches!(t, Tok::Punct(p) if p == "="));
            if let Some(eq) = eq {
                out.push((name.clone(), &item[eq + 1..]));
            }
            i = next;
        } else {
            i += 1;
        }
    }
    out
}

/// The `fn` items of an impl body.
fn methods(body: &[Tok]) -> Vec<FnSrc<'_>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < body.len() {
        let is_fn = matches!(&body[i], Tok::Ident(w) if w == "fn");
        if let (true, Some(Tok::Ident(name))) = (is_fn, body.get(i + 1)) {
            let open =
                (i + 2..body.len()).find(|&j| matches!(body[j], Tok::Group(Delim::Brace, _)));
            let Some(open) = open else {
                return out;
            };
            if let Tok::Group(_, inner) = &body[open] {
                out.push(FnSrc {
                    name: name.clone(),
                    sig: &body[i + 2..open],
                    body: inner,
                });
            }
            i = open + 1;
        } else {
            i += 1;
        }
    }
    out
}

/// The strings of a constant `["a", "b"]`.
pub(super) fn const_strs(value: &[Tok]) -> Option<Vec<String>> {
    const_list(value, lit_str)
}

/// The integers of a constant `[0usize, 2usize]`.
pub(super) fn const_ints(value: &[Tok]) -> Option<Vec<usize>> {
    const_list(value, |l| {
        super::lex::lit_int(l).and_then(|n| usize::try_from(n).ok())
    })
}

/// The last name of each path of a constant `[a::B, a::C]` (`CONSERVED`'s
/// variants).
pub(super) fn const_variants(value: &[Tok]) -> Option<Vec<String>> {
    let [Tok::Group(Delim::Bracket, inner)] = value else {
        return None;
    };
    inner
        .split(|t| matches!(t, Tok::Punct(p) if p == ","))
        .filter(|path| !path.is_empty())
        .map(|path| match path.last() {
            Some(Tok::Ident(name)) => Some(name.clone()),
            _ => None,
        })
        .collect()
}

fn const_list<X>(value: &[Tok], f: impl Fn(&str) -> Option<X>) -> Option<Vec<X>> {
    let [Tok::Group(Delim::Bracket, inner)] = value else {
        return None;
    };
    inner
        .iter()
        .filter(|t| !matches!(t, Tok::Punct(p) if p == ","))
        .map(|t| match t {
            Tok::Lit(l) => f(l),
            _ => None,
        })
        .collect()
}
