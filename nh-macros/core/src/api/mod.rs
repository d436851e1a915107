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

mod atlas;
mod cache;
mod lanes;
mod named;
mod table;

pub use atlas::{ChartShape, EulerShape};
use cache::{Cache, new_fn};
pub use table::{Arguments, GeneratedMethod, METHODS, Returns};

use crate::model::{Output, Outputs};
use proc_macro2::{Ident, Literal, Span, TokenStream};
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
    /// Which coordinate each implicit or holonomic constraint is solved
    /// for (the documentation of `DEPENDENT`); `None` when every
    /// constraint is explicit.
    pub dependent_doc: Option<String>,
    /// Whether some constraint has an affine or time-dependent term.
    pub affine: bool,
    /// Whether some dependent velocity depends on time explicitly (then
    /// `dependent_velocities` takes `t`).
    pub rheonomic: bool,
    /// The generalized speeds, for a system written in them (DESIGN §9);
    /// empty otherwise.
    pub speeds: Vec<String>,
    /// Number of rolling contacts (`rolls(..)` lines).
    pub contacts: usize,
    /// The parameters `sensitivities` differentiates by, in order (all of
    /// them unless listed, `sensitivities(m, k)`).
    pub sensitivity_params: Vec<Ident>,
    /// The charts of the atlas (DESIGN §9.3), the system's own first;
    /// empty for a system with one chart.
    pub atlas: Vec<ChartShape>,
    /// The cyclic coordinates and the verdicts on their momenta, with
    /// `outputs { momenta }` (§5.5); empty otherwise.
    pub momenta: Vec<MomentumShape>,
    /// The names of the declared symmetries (`symmetries { .. }`).
    pub symmetries: Vec<String>,
    /// The momenta along the directions of the declared symmetries the
    /// constraints allow: the verdict on each and its direction in words.
    pub symmetry_momenta: Vec<(&'static str, String)>,
    /// The names of the declared momenta (`momenta { .. }`).
    pub momentum_names: Vec<String>,
    /// The verdicts on the declared momenta, each with its words (empty in
    /// a stand-in).
    pub declared_momenta: Vec<(&'static str, String)>,
}

/// A cyclic coordinate and the verdict on its momentum (§5.5).
pub struct MomentumShape {
    /// The coordinate's index in q.
    pub coordinate: usize,
    /// The runtime's `Conservation` variant: `Conserved`, `NotConserved`
    /// or `Undecided`.
    pub verdict: &'static str,
    /// The verdict in words, for the documentation.
    pub doc: String,
}

impl Shape<'_> {
    /// Whether the system is written in generalized speeds.
    pub fn in_speeds(&self) -> bool {
        !self.speeds.is_empty()
    }
}

/// The body and documentation of one generated method.
pub struct Method {
    /// Rustdoc text.
    pub doc: String,
    /// Statements and final expression.
    pub body: TokenStream,
}

