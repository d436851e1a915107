//! The parameter-only values computed once (the cache) and the
//! constructor that fills it.

use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// Values that depend on parameters alone: computed when the parameters
/// are set, kept in a cache with the parameters it was computed for; a
/// method whose parameters were changed since (the fields are public)
/// computes them afresh, so a stale cache is never read.
pub(crate) struct Cache {
    /// The number of cached values (none: no cache).
    pub(crate) len: usize,
    /// The struct's fields holding the cache.
    pub(crate) fields: TokenStream,
    /// The initialisers of those fields in `new`.
    pub(crate) init: TokenStream,
    /// The methods computing and reading the cache.
    pub(crate) methods: TokenStream,
}

impl Cache {
    pub(crate) fn new(params: &[Ident], (len, hoist_code): (usize, TokenStream)) -> Cache {
        if len == 0 {
            return Cache {
                len,
                fields: quote!(),
                init: quote!(),
                methods: quote!(),
            };
        }
        let n_par = params.len();
        let slots = 0..n_par;
        // The check joins its comparisons with `&`, not `&&`: LLVM makes one
        // packed comparison and one branch of them (the bicycle's call 17%
        // faster than with 26 branches). The cache's computation stays
        // inline: `#[cold] #[inline(never)]` on it made that call 28% slower.
        Cache {
            len,
            fields: quote! {
                #[doc(hidden)]
                __nh_cache: [T; #len],
                #[doc(hidden)]
                __nh_cache_for: [T; #n_par],
            },
            init: quote!(__nh_cache: [T::zero(); #len], __nh_cache_for: [#(#params),*],),
            methods: quote! {
                /// The values that depend on the parameters alone, computed once.
                fn __nh_compute_cache(&self) -> [T; #len] {
                    let mut __nh_hoisted = [T::zero(); #len];
                    #hoist_code
                    __nh_hoisted
                }

                /// Whether the cache holds the values of the current
                /// parameters (a public parameter may have changed since).
                #[inline(always)]
                fn __nh_cache_current(&self) -> bool {
                    #((self.__nh_cache_for[#slots] == self.#params))&*
                }
            },
        }
    }
}

/// `new`, taking the parameters under their own names (the block around
/// the impls shadows any constant of those names, see below): a `const fn`
/// unless it fills a cache.
pub(crate) fn new_fn(params: &[Ident], cache: &Cache) -> TokenStream {
    let new_doc = format!(
        "A system with the given parameters ({}).",
        if params.is_empty() {
            "none".to_string()
        } else {
            params
                .iter()
                .map(|p| format!("`{p}`"))
                .collect::<Vec<_>>()
                .join(", ")
        }
    );
    let phantom_init = if params.is_empty() {
        quote!(__nh_scalar: ::core::marker::PhantomData,)
    } else {
        quote!()
    };
    if cache.len == 0 {
        quote! {
            #[doc = #new_doc]
            pub const fn new(#(#params: T),*) -> Self {
                Self { #(#params: #params,)* #phantom_init }
            }
        }
    } else {
        let cache_init = &cache.init;
        quote! {
            #[doc = #new_doc]
            pub fn new(#(#params: T),*) -> Self {
                let mut __nh_new = Self { #(#params: #params,)* #phantom_init #cache_init };
                __nh_new.__nh_cache = __nh_new.__nh_compute_cache();
                __nh_new
            }
        }
    }
}
