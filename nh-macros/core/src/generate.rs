//! Assembly of the generated struct, its inherent methods and its runtime
//! trait implementation (DESIGN §3), from the derived mechanics.

use crate::ctxt::Ctxt;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::lower::Model;
use crate::mechanics::{CurvatureRoute, MultiplierRoute};
use crate::parse::SystemDef;
use crate::sym::{ExprId, ZERO};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// Which derivation `accelerations` uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Lagrange multipliers eliminated by projection, (5.9)/(5.10).
    Multiplier,
    /// The constrained Lagrangian with the curvature term, (5.20)/(5.21).
    Curvature,
}

/// Figures about one expansion, for statistics and tests.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// The struct's name.
    pub name: String,
    /// Operations of `accelerations` by the multiplier route, after CSE.
    pub ops_multiplier: usize,
    /// Operations of `accelerations` by the curvature route, after CSE.
    pub ops_curvature: usize,
    /// Estimated cost (in additions) of the multiplier route.
    pub cost_multiplier: usize,
    /// Estimated cost (in additions) of the curvature route.
    pub cost_curvature: usize,
    /// The route `accelerations` uses.
    pub route: Option<Route>,
    /// Distinct expressions in the engine's graph at the end.
    pub graph_size: usize,
    /// Derivatives computed (memo misses).
    pub derivatives: usize,
    /// Whether every curvature entry is identically zero.
    pub integrable: bool,
    /// Which outputs were derived.
    pub derived: Vec<&'static str>,
    /// Lines of generated code (one statement or item per line, as `cargo expand` prints it).
    pub lines: usize,
}

impl Stats {
    /// One line: operation counts, route, graph size.
    pub fn summary(&self) -> String {
        format!(
            "accelerations: multiplier route {} ops (cost {}), curvature route {} ops (cost {}) after CSE, using the {} route; {} generated lines; graph {} expressions, {} derivatives; integrable: {}",
            self.ops_multiplier,
            self.cost_multiplier,
            self.ops_curvature,
            self.cost_curvature,
            match self.route {
                Some(Route::Multiplier) => "multiplier",
                Some(Route::Curvature) => "curvature",
                None => "(none)",
            },
            self.lines,
            self.graph_size,
            self.derivatives,
            self.integrable
        )
    }
}

/// Where the values of a function's arguments come from.
struct Args {
    coord: Vec<TokenStream>,
    rvel: Vec<TokenStream>,
}

