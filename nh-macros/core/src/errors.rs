//! The errors an expansion reports, read back from its tokens: outside the
//! compiler (the `expand` tool, tests) nothing prints the `compile_error!`
//! invocations the expansion carries.

use proc_macro2::{Span, TokenStream, TokenTree};

/// One error of an expansion: its message and the source range it points
/// at (the spans of the input's tokens; with proc-macro2's `span-locations`
/// feature, `start.start()` and `end.end()` give its lines and columns).
#[derive(Clone, Debug)]
pub struct ReportedError {
    /// The message, as the compiler would print it after `error: `.
    pub message: String,
    /// The span where the culprit starts.
    pub start: Span,
    /// The span where the culprit ends.
    pub end: Span,
}

/// Every error an expansion reports (its `compile_error! { "message" }`
/// invocations, at any depth), in the order the compiler would print them.
/// Empty for an expansion without errors.
pub fn reported_errors(expansion: &TokenStream) -> Vec<ReportedError> {
    let mut errors = Vec::new();
    collect(expansion.clone(), &mut errors);
    errors
}

fn collect(tokens: TokenStream, errors: &mut Vec<ReportedError>) {
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    for (i, tt) in tokens.iter().enumerate() {
        match tt {
            TokenTree::Ident(id) if id == "compile_error" => {
                if let (Some(TokenTree::Punct(bang)), Some(TokenTree::Group(args))) =
                    (tokens.get(i + 1), tokens.get(i + 2))
                    && bang.as_char() == '!'
                    && let Some(message) = message_of(args.stream())
                {
                    errors.push(ReportedError {
                        message,
                        start: id.span(),
                        end: args.span(),
                    });
                }
            }
            TokenTree::Group(g) => collect(g.stream(), errors),
            _ => {}
        }
    }
}

/// The text of the string literal a `compile_error!` holds.
fn message_of(args: TokenStream) -> Option<String> {
    syn::parse2::<syn::LitStr>(args).ok().map(|lit| lit.value())
}

#[cfg(test)]
mod tests {
    use super::reported_errors;

    #[test]
    fn reads_every_error_with_its_message() {
        let a = syn::Error::new(proc_macro2::Span::call_site(), "first \"quoted\"");
        let b = syn::Error::new(proc_macro2::Span::call_site(), "second");
        let (a, b) = (a.to_compile_error(), b.to_compile_error());
        let expansion = quote::quote!(const _: () = (); #a mod m { #b });
        let messages: Vec<String> = reported_errors(&expansion)
            .into_iter()
            .map(|e| e.message)
            .collect();
        assert_eq!(messages, ["first \"quoted\"", "second"]);
        assert!(
            reported_errors(&quote::quote!(
                fn compile_error() {}
            ))
            .is_empty()
        );
    }
}
