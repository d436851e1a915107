//! Error collection, modelled on serde_derive's `Ctxt`: every stage records
//! its errors here and carries on, so one compilation reports every
//! independent mistake; the caller combines them at the end.

use proc_macro2::{Ident, Span, TokenStream};
use quote::ToTokens;
use std::fmt::Display;

/// Collects errors during parsing, lowering and derivation.
#[derive(Default)]
pub struct Ctxt {
    errors: Vec<syn::Error>,
    /// The number of constraint rows, when lowering found it although the
    /// system has errors: the stand-in emitted next to them then has the
    /// dimensions of the real API (a contact's height row, a contact row
    /// implied by the rows before it, are known only from lowering).
    pub constraint_rows: Option<usize>,
}

/// A source range given by its first and last token spans; used to point an
/// error at a whole subexpression on stable Rust (where `Span::join` is not
/// available, `syn::Error::new_spanned` covers first-to-last token).
#[derive(Clone, Copy, Debug)]
pub struct SpanRange {
    /// Span of the first token.
    pub first: Span,
    /// Span of the last token.
    pub last: Span,
}

impl SpanRange {
    /// A range of one token.
    pub fn single(s: Span) -> SpanRange {
        SpanRange { first: s, last: s }
    }

    /// The range from the start of `self` to the end of `other`.
    pub fn to(self, other: SpanRange) -> SpanRange {
        SpanRange {
            first: self.first,
            last: other.last,
        }
    }
}

impl ToTokens for SpanRange {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        tokens.extend([
            proc_macro2::TokenTree::Ident(Ident::new("first", self.first)),
            proc_macro2::TokenTree::Ident(Ident::new("last", self.last)),
        ]);
    }
}

/// A part of the input a stage is deriving, and what it is doing with it:
/// named to the engine while the stage works ([`Engine::enter`]), so that
/// an error for a limit exceeded there points at it (DESIGN §5).
///
/// [`Engine::enter`]: crate::sym::Engine::enter
#[derive(Clone, Debug)]
pub struct Site {
    /// The tokens of the part of the input.
    pub range: SpanRange,
    /// What is being done, as a message says it: "expanding `a3`",
    /// "differentiating the Lagrangian".
    pub task: String,
}

impl Site {
    /// The site `range`, where the stage is doing `task`.
    pub fn new(range: SpanRange, task: impl Into<String>) -> Site {
        Site {
            range,
            task: task.into(),
        }
    }
}

impl Ctxt {
    /// A new, empty context.
    pub fn new() -> Ctxt {
        Ctxt::default()
    }

    /// Records an error spanning `range`.
    pub fn error(&mut self, range: SpanRange, msg: impl Display) {
        self.errors.push(syn::Error::new_spanned(range, msg));
    }

    /// Records an error at one span.
    pub fn error_at(&mut self, span: Span, msg: impl Display) {
        self.errors.push(syn::Error::new(span, msg));
    }

    /// Records a syn error (from a failed parse).
    pub fn syn_error(&mut self, e: syn::Error) {
        self.errors.push(e);
    }

    /// Number of errors so far.
    pub fn len(&self) -> usize {
        self.errors.len()
    }

    /// The individual errors.
    #[cfg(test)]
    pub fn errors(&self) -> &[syn::Error] {
        &self.errors
    }

    /// Drops the errors recorded after the first `len`: those that follow
    /// from a derivation abandoned at a limit, whose values are meaningless.
    pub fn truncate(&mut self, len: usize) {
        self.errors.truncate(len);
    }

    /// Whether no error has been recorded.
    pub fn is_empty(&self) -> bool {
        self.errors.is_empty()
    }

    /// The recorded errors, one combined error if there are any.
    pub fn finish(self) -> Result<(), syn::Error> {
        let mut it = self.errors.into_iter();
        match it.next() {
            None => Ok(()),
            Some(mut first) => {
                for e in it {
                    first.combine(e);
                }
                Err(first)
            }
        }
    }
}