/// Supplies the bodies of the generated methods.
pub trait Bodies {
    /// The body of `method`, asked for once per method the system has, in
    /// the order of [`METHODS`].
    fn method(&mut self, method: GeneratedMethod) -> Method;
    /// Extra associated constants (route figures), emitted with `routes`.
    fn route_consts(&mut self) -> TokenStream;
    /// Provided methods of the runtime trait the system overrides, for
    /// state type `xty`: its chart's regularity (implicit or holonomic
    /// constraints, generalized speeds), the holonomic residual and the
    /// projection (`chart_regularity`, `constraint_residual`, `project`);
    /// none by default.
    fn runtime_hooks(&mut self, xty: &TokenStream) -> TokenStream {
        let _ = xty;
        TokenStream::new()
    }
    /// The parameter-only values hoisted out of the methods (asked for after
    /// every method): their number and the statements computing them into
    /// `c: [T; number]` from `self`'s parameters.
    fn hoisting(&mut self) -> (usize, TokenStream);
    /// Lines for the struct's documentation on its vectors, rotations,
    /// bodies and rolling contacts; none by default.
    fn description(&self) -> Vec<String> {
        Vec::new()
    }
    /// Whether an output asked for gets its method even where the form of
    /// the system has none (`multipliers` in generalized speeds): only the
    /// stand-in, whose errors already say so, keeps the method the user
    /// meant to call.
    fn every_output_asked(&self) -> bool {
        false
    }
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

/// The sizes of a system: n coordinates, k independent, p constraints,
/// m inputs, and the state's length n + k.
#[derive(Clone, Copy)]
struct Dims {
    n: usize,
    k: usize,
    p: usize,
    inputs: usize,
    state: usize,
    /// Whether the system is in generalized speeds.
    speeds: bool,
    /// Number of rolling contacts.
    contacts: usize,
    /// Number of parameters of the sensitivities.
    sens: usize,
    /// Number of cyclic coordinates (`outputs { momenta }`).
    cyclic: usize,
    /// Number of momenta of the declared symmetries.
    symmetric: usize,
    /// Number of declared momenta.
    declared: usize,
}

impl Dims {
    fn of(shape: &Shape) -> Dims {
        let n = shape.coords.len();
        let k = if shape.in_speeds() {
            shape.speeds.len()
        } else {
            shape.independent.len()
        };
        Dims {
            n,
            k,
            p: shape.dependent.len(),
            inputs: shape.inputs.len(),
            state: n + k,
            speeds: shape.in_speeds(),
            contacts: shape.contacts,
            sens: shape.sensitivity_params.len(),
            cyclic: shape.momenta.len(),
            symmetric: shape.symmetry_momenta.len(),
            declared: shape.momentum_names.len(),
        }
    }

    /// The augmented state's length of the sensitivities, D·(1 + P + D).
    fn augmented(self) -> usize {
        self.state * (1 + self.sens + self.state)
    }

