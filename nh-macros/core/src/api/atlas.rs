//! The runtime trait's atlas methods (DESIGN §9.3): the system's charts,
//! each of the others a hidden system of its own (the same definition with
//! the implicit and holonomic rows solved for other coordinates), reached
//! by a `match` on the chart's index.

use super::{Dims, Shape, field_names, svector};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

/// One chart of the atlas, as the API sees it.
#[derive(Clone, Debug)]
pub struct ChartShape {
    /// The hidden struct of the chart (`None`: the system's own chart).
    pub system: Option<Ident>,
    /// "solved for `x`, `y`".
    pub name: String,
    /// Where the chart is singular.
    pub singular: String,
    /// Indices of its independent coordinates.
    pub independent: Vec<usize>,
    /// Indices of its dependent coordinates, ascending.
    pub dependent: Vec<usize>,
    /// Whether its `dependent_velocities` takes `t`.
    pub rheonomic: bool,
    /// Whether its hidden system has a Jacobian.
    pub jacobian: bool,
    /// The sequence its free rotation is read in (DESIGN §9.4), in an
    /// atlas of a rotation's charts.
    pub euler: Option<EulerShape>,
}

/// A free rotation's sequence in one chart.
#[derive(Clone, Debug)]
pub struct EulerShape {
    /// The runtime's `EulerSequence` constant: `ZYX`.
    pub sequence: String,
    /// The angles' coordinates (indices in q), in the order of the factors.
    pub angles: [usize; 3],
    /// Whether the system writes the angular velocity in world components
    /// (the runtime's `FreeRotation::world`).
    pub world: bool,
}

/// The lines of the struct's documentation that list the charts.
pub fn atlas_doc(shape: &Shape) -> Vec<String> {
    if shape.atlas.is_empty() {
        return Vec::new();
    }
    let mut lines = vec![
        String::new(),
        "# Charts".to_string(),
        String::new(),
        format!(
            "The constraints are solved for the dependent velocities in one of {} charts (DESIGN §9.3); a run starts in chart 0, the layout of the state, and the integrators move to another chart where the current one degrades (`OdeSystem::change_chart`):",
            shape.atlas.len()
        ),
        String::new(),
    ];
    for (c, chart) in shape.atlas.iter().enumerate() {
        lines.push(format!(
            "{c}. {}: singular where {}",
            chart.name, chart.singular
        ));
    }
    lines
}

