//! The named companions of a system `Name`: `NameCoordinates`,
//! `NameVelocities` and `NameParameters`, plain structs with one field per
//! coordinate, per velocity of the state and per parameter, and the
//! methods that build the state and the system from them and read the
//! state back (`state`, `split`, `state_from_velocities`,
//! `from_parameters`, `parameters`).
//!
//! The companions are defined in a hidden module `__nh_Name` next to the
//! struct and imported from it with the struct's visibility (and the
//! attributes it passes on to every item). Their names are the system's
//! with a suffix, spanned at the system's name: a name already taken in the
//! module is reported there (the name is defined twice), and the generated
//! code, which reaches the companions through the hidden module, is not
//! affected, so no follow-up errors bury that one.

use super::{Dims, Shape, svector};
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::{format_ident, quote};

/// What the companions add to the expansion.
pub struct Companions {
    /// The companion structs, emitted next to the system's struct.
    pub structs: TokenStream,
    /// Their trait implementations, emitted in the block around the impls.
    pub impls: TokenStream,
    /// The methods of the system that use them, in its inherent impl.
    pub methods: TokenStream,
}

/// One companion struct: its name, its path from the generated code, field
/// names and the documentation of the struct and of each field.
struct Companion {
    name: Ident,
    path: TokenStream,
    fields: Vec<Ident>,
    doc: String,
    field_docs: Vec<String>,
}

/// The argument names the companions' methods introduce (the block around
/// the impls shadows a user's constant of each name, see `argument_names`).
pub const ARGUMENTS: [&str; 5] = ["v", "qdot", "parameters", "t", "known"];

/// The companions of a system of this shape, whose parameters are the
/// fields `params`.
pub fn companions(shape: &Shape, dims: Dims, params: &[Ident]) -> Companions {
    let coordinates = coordinates(shape);
    let velocities = velocities(shape);
    let parameters = parameters(shape, params);
    let structs = hidden_module(
        shape,
        [&coordinates, &velocities, &parameters],
        params.is_empty(),
    );
    let impls = [(&coordinates, dims.n), (&velocities, dims.k)]
        .into_iter()
        .map(|(c, len)| c.vector_conversions(len))
        .chain([parameters_conversion(shape.name, &parameters)])
        .collect();
    let mut methods = state_methods(shape, dims, &coordinates, &velocities);
    methods.extend(state_from_velocities(shape, dims, &coordinates));
    methods.extend(state_from_known_velocities(shape, dims, &coordinates));
    methods.extend(parameter_methods(&parameters));
    Companions {
        structs,
        impls,
        methods,
    }
}

/// The hidden module `__nh_Name` defining the companions, and the import
/// of each under its own name, with the system's visibility.
fn hidden_module(shape: &Shape, companions: [&Companion; 3], no_parameters: bool) -> TokenStream {
    let (vis, module) = (shape.vis, module(shape.name));
    let inherited = crate::attrs::inherited(shape.attrs);
    let defaults = [true, true, no_parameters];
    let definitions = companions
        .iter()
        .zip(defaults)
        .map(|(c, d)| c.definition(d));
    let names = companions.iter().map(|c| &c.name);
    quote! {
        #(#inherited)*
        #[doc(hidden)]
        #[allow(non_snake_case)]
        mod #module {
            #(#definitions)*
        }

        #(#inherited)*
        #[doc(inline)]
        #[allow(unused_imports)]
        #vis use #module::{#(#names),*};
    }
}

/// The name of the hidden module of the companions of `system`.
fn module(system: &Ident) -> Ident {
    format_ident!("__nh_{}", system, span = system.span())
}

