//! The `nonholonomic_system!` procedural macro. This crate is a thin entry
//! point: parsing, symbolic derivation and code emission live in `nh-core`.
//! Use it through the `nonholonomic` facade crate, whose documentation
//! describes the input language: the facade's `nonholonomic_system!` is a
//! `macro_rules!` wrapper that calls this macro with its own path in front,
//! `@crate($crate) ..`, so the generated code finds the facade under any
//! name it is imported as.
#![forbid(unsafe_code)]

use proc_macro::TokenStream;

/// Derives the equations of motion of a mechanical system with linear
/// velocity constraints at compile time. See the `nonholonomic` crate, whose
/// `nonholonomic_system!` wrapper calls this macro as
/// `nonholonomic_system! { @crate($crate) pub struct .. }`; without the
/// `@crate(..)` prefix the generated code names `::nonholonomic`.
///
/// With the environment variable `NH_STATS=1` set while compiling, the macro
/// prints the expansion's figures (time, operation counts of both routes,
/// the route chosen) to standard error.
#[proc_macro]
pub fn nonholonomic_system(input: TokenStream) -> TokenStream {
    nh_core::with_text_parser(compiler_lexer, || expand(input))
}

/// Generated text lexed by the compiler directly (see
/// `nh_core::with_text_parser`).
fn compiler_lexer(text: &str) -> Option<proc_macro2::TokenStream> {
    text.parse::<TokenStream>().ok().map(Into::into)
}

fn expand(input: TokenStream) -> TokenStream {
    if std::env::var_os("NH_STATS").is_none_or(|v| v != "1") {
        return nh_core::expand(input.into()).into();
    }
    let start = std::time::Instant::now();
    let (out, stats) = nh_core::expand_with_stats(input.into());
    eprintln!(
        "nonholonomic_system! {}: expanded in {:.2} ms; {}",
        stats.name,
        start.elapsed().as_secs_f64() * 1e3,
        stats.summary()
    );
    out.into()
}