impl Args {
    fn vectors(n: usize, k: usize) -> Args {
        Args {
            coord: (0..n).map(|i| quote!(q[#i])).collect(),
            rvel: (0..k).map(|j| quote!(rdot[#j])).collect(),
        }
    }

    fn state(n: usize, k: usize) -> Args {
        Args {
            coord: (0..n).map(|i| quote!(x[#i])).collect(),
            rvel: (0..k)
                .map(|j| {
                    let ix = n + j;
                    quote!(x[#ix])
                })
                .collect(),
        }
    }
}

/// A graph with every symbol of the model bound to its source.
fn bound_dag(m: &Model, args: &Args) -> Dag {
    let mut d = Dag::new();
    for (i, &s) in m.coord_syms.iter().enumerate() {
        let l = d.leaf_named(
            args.coord[i].clone(),
            &format!("q_{}", syn::ext::IdentExt::unraw(&m.coords[i])),
        );
        d.bind(s, l);
    }
    for (j, &i) in m.independent.iter().enumerate() {
        let l = d.leaf_named(
            args.rvel[j].clone(),
            &format!("dot_{}", syn::ext::IdentExt::unraw(&m.coords[i])),
        );
        d.bind(m.vel_syms[i], l);
    }
    for (p, &s) in m.params.iter().zip(&m.param_syms) {
        let l = d.leaf_named(
            quote!(self.#p),
            &format!("p_{}", syn::ext::IdentExt::unraw(p)),
        );
        d.bind(s, l);
    }
    for (j, &s) in m.input_syms.iter().enumerate() {
        let l = d.leaf_named(
            quote!(u[#j]),
            &format!("u_{}", syn::ext::IdentExt::unraw(&m.inputs[j])),
        );
        d.bind(s, l);
    }
    let t = d.leaf_named(quote!(t), "time");
    d.bind(m.t_sym, t);
    let pi = d.pi();
    d.bind(m.pi_sym, pi);
    // dependent velocities: computed from the constraints (5.3)
    for (a, &s) in m.dependent.iter().enumerate() {
        let v = d.expr(&m.engine, m.dependent_velocity[a]);
        d.label(
            v,
            format!(
                "dot({}): dependent velocity from the constraint (5.3)",
                m.coords[s]
            ),
        );
        d.bind(m.vel_syms[s], v);
    }
    d
}

fn exprs(d: &mut Dag, m: &Model, v: &[ExprId]) -> Vec<Node> {
    v.iter().map(|&e| d.expr(&m.engine, e)).collect()
}

fn matrix(d: &mut Dag, m: &Model, v: &[Vec<ExprId>]) -> Vec<Vec<Node>> {
    v.iter().map(|row| exprs(d, m, row)).collect()
}

/// The multiplier route in the graph: returns (r̈, q̈-independent parts) and
/// keeps the mass matrix and bias for the multipliers.
struct MultiplierNodes {
    rdd: Vec<Node>,
    mass: Vec<Vec<Node>>,
    bias: Vec<Node>,
    c: Vec<Vec<Node>>,
    acc_bias: Vec<Node>,
    pivots: Vec<Node>,
}

fn multiplier_nodes(d: &mut Dag, m: &Model, r: &MultiplierRoute) -> MultiplierNodes {
    let (n, k) = (m.n(), m.k());
    let mass = matrix(d, m, &r.mass);
    for (i, row) in mass.iter().enumerate() {
        for (j, &x) in row.iter().enumerate().skip(i) {
            d.label(x, format!("mass matrix ∂²L/∂q̇{i}∂q̇{j}"));
        }
    }
    let bias = exprs(d, m, &r.bias);
    for (i, &x) in bias.iter().enumerate() {
        d.label(
            x,
            format!("Euler–Lagrange term {i} without accelerations (3.9), forces included"),
        );
    }
    // q̇ = C ṙ with C = [I; −A] (rows in coordinate order)
    let mut c = vec![vec![ZERO_NODE; k]; n];
    for (j, &i) in m.independent.iter().enumerate() {
        c[i][j] = ONE_NODE;
    }
    for (a, &s) in m.dependent.iter().enumerate() {
        for b in 0..k {
            let x = d.expr(&m.engine, m.a_matrix[a][b]);
            c[s][b] = d.neg(x);
        }
    }
    // q̈ = C r̈ + acc_bias, acc_bias_s = −Ȧ ṙ
    let mut acc_bias = vec![ZERO_NODE; n];
    for (a, &s) in m.dependent.iter().enumerate() {
        acc_bias[s] = d.expr(&m.engine, r.dependent_bias[a]);
    }
    // Cᵀ M C r̈ = −Cᵀ (M acc_bias + h)   (5.9)
    let mut mc = vec![vec![ZERO_NODE; k]; n];
    for i in 0..n {
        for b in 0..k {
            let mut acc = ZERO_NODE;
            for j in 0..n {
                let t = d.mul(mass[i][j], c[j][b]);
                acc = d.add(acc, t);
            }
            mc[i][b] = acc;
        }
    }
    let mut mr = vec![vec![ZERO_NODE; k]; k];
    for a in 0..k {
        for b in a..k {
            let mut acc = ZERO_NODE;
            for i in 0..n {
                let t = d.mul(c[i][a], mc[i][b]);
                acc = d.add(acc, t);
            }
            mr[a][b] = acc;
            mr[b][a] = acc;
        }
    }
    let mut g = Vec::with_capacity(n);
    for i in 0..n {
        let mut acc = bias[i];
        for j in 0..n {
            let t = d.mul(mass[i][j], acc_bias[j]);
            acc = d.add(acc, t);
        }
        g.push(acc);
    }
    let mut f = Vec::with_capacity(k);
    for a in 0..k {
        let mut acc = ZERO_NODE;
        for i in 0..n {
            let t = d.mul(c[i][a], g[i]);
            acc = d.add(acc, t);
        }
        f.push(d.neg(acc));
    }
    for (a, row) in mr.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("projected mass matrix (Cᵀ M C)[{a}][{b}] of (5.9)"),
            );
        }
    }
    let (rdd, pivots) = d.solve_symmetric(&mr, &f);
    for (a, &v) in rdd.iter().enumerate() {
        d.label(v, format!("r̈{a}: (5.9) solved by LDLᵀ"));
    }
    MultiplierNodes {
        rdd,
        mass,
        bias,
        c,
        acc_bias,
        pivots,
    }
}

fn curvature_nodes(d: &mut Dag, m: &Model, r: &CurvatureRoute) -> (Vec<Node>, Vec<Node>) {
    let mass = matrix(d, m, &r.mass);
    for (a, row) in mass.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("reduced mass matrix ∂²Lc/∂ṙ{a}∂ṙ{b} of the constrained Lagrangian (5.12)"),
            );
        }
    }
    let rhs = exprs(d, m, &r.rhs);
    for (a, &x) in rhs.iter().enumerate() {
        d.label(x, format!("right side {a} of (5.20): projected forces minus the velocity terms and the curvature term Σ B ṙ ∂L/∂ṡ (5.21)"));
    }
    let (x, piv) = d.solve_symmetric(&mass, &rhs);
    for (a, &v) in x.iter().enumerate() {
        d.label(v, format!("r̈{a}: the reduced mass matrix solved by LDLᵀ"));
    }
    (x, piv)
}

fn vector_expr(k: usize, items: &[TokenStream]) -> TokenStream {
    quote!(::nonholonomic::__private::nalgebra::SVector::<T, #k>::from([#(#items),*]))
}

/// Builds the whole expansion for a lowered model.
pub fn generate(def: &SystemDef, mut m: Model, cx: &mut Ctxt) -> (TokenStream, Stats) {
    let (n, k, p) = (m.n(), m.k(), m.p());
    let mut stats = Stats {
        name: def.name.to_string(),
        ..Stats::default()
    };
    let name = &def.name;
    let vis = &def.vis;
    let attrs = &def.attrs;
    let params = m.params.clone();
    let has_inputs = !m.inputs.is_empty();
    let n_in = m.inputs.len();

    // ---- derivations (only what is needed)
    let mult = m.multiplier_route();
    let curv = m.curvature();
    let croute = m.curvature_route(&curv);
    stats
        .derived
        .extend(["accelerations (both routes)", "curvature terms"]);
    let integrable = curv.iter().flatten().flatten().all(|&b| b == ZERO);
    stats.integrable = integrable;

    // a coordinate whose velocity is absent from the constrained Lagrangian
    for (a, &i) in m.independent.iter().enumerate() {
        if croute.mass[a][a] == ZERO {
            cx.error_at(
                m.coords[i].span(),
                format!(
                    "the velocity of `{}` appears nowhere in the Lagrangian (after the constraints are substituted), so the reduced mass matrix is singular and its acceleration is undetermined; give `{}` a kinetic energy term or make it dependent through a constraint",
                    m.coords[i], m.coords[i]
                ),
            );
        }
    }
    if !cx.is_empty() {
        return (TokenStream::new(), stats);
    }

    // ---- the two routes for accelerations, measured by operation count
    let args_v = Args::vectors(n, k);
    let mut d1 = bound_dag(&m, &args_v);
    let mn = multiplier_nodes(&mut d1, &m, &mult);
    stats.ops_multiplier = d1.op_count(&mn.rdd);
    let mut d2 = bound_dag(&m, &args_v);
    let (rdd2, piv2) = curvature_nodes(&mut d2, &m, &croute);
    stats.ops_curvature = d2.op_count(&rdd2);
    if mn.pivots.iter().chain(&piv2).any(|&x| x == ZERO_NODE) {
        cx.error_at(
            name.span(),
            "the reduced mass matrix is structurally singular: some combination of independent velocities carries no kinetic energy; check the Lagrangian and the choice of dependent coordinates",
        );
        return (TokenStream::new(), stats);
    }
    stats.cost_multiplier = d1.cost_estimate(&mn.rdd);
    stats.cost_curvature = d2.cost_estimate(&rdd2);
    let route = if stats.cost_curvature <= stats.cost_multiplier {
        Route::Curvature
    } else {
        Route::Multiplier
    };
    stats.route = Some(route);

    let build_acc = |m: &Model, args: &Args, route: Route| -> (Dag, Vec<Node>) {
        let mut d = bound_dag(m, args);
        let rdd = match route {
            Route::Multiplier => multiplier_nodes(&mut d, m, &mult).rdd,
            Route::Curvature => curvature_nodes(&mut d, m, &croute).0,
        };
        (d, rdd)
    };

    let svec = |len: usize| quote!(::nonholonomic::__private::nalgebra::SVector<T, #len>);
    let qty = svec(n);
    let rty = svec(k);
    let pty = svec(p);
    let uty = svec(n_in);
    let u_arg = if has_inputs {
        quote!(, u: &#uty)
    } else {
        quote!()
    };
    let u_doc = if has_inputs {
        "\n\n`u` holds the inputs in declared order."
    } else {
        ""
    };

    let mut methods = TokenStream::new();

    // ---- dependent_velocities
    {
        let mut d = bound_dag(&m, &args_v);
        let outs: Vec<Node> = m
            .dependent_velocity
            .iter()
            .map(|&e| d.expr(&m.engine, e))
            .collect();
        let (stmts, o) = d.emit(&outs);
        let body = vector_expr(p, &o);
        methods.extend(quote! {
            /// The dependent velocities ṡ = −A(q) ṙ of the constraints (5.3), in
            /// the order of [`Self::DEPENDENT`].
            #[inline]
            pub fn dependent_velocities(&self, q: &#qty, rdot: &#rty) -> #pty {
                let _ = (q, rdot);
                #stmts
                #body
            }
        });
    }

    // ---- accelerations
    let route_doc = |route: Route| match route {
        Route::Multiplier => {
            "the multiplier route: the Euler–Lagrange terms (3.9) projected onto the constraint distribution, (5.9)"
        }
        Route::Curvature => {
            "the curvature route: the constrained Lagrangian Lc (5.12) with the curvature term of (5.20)–(5.21)"
        }
    };
    let acc_method = |fname: proc_macro2::Ident, route: Route, doc: String| -> TokenStream {
        let (d, rdd) = build_acc(&m, &args_v, route);
        let (stmts, o) = d.emit(&rdd);
        let body = vector_expr(k, &o);
        quote! {
            #[doc = #doc]
            #[inline]
            pub fn #fname(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> #rty {
                let _ = (t, q, rdot);
                #stmts
                #body
            }
        }
    };
    let (ops_used, ops_other) = match route {
        Route::Curvature => (stats.ops_curvature, stats.ops_multiplier),
        Route::Multiplier => (stats.ops_multiplier, stats.ops_curvature),
    };
    methods.extend(acc_method(
        format_ident!("accelerations"),
        route,
        format!(
            "The reduced equations of motion: r̈, the accelerations of the independent coordinates (in the order of [`Self::INDEPENDENT`]) at time `t`, coordinates `q` and independent velocities `rdot`.{u_doc}\n\nDerived by {}; {} operations after common-subexpression elimination (the other route needs {}). The k × k reduced mass matrix is factorised as LDLᵀ, unrolled, with its structural zeros pruned.",
            route_doc(route),
            ops_used,
            ops_other
        ),
    ));
    if m.outputs.routes {
        let (om, oc) = (stats.ops_multiplier, stats.ops_curvature);
        let chosen = match route {
            Route::Multiplier => "multiplier",
            Route::Curvature => "curvature",
        };
        methods.extend(quote! {
            /// Operations (after CSE) of r̈ by the multiplier route (5.9).
            pub const OPS_MULTIPLIER_ROUTE: usize = #om;
            /// Operations (after CSE) of r̈ by the curvature route (5.20).
            pub const OPS_CURVATURE_ROUTE: usize = #oc;
            /// The route [`Self::accelerations`] uses: `"multiplier"` or `"curvature"`.
            pub const ROUTE: &'static str = #chosen;
        });
        methods.extend(acc_method(
            format_ident!("accelerations_multiplier_route"),
            Route::Multiplier,
            format!(
                "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
                route_doc(Route::Multiplier),
                stats.ops_multiplier
            ),
        ));
        methods.extend(acc_method(
            format_ident!("accelerations_curvature_route"),
            Route::Curvature,
            format!(
                "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
                route_doc(Route::Curvature),
                stats.ops_curvature
            ),
        ));
        // the curvature route's reduced system, for measuring solvers against
        // the unrolled LDLᵀ and for conditioning checks
        let mut d = bound_dag(&m, &args_v);
        let mass = matrix(&mut d, &m, &croute.mass);
        let rhs = exprs(&mut d, &m, &croute.rhs);
        let mut outs: Vec<Node> = mass.iter().flatten().copied().collect();
        outs.extend(&rhs);
        let (stmts, o) = d.emit(&outs);
        let (mo, fo) = o.split_at(k * k);
        let kk_expr = quote!(::nonholonomic::__private::nalgebra::SMatrix::<T, #k, #k>);
        let kk = quote!(::nonholonomic::__private::nalgebra::SMatrix<T, #k, #k>);
        let fvec = vector_expr(k, fo);
        methods.extend(quote! {
            /// The reduced equations Mc r̈ = f of the curvature route as a matrix and
            /// a vector: Mc = ∂²Lc/∂ṙ∂ṙ (5.12) and f the right side of (5.20).
            /// [`Self::accelerations`] solves them by an unrolled LDLᵀ factorisation.
            #[inline]
            pub fn reduced_system(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> (#kk, #rty) {
                let _ = (t, q, rdot);
                #stmts
                (#kk_expr::from_row_slice(&[#(#mo),*]), #fvec)
            }
        });
        stats.derived.push("routes");
    }

    // ---- multipliers
    if m.outputs.multipliers {
        let mut d = bound_dag(&m, &args_v);
        let mn = multiplier_nodes(&mut d, &m, &mult);
        // q̈ = C r̈ + acc_bias; λ_a = E_{s_a} = (M q̈ + h)_{s_a}   (5.10)
        let mut qdd = mn.acc_bias.clone();
        for (i, row) in mn.c.iter().enumerate() {
            for (b, &cib) in row.iter().enumerate() {
                let t = d.mul(cib, mn.rdd[b]);
                qdd[i] = d.add(qdd[i], t);
            }
        }
        let mut lam = Vec::with_capacity(p);
        for &s in &m.dependent {
            let mut acc = mn.bias[s];
            for j in 0..n {
                let t = d.mul(mn.mass[s][j], qdd[j]);
                acc = d.add(acc, t);
            }
            lam.push(acc);
        }
        let (stmts, o) = d.emit(&lam);
        let body = vector_expr(p, &o);
        methods.extend(quote! {
            /// The Lagrange multipliers λ_a = d/dt ∂L/∂ṡ_a − ∂L/∂s_a − Q_{s_a} along
            /// the motion (5.10), one per dependent coordinate: the generalized
            /// constraint forces, with the sign convention E(L) = Cᵀλ, C = [A | I].
            #[inline]
            pub fn multipliers(&self, t: T, q: &#qty, rdot: &#rty #u_arg) -> #pty {
                let _ = (t, q, rdot);
                #stmts
                #body
            }
        });
        stats.derived.push("multipliers");
    }

    // ---- curvature
    if m.outputs.curvature {
        let mut d = bound_dag(&m, &args_v);
        let mut nodes = Vec::new();
        let mut places = Vec::new();
        for (b, mat) in curv.iter().enumerate() {
            for al in 0..k {
                for be in (al + 1)..k {
                    if mat[al][be] != ZERO {
                        nodes.push(d.expr(&m.engine, mat[al][be]));
                        places.push((b, al, be));
                    }
                }
            }
        }
        let (stmts, o) = d.emit(&nodes);
        let mut sets = TokenStream::new();
        for ((b, al, be), v) in places.iter().zip(&o) {
            sets.extend(quote! {
                b[#b][(#al, #be)] = #v;
                b[#b][(#be, #al)] = -#v;
            });
        }
        let kk = quote!(::nonholonomic::__private::nalgebra::SMatrix<T, #k, #k>);
        let kk_expr = quote!(::nonholonomic::__private::nalgebra::SMatrix::<T, #k, #k>);
        let mutable = if places.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        methods.extend(quote! {
            /// The curvature of the constraint connection, (5.21):
            /// `B[b][(α, β)]` = B^b_{αβ}, antisymmetric in (α, β); entries that are
            /// identically zero are not computed.
            #[inline]
            pub fn curvature(&self, q: &#qty) -> [#kk; #p] {
                let _ = q;
                #stmts
                let #mutable b: [#kk; #p] = [#kk_expr::zeros(); #p];
                #sets
                b
            }
        });
        stats.derived.push("curvature");
    }

    // ---- energy
    if m.outputs.energy {
        let en = m.energy();
        if m.engine.depends_on(en, m.t_sym)
            || m.input_syms.iter().any(|&u| m.engine.depends_on(en, u))
        {
            cx.error_at(
                def.outputs
                    .as_ref()
                    .map(|o| o.0.span())
                    .unwrap_or(name.span()),
                "output `energy` needs a Lagrangian that does not depend on time `t`",
            );
        }
        let mut d = bound_dag(&m, &args_v);
        let node = d.expr(&m.engine, en);
        let (stmts, o) = d.emit(&[node]);
        let v = &o[0];
        methods.extend(quote! {
            /// The energy E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities.
            #[inline]
            pub fn energy(&self, q: &#qty, rdot: &#rty) -> T {
                let _ = (q, rdot);
                #stmts
                #v
            }
        });
        stats.derived.push("energy");
    }

    // ---- constraint_matrix
    if m.outputs.constraint_matrix {
        let mut d = bound_dag(&m, &args_v);
        let nodes: Vec<Node> = m
            .a_matrix
            .iter()
            .flatten()
            .map(|&e| d.expr(&m.engine, e))
            .collect();
        let (stmts, o) = d.emit(&nodes);
        let pk = quote!(::nonholonomic::__private::nalgebra::SMatrix<T, #p, #k>);
        let pk_expr = quote!(::nonholonomic::__private::nalgebra::SMatrix::<T, #p, #k>);
        methods.extend(quote! {
            /// The constraint matrix A^a_α of ṡ_a = −Σ_α A^a_α ṙ_α (5.3): rows follow
            /// [`Self::DEPENDENT`], columns [`Self::INDEPENDENT`].
            #[inline]
            pub fn constraint_matrix(&self, q: &#qty) -> #pk {
                let _ = q;
                #stmts
                #pk_expr::from_row_slice(&[#(#o),*])
            }
        });
        stats.derived.push("constraint_matrix");
    }

    // ---- mass_matrix
    if m.outputs.mass_matrix {
        let depends_on_vel = mult.mass.iter().flatten().any(|&e| {
            m.vel_syms.iter().any(|&v| m.engine.depends_on(e, v)) || m.engine.depends_on(e, m.t_sym)
        });
        if depends_on_vel {
            cx.error_at(
                def.outputs.as_ref().map(|o| o.0.span()).unwrap_or(name.span()),
                "output `mass_matrix` needs a Lagrangian quadratic in the velocities with time-independent coefficients",
            );
        }
        let mut d = bound_dag(&m, &args_v);
        let nodes: Vec<Node> = mult
            .mass
            .iter()
            .flatten()
            .map(|&e| d.expr(&m.engine, e))
            .collect();
        let (stmts, o) = d.emit(&nodes);
        let nn = quote!(::nonholonomic::__private::nalgebra::SMatrix<T, #n, #n>);
        let nn_expr = quote!(::nonholonomic::__private::nalgebra::SMatrix::<T, #n, #n>);
        methods.extend(quote! {
            /// The mass matrix ∂²L/∂q̇_i∂q̇_j in coordinate order.
            #[inline]
            pub fn mass_matrix(&self, q: &#qty) -> #nn {
                let _ = q;
                #stmts
                #nn_expr::from_row_slice(&[#(#o),*])
            }
        });
        stats.derived.push("mass_matrix");
    }

    if m.outputs.jacobian {
        cx.error_at(
            def.outputs.as_ref().map(|o| o.0.span()).unwrap_or(name.span()),
            "output `jacobian` is not available yet: the runtime's Rosenbrock solver falls back to finite differences; remove `jacobian` from `outputs`",
        );
    }

    // ---- the first-order system for the runtime
    let dim = n + k;
    let args_x = Args::state(n, k);
    let (dx, rdd_x) = build_acc(&m, &args_x, route);
    let mut dx = dx;
    let mut outs = Vec::with_capacity(dim);
    for i in 0..n {
        let node = match m.independent.iter().position(|&r| r == i) {
            Some(j) => dx.leaf_named(
                args_x.rvel[j].clone(),
                &format!("dot_{}", syn::ext::IdentExt::unraw(&m.coords[i])),
            ),
            None => {
                let a = m.dependent.iter().position(|&s| s == i).unwrap_or(0);
                dx.expr(&m.engine, m.dependent_velocity[a])
            }
        };
        outs.push(node);
    }
    outs.extend(rdd_x);
    let (rhs_stmts, rhs_o) = dx.emit(&outs);
    let rhs_body = vector_expr(dim, &rhs_o);
    let xty = svec(dim);
    let runtime_impl = if has_inputs {
        quote! {
            #[allow(non_snake_case, clippy::all, clippy::pedantic, unused_variables, unused_parens, unused_doc_comments)]
            impl<T: ::nonholonomic::__private::nalgebra::RealField + Copy>
                ::nonholonomic::__private::nh_runtime::ControlledSystem<T, #dim, #n_in> for #name<T>
            {
                /// ẋ for the state x = [q, ṙ]: ẋ = [q̇(q, ṙ), r̈(t, q, ṙ, u)].
                #[inline]
                fn rhs_with_input(&self, t: T, x: &#xty, u: &#uty) -> #xty {
                    let _ = (t, x, u);
                    #rhs_stmts
                    #rhs_body
                }
            }
        }
    } else {
        quote! {
            #[allow(non_snake_case, clippy::all, clippy::pedantic, unused_variables, unused_parens, unused_doc_comments)]
            impl<T: ::nonholonomic::__private::nalgebra::RealField + Copy>
                ::nonholonomic::__private::nh_runtime::OdeSystem<T, #dim> for #name<T>
            {
                /// ẋ for the state x = [q, ṙ]: ẋ = [q̇(q, ṙ), r̈(t, q, ṙ)].
                #[inline]
                fn rhs(&self, t: T, x: &#xty) -> #xty {
                    let _ = (t, x);
                    #rhs_stmts
                    #rhs_body
                }
            }
        }
    };

    // ---- constants, struct, constructor
    let coord_names: Vec<Literal> = m
        .coords
        .iter()
        .map(|c| Literal::string(&c.to_string()))
        .collect();
    let input_names: Vec<Literal> = m
        .inputs
        .iter()
        .map(|c| Literal::string(&c.to_string()))
        .collect();
    let indep = &m.independent;
    let dep = &m.dependent;
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
    // argument names that cannot collide with a constant of the user's scope
    // (an identifier pattern that names a constant would match it instead)
    let param_args: Vec<proc_macro2::Ident> = params
        .iter()
        .map(|p| format_ident!("p_{}", syn::ext::IdentExt::unraw(p)))
        .collect();
    let field_docs: Vec<String> = params.iter().map(|p| format!("Parameter `{p}`.")).collect();
    let phantom_field = if params.is_empty() {
        quote!(#[doc(hidden)] pub __scalar: ::core::marker::PhantomData<T>,)
    } else {
        quote!()
    };
    let phantom_init = if params.is_empty() {
        quote!(__scalar: ::core::marker::PhantomData,)
    } else {
        quote!()
    };
    let derive = if params.is_empty() {
        quote!(#[derive(Clone, Copy, Debug, PartialEq, Default)])
    } else {
        quote!(#[derive(Clone, Copy, Debug, PartialEq)])
    };
    let tokens = quote! {
        #(#attrs)*
        #[allow(non_snake_case)]
        #derive
        #vis struct #name<T = f64> {
            #(#[doc = #field_docs] pub #params: T,)*
            #phantom_field
        }

        #[allow(non_snake_case, clippy::all, clippy::pedantic, unused_variables, unused_parens, unused_doc_comments)]
        impl<T: ::nonholonomic::__private::nalgebra::RealField + Copy> #name<T> {
            /// The generalized coordinates in declared order: the coordinate order of `q` everywhere.
            pub const COORDINATES: [&'static str; #n] = [#(#coord_names),*];
            /// Indices in `q` of the independent coordinates r, ascending.
            pub const INDEPENDENT: [usize; #k] = [#(#indep),*];
            /// Indices in `q` of the dependent coordinates s (one per constraint), ascending.
            pub const DEPENDENT: [usize; #p] = [#(#dep),*];
            /// The inputs in declared order.
            pub const INPUTS: [&'static str; #n_in] = [#(#input_names),*];
            /// Number of coordinates n.
            pub const N: usize = #n;
            /// Number of independent coordinates k = n − p.
            pub const K: usize = #k;
            /// Number of constraints p.
            pub const P: usize = #p;
            /// Length of the runtime state x = [q, ṙ]: n + k.
            pub const STATE_DIM: usize = #dim;
            #[doc = #integrable_doc]
            pub const INTEGRABLE: bool = #integrable;

            #[doc = #new_doc]
            pub const fn new(#(#param_args: T),*) -> Self {
                Self { #(#params: #param_args,)* #phantom_init }
            }

            #methods
        }

        #runtime_impl
    };
    stats.graph_size = m.engine.num_exprs();
    stats.lines = count_lines(&tokens);
    stats.derivatives = m.engine.counters.derivatives;
    (tokens, stats)
}

/// Lines of code the way a pretty-printer lays them out: one per statement,
/// item, attribute and brace.
fn count_lines(tokens: &TokenStream) -> usize {
    let mut lines = 0;
    for tt in tokens.clone() {
        match tt {
            proc_macro2::TokenTree::Punct(p) if p.as_char() == ';' => lines += 1,
            proc_macro2::TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace => {
                lines += 2 + count_lines(&g.stream())
            }
            proc_macro2::TokenTree::Group(g)
                if g.delimiter() == proc_macro2::Delimiter::Bracket =>
            {
                lines += 1
            }
            _ => {}
        }
    }
    lines
}