/// A companion named `system` + `suffix`, spanned at the system's name,
/// and its path through the hidden module.
fn companion_name(system: &Ident, suffix: &str) -> (Ident, TokenStream) {
    let name = format_ident!("{}{}", system, suffix, span = system.span());
    let module = module(system);
    (name.clone(), quote!(#module::#name))
}

/// An intra-doc link from the hidden module to `system` (`item` empty) or
/// to its item `item`.
fn link(system: &Ident, item: &str) -> String {
    if item.is_empty() {
        format!("[`{system}`](super::{system})")
    } else {
        format!("[`{system}::{item}`](super::{system}::{item})")
    }
}

/// `NameCoordinates`: one field per coordinate, in coordinate order.
fn coordinates(shape: &Shape) -> Companion {
    let name = shape.name;
    let (id, path) = companion_name(name, "Coordinates");
    let (system, state, split) = (link(name, ""), link(name, "state"), link(name, "split"));
    let from_velocities = link(name, "state_from_velocities");
    Companion {
        name: id,
        path,
        fields: field_names(&shape.coords),
        doc: format!(
            "The coordinates of {system} by name, in its coordinate order (`{name}::COORDINATES`): \
             the first part of its state, built by {state} and read by {split}. \
             {from_velocities} takes the velocities of the coordinates in one of these too."
        ),
        field_docs: shape
            .coords
            .iter()
            .map(|c| format!("The coordinate `{c}` (or its velocity `dot({c})`)."))
            .collect(),
    }
}

/// `NameVelocities`: the velocity part of the state, one field per
/// independent coordinate (named by it) or per generalized speed.
fn velocities(shape: &Shape) -> Companion {
    let name = shape.name;
    let system = link(name, "");
    let (names, doc, field_docs) = if shape.in_speeds() {
        (
            shape.speeds.clone(),
            format!(
                "The generalized speeds of {system} by name, in the order of `{name}::SPEEDS`: \
                 the second part of its state x = [q, u]."
            ),
            shape
                .speeds
                .iter()
                .map(|s| format!("The speed `{s}`."))
                .collect(),
        )
    } else {
        let independent: Vec<String> = shape
            .independent
            .iter()
            .filter_map(|&i| shape.coords.get(i).cloned())
            .collect();
        let field_docs = independent
            .iter()
            .map(|c| format!("The velocity `dot({c})` of the independent coordinate `{c}`."))
            .collect();
        (
            independent,
            format!(
                "The independent velocities of {system}, each named by its coordinate, in the order of \
                 `{name}::INDEPENDENT`: the second part of its state x = [q, ṙ]. The velocities of the \
                 dependent coordinates follow from the constraints; to give every velocity and have them \
                 checked, use {}.",
                link(name, "state_from_velocities")
            ),
            field_docs,
        )
    };
    let (id, path) = companion_name(name, "Velocities");
    Companion {
        name: id,
        path,
        fields: field_names(&names),
        doc,
        field_docs,
    }
}

/// `NameParameters`: one field per parameter, in declared order.
fn parameters(shape: &Shape, params: &[Ident]) -> Companion {
    let name = shape.name;
    let (id, path) = companion_name(name, "Parameters");
    Companion {
        name: id,
        path,
        fields: params.to_vec(),
        doc: format!(
            "The parameters of {} by name: a struct literal names every parameter and the \
             compiler checks that none is missing. {} (or `From`) builds the system from it, {} \
             reads them back.",
            link(name, ""),
            link(name, "from_parameters"),
            link(name, "parameters")
        ),
        field_docs: shape
            .params
            .iter()
            .map(|p| {
                let p = syn::ext::IdentExt::unraw(p);
                format!("The parameter `{p}`.")
            })
            .collect(),
    }
}

/// The names as fields: a keyword becomes a raw identifier (`r#type`); a
/// name that cannot be a field (`self`, `_`, a repeated name: all already
/// reported as errors) gets a stand-in, so that the struct still compiles.
fn field_names(names: &[String]) -> Vec<Ident> {
    names
        .iter()
        .enumerate()
        .map(|(i, n)| match field_name(n) {
            Some(id) if !names[..i].contains(n) => id,
            _ => format_ident!("__nh_field_{}", i),
        })
        .collect()
}

/// The field for a name as written (raw prefix removed), if it can be one.
fn field_name(name: &str) -> Option<Ident> {
    let mut chars = name.chars();
    let well_formed = chars.next().is_some_and(|c| c == '_' || c.is_alphabetic())
        && chars.all(|c| c == '_' || c.is_alphanumeric());
    if !well_formed || ["self", "Self", "super", "crate", "_"].contains(&name) {
        return None;
    }
    let id = Ident::new(name, Span::call_site());
    Some(if crate::names::is_rust_identifier(&id) {
        id
    } else {
        Ident::new_raw(name, Span::call_site())
    })
}

impl Companion {
    /// The struct: `T` defaults to `f64` as for the system; without fields
    /// it holds a hidden marker and derives `Default` to be built.
    fn definition(&self, default: bool) -> TokenStream {
        let Companion {
            name,
            fields,
            doc,
            field_docs,
            ..
        } = self;
        let phantom = fields
            .is_empty()
            .then(|| quote!(#[doc(hidden)] pub __nh_scalar: ::core::marker::PhantomData<T>,));
        let default = default.then(|| quote!(::core::default::Default,));
        quote! {
            #[doc = #doc]
            #[allow(non_snake_case, dead_code)]
            #[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::cmp::PartialEq, #default)]
            pub struct #name<T = ::core::primitive::f64> {
                #(#[doc = #field_docs] pub #fields: T,)*
                #phantom
            }
        }
    }

    /// `Name { a: e0, b: e1, .. }` from the expressions `values`, in field order.
    fn literal(&self, values: &[TokenStream]) -> TokenStream {
        let (path, fields) = (&self.path, &self.fields);
        let phantom = fields
            .is_empty()
            .then(|| quote!(__nh_scalar: ::core::marker::PhantomData,));
        quote!(#path { #(#fields: #values,)* #phantom })
    }

    /// The fields of the value `value` (an expression) as a list of `T`s.
    fn values(&self, value: &TokenStream) -> Vec<TokenStream> {
        self.fields.iter().map(|f| quote!(#value.#f)).collect()
    }

    /// `From` between the struct and `SVector<T, len>`, both ways.
    fn vector_conversions(&self, len: usize) -> TokenStream {
        let name = &self.path;
        let vty = svector(len);
        let values = self.values(&quote!(__nh_named));
        let components: Vec<TokenStream> = (0..len).map(|i| quote!(__nh_vector[#i])).collect();
        let literal = self.literal(&components);
        quote! {
            #[automatically_derived]
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy> ::core::convert::From<#name<T>> for #vty {
                /// The values in field order.
                #[inline]
                fn from(__nh_named: #name<T>) -> Self {
                    <#vty>::from([#(#values),*])
                }
            }
            #[automatically_derived]
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy> ::core::convert::From<#vty> for #name<T> {
                /// The fields in order from the vector's entries.
                #[inline]
                fn from(__nh_vector: #vty) -> Self {
                    #literal
                }
            }
        }
    }
}

/// `impl From<NameParameters<T>> for Name<T>`.
fn parameters_conversion(system: &Ident, parameters: &Companion) -> TokenStream {
    let name = &parameters.path;
    quote! {
        #[automatically_derived]
        impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy> ::core::convert::From<#name<T>> for #system<T> {
            /// [`Self::from_parameters`].
            #[inline]
            fn from(parameters: #name<T>) -> Self {
                Self::from_parameters(parameters)
            }
        }
    }
}

/// `state` and `split`: the state from named parts and back.
fn state_methods(shape: &Shape, dims: Dims, coords: &Companion, vels: &Companion) -> TokenStream {
    let (cname, vname, xty) = (&coords.path, &vels.path, svector(dims.state));
    let values: Vec<TokenStream> = coords
        .values(&quote!(q))
        .into_iter()
        .chain(vels.values(&quote!(v)))
        .collect();
    let (q_parts, v_parts): (Vec<TokenStream>, Vec<TokenStream>) = (
        (0..dims.n).map(|i| quote!(x[#i])).collect(),
        (dims.n..dims.state).map(|i| quote!(x[#i])).collect(),
    );
    let (q_literal, v_literal) = (coords.literal(&q_parts), vels.literal(&v_parts));
    let name = shape.name;
    let part = if shape.in_speeds() {
        "the generalized speeds u"
    } else {
        "the independent velocities ṙ"
    };
    let state_doc = format!(
        "The state x = [q, {}] from the coordinates `q` and {part} `v` by name: \
         the initial state for an integrator. [`{name}::split`] is its inverse.",
        if shape.in_speeds() { "u" } else { "ṙ" }
    );
    let split_doc = format!(
        "The coordinates and {part} of a state `x` by name (an outcome's final state, \
         an observed or a dense-output sample): the inverse of [`{name}::state`]."
    );
    quote! {
        #[doc = #state_doc]
        #[inline]
        pub fn state(q: #cname<T>, v: #vname<T>) -> #xty {
            <#xty>::from([#(#values),*])
        }

        #[doc = #split_doc]
        #[inline]
        pub fn split(x: &#xty) -> (#cname<T>, #vname<T>) {
            (#q_literal, #v_literal)
        }
    }
}

/// `state_from_velocities`: the state from the velocities of all
/// coordinates, checked against the constraints.
/// `state_from_known_velocities`: the state from the velocities known for
/// some coordinates, the others solved from the constraints.
fn state_from_known_velocities(shape: &Shape, dims: Dims, coords: &Companion) -> TokenStream {
    let (cname, xty, qty, vty) = (
        &coords.path,
        svector(dims.state),
        svector(dims.n),
        svector(dims.k),
    );
    let (n, k) = (dims.n, dims.k);
    let names: Vec<Literal> = shape.coords.iter().map(|c| Literal::string(c)).collect();
    let fields = &coords.fields;
    let timed = shape.in_speeds() || shape.rheonomic;
    let (t_arg, t_val) = if timed {
        (quote!(t: T,), quote!(t,))
    } else {
        (quote!(), quote!())
    };
    let map = if shape.in_speeds() {
        quote!(|__nh_v: &#vty| self.velocities(t, &__nh_q, __nh_v))
    } else {
        let independent = &shape.independent;
        let slots = 0..k;
        let (at, dep): (Vec<usize>, Vec<usize>) =
            shape.dependent.iter().copied().enumerate().unzip();
        quote!(|__nh_v: &#vty| {
            let __nh_sdot = self.dependent_velocities(#t_val &__nh_q, __nh_v);
            let mut __nh_all = <#qty>::zeros();
            #(__nh_all[#independent] = __nh_v[#slots];)*
            #(__nh_all[#dep] = __nh_sdot[#at];)*
            __nh_all
        })
    };
    let doc = "The state from the coordinates `q` and the velocities known for some coordinates \
               (`Some` in `known`, by name; `None` for the others), for initial conditions known as \
               physical velocities (a wheel's rate, a heading rate): the velocities of the state are \
               solved from the constraints so that every known velocity holds (least squares, then \
               checked to 1e-9 of the largest velocity). Fails with `KnownVelocitiesError::TooFew` \
               when the known velocities leave the motion undetermined (fewer than the independent \
               velocities, or ones the constraints tie together) and with `Violation` when they \
               break the constraints.";
    quote! {
        #[doc = #doc]
        #[inline]
        pub fn state_from_known_velocities(
            &self,
            #t_arg
            q: #cname<T>,
            known: #cname<::core::option::Option<T>>,
        ) -> ::core::result::Result<#xty, __nh_private::nh_runtime::KnownVelocitiesError<T>> {
            let __nh_q = <#qty>::from(q);
            let __nh_known = [#(known.#fields),*];
            let __nh_v = __nh_private::nh_runtime::velocities_from_known(&[#(#names),*], #map, &__nh_known)?;
            let mut __nh_x = <#xty>::zeros();
            __nh_x.fixed_rows_mut::<#n>(0).copy_from(&__nh_q);
            __nh_x.fixed_rows_mut::<#k>(#n).copy_from(&__nh_v);
            ::core::result::Result::Ok(__nh_x)
        }
    }
}

fn state_from_velocities(shape: &Shape, dims: Dims, coords: &Companion) -> TokenStream {
    let (cname, xty, qty) = (&coords.path, svector(dims.state), svector(dims.n));
    let (n, k) = (dims.n, dims.k);
    let names: Vec<Literal> = shape.coords.iter().map(|c| Literal::string(c)).collect();
    let timed = shape.in_speeds() || shape.rheonomic;
    let (t_arg, t_val) = if timed {
        (quote!(t: T,), quote!(t,))
    } else {
        (quote!(), quote!())
    };
    let (implied, velocity_part, doc) = if shape.in_speeds() {
        implied_by_speeds(shape, dims)
    } else {
        implied_by_constraints(shape, dims, &t_val)
    };
    quote! {
        #[doc = #doc]
        #[inline]
        pub fn state_from_velocities(&self, #t_arg q: #cname<T>, qdot: #cname<T>)
            -> ::core::result::Result<#xty, __nh_private::nh_runtime::ConstraintViolation<T>>
        {
            let __nh_q = <#qty>::from(q);
            let __nh_qdot = <#qty>::from(qdot);
            #implied
            __nh_private::nh_runtime::ConstraintViolation::check(&[#(#names),*], &__nh_qdot, &__nh_implied)?;
            let mut __nh_x = <#xty>::zeros();
            __nh_x.fixed_rows_mut::<#n>(0).copy_from(&__nh_q);
            __nh_x.fixed_rows_mut::<#k>(#n).copy_from(&#velocity_part);
            ::core::result::Result::Ok(__nh_x)
        }
    }
}

/// The velocities the constraints imply (`__nh_implied`: the given ones
/// with the dependent velocities computed from the independent ones), the
/// state's velocity part, and the documentation.
fn implied_by_constraints(
    shape: &Shape,
    dims: Dims,
    t_val: &TokenStream,
) -> (TokenStream, TokenStream, String) {
    let rty = svector(dims.k);
    let independent: Vec<usize> = shape.independent.clone();
    let dependent: Vec<(usize, usize)> = shape.dependent.iter().copied().enumerate().collect();
    let (slots, dep): (Vec<usize>, Vec<usize>) = dependent.into_iter().unzip();
    let name = shape.name;
    let code = quote! {
        let __nh_rdot = <#rty>::from([#(__nh_qdot[#independent]),*]);
        let __nh_sdot = self.dependent_velocities(#t_val &__nh_q, &__nh_rdot);
        let mut __nh_implied = __nh_qdot;
        #(__nh_implied[#dep] = __nh_sdot[#slots];)*
    };
    let doc = format!(
        "The state x = [q, ṙ] from the coordinates `q` and the velocities of *all* coordinates \
         `qdot` (both by name), for initial conditions known as physical velocities. The velocities \
         of the dependent coordinates (`{name}::DEPENDENT`) must be those the constraints give at `q` \
         and the independent velocities (see `dependent_velocities`), to a relative tolerance of 1e-9 \
         of the largest velocity; otherwise the error names the coordinate whose velocity is furthest \
         off, with both values. The coordinates themselves are taken as given (for holonomic \
         constraints, the integrators project them onto the constraints after the first step)."
    );
    (code, quote!(__nh_rdot), doc)
}

/// As [`implied_by_constraints`], for a system in generalized speeds: the
/// speeds closest to the velocities (least squares on the kinematics),
/// and the velocities they give.
fn implied_by_speeds(shape: &Shape, dims: Dims) -> (TokenStream, TokenStream, String) {
    let uty = svector(dims.k);
    let name = shape.name;
    let code = quote! {
        let __nh_u = __nh_private::nh_runtime::speeds_from_velocities(
            |__nh_speeds: &#uty| self.velocities(t, &__nh_q, __nh_speeds),
            &__nh_qdot,
        );
        let __nh_implied = self.velocities(t, &__nh_q, &__nh_u);
    };
    let doc = format!(
        "The state x = [q, u] at time `t` from the coordinates `q` and the velocities of all \
         coordinates `qdot` (both by name), for initial conditions known as physical velocities: \
         the speeds u are those whose kinematics q̇ = S(q, t) u + σ(q, t) gives `qdot` (solved by \
         least squares, see `nh_runtime::speeds_from_velocities`). If `qdot` is not of that form \
         (it breaks the constraints the kinematics builds in) by more than 1e-9 of the largest \
         velocity, the error names the coordinate whose velocity is furthest from S u + σ. With the \
         speeds known, [`{name}::state`] builds the state directly."
    );
    (code, quote!(__nh_u), doc)
}

/// `from_parameters` and `parameters`.
fn parameter_methods(parameters: &Companion) -> TokenStream {
    let name = &parameters.path;
    let values = parameters.values(&quote!(parameters));
    let own: Vec<TokenStream> = parameters.values(&quote!(self));
    let literal = parameters.literal(&own);
    quote! {
        /// The system with the parameters given by name: the same as `new` with them in declared order.
        #[inline]
        pub fn from_parameters(parameters: #name<T>) -> Self {
            Self::new(#(#values),*)
        }

        /// The parameters by name (the current values of the fields).
        #[inline]
        pub fn parameters(&self) -> #name<T> {
            #literal
        }
    }
}
