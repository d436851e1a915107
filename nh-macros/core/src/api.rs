//! The generated API of DESIGN §3: the struct, its constants, the method
//! signatures and the runtime trait implementation. Method bodies are
//! supplied by the caller: the derivation's straight-line code, or, for a
//! system with errors, a stand-in that keeps the user's other code
//! type-checking so that no follow-up errors bury the real ones.
//!
//! Hygiene: everything but the struct is emitted inside one anonymous
//! `const _: () = { .. };` block, which brings the facade's private paths in
//! as `__nh_private` (from the `$crate` the facade's wrapper passes, so a
//! renamed dependency works) and declares a function for each argument name
//! (`t`, `q`, `rdot`, `x`, `u` and the parameters of `new`): a user's
//! constant, static or unit struct of that name in scope would otherwise be
//! matched by the argument pattern instead of binding it. Every other
//! identifier the generated code introduces (locals, temporaries, the cache)
//! starts with `__nh_`.

use crate::lower::Outputs;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use syn::Visibility;

/// Everything the signatures depend on.
pub struct Shape<'a> {
    /// Attributes (doc comments, cfg, lints, further derives) for the struct.
    pub attrs: &'a [TokenStream],
    /// The path of the `nonholonomic` facade (`$crate` from its wrapper).
    pub krate: &'a TokenStream,
    /// Visibility.
    pub vis: &'a Visibility,
    /// Struct name.
    pub name: &'a Ident,
    /// Parameters in declared order.
    pub params: Vec<Ident>,
    /// Coordinate names in declared order.
    pub coords: Vec<String>,
    /// Input names.
    pub inputs: Vec<String>,
    /// Indices of the independent coordinates.
    pub independent: Vec<usize>,
    /// Indices of the dependent coordinates.
    pub dependent: Vec<usize>,
    /// Requested outputs.
    pub outputs: Outputs,
    /// Whether every curvature coefficient vanishes identically.
    pub integrable: bool,
}

/// The body and documentation of one generated method.
pub struct Method {
    /// Rustdoc text.
    pub doc: String,
    /// Statements and final expression.
    pub body: TokenStream,
}

/// Supplies method bodies by method name: `dependent_velocities`,
/// `accelerations`, `accelerations_multiplier_route`,
/// `accelerations_curvature_route`, `reduced_system`, `multipliers`,
/// `curvature`, `energy`, `constraint_matrix`, `mass_matrix`, `rhs`.
pub trait Bodies {
    /// The method named `name`.
    fn method(&mut self, name: &str) -> Method;
    /// Extra associated constants (route figures), emitted with `routes`.
    fn route_consts(&mut self) -> TokenStream;
    /// The parameter-only values hoisted out of the methods (asked for after
    /// every method): their number and the statements computing them into
    /// `c: [T; number]` from `self`'s parameters.
    fn hoisting(&mut self) -> (usize, TokenStream);
}

/// The facade's private module in generated code: a `use` in the block
/// around the generated items brings it in under this name.
pub fn private() -> TokenStream {
    quote!(__nh_private)
}