    /// `, u: &SVector<T, m>` for a system with inputs.
    fn u_arg(self) -> TokenStream {
        if self.inputs > 0 {
            let uty = svector(self.inputs);
            quote!(, u: &#uty)
        } else {
            quote!()
        }
    }

    /// The arguments of a method, `&self` included.
    fn arguments(self, takes: Arguments) -> TokenStream {
        let (qty, rty, xty, u_arg) = (
            svector(self.n),
            svector(self.k),
            svector(self.state),
            self.u_arg(),
        );
        let vel = velocity_argument(self.speeds);
        match takes {
            Arguments::Coordinates => quote!(&self, q: &#qty),
            Arguments::Velocities => quote!(&self, q: &#qty, #vel: &#rty),
            Arguments::TimedVelocities => quote!(&self, t: T, q: &#qty, #vel: &#rty),
            Arguments::Motion => quote!(&self, t: T, q: &#qty, #vel: &#rty #u_arg),
            Arguments::State => quote!(&self, t: T, x: &#xty #u_arg),
            Arguments::Kinematics => quote!(&self, t: T, q: &#qty, #vel: &#rty),
            Arguments::Variational => {
                let (dp, dd) = (
                    smatrix(self.state, self.sens),
                    smatrix(self.state, self.state),
                );
                quote!(&self, t: T, x: &#xty, s_p: &#dp, s_x0: &#dd)
            }
            Arguments::Receiver => quote!(&self),
        }
    }

    /// The return type of a method.
    fn returns(self, returns: Returns) -> TokenStream {
        let Dims { n, k, p, .. } = self;
        let dim = self.state;
        match returns {
            Returns::Dependent => svector(p),
            Returns::Independent => svector(k),
            Returns::ReducedSystem => {
                let (kk, rty) = (smatrix(k, k), svector(k));
                quote!((#kk, #rty))
            }
            Returns::Curvature => {
                let kk = smatrix(k, k);
                quote!([#kk; #p])
            }
            Returns::Scalar => quote!(T),
            Returns::Cyclic => svector(self.cyclic),
            Returns::Symmetric => svector(self.symmetric),
            Returns::Declared => svector(self.declared),
            Returns::ConstraintMatrix => smatrix(p, k),
            Returns::ContactPoints => smatrix(3, self.contacts),
            Returns::MassMatrix if self.speeds => smatrix(k, k),
            Returns::MassMatrix => smatrix(n, n),
            Returns::Coordinates => svector(n),
            Returns::StateMatrix => smatrix(dim, dim),
            Returns::StateAndInputMatrices => {
                let (dd, du) = (smatrix(dim, dim), smatrix(dim, self.inputs));
                quote!((#dd, #du))
            }
            Returns::State => svector(dim),
            Returns::ParameterMatrix => smatrix(dim, self.sens),
            Returns::Variational => {
                let (dp, dd) = (smatrix(dim, self.sens), smatrix(dim, dim));
                let xty = svector(dim);
                quote!((#xty, #dp, #dd))
            }
            Returns::SensitivitySystem => {
                let (p, a) = (self.sens, self.augmented());
                quote!(__nh_private::nh_runtime::Sensitivities<'_, Self, #dim, #p, #a>)
            }
        }
    }
}

/// The whole expansion for a system of the given shape.
pub fn expand(shape: &Shape, bodies: &mut dyn Bodies) -> TokenStream {
    let dims = Dims::of(shape);
    let params = field_names(&shape.params);
    let Inherent {
        lanes: lane_methods,
        scalar: methods,
        in_lanes,
    } = inherent_methods(shape, dims, bodies);
    let route_consts = if shape.outputs.contains(Output::Routes) {
        bodies.route_consts()
    } else {
        quote!()
    };
    let rhs = bodies.method(GeneratedMethod::Rhs);
    let mut hooks = bodies.runtime_hooks(&svector(dims.state));
    hooks.extend(atlas::atlas_methods(shape, dims));
    let lane_impl = lane_impl(shape, dims, &rhs, &in_lanes);
    let runtime_impl = runtime_impl(shape, dims, rhs, hooks);
    let jacobian_impl = jacobian_impl(shape, dims);
    let (sensitivity_consts, sensitivity_impl) = sensitivities(shape, dims);
    let hoisting = bodies.hoisting();
    let (lane_methods, methods, lane_bound, lane_impl) =
        lanes_if_cache_allows(&hoisting.1, lane_methods, methods, lane_impl);
    let cache = Cache::new(&params, hoisting);
    let constants = constants(shape, dims);
    let new_fn = new_fn(&params, &cache);
    let named::Companions {
        structs: companions,
        impls: companion_impls,
        methods: companion_methods,
    } = named::companions(shape, dims, &params);
    let Cache {
        fields: cache_fields,
        methods: cache_methods,
        ..
    } = cache;
    let Shape {
        attrs, vis, name, ..
    } = shape;
    let (phantom_field, derive) = phantom_and_derive(params.is_empty());
    let field_docs: Vec<String> = params.iter().map(|p| format!("Parameter `{p}`.")).collect();
    let description = struct_description(shape, &*bodies);
    let inherited = crate::attrs::inherited(attrs);
    let krate = shape.krate;
    let private = private();
    let arg_names = argument_names(&params, dims.speeds);
    let allow = allow_lints();
    // the derives of `crate::attrs::DERIVED` (a user's derive of one of
    // them is an error at its path, see `attrs::check_derives`)
    quote! {
        #(#attrs)*
        #(#[doc = #description])*
        #[allow(non_snake_case)]
        #derive
        #vis struct #name<T = ::core::primitive::f64> {
            #(#[doc = #field_docs] pub #params: T,)*
            #phantom_field
            #cache_fields
        }

        #companions

        #(#inherited)*
        const _: () = {
            use #krate::__private as #private;
            #(
                #[allow(dead_code, non_snake_case, clippy::all)]
                fn #arg_names() {}
            )*

            // the constants do not depend on the scalar: on `Name<f64>`
            // alone, `Name::N` needs no type argument (an impl for every
            // `T` would leave `T` to infer, and nothing fixes it)
            #allow
            impl #name<::core::primitive::f64> {
                #constants
                #route_consts
                #sensitivity_consts
            }

            // straight-line methods, for `f64` and for lanes alike (DESIGN §6.8)
            #allow
            impl<T: #lane_bound> #name<T> {
                #new_fn
                #cache_methods

                /// A constant of the generated code as `T`.
                #[doc(hidden)]
                #[inline(always)]
                fn __nh_c(x: ::core::primitive::f64) -> T {
                    __nh_private::nalgebra::convert::<::core::primitive::f64, T>(x)
                }

                #lane_methods
            }

            #allow
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy> #name<T> {
                #companion_methods
                #methods
            }

            #runtime_impl
            #lane_impl
            #jacobian_impl
            #sensitivity_impl
            #companion_impls
        };
    }
}

/// The impls of the methods (DESIGN §6.8): the straight-line ones for
/// every `T: Lanes`, with the lanes' runtime trait, when the parameter
/// cache (computed in that impl) is straight-line too; otherwise all of
/// them for `T: RealField` and no lanes. Returns (methods in the first
/// impl, methods in the `RealField` impl, the first impl's bound, the
/// runtime trait's impl).
fn lanes_if_cache_allows(
    cache_code: &TokenStream,
    lane_methods: TokenStream,
    methods: TokenStream,
    lane_impl: TokenStream,
) -> (TokenStream, TokenStream, TokenStream, TokenStream) {
    if lanes::straight_line(cache_code) {
        let bound = quote!(__nh_private::nh_runtime::Lanes);
        (lane_methods, methods, bound, lane_impl)
    } else {
        let scalar = quote!(__nh_private::nalgebra::RealField + ::core::marker::Copy);
        (quote!(), quote!(#lane_methods #methods), scalar, quote!())
    }
}

/// The struct's marker field for the scalar when it has no parameters (a
/// field of type `T` otherwise fixes it), and its derives.
fn phantom_and_derive(no_parameters: bool) -> (TokenStream, TokenStream) {
    if no_parameters {
        (
            quote!(#[doc(hidden)] pub __nh_scalar: ::core::marker::PhantomData<T>,),
            quote!(#[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::cmp::PartialEq, ::core::default::Default)]),
        )
    } else {
        (
            quote!(),
            quote!(#[derive(::core::clone::Clone, ::core::marker::Copy, ::core::fmt::Debug, ::core::cmp::PartialEq)]),
        )
    }
}

/// The struct's documentation after the user's: its vectors, rotations,
/// bodies and contacts, then its charts.
fn struct_description(shape: &Shape, bodies: &dyn Bodies) -> Vec<String> {
    let mut description = bodies.description();
    if !description.is_empty() {
        description.splice(
            0..0,
            [
                String::new(),
                "# Vectors, rotations and bodies".to_string(),
                String::new(),
            ],
        );
    }
    description.extend(atlas::atlas_doc(shape));
    description
}

/// The parameters as field names: a parameter that cannot be a field (a
/// keyword such as `self`, or a repeated name: both already reported) gets
/// a stand-in name, so the struct emitted next to the errors compiles and
/// `new` keeps its arity.
fn field_names(params: &[Ident]) -> Vec<Ident> {
    params
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if crate::names::is_rust_identifier(p) && !params[..i].contains(p) {
                p.clone()
            } else {
                format_ident!("__nh_parameter_{}", i)
            }
        })
        .collect()
}

/// The inherent methods of a system, in two impls.
struct Inherent {
    /// The straight-line methods: for every `T: Lanes`.
    lanes: TokenStream,
    /// The others: for `T: RealField`.
    scalar: TokenStream,
    /// The names of the methods in `lanes`.
    in_lanes: Vec<String>,
}

/// The inherent methods the system has, from the table, with their bodies.
fn inherent_methods(shape: &Shape, dims: Dims, bodies: &mut dyn Bodies) -> Inherent {
    let mut methods = Inherent {
        lanes: TokenStream::new(),
        scalar: TokenStream::new(),
        in_lanes: Vec::new(),
    };
    for spec in METHODS.iter().filter(|s| s.method != GeneratedMethod::Rhs) {
        let asked = spec.requested_by.is_some_and(|o| shape.outputs.contains(o));
        if !(spec.is_requested(shape) || bodies.every_output_asked() && asked) {
            continue;
        }
        let Method { doc, body } = bodies.method(spec.method);
        let id = format_ident!("{}", spec.name);
        let takes = match spec.takes {
            Arguments::Velocities if shape.rheonomic => Arguments::TimedVelocities,
            takes => takes,
        };
        let (args, ret) = (dims.arguments(takes), dims.returns(spec.returns));
        let method = quote! {
            #[doc = #doc]
            #[inline]
            pub fn #id(#args) -> #ret {
                #body
            }
        };
        if lanes::straight_line(&body) {
            methods.lanes.extend(method);
            methods.in_lanes.push(spec.name.to_string());
        } else {
            methods.scalar.extend(method);
        }
    }
    methods
}

/// The runtime's `LaneSystem` (`LaneControlledSystem` with inputs) for a
/// system whose right-hand side, and every method it calls, is
/// straight-line (DESIGN §6.8).
fn lane_impl(shape: &Shape, dims: Dims, rhs: &Method, in_lanes: &[String]) -> TokenStream {
    let body = &rhs.body;
    let calls = lanes::calls_on_self(body);
    if !lanes::straight_line(body) || !calls.iter().all(|c| in_lanes.contains(c)) {
        return quote!();
    }
    let (name, dim, n_in) = (shape.name, dims.state, dims.inputs);
    let xty = svector(dim);
    let allow = allow_lints();
    if n_in > 0 {
        let uty = svector(n_in);
        return quote! {
            #allow
            impl<T: __nh_private::nh_runtime::Lanes> __nh_private::nh_runtime::LaneControlledSystem<T, #dim, #n_in> for #name<T> {
                /// The first-order system's right-hand side at one state and input per lane (see `ControlledSystem::rhs_with_input`).
                #[inline]
                fn lane_rhs_with_input(&self, t: T, x: &#xty, u: &#uty) -> #xty {
                    #body
                }
            }
        };
    }
    quote! {
        #allow
        impl<T: __nh_private::nh_runtime::Lanes> __nh_private::nh_runtime::LaneSystem<T, #dim> for #name<T> {
            /// The first-order system's right-hand side at one state per lane (see `OdeSystem::rhs`).
            #[inline]
            fn lane_rhs(&self, t: T, x: &#xty) -> #xty {
                #body
            }
        }
    }
}

/// The runtime trait implementation: `OdeSystem`, or `ControlledSystem`
/// for a system with inputs.
fn runtime_impl(shape: &Shape, dims: Dims, rhs: Method, hooks: TokenStream) -> TokenStream {
    let Method { doc, body } = rhs;
    let (name, dim, n_in) = (shape.name, dims.state, dims.inputs);
    let xty = svector(dim);
    let allow = allow_lints();
    let (runtime_trait, rhs_fn) = if n_in > 0 {
        let uty = svector(n_in);
        (
            quote!(ControlledSystem<T, #dim, #n_in>),
            quote!(fn rhs_with_input(&self, t: T, x: &#xty, u: &#uty) -> #xty),
        )
    } else {
        (
            quote!(OdeSystem<T, #dim>),
            quote!(fn rhs(&self, t: T, x: &#xty) -> #xty),
        )
    };
    quote! {
        #allow
        impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
            __nh_private::nh_runtime::#runtime_trait for #name<T>
        {
            #[doc = #doc]
            #[inline]
            #rhs_fn {
                #body
            }
            #hooks
        }
    }
}

/// The runtime's `OdeJacobian` for a system with `jacobian` (its
/// `ControlledJacobian` with inputs, which `Driven` makes an `OdeJacobian`).
fn jacobian_impl(shape: &Shape, dims: Dims) -> TokenStream {
    if !shape.outputs.contains(Output::Jacobian) {
        return quote!();
    }
    let (name, dim, n_in) = (shape.name, dims.state, dims.inputs);
    let (xty, dd) = (svector(dim), smatrix(dim, dim));
    let allow = allow_lints();
    let in_chart = atlas::jacobian_in_chart(shape, dims);
    if n_in > 0 {
        let uty = svector(n_in);
        return quote! {
            #allow
            impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
                __nh_private::nh_runtime::ControlledJacobian<T, #dim, #n_in> for #name<T>
            {
                /// ∂f/∂x of the first-order system at the input `u`, derived symbolically (see the inherent `jacobian`).
                #[inline]
                fn jacobian_with_input(&self, t: T, x: &#xty, u: &#uty) -> #dd {
                    #name::jacobian(self, t, x, u)
                }

                /// ∂f/∂t at the input `u`, derived symbolically (see the inherent `time_derivative`).
                #[inline]
                fn time_derivative_with_input(&self, t: T, x: &#xty, u: &#uty) -> ::core::option::Option<#xty> {
                    ::core::option::Option::Some(#name::time_derivative(self, t, x, u))
                }
                #in_chart
            }
        };
    }
    quote! {
        #allow
        impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
            __nh_private::nh_runtime::OdeJacobian<T, #dim> for #name<T>
        {
            /// ∂f/∂x of the first-order system, derived symbolically (see the inherent `jacobian`).
            #[inline]
            fn jacobian(&self, t: T, x: &#xty) -> #dd {
                #name::jacobian(self, t, x)
            }

            /// ∂f/∂t, derived symbolically (see the inherent `time_derivative`).
            #[inline]
            fn time_derivative(&self, t: T, x: &#xty) -> ::core::option::Option<#xty> {
                ::core::option::Option::Some(#name::time_derivative(self, t, x))
            }
            #in_chart
        }
    }
}

/// For a system with `sensitivities`: its constants (the parameters and
/// the augmented dimension) and the runtime's `ParameterJacobian` (not
/// with inputs, which `sensitivities` rejects).
fn sensitivities(shape: &Shape, dims: Dims) -> (TokenStream, TokenStream) {
    if !shape.outputs.contains(Output::Sensitivities) {
        return (quote!(), quote!());
    }
    let (dim, p, a) = (dims.state, dims.sens, dims.augmented());
    let names: Vec<Literal> = shape
        .sensitivity_params
        .iter()
        .map(|p| Literal::string(&syn::ext::IdentExt::unraw(p).to_string()))
        .collect();
    let consts = quote! {
        /// The parameters of [`Self::parameter_jacobian`] and [`Self::sensitivities`], in the order of their columns.
        pub const SENSITIVITY_PARAMETERS: [&'static ::core::primitive::str; #p] = [#(#names),*];
        /// Length of the augmented state of [`Self::sensitivities`], [x, ∂x/∂p, ∂x/∂x0] (columns stacked): D·(1 + P + D) with D = [`Self::STATE_DIM`] and P the number of [`Self::SENSITIVITY_PARAMETERS`].
        pub const SENSITIVITY_DIM: ::core::primitive::usize = #a;
    };
    if dims.inputs > 0 {
        return (consts, quote!());
    }
    let name = shape.name;
    let (xty, dp, dd) = (svector(dim), smatrix(dim, p), smatrix(dim, dim));
    let allow = allow_lints();
    let imp = quote! {
        #allow
        impl<T: __nh_private::nalgebra::RealField + ::core::marker::Copy>
            __nh_private::nh_runtime::ParameterJacobian<T, #dim, #p> for #name<T>
        {
            /// ∂f/∂p, derived symbolically (see the inherent `parameter_jacobian`).
            #[inline]
            fn parameter_jacobian(&self, t: T, x: &#xty) -> #dp {
                #name::parameter_jacobian(self, t, x)
            }

            /// The variational equations in one body (see the inherent `variational_rhs`).
            #[inline]
            fn variational_rhs(&self, t: T, x: &#xty, s_p: &#dp, s_x0: &#dd) -> (#xty, #dp, #dd) {
                #name::variational_rhs(self, t, x, s_p, s_x0)
            }
        }
    };
    (consts, imp)
}

/// The associated constants: the coordinates, their partition, the inputs,
/// the sizes and integrability.
fn constants(shape: &Shape, dims: Dims) -> TokenStream {
    let Dims { n, k, p, .. } = dims;
    let (n_in, dim) = (dims.inputs, dims.state);
    let coord_names: Vec<Literal> = shape.coords.iter().map(|c| Literal::string(c)).collect();
    let input_names: Vec<Literal> = shape.inputs.iter().map(|c| Literal::string(c)).collect();
    if dims.speeds {
        let speed_names: Vec<Literal> = shape.speeds.iter().map(|c| Literal::string(c)).collect();
        return quote! {
            /// The generalized coordinates in declared order: the coordinate order of `q` everywhere.
            pub const COORDINATES: [&'static ::core::primitive::str; #n] = [#(#coord_names),*];
            /// The generalized speeds u in declared order: the order of `speeds` everywhere.
            pub const SPEEDS: [&'static ::core::primitive::str; #k] = [#(#speed_names),*];
            /// The inputs in declared order.
            pub const INPUTS: [&'static ::core::primitive::str; #n_in] = [#(#input_names),*];
            /// Number of coordinates n.
            pub const N: ::core::primitive::usize = #n;
            /// Number of generalized speeds k.
            pub const K: ::core::primitive::usize = #k;
            /// Length of the runtime state x = [q, u]: n + k.
            pub const STATE_DIM: ::core::primitive::usize = #dim;
        };
    }
    let indep = &shape.independent;
    let dep = &shape.dependent;
    let integrable = shape.integrable;
    let momenta = momentum_constants(shape);
    let symmetries = symmetry_constants(shape);
    let declared = declared_momentum_constants(shape);
    let integrable_doc = if p == 0 {
        "No constraints: trivially `true`.".to_string()
    } else if shape.affine {
        "`false`: some constraint has an affine or time-dependent term, which the curvature test (5.21) does not cover; such constraints are not reported as integrable.".to_string()
    } else if integrable {
        "`true`: every curvature coefficient B^b_{αβ} (5.21) is identically zero, so the constraints are integrable (holonomic in disguise) and could be eliminated by integrating them.".to_string()
    } else {
        "`false`: some curvature coefficient B^b_{αβ} (5.21) is not identically zero, so the constraints are genuinely nonholonomic.".to_string()
    };
    let dependent_doc = match &shape.dependent_doc {
        Some(doc) => quote!(#[doc = #doc]),
        None => quote!(
            /// Indices in `q` of the dependent coordinates s (one per constraint), ascending.
        ),
    };
    quote! {
        /// The generalized coordinates in declared order: the coordinate order of `q` everywhere.
        pub const COORDINATES: [&'static ::core::primitive::str; #n] = [#(#coord_names),*];
        /// Indices in `q` of the independent coordinates r, ascending.
        pub const INDEPENDENT: [::core::primitive::usize; #k] = [#(#indep),*];
        #dependent_doc
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
        #momenta
        #symmetries
        #declared
    }
}

/// `MOMENTA` and `MOMENTUM_CONSERVED`, for declared momenta (a stand-in,
/// whose system has errors, says `Undecided`).
fn declared_momentum_constants(shape: &Shape) -> TokenStream {
    if shape.momentum_names.is_empty() {
        return TokenStream::new();
    }
    let d = shape.momentum_names.len();
    let names = shape.momentum_names.iter().map(|n| Literal::string(n));
    let verdicts = (0..d).map(|i| {
        let v = shape.declared_momenta.get(i).map_or("Undecided", |v| v.0);
        let v = Ident::new(v, Span::call_site());
        quote!(__nh_private::nh_runtime::Conservation::#v)
    });
    let mut doc = String::from(
        "Whether each declared momentum is conserved along the motion: J = ⟨∂L/∂q̇, X(q)⟩ along its direction X(q), a motion the constraints allow, whose rate is dJ/dt = ⟨∂L/∂q, X⟩ + ⟨∂L/∂q̇, Ẋ⟩ + ⟨Q, X⟩.\n",
    );
    for (name, (_, words)) in shape.momentum_names.iter().zip(&shape.declared_momenta) {
        doc.push_str(&format!("\n- `{name}`: {words}"));
    }
    quote! {
        /// The declared momenta (`momenta { .. }`) in declared order, each along a motion the constraints allow (checked at compile time).
        pub const MOMENTA: [&'static ::core::primitive::str; #d] = [#(#names),*];
        #[doc = #doc]
        pub const MOMENTUM_CONSERVED: [__nh_private::nh_runtime::Conservation; #d] = [#(#verdicts),*];
    }
}

/// `SYMMETRIES` and `SYMMETRY_CONSERVED`, for declared symmetries.
fn symmetry_constants(shape: &Shape) -> TokenStream {
    if shape.symmetries.is_empty() {
        return TokenStream::new();
    }
    let g = shape.symmetries.len();
    let s = shape.symmetry_momenta.len();
    let names = shape.symmetries.iter().map(|n| Literal::string(n));
    let verdicts = shape.symmetry_momenta.iter().map(|(v, _)| {
        let v = Ident::new(v, Span::call_site());
        quote!(__nh_private::nh_runtime::Conservation::#v)
    });
    let mut doc = String::from(
        "Whether each momentum of `symmetry_momenta` is conserved along the motion: the momentum J = ⟨∂L/∂q̇, ξ(q)⟩ along a direction ξ(q) = Σ_i c_i(q) ξ_i of the declared symmetries' generators that the constraints allow, whose rate is dJ/dt = ⟨∂L/∂q̇, Σ_i ċ_i ξ_i⟩ + ⟨Q, ξ(q)⟩ (the nonholonomic momentum equation).\n",
    );
    for (i, (_, d)) in shape.symmetry_momenta.iter().enumerate() {
        doc.push_str(&format!("\n{i}. {d}"));
    }
    quote! {
        /// The declared symmetries in declared order: one-parameter groups whose flows leave the Lagrangian, the forces and the constraints invariant (checked at compile time).
        pub const SYMMETRIES: [&'static ::core::primitive::str; #g] = [#(#names),*];
        #[doc = #doc]
        pub const SYMMETRY_CONSERVED: [__nh_private::nh_runtime::Conservation; #s] = [#(#verdicts),*];
    }
}

/// `CYCLIC` and `CONSERVED`, with `outputs { momenta }` (§5.5).
fn momentum_constants(shape: &Shape) -> TokenStream {
    if !shape.outputs.contains(Output::Momenta) {
        return TokenStream::new();
    }
    let m = shape.momenta.len();
    let cyclic = shape.momenta.iter().map(|c| c.coordinate);
    let verdicts = shape.momenta.iter().map(|c| {
        let v = Ident::new(c.verdict, Span::call_site());
        quote!(__nh_private::nh_runtime::Conservation::#v)
    });
    let mut doc = String::from(
        "Whether the momentum p_k = ∂Lc/∂ṙ_k of each cyclic coordinate (in the order of `CYCLIC`) is conserved: its rate (5.36), `momentum_rates`, vanishes identically (`Conserved`, proved by the engine), is nonzero somewhere (`NotConserved`), or vanishes at every sampled point without being proved zero (`Undecided`).\n",
    );
    for c in &shape.momenta {
        doc.push_str(&format!("\n- `{}`: {}", shape.coords[c.coordinate], c.doc));
    }
    quote! {
        /// Indices in `q` of the cyclic coordinates (§5.5): independent coordinates of which the Lagrangian, the forces and the constraints are free. `momenta` and `momentum_rates` follow this order.
        pub const CYCLIC: [::core::primitive::usize; #m] = [#(#cyclic),*];
        #[doc = #doc]
        pub const CONSERVED: [__nh_private::nh_runtime::Conservation; #m] = [#(#verdicts),*];
    }
}

/// A function for every argument name: it shadows a user's constant,
/// static or unit struct of that name, which the argument pattern would
/// match instead of binding (functions do not take part in patterns).
fn argument_names(params: &[Ident], speeds: bool) -> Vec<Ident> {
    let mut arg_names: Vec<Ident> = ["t", "q", "rdot", "x", "u", "s_p", "s_x0"]
        .iter()
        .map(|a| format_ident!("{a}"))
        .collect();
    if speeds {
        arg_names.push(velocity_argument(true));
    }
    for a in named::ARGUMENTS {
        let a = format_ident!("{a}");
        if !arg_names.contains(&a) {
            arg_names.push(a);
        }
    }
    for p in params {
        if !arg_names.contains(p) {
            arg_names.push(p.clone());
        }
    }
    arg_names
}

/// The name of the argument holding the state's velocity part: `rdot`
/// (the independent velocities), or `speeds` in generalized speeds.
pub fn velocity_argument(speeds: bool) -> Ident {
    format_ident!("{}", if speeds { "speeds" } else { "rdot" })
}

/// Bodies of a system that failed to expand: each method diverges. They are
/// never run, since the expansion also carries the compile errors; they only
/// keep the user's code that calls the system free of follow-up errors.
pub struct StandIn;

impl Bodies for StandIn {
    fn hoisting(&mut self) -> (usize, TokenStream) {
        (0, TokenStream::new())
    }

    fn method(&mut self, _method: GeneratedMethod) -> Method {
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

    fn every_output_asked(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::{GeneratedMethod, METHODS};

    #[test]
    fn every_method_has_its_row() {
        for (i, spec) in METHODS.iter().enumerate() {
            assert_eq!(spec.method as usize, i, "{}", spec.name);
            assert_eq!(spec.method.spec().name, spec.name);
        }
        assert_eq!(GeneratedMethod::Rhs.spec().name, "rhs");
    }
}
