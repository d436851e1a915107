//! The expression grammar of the input language (DESIGN §2): sums,
//! products, powers, unary minus, calls, vectors and components, with
//! exact rational numbers.

use super::{BinOp, Expr};
use crate::ctxt::SpanRange;
use crate::names;
use crate::sym::Rational;
use proc_macro2::{Delimiter, Ident, Span, TokenTree};
use syn::Token;
use syn::ext::IdentExt;
use syn::parse::ParseStream;

/// Deepest expression nesting accepted; deeper input is a clear error rather
/// than a stack overflow.
pub const MAX_DEPTH: usize = 256;

/// Parses an expression that must use up the whole stream.
pub(super) fn parse_expr_all(input: ParseStream) -> syn::Result<Expr> {
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
pub(super) fn parse_expr(input: ParseStream, depth: usize) -> syn::Result<Expr> {
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
    use syn::parse::Parser;

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
}