/// Path of nalgebra's static vector type in generated code.
pub fn svector(len: usize) -> TokenStream {
    quote!(__nh_private::nalgebra::SVector<T, #len>)
}

/// Path of nalgebra's static matrix type in generated code.
pub fn smatrix(r: usize, c: usize) -> TokenStream {
    quote!(__nh_private::nalgebra::SMatrix<T, #r, #c>)
}

/// Lints that do not apply to generated straight-line code.
fn allow_lints() -> TokenStream {
    quote!(#[allow(non_snake_case, clippy::all, clippy::pedantic, unused_variables, unused_parens, unused_doc_comments)])
}

/// The whole expansion for a system of the given shape.
pub fn expand(shape: &Shape, bodies: &mut dyn Bodies) -> TokenStream {
    let (n, k, p) = (
        shape.coords.len(),
        shape.independent.len(),
        shape.dependent.len(),
    );
    let n_in = shape.inputs.len();
    let dim = n + k;
    let Shape {
        attrs, vis, name, ..
    } = shape;
    // a parameter that cannot be a field (a keyword such as `self`, or a
    // repeated name: both already reported) gets a stand-in name, so the
    // struct emitted next to the errors compiles and `new` keeps its arity
    let params: &Vec<Ident> = &shape
        .params
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if crate::names::is_rust_identifier(p) && !shape.params[..i].contains(p) {
                p.clone()
            } else {
                format_ident!("__nh_parameter_{}", i)
            }
        })
        .collect();
    let (qty, rty, pty, uty, xty) = (
        svector(n),
        svector(k),
        svector(p),
        svector(n_in),
        svector(dim),
    );
    let has_inputs = n_in > 0;
    let u_arg = if has_inputs {
        quote!(, u: &#uty)
    } else {
        quote!()
    };
    let allow = allow_lints();

    let mut method = |fname: &str, sig: TokenStream| -> TokenStream {
        let Method { doc, body } = bodies.method(fname);
        quote! {
            #[doc = #doc]
            #[inline]
            #sig {
                #body
            }
        }
    };
    let mut methods = TokenStream::new();
    methods.extend(method(
        "dependent_velocities",
        quote!(pub fn dependent_velocities(&self, q: &#qty, rdot: &#rty) -> #pty),
    ));
    methods.extend(method(
        "accelerations",
        quote!(pub fn accelerations(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> #rty),
    ));
    let o = &shape.outputs;
    if o.routes {
        for f in [
            "accelerations_multiplier_route",
            "accelerations_curvature_route",
        ] {
            let id = format_ident!("{f}");
            methods.extend(method(
                f,
                quote!(pub fn #id(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> #rty),
            ));
        }
        let kk = smatrix(k, k);
        methods.extend(method(
            "reduced_system",
            quote!(pub fn reduced_system(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> (#kk, #rty)),
        ));
    }
    if o.multipliers {
        methods.extend(method(
            "multipliers",
            quote!(pub fn multipliers(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> #pty),
        ));
    }
    if o.curvature {
        let kk = smatrix(k, k);
        methods.extend(method(
            "curvature",
            quote!(pub fn curvature(&self, q: &#qty) -> [#kk; #p]),
        ));
    }
    if o.energy {
        methods.extend(method(
            "energy",
            quote!(pub fn energy(&self, q: &#qty, rdot: &#rty) -> T),
        ));
    }
    if o.constraint_matrix {
        let pk = smatrix(p, k);
        methods.extend(method(
            "constraint_matrix",
            quote!(pub fn constraint_matrix(&self, q: &#qty) -> #pk),
        ));
    }
    if o.mass_matrix {
        let nn = smatrix(n, n);
        methods.extend(method(
            "mass_matrix",
            quote!(pub fn mass_matrix(&self, q: &#qty) -> #nn),
        ));
    }
    if o.linearization {
        let (dd, du) = (smatrix(dim, dim), smatrix(dim, n_in));
        methods.extend(method(
            "linearization",
            quote!(pub fn linearization(&self, t: T, x: &#xty #u_arg) -> (#dd, #du)),
        ));
    }
    let mut jacobian_impl = quote!();
    if o.jacobian {
        let dd = smatrix(dim, dim);
        methods.extend(method(
            "jacobian",
            quote!(pub fn jacobian(&self, t: T, x: &#xty #u_arg) -> #dd),
        ));
        if !has_inputs {
            jacobian_impl = quote! {
                #allow
                impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
                    __nh_private::nh_runtime::OdeJacobian<T, #dim> for #name<T>
                {
                    /// ∂f/∂x of the first-order system, derived symbolically (see the inherent `jacobian`).
                    #[inline]
                    fn jacobian(&self, t: T, x: &#xty) -> #dd {
                        #name::jacobian(self, t, x)
                    }
                }
            };
        }
    }
    let route_consts = if o.routes {
        bodies.route_consts()
    } else {
        quote!()
    };

    let Method {
        doc: rhs_doc,
        body: rhs_body,
    } = bodies.method("rhs");
    let runtime_impl = if has_inputs {
        quote! {
            #allow
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
                __nh_private::nh_runtime::ControlledSystem<T, #dim, #n_in> for #name<T>
            {
                #[doc = #rhs_doc]
                #[inline]
                fn rhs_with_input(&self, t: T, x: &#xty, u: &#uty) -> #xty {
                    #rhs_body
                }
            }
        }
    } else {
        quote! {
            #allow
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
                __nh_private::nh_runtime::OdeSystem<T, #dim> for #name<T>
            {
                #[doc = #rhs_doc]
                #[inline]
                fn rhs(&self, t: T, x: &#xty) -> #xty {
                    #rhs_body
                }
            }
        }
    };

    // `new` takes the parameters under their own names (the block around
    // the impls shadows any constant of those names, see below)
    let param_args = params;
    // values that depend on parameters alone: computed when the parameters
    // are set, kept in a cache with the parameters it was computed for; a
    // method whose parameters were changed since (the fields are public)
    // computes them afresh, so a stale cache is never read
    let (n_hoisted, hoist_code) = bodies.hoisting();
    let n_par = params.len();
    let (cache_fields, cache_init, cache_methods, new_const) = if n_hoisted > 0 {
        (
            quote! {
                #[doc(hidden)]
                __nh_cache: [T; #n_hoisted],
                #[doc(hidden)]
                __nh_cache_for: [T; #n_par],
            },
            quote!(__nh_cache: [T::zero(); #n_hoisted], __nh_cache_for: [#(#param_args),*],),
            quote! {
                /// The values that depend on the parameters alone, computed once.
                fn __nh_compute_cache(&self) -> [T; #n_hoisted] {
                    let mut __nh_hoisted = [T::zero(); #n_hoisted];
                    #hoist_code
                    __nh_hoisted
                }

                /// The cache, or the values afresh if a parameter changed since.
                #[inline(always)]
                fn __nh_cached(&self) -> [T; #n_hoisted] {
                    if self.__nh_cache_for == [#(self.#params),*] {
                        self.__nh_cache
                    } else {
                        self.__nh_compute_cache()
                    }
                }
            },
            false,
        )
    } else {
        (quote!(), quote!(), quote!(), true)
    };
    let coord_names: Vec<Literal> = shape.coords.iter().map(|c| Literal::string(c)).collect();
    let input_names: Vec<Literal> = shape.inputs.iter().map(|c| Literal::string(c)).collect();
    let indep = &shape.independent;
    let dep = &shape.dependent;
    let integrable = shape.integrable;
    let integrable_doc = if p == 0 {
        "No constraints: trivially `true`.".to_string()
    } else if integrable {
        "`true`: every curvature coefficient B^b_{αβ} (5.21) is identically zero, so the constraints are integrable (holonomic in disguise) and could be eliminated by integrating them.".to_string()
    } else {
        "`false`: some curvature coefficient B^b_{αβ} (5.21) is not identically zero, so the constraints are genuinely nonholonomic.".to_string()
    };
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
    let field_docs: Vec<String> = params.iter().map(|p| format!("Parameter `{p}`.")).collect();
    // the derives of `crate::attrs::DERIVED` (a user's derive of one of
    // them is an error at its path, see `attrs::check_derives`)
    let (phantom_field, phantom_init, derive) = if params.is_empty() {
        (
            quote!(#[doc(hidden)] pub __nh_scalar: ::core::marker::PhantomData<T>,),
            quote!(__nh_scalar: ::core::marker::PhantomData,),
            quote!(#[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::cmp::PartialEq, ::core::default::Default)]),
        )
    } else {
        (
            quote!(),
            quote!(),
            quote!(#[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::cmp::PartialEq)]),
        )
    };
    let new_fn = if new_const {
        quote! {
            #[doc = #new_doc]
            pub const fn new(#(#param_args: T),*) -> Self {
                Self { #(#params: #param_args,)* #phantom_init }
            }
        }
    } else {
        quote! {
            #[doc = #new_doc]
            pub fn new(#(#param_args: T),*) -> Self {
                let mut __nh_new = Self { #(#params: #param_args,)* #phantom_init #cache_init };
                __nh_new.__nh_cache = __nh_new.__nh_compute_cache();
                __nh_new
            }
        }
    };
    let inherited = crate::attrs::inherited(attrs);
    let krate = shape.krate;
    let private = private();
    // a function for every argument name: it shadows a user's constant,
    // static or unit struct of that name, which the argument pattern would
    // match instead of binding (functions do not take part in patterns)
    let mut arg_names: Vec<Ident> = ["t", "q", "rdot", "x", "u"]
        .iter()
        .map(|a| format_ident!("{a}"))
        .collect();
    for p in params {
        if !arg_names.contains(p) {
            arg_names.push(p.clone());
        }
    }
    quote! {
        #(#attrs)*
        #[allow(non_snake_case)]
        #derive
        #vis struct #name<T = ::core::primitive::f64> {
            #(#[doc = #field_docs] pub #params: T,)*
            #phantom_field
            #cache_fields
        }

        #(#inherited)*
        const _: () = {
            use #krate::__private as #private;
            #(
                #[allow(dead_code, non_snake_case, clippy::all)]
                fn #arg_names() {}
            )*

            #allow
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy> #name<T> {
                /// The generalized coordinates in declared order: the coordinate order of `q` everywhere.
                pub const COORDINATES: [&'static ::core::primitive::str; #n] = [#(#coord_names),*];
                /// Indices in `q` of the independent coordinates r, ascending.
                pub const INDEPENDENT: [::core::primitive::usize; #k] = [#(#indep),*];
                /// Indices in `q` of the dependent coordinates s (one per constraint), ascending.
                pub const DEPENDENT: [::core::primitive::usize; #p] = [#(#dep),*];
                /// The inputs in declared order.
                pub const INPUTS: [&'static ::core::primitive::str; #n_in] = [#(#input_names),*];
                /// Number of coordinates n.
                pub const N: ::core::primitive::usize = #n;
                /// Number of independent coordinates k = n − p.
                pub const K: ::core::primitive::usize = #k;
                /// Number of constraints p.
                pub const P: ::core::primitive::usize = #p;
                /// Length of the runtime state x = [q, ṙ]: n + k.
                pub const STATE_DIM: ::core::primitive::usize = #dim;
                #[doc = #integrable_doc]
                pub const INTEGRABLE: ::core::primitive::bool = #integrable;
                #route_consts

                #new_fn
                #cache_methods

                /// A constant of the generated code as `T`.
                #[doc(hidden)]
                #[inline(always)]
                fn __nh_c(x: ::core::primitive::f64) -> T {
                    __nh_private::nalgebra::convert::<::core::primitive::f64, T>(x)
                }

                #methods
            }

            #runtime_impl
            #jacobian_impl
        };
    }
}

/// Bodies of a system that failed to expand: each method diverges. They are
/// never run, since the expansion also carries the compile errors; they only
/// keep the user's code that calls the system free of follow-up errors.
pub struct StandIn;

impl Bodies for StandIn {
    fn hoisting(&mut self) -> (usize, TokenStream) {
        (0, TokenStream::new())
    }

    fn method(&mut self, _name: &str) -> Method {
        Method {
            doc: "Not generated: the system definition has errors (see the compile errors).".into(),
            body: quote!(::core::panic!(
                "nonholonomic_system! did not expand: see the compile errors"
            )),
        }
    }

    fn route_consts(&mut self) -> TokenStream {
        quote! {
            /// Not generated (the system has errors).
            pub const OPS_MULTIPLIER_ROUTE: usize = 0;
            /// Not generated (the system has errors).
            pub const OPS_CURVATURE_ROUTE: usize = 0;
            /// Not generated (the system has errors).
            pub const ROUTE: &'static str = "";
        }
    }
}
