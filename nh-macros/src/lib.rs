//! The `nonholonomic_system!` procedural macro. This crate is a thin entry
//! point: parsing, symbolic derivation and code emission live in `nh-core`.
//! Use it through the `nonholonomic` facade crate, whose documentation
//! describes the input language.
#![forbid(unsafe_code)]

use proc_macro::TokenStream;

/// Derives the equations of motion of a mechanical system with linear
/// velocity constraints at compile time. See the `nonholonomic` crate.
#[proc_macro]
pub fn nonholonomic_system(input: TokenStream) -> TokenStream {
    nh_core::expand(input.into()).into()
}
