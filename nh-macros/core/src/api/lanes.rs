//! Which generated methods evaluate one state per lane (DESIGN §6.8):
//! a method whose body is straight-line arithmetic compiles for every
//! `T: nh_runtime::Lanes` (a SIMD scalar as well as `f64`), since the body
//! calls the elementary functions by the names `Lanes` gives them. A body
//! with a branch on a value, a loop or an ordered comparison (the sign
//! function, the projection's Newton loop, a chart's test) needs
//! `RealField` and stays in the scalar impl.

use proc_macro2::{TokenStream, TokenTree};

/// What a body may not contain to run in lanes: control flow over values
/// and the operations of `RealField` that `SimdRealField` lacks.
const SCALAR_ONLY: &[&str] = &[
    "for",
    "while",
    "loop",
    "match",
    "is_finite",
    "default_epsilon",
    "max",
    "min",
    "clamp",
    "signum",
    "partial_cmp",
    "lu",
    "cholesky",
    "try_inverse",
    "solve",
    "norm",
];

/// Whether `body` is straight-line code that compiles for lanes: none of
/// [`SCALAR_ONLY`], no ordered comparison, and no `if` but the one on
/// whether the parameter cache is current (a `bool` whatever `T` is).
pub(super) fn straight_line(body: &TokenStream) -> bool {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    tokens.iter().enumerate().all(|(i, tt)| match tt {
        TokenTree::Group(g) => straight_line(&g.stream()),
        TokenTree::Ident(id) if id == "if" => on_cache(&tokens[i + 1..]),
        TokenTree::Ident(id) => !SCALAR_ONLY.iter().any(|w| id == w),
        TokenTree::Punct(p) => !matches!(p.as_char(), '<' | '>') || generic_bracket(&tokens, i),
        TokenTree::Literal(_) => true,
    })
}

/// Whether the tokens after an `if` are `self . __nh_cache_current`.
fn on_cache(rest: &[TokenTree]) -> bool {
    matches!(rest, [TokenTree::Ident(s), TokenTree::Punct(d), TokenTree::Ident(m), ..]
        if s == "self" && d.as_char() == '.' && m == "__nh_cache_current")
}

/// Whether the `<` or `>` at `i` brackets generic arguments (`::<`, a type
/// such as `SVector<T, 3>`, the `->` of a return type) rather than compares.
fn generic_bracket(tokens: &[TokenTree], i: usize) -> bool {
    let before = |k: usize| i.checked_sub(k).map(|j| &tokens[j]);
    match before(1) {
        Some(TokenTree::Punct(p)) => matches!(p.as_char(), ':' | '-' | '<' | ','),
        Some(TokenTree::Ident(id)) => {
            let s = id.to_string();
            s.starts_with(char::is_uppercase) || s == "fixed_rows" || s == "fixed_view"
        }
        Some(TokenTree::Literal(l)) => l.to_string().ends_with("usize"),
        _ => false,
    }
}

/// The inherent methods `body` calls on `self` (`self . name (`).
pub(super) fn calls_on_self(body: &TokenStream) -> Vec<String> {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    let mut calls = Vec::new();
    for (i, tt) in tokens.iter().enumerate() {
        match tt {
            TokenTree::Group(g) => calls.extend(calls_on_self(&g.stream())),
            TokenTree::Ident(s) if s == "self" => {
                if let [
                    TokenTree::Punct(d),
                    TokenTree::Ident(m),
                    TokenTree::Group(_),
                    ..,
                ] = &tokens[i + 1..]
                    && d.as_char() == '.'
                {
                    calls.push(m.to_string());
                }
            }
            _ => {}
        }
    }
    calls
}

#[cfg(test)]
mod tests {
    use super::*;
    use quote::quote;

    #[test]
    fn arithmetic_with_the_cache_check_runs_in_lanes() {
        let body = quote! {
            let __nh_cache = if self.__nh_cache_current() { &self.__nh_cache } else { &__nh_fresh };
            let (s, c): (T, T) = q[0usize].sin_cos();
            let v = x.fixed_rows::<3usize>(0).into_owned();
            __nh_private::nalgebra::SVector::<T, 2usize>::from([s * c, (s + c).sqrt()])
        };
        assert!(straight_line(&body));
    }

    #[test]
    fn branches_loops_and_comparisons_stay_scalar() {
        let sign = quote!({
            let s: T = a;
            if s > T::zero() { T::one() } else { s }
        });
        let newton = quote!(for i in 0..8usize {
            x[1usize] += step;
        });
        let compare = quote!(let ok = (a - b) < c;);
        for body in [sign, newton, compare] {
            assert!(!straight_line(&body), "{body}");
        }
    }

    #[test]
    fn calls_on_self_lists_the_methods() {
        let body = quote! {
            let s = self.dependent_velocities(&q, &r);
            let a = self.accelerations(t, &q, &r);
            let p = self.g;
        };
        assert_eq!(
            calls_on_self(&body),
            ["dependent_velocities", "accelerations"]
        );
    }
}