/// The atlas methods of the runtime trait for state type `xty`; none for
/// a system with one chart.
pub fn atlas_methods(shape: &Shape, dims: Dims) -> TokenStream {
    if shape.atlas.is_empty() {
        return TokenStream::new();
    }
    let dim = dims.state;
    let xty = svector(dim);
    let n_in = dims.inputs;
    let (trait_path, rhs_call, rhs_sig) = if n_in > 0 {
        let uty = svector(n_in);
        (
            quote!(__nh_private::nh_runtime::ControlledSystem<T, #dim, #n_in>),
            quote!(rhs_with_input),
            quote!(fn rhs_with_input_in_chart(&self, chart: usize, t: T, x: &#xty, u: &#uty) -> #xty),
        )
    } else {
        (
            quote!(__nh_private::nh_runtime::OdeSystem<T, #dim>),
            quote!(rhs),
            quote!(fn rhs_in_chart(&self, chart: usize, t: T, x: &#xty) -> #xty),
        )
    };
    let u_arg = if n_in > 0 { quote!(, u) } else { quote!() };
    let params = field_names(&shape.params);
    let count = shape.atlas.len();
    // the system of chart `c`, as an expression
    let system = |c: &ChartShape| match &c.system {
        Some(id) => quote!(&#id::<T>::new(#(self.#params),*)),
        None => quote!(self),
    };
    let arms = |body: &dyn Fn(TokenStream) -> TokenStream| {
        let mut arms = TokenStream::new();
        for (c, chart) in shape.atlas.iter().enumerate().skip(1) {
            let b = body(system(chart));
            arms.extend(quote!(#c => #b,));
        }
        let own = body(quote!(self));
        quote!(match chart { #arms _ => #own })
    };
    let names: Vec<TokenStream> = shape
        .atlas
        .iter()
        .enumerate()
        .skip(1)
        .map(|(c, chart)| {
            let name = &chart.name;
            quote!(#c => #name,)
        })
        .collect();
    let own_name = &shape.atlas[0].name;
    let rhs = arms(&|s| quote!(<_ as #trait_path>::#rhs_call(#s, t, x #u_arg)));
    let regularity = arms(&|s| quote!(<_ as #trait_path>::chart_regularity(#s, t, x)));
    let pole = arms(&|s| quote!(<_ as #trait_path>::crossed_pole(#s, t0, x0, t1, x1)));
    let residual = arms(&|s| quote!(<_ as #trait_path>::constraint_residual(#s, t, x)));
    let project = arms(&|s| quote!(<_ as #trait_path>::project(#s, t, x)));
    let change = change_chart(shape, dims, &system);
    // the charts of a free rotation leave a sequence at |cos β| = 0.4, where
    // the one whose pole is in the same row has |cos β| ≥ 0.91 (DESIGN §9.4)
    let switch_below = shape.atlas.iter().any(|c| c.euler.is_some()).then(|| {
        quote! {
            #[inline]
            fn chart_switch_below(&self, chart: usize) -> f64 {
                let _ = chart;
                0.4
            }
        }
    });
    let free_rotation = free_rotation(shape, dims);
    quote! {
        #[inline]
        fn charts(&self) -> usize { #count }
        fn chart_name(&self, chart: usize) -> &'static str {
            match chart { #(#names)* _ => #own_name }
        }
        #[inline]
        #rhs_sig { #rhs }
        #[inline]
        fn chart_regularity_in(&self, chart: usize, t: T, x: &#xty) -> ::core::option::Option<T> { #regularity }
        #[inline]
        fn crossed_pole_in(&self, chart: usize, t0: T, x0: &#xty, t1: T, x1: &#xty) -> ::core::option::Option<&'static str> { #pole }
        #[inline]
        fn constraint_residual_in(&self, chart: usize, t: T, x: &#xty) -> ::core::option::Option<T> { #residual }
        #[inline]
        fn project_in(&self, chart: usize, t: T, x: &mut #xty) -> ::core::result::Result<bool, __nh_private::nh_runtime::ProjectionFailure<T>> { #project }
        #change
        #switch_below
        #free_rotation
    }
}

/// `free_rotation`, for charts of a free rotation: each chart's sequence,
/// the slots of the angles (their coordinates) and of their rates (the
/// independent velocities after the coordinates).
fn free_rotation(shape: &Shape, dims: Dims) -> Option<TokenStream> {
    let (mut arms, mut own) = (TokenStream::new(), None);
    for (c, chart) in shape.atlas.iter().enumerate() {
        let e = chart.euler.as_ref()?;
        let id = Ident::new(&e.sequence, proc_macro2::Span::call_site());
        let rates = e.angles.map(|a| {
            chart
                .independent
                .iter()
                .position(|&i| i == a)
                .map(|p| dims.n + p)
        });
        let [Some(r0), Some(r1), Some(r2)] = rates else {
            return None;
        };
        let world = e.world;
        let angles = e.angles.map(Literal::usize_unsuffixed);
        let rates = [r0, r1, r2].map(Literal::usize_unsuffixed);
        let arm = quote! {
            __nh_private::nh_runtime::FreeRotation {
                sequence: __nh_private::nh_runtime::EulerSequence::#id,
                angles: [#(#angles),*],
                rates: [#(#rates),*],
                world: #world,
            }
        };
        if c == 0 {
            own = Some(arm);
        } else {
            arms.extend(quote!(#c => #arm,));
        }
    }
    let own = own?;
    Some(quote! {
        #[inline]
        fn free_rotation(&self, chart: usize) -> ::core::option::Option<__nh_private::nh_runtime::FreeRotation> {
            ::core::option::Option::Some(match chart { #arms _ => #own })
        }
    })
}

/// `change_chart`: the full velocity from chart `from`'s dependent
/// velocities, then chart `to`'s independent velocities read off it; with
/// charts of a free rotation, its angles and their rates in `to`'s
/// sequence in between, and `change_chart_near`, whose angles are the ones
/// nearest `near`'s.
fn change_chart(
    shape: &Shape,
    dims: Dims,
    system: &dyn Fn(&ChartShape) -> TokenStream,
) -> TokenStream {
    let xty = svector(dims.state);
    let body = |near: TokenStream| change_chart_body(shape, dims, system, near);
    let Some(angles) = shape
        .atlas
        .iter()
        .find_map(|c| c.euler.as_ref())
        .map(|e| e.angles)
    else {
        let plain = body(TokenStream::new());
        return quote! {
            fn change_chart(&self, from: usize, to: usize, t: T, x: &#xty) -> #xty {
                #plain
            }
        };
    };
    let lits = angles.map(Literal::usize_unsuffixed);
    let principal = body(quote!(::core::option::Option::None));
    let nearest = body(quote!(::core::option::Option::Some(&[#(near[#lits]),*])));
    quote! {
        fn change_chart(&self, from: usize, to: usize, t: T, x: &#xty) -> #xty {
            #principal
        }
        fn change_chart_near(&self, from: usize, to: usize, t: T, x: &#xty, near: &#xty) -> #xty {
            #nearest
        }
    }
}

/// The body of `change_chart` (`near`: empty without charts of a free
/// rotation, else the `Option` of the angles to be nearest).
fn change_chart_body(
    shape: &Shape,
    dims: Dims,
    system: &dyn Fn(&ChartShape) -> TokenStream,
    near: TokenStream,
) -> TokenStream {
    let (n, k) = (dims.n, dims.k);
    let qty = svector(n);
    let rty = svector(k);
    let mut from_arms = TokenStream::new();
    let mut to_arms = TokenStream::new();
    let mut seq_arms = TokenStream::new();
    for (c, chart) in shape.atlas.iter().enumerate() {
        let s = system(chart);
        let t_arg = if chart.rheonomic {
            quote!(t,)
        } else {
            quote!()
        };
        let lit = |v: &[usize]| -> Vec<Literal> {
            v.iter().map(|&i| Literal::usize_unsuffixed(i)).collect()
        };
        let (ind, dep) = (lit(&chart.independent), lit(&chart.dependent));
        let (ia, da) = (
            lit(&(0..k).collect::<Vec<_>>()),
            lit(&(0..dep.len()).collect::<Vec<_>>()),
        );
        let fill = quote! {{
            let __nh_s = (#s).dependent_velocities(#t_arg &__nh_q, &__nh_r);
            #(__nh_qdot[#ind] = __nh_r[#ia];)*
            #(__nh_qdot[#dep] = __nh_s[#da];)*
        }};
        let to = quote!([#(#ind),*]);
        let seq = chart.euler.as_ref().map(|e| {
            let id = Ident::new(&e.sequence, proc_macro2::Span::call_site());
            quote!(__nh_private::nh_runtime::EulerSequence::#id)
        });
        if c == 0 {
            from_arms.extend(quote!(_ => #fill));
            to_arms.extend(quote!(_ => #to));
            seq_arms.extend(quote!(_ => #seq));
        } else {
            from_arms = quote!(#c => #fill, #from_arms);
            to_arms = quote!(#c => #to, #to_arms);
            seq_arms = quote!(#c => #seq, #seq_arms);
        }
    }
    let rotation = shape.atlas.iter().find_map(|c| c.euler.as_ref()).map(|e| {
        let a = e.angles.map(Literal::usize_unsuffixed);
        let i = [0usize, 1, 2].map(Literal::usize_unsuffixed);
        quote! {
            // the free rotation: its angles and their rates in `to`'s sequence
            let __nh_seq = |__nh_c: usize| match __nh_c { #seq_arms };
            let (__nh_a, __nh_w) = __nh_private::nh_runtime::EulerSequence::change(
                __nh_seq(from),
                __nh_seq(to),
                &[#(__nh_q[#a]),*],
                &[#(__nh_qdot[#a]),*],
                #near,
            );
            #(__nh_y[#a] = __nh_a[#i];)*
            #(__nh_qdot[#a] = __nh_w[#i];)*
        }
    });
    quote! {
        let _ = t;
        if from == to {
            return *x;
        }
        let __nh_q: #qty = x.fixed_rows::<#n>(0).into_owned();
        let __nh_r: #rty = x.fixed_rows::<#k>(#n).into_owned();
        let mut __nh_qdot: #qty = <#qty>::zeros();
        match from { #from_arms }
        let __nh_to: [usize; #k] = match to { #to_arms };
        let mut __nh_y = *x;
        #rotation
        for (__nh_a, &__nh_i) in __nh_to.iter().enumerate() {
            __nh_y[#n + __nh_a] = __nh_qdot[__nh_i];
        }
        __nh_y
    }
}

/// `jacobian_in_chart` (`jacobian_with_input_in_chart` with inputs) of
/// the Jacobian's runtime trait, for a system with an atlas.
pub fn jacobian_in_chart(shape: &Shape, dims: Dims) -> TokenStream {
    if shape.atlas.is_empty() {
        return TokenStream::new();
    }
    let dim = dims.state;
    let (xty, dd) = (svector(dim), super::smatrix(dim, dim));
    let params = field_names(&shape.params);
    let n_in = dims.inputs;
    let (path, call, sig) = if n_in > 0 {
        let uty = svector(n_in);
        (
            quote!(__nh_private::nh_runtime::ControlledJacobian<T, #dim, #n_in>),
            quote!(jacobian_with_input),
            quote!(fn jacobian_with_input_in_chart(&self, chart: usize, t: T, x: &#xty, u: &#uty) -> ::core::option::Option<#dd>),
        )
    } else {
        (
            quote!(__nh_private::nh_runtime::OdeJacobian<T, #dim>),
            quote!(jacobian),
            quote!(fn jacobian_in_chart(&self, chart: usize, t: T, x: &#xty) -> ::core::option::Option<#dd>),
        )
    };
    let u_arg = if n_in > 0 { quote!(, u) } else { quote!() };
    let mut arms = TokenStream::new();
    for (c, chart) in shape.atlas.iter().enumerate().skip(1) {
        if let (Some(id), true) = (&chart.system, chart.jacobian) {
            arms.extend(quote! {
                #c => ::core::option::Option::Some(<_ as #path>::#call(&#id::<T>::new(#(self.#params),*), t, x #u_arg)),
            });
        }
    }
    quote! {
        #[inline]
        #sig {
            match chart {
                #arms
                0 => ::core::option::Option::Some(<_ as #path>::#call(self, t, x #u_arg)),
                _ => ::core::option::Option::None,
            }
        }
    }
}
