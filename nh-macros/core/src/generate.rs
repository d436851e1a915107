//! Assembly of the generated struct, its inherent methods and its runtime
//! trait implementation (DESIGN §3), from the derived mechanics.

use crate::api::{Bodies, Method, Shape};
use crate::ctxt::Ctxt;
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::lower::Model;
use crate::mechanics::{CurvatureRoute, MultiplierRoute};
use crate::parse::SystemDef;
use crate::sym::{ExprId, SymId, ZERO};
use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// Operations of r̈ beyond which other methods call `accelerations` (and
/// `reduced_system`) instead of repeating their code.
const LARGE_OPS: usize = 400;

/// Largest number of independent coordinates k for which the curvature
/// route is derived to compete with the multiplier route (always, with
/// `outputs { routes }`). Beyond it the curvature route's right side,
/// symbolic in all k velocities, costs more to derive than it can save.
const CURVATURE_ROUTE_MAX_K: usize = 6;

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
    /// Whether that was proved symbolically (otherwise numerically).
    pub integrable_proved: bool,
    /// Which outputs were derived.
    pub derived: Vec<&'static str>,
    /// Lines of generated code (one statement or item per line, as `cargo expand` prints it).
    pub lines: usize,
}

impl Stats {
    /// One line: operation counts, route, graph size.
    pub fn summary(&self) -> String {
        let curvature = if self.ops_curvature == 0 {
            "not derived (k > 6)".to_string()
        } else {
            format!("{} ops (cost {})", self.ops_curvature, self.cost_curvature)
        };
        format!(
            "accelerations: multiplier route {} ops (cost {}), curvature route {curvature} after CSE, using the {} route; {} generated lines; graph {} expressions, {} derivatives; integrable: {}",
            self.ops_multiplier,
            self.cost_multiplier,
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
        let l = d.leaf_param(
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
    /// The LDLᵀ factorisation of Cᵀ M C, reused for derivatives.
    fac: crate::emit::Ldlt,
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
    let fac = d.factor_symmetric(&mr);
    let rdd = d.solve_factored(&fac, &f);
    for (a, &v) in rdd.iter().enumerate() {
        d.label(v, format!("r̈{a}: (5.9) solved by LDLᵀ"));
    }
    MultiplierNodes {
        rdd,
        mass,
        bias,
        c,
        acc_bias,
        pivots: fac.d.clone(),
        fac,
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
    if let Some(sol) = &r.solution {
        let x = exprs(d, m, sol);
        for (a, &v) in x.iter().enumerate() {
            d.label(
                v,
                format!("r̈{a}: (5.20) with the reduced mass matrix inverted symbolically (LDLᵀ)"),
            );
        }
        return (x, Vec::new());
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
    quote!(__nh_private::nalgebra::SVector::<T, #k>::from([#(#items),*]))
}

/// The route descriptions used in the generated docs.
fn route_doc(route: Route) -> &'static str {
    match route {
        Route::Multiplier => {
            "the multiplier route: the Euler–Lagrange terms (3.9) projected onto the constraint distribution, (5.9)"
        }
        Route::Curvature => {
            "the curvature route: the constrained Lagrangian Lc (5.12) with the curvature term of (5.20)–(5.21)"
        }
    }
}

/// Method bodies computed from the derivation, on demand: a method that is
/// not requested is never emitted.
struct Derived<'a> {
    m: &'a mut Model,
    mult: MultiplierRoute,
    curv: Vec<Vec<Vec<ExprId>>>,
    croute: CurvatureRoute,
    route: Route,
    stats: &'a mut Stats,
    energy: Option<ExprId>,
    /// Parameter-only values hoisted out of the methods: the code computing
    /// each method's share of the cache, and the cache length so far.
    hoist_blocks: Vec<TokenStream>,
    hoist_len: usize,
    hoist_seen: rustc_hash::FxHashMap<String, usize>,
    /// The graph of r̈ by the chosen route (from the comparison of routes),
    /// until `accelerations` emits it.
    chosen: Option<(Dag, Vec<Node>)>,
}

impl Derived<'_> {
    /// Emits a method's values; those that depend on parameters alone are
    /// computed once, when the parameters are set, into a cache the method
    /// reads (see `api::expand`).
    fn emit_hoisted(&mut self, d: &Dag, outs: &[Node]) -> (TokenStream, Vec<TokenStream>) {
        // `NH_HOIST=0` while compiling turns hoisting off (to measure it)
        let enabled = std::env::var_os("NH_HOIST").is_none_or(|v| v != "0");
        let hoisted = if self.m.params.is_empty() || !enabled {
            Vec::new()
        } else {
            d.hoistable(outs)
        };
        if hoisted.is_empty() {
            return d.emit(outs);
        }
        let (htext, houts) = d.emit_text(&hoisted, &rustc_hash::FxHashMap::default());
        // methods that hoist the same values share their cache slots
        let key = format!("{htext} => {}", houts.join(","));
        let base = match self.hoist_seen.get(&key) {
            Some(&base) => base,
            None => {
                let base = self.hoist_len;
                let mut block = htext;
                for (j, v) in houts.iter().enumerate() {
                    block.push_str(&format!("__nh_hoisted[{}] = {v};\n", base + j));
                }
                let hstmts = crate::emit::parse_text(&block);
                self.hoist_blocks.push(quote!({ #hstmts }));
                self.hoist_len += hoisted.len();
                self.hoist_seen.insert(key, base);
                base
            }
        };
        let given: rustc_hash::FxHashMap<Node, TokenStream> = hoisted
            .iter()
            .enumerate()
            .map(|(j, &h)| {
                let i = base + j;
                (h, quote!(__nh_cache[#i]))
            })
            .collect();
        let (stmts, o) = d.emit_with(outs, &given);
        (quote!(let __nh_cache = self.__nh_cached(); #stmts), o)
    }

    fn acc_nodes(&self, d: &mut Dag, route: Route) -> Vec<Node> {
        match route {
            Route::Multiplier => multiplier_nodes(d, self.m, &self.mult).rdd,
            Route::Curvature => curvature_nodes(d, self.m, &self.croute).0,
        }
    }

    fn accelerations(&mut self, route: Route, doc: String) -> Method {
        let (n, k) = (self.m.n(), self.m.k());
        // the chosen route's graph, built once when the routes were compared
        let (d, rdd) = match self.chosen.take() {
            Some(g) if route == self.route => g,
            other => {
                self.chosen = other;
                let mut d = bound_dag(self.m, &Args::vectors(n, k));
                let rdd = self.acc_nodes(&mut d, route);
                (d, rdd)
            }
        };
        let (stmts, o) = self.emit_hoisted(&d, &rdd);
        let ret = vector_expr(k, &o);
        Method {
            doc,
            body: quote! { let _ = (t, q, rdot); #stmts #ret },
        }
    }
}

impl Derived<'_> {
    /// Is the chosen route's r̈ large enough that methods needing it call
    /// [`accelerations`] instead of repeating its code? (Small systems keep
    /// one fused body per method: their shared work is a few operations.)
    fn is_large(&self) -> bool {
        let ops = match self.route {
            Route::Multiplier => self.stats.ops_multiplier,
            Route::Curvature => self.stats.ops_curvature,
        };
        ops > LARGE_OPS
    }

    /// `, u` when the system has inputs (to forward them to another method).
    fn u_forward(&self) -> TokenStream {
        if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(, u)
        }
    }

    /// r̈ by the curvature route of a large system: `reduced_system`'s Mc and
    /// f (when it is emitted, else the same code inline) solved by an
    /// unrolled LDLᵀ.
    fn curvature_route_from_reduced(&mut self) -> Method {
        let k = self.m.k();
        let (n, u) = (self.m.n(), self.u_forward());
        let doc = format!(
            "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
            route_doc(Route::Curvature),
            self.stats.ops_curvature
        );
        if !self.m.outputs.routes {
            return self.accelerations(Route::Curvature, doc);
        }
        let mut d = bound_dag(self.m, &Args::vectors(n, k));
        let mass: Vec<Vec<Node>> = (0..k)
            .map(|a| (0..k).map(|b| d.leaf(quote!(__nh_mc[(#a, #b)]))).collect())
            .collect();
        let rhs: Vec<Node> = (0..k).map(|a| d.leaf(quote!(__nh_f[#a]))).collect();
        let (x, _) = d.solve_symmetric(&mass, &rhs);
        let (stmts, o) = d.emit(&x);
        let ret = vector_expr(k, &o);
        Method {
            doc,
            body: quote! {
                let (__nh_mc, __nh_f) = self.reduced_system(t, q, rdot #u);
                #stmts #ret
            },
        }
    }

    /// The state variables in order: q, then ṙ.
    fn state_vars(&self) -> Vec<SymId> {
        self.m
            .coord_syms
            .iter()
            .copied()
            .chain(self.m.independent.iter().map(|&i| self.m.vel_syms[i]))
            .collect()
    }

    /// ∂f/∂z for each variable z of `vars`, as rows of f = [q̇, r̈] (n + k
    /// rows, one column per variable): the dependent velocities differentiated
    /// symbolically, r̈ through the reduced solve, ∂r̈/∂z = Mc⁻¹ (∂f/∂z −
    /// (∂Mc/∂z) r̈), with one factorisation for every column.
    fn derivative_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        if let Some(sol) = self.croute.solution.clone() {
            // r̈ in closed form: differentiate it directly (factors that cancel
            // in r̈, such as the mass, then cancel in its derivatives too)
            let mut out = self.velocity_rows(d, vars);
            for (c, &z) in vars.iter().enumerate() {
                for al in 0..k {
                    let e = self.m.engine.diff(sol[al], z);
                    out[n + al][c] = d.expr(&self.m.engine, e);
                }
            }
            return out;
        }
        if self.route == Route::Multiplier {
            return self.multiplier_columns(d, vars);
        }
        let mass = matrix(d, self.m, &self.croute.mass);
        let rhs = exprs(d, self.m, &self.croute.rhs);
        let fac = d.factor_symmetric(&mass);
        let rdd = d.solve_factored(&fac, &rhs);
        let mut out = self.velocity_rows(d, vars);
        for (c, &z) in vars.iter().enumerate() {
            let mut col_rhs = Vec::with_capacity(k);
            for al in 0..k {
                let df = self.m.engine.diff(self.croute.rhs[al], z);
                let mut v = d.expr(&self.m.engine, df);
                for be in 0..k {
                    let dm = self.m.engine.diff(self.croute.mass[al][be], z);
                    if dm != ZERO {
                        let dmn = d.expr(&self.m.engine, dm);
                        let t = d.mul(dmn, rdd[be]);
                        v = d.sub(v, t);
                    }
                }
                col_rhs.push(v);
            }
            let col = d.solve_factored(&fac, &col_rhs);
            for al in 0..k {
                out[n + al][c] = col[al];
            }
        }
        out
    }

    /// ∂f/∂z through the multiplier route (5.9): r̈ solves R(z, r̈) = Cᵀ E = 0
    /// with E = M q̈ + h and q̈ = C r̈ + b (b = −Ȧ ṙ), so ∂r̈/∂z =
    /// −(Cᵀ M C)⁻¹ ∂R/∂z at fixed r̈, with the factorisation of r̈'s own solve.
    /// Each ∂/∂z is a total derivative: the dependent velocities ṡ(q, ṙ) in
    /// M, h and b are differentiated through the constraints (5.3).
    fn multiplier_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mn = multiplier_nodes(d, self.m, &self.mult);
        let mut qdd = mn.acc_bias.clone();
        for i in 0..n {
            for b in 0..k {
                let t = d.mul(mn.c[i][b], mn.rdd[b]);
                qdd[i] = d.add(qdd[i], t);
            }
        }
        let mut e_nodes = Vec::with_capacity(n);
        for i in 0..n {
            let mut acc = mn.bias[i];
            for j in 0..n {
                let t = d.mul(mn.mass[i][j], qdd[j]);
                acc = d.add(acc, t);
            }
            e_nodes.push(acc);
        }
        let mut out = self.velocity_rows(d, vars);
        for (col, &z) in vars.iter().enumerate() {
            let dsdot: Vec<Node> = (0..self.m.p())
                .map(|a| {
                    let e = self.m.engine.diff(self.m.dependent_velocity[a], z);
                    d.expr(&self.m.engine, e)
                })
                .collect();
            // ∂C/∂z: only the rows of the dependent coordinates, −∂A/∂z
            let mut dc = vec![vec![ZERO_NODE; k]; n];
            let dependent = self.m.dependent.clone();
            for (a, &s) in dependent.iter().enumerate() {
                for b in 0..k {
                    let e = self.total_diff(d, self.m.a_matrix[a][b], z, &dsdot);
                    dc[s][b] = d.neg(e);
                }
            }
            // ∂q̈/∂z at fixed r̈
            let mut dqdd = vec![ZERO_NODE; n];
            for (a, &s) in dependent.iter().enumerate() {
                let mut acc = self.total_diff(d, self.mult.dependent_bias[a], z, &dsdot);
                for b in 0..k {
                    let t = d.mul(dc[s][b], mn.rdd[b]);
                    acc = d.add(acc, t);
                }
                dqdd[s] = acc;
            }
            // ∂E/∂z = ∂M/∂z q̈ + M ∂q̈/∂z + ∂h/∂z
            let mut de = Vec::with_capacity(n);
            for i in 0..n {
                let mut acc = self.total_diff(d, self.mult.bias[i], z, &dsdot);
                for j in 0..n {
                    let dm = self.total_diff(d, self.mult.mass[i][j], z, &dsdot);
                    let t = d.mul(dm, qdd[j]);
                    acc = d.add(acc, t);
                    let t = d.mul(mn.mass[i][j], dqdd[j]);
                    acc = d.add(acc, t);
                }
                de.push(acc);
            }
            // −∂R/∂z = −Σ_i (∂C_iα/∂z E_i + C_iα ∂E_i/∂z)
            let mut rhs = Vec::with_capacity(k);
            for al in 0..k {
                let mut acc = ZERO_NODE;
                for i in 0..n {
                    let t = d.mul(dc[i][al], e_nodes[i]);
                    acc = d.add(acc, t);
                    let t = d.mul(mn.c[i][al], de[i]);
                    acc = d.add(acc, t);
                }
                rhs.push(d.neg(acc));
            }
            let x = d.solve_factored(&mn.fac, &rhs);
            for al in 0..k {
                out[n + al][col] = x[al];
            }
        }
        out
    }

    /// The total derivative of `e` with respect to `z` as a node: ∂e/∂z plus
    /// Σ_a ∂e/∂ṡ_a ∂ṡ_a/∂z, the dependent velocities ṡ being functions of
    /// q and ṙ through the constraints.
    fn total_diff(&mut self, d: &mut Dag, e: ExprId, z: SymId, dsdot: &[Node]) -> Node {
        let direct = self.m.engine.diff(e, z);
        let mut acc = d.expr(&self.m.engine, direct);
        for (a, &s) in self.m.dependent.iter().enumerate() {
            if dsdot[a] == ZERO_NODE {
                continue;
            }
            let de = self.m.engine.diff(e, self.m.vel_syms[s]);
            if de != ZERO {
                let x = d.expr(&self.m.engine, de);
                let t = d.mul(x, dsdot[a]);
                acc = d.add(acc, t);
            }
        }
        acc
    }

    /// The rows of q̇ in ∂f/∂z (the first n rows; the other k are zero).
    fn velocity_rows(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mut out = vec![vec![ZERO_NODE; vars.len()]; n + k];
        for i in 0..n {
            match self.m.independent.iter().position(|&r| r == i) {
                Some(j) => {
                    if let Some(c) = vars
                        .iter()
                        .position(|&z| z == self.m.vel_syms[self.m.independent[j]])
                    {
                        out[i][c] = ONE_NODE;
                    }
                }
                None => {
                    let a = self.m.dependent.iter().position(|&s| s == i).unwrap_or(0);
                    for (c, &z) in vars.iter().enumerate() {
                        let e = self.m.engine.diff(self.m.dependent_velocity[a], z);
                        out[i][c] = d.expr(&self.m.engine, e);
                    }
                }
            }
        }
        out
    }
}

impl Derived<'_> {
    /// `dependent_velocities`: ṡ = −A ṙ (5.3).
    fn dependent_velocities_method(&mut self) -> Method {
        let p = self.m.p();
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let outs = exprs(&mut d, self.m, &self.m.dependent_velocity);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let ret = vector_expr(p, &o);
        Method {
            doc: "The dependent velocities ṡ = −A(q) ṙ of the constraints (5.3), in the order of [`Self::DEPENDENT`].".into(),
            body: quote! { let _ = (q, rdot); #stmts #ret },
        }
    }

    /// `reduced_system`: Mc and f of the curvature route (5.20).
    fn reduced_system_method(&mut self) -> Method {
        let k = self.m.k();
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let mass = matrix(&mut d, self.m, &self.croute.mass);
        let rhs = exprs(&mut d, self.m, &self.croute.rhs);
        let mut outs: Vec<Node> = mass.iter().flatten().copied().collect();
        outs.extend(&rhs);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let (mo, fo) = o.split_at(k * k);
        let kk = quote!(__nh_private::nalgebra::SMatrix::<T, #k, #k>);
        let f = vector_expr(k, fo);
        Method {
            doc: "The reduced equations Mc r̈ = f of the curvature route as a matrix and a vector: Mc = ∂²Lc/∂ṙ∂ṙ (5.12) and f the right side of (5.20). [`Self::accelerations`] solves them by an unrolled LDLᵀ factorisation.".into(),
            body: quote! { let _ = (t, q, rdot); #stmts (#kk::from_row_slice(&[#(#mo),*]), #f) },
        }
    }

    /// `multipliers`: λ = E_s along the motion (5.10).
    fn multipliers_method(&mut self) -> Method {
        let (n, k, p) = (self.m.n(), self.m.k(), self.m.p());
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let mut mn = multiplier_nodes(&mut d, self.m, &self.mult);
        let large = self.is_large();
        let u = self.u_forward();
        let prologue = if large {
            // r̈ from `accelerations`, not a second copy of its solve
            mn.rdd = (0..k).map(|b| d.leaf(quote!(__nh_rdd[#b]))).collect();
            quote!(let __nh_rdd = self.accelerations(t, q, rdot #u);)
        } else {
            quote!()
        };
        // q̈ = C r̈ + acc_bias; λ_a = E_{s_a} = (M q̈ + h)_{s_a}   (5.10)
        let mut qdd = mn.acc_bias.clone();
        for (i, row) in mn.c.iter().enumerate() {
            for (b, &cib) in row.iter().enumerate() {
                let t = d.mul(cib, mn.rdd[b]);
                qdd[i] = d.add(qdd[i], t);
            }
        }
        let mut lam = Vec::with_capacity(p);
        for (a, &s) in self.m.dependent.iter().enumerate() {
            let mut acc = mn.bias[s];
            for j in 0..n {
                let t = d.mul(mn.mass[s][j], qdd[j]);
                acc = d.add(acc, t);
            }
            d.label(acc, format!("λ{a} = E_(s{a}) (5.10)"));
            lam.push(acc);
        }
        let (stmts, o) = self.emit_hoisted(&d, &lam);
        let ret = vector_expr(p, &o);
        self.stats.derived.push("multipliers");
        Method {
            doc: "The Lagrange multipliers λ_a = d/dt ∂L/∂ṡ_a − ∂L/∂s_a − Q_{s_a} along the motion (5.10), one per dependent coordinate: the generalized constraint forces, with the sign convention E(L) = Cᵀλ, C = [A | I].".into(),
            body: quote! { let _ = (t, q, rdot); #prologue #stmts #ret },
        }
    }

    /// `curvature`: the coefficients B of (5.21).
    fn curvature_method(&mut self) -> Method {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let mut nodes = Vec::new();
        let mut places = Vec::new();
        for (b, mat) in self.curv.iter().enumerate() {
            for al in 0..k {
                for be in (al + 1)..k {
                    if mat[al][be] != ZERO {
                        let x = d.expr(&self.m.engine, mat[al][be]);
                        d.label(x, format!("B^{b}_({al},{be}) (5.21)"));
                        nodes.push(x);
                        places.push((b, al, be));
                    }
                }
            }
        }
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let mut sets = TokenStream::new();
        for ((b, al, be), v) in places.iter().zip(&o) {
            sets.extend(quote! {
                __nh_b[#b][(#al, #be)] = #v;
                __nh_b[#b][(#be, #al)] = -#v;
            });
        }
        let kk = quote!(__nh_private::nalgebra::SMatrix<T, #k, #k>);
        let kk_expr = quote!(__nh_private::nalgebra::SMatrix::<T, #k, #k>);
        let mutable = if places.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        self.stats.derived.push("curvature");
        Method {
            doc: "The curvature of the constraint connection, (5.21): `B[b][(α, β)]` = B^b_{αβ}, antisymmetric in (α, β); entries that are identically zero are not computed.".into(),
            body: quote! {
                let _ = q;
                #stmts
                let #mutable __nh_b: [#kk; #p] = [#kk_expr::zeros(); #p];
                #sets
                __nh_b
            },
        }
    }

    /// `energy`: E = Σ q̇ ∂L/∂q̇ − L.
    fn energy_method(&mut self) -> Method {
        let args = Args::vectors(self.m.n(), self.m.k());
        let en = self.energy.unwrap_or(ZERO);
        let mut d = bound_dag(self.m, &args);
        let node = d.expr(&self.m.engine, en);
        let (stmts, o) = self.emit_hoisted(&d, &[node]);
        let v = &o[0];
        self.stats.derived.push("energy");
        Method {
            doc: "The energy E = Σ q̇_i ∂L/∂q̇_i − L at the constrained velocities.".into(),
            body: quote! { let _ = (q, rdot); #stmts #v },
        }
    }

    /// `constraint_matrix`: A of (5.3).
    fn constraint_matrix_method(&mut self) -> Method {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let flat: Vec<ExprId> = self.m.a_matrix.iter().flatten().copied().collect();
        let nodes = exprs(&mut d, self.m, &flat);
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let pk = quote!(__nh_private::nalgebra::SMatrix::<T, #p, #k>);
        self.stats.derived.push("constraint_matrix");
        Method {
            doc: "The constraint matrix A^a_α of ṡ_a = −Σ_α A^a_α ṙ_α (5.3): rows follow [`Self::DEPENDENT`], columns [`Self::INDEPENDENT`].".into(),
            body: quote! { let _ = q; #stmts #pk::from_row_slice(&[#(#o),*]) },
        }
    }

    /// `mass_matrix`: ∂²L/∂q̇∂q̇.
    fn mass_matrix_method(&mut self) -> Method {
        let n = self.m.n();
        let args = Args::vectors(self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &args);
        let flat: Vec<ExprId> = self.mult.mass.iter().flatten().copied().collect();
        let nodes = exprs(&mut d, self.m, &flat);
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let nn = quote!(__nh_private::nalgebra::SMatrix::<T, #n, #n>);
        self.stats.derived.push("mass_matrix");
        Method {
            doc: "The mass matrix ∂²L/∂q̇_i∂q̇_j in coordinate order.".into(),
            body: quote! { let _ = q; #stmts #nn::from_row_slice(&[#(#o),*]) },
        }
    }

    /// `jacobian`: ∂f/∂x of the first-order system.
    fn jacobian_method(&mut self) -> Method {
        let (n, k) = (self.m.n(), self.m.k());
        let dim = n + k;
        let args_x = Args::state(n, k);
        let mut d = bound_dag(self.m, &args_x);
        let vars = self.state_vars();
        let jac = self.derivative_columns(&mut d, &vars);
        let flat: Vec<Node> = jac.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        self.stats.derived.push("jacobian");
        Method {
            doc: "The Jacobian ∂f/∂x of the first-order system x = [q, ṙ] ↦ [q̇, r̈], derived symbolically through the reduced solve: ∂r̈/∂z = Mc⁻¹ (∂f/∂z − (∂Mc/∂z) r̈) with the curvature route's Mc and f (5.20), reusing one LDLᵀ factorisation for every column.".into(),
            body: quote! { let _ = (t, x); #u #stmts #dd::from_row_slice(&[#(#o),*]) },
        }
    }

    /// `linearization`: A = ∂f/∂x and B = ∂f/∂u.
    fn linearization_method(&mut self) -> Method {
        let (n, k) = (self.m.n(), self.m.k());
        let (dim, m_in) = (n + k, self.m.inputs.len());
        let args_x = Args::state(n, k);
        let mut d = bound_dag(self.m, &args_x);
        let mut vars = self.state_vars();
        vars.extend(self.m.input_syms.iter().copied());
        let cols = self.derivative_columns(&mut d, &vars);
        let a: Vec<Node> = cols
            .iter()
            .flat_map(|row| row[..dim].iter().copied())
            .collect();
        let b: Vec<Node> = cols
            .iter()
            .flat_map(|row| row[dim..].iter().copied())
            .collect();
        let mut all = a.clone();
        all.extend(&b);
        let (stmts, o) = self.emit_hoisted(&d, &all);
        let (ao, bo) = o.split_at(a.len());
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        let du = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #m_in>);
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        self.stats.derived.push("linearization");
        Method {
            doc: "The linearisation of the first-order system ẋ = f(t, x, u) at (t, x, u): A = ∂f/∂x and B = ∂f/∂u, derived symbolically through the reduced solve (as for the Jacobian): ∂r̈/∂z = Mc⁻¹ (∂f/∂z − (∂Mc/∂z) r̈) (5.20). For controller design: δẋ ≈ A δx + B δu.".into(),
            body: quote! { let _ = (t, x); #u #stmts (#dd::from_row_slice(&[#(#ao),*]), #du::from_row_slice(&[#(#bo),*])) },
        }
    }

    /// The runtime's `rhs`: q̇ and r̈ from their inlined methods.
    fn rhs_method(&mut self) -> Method {
        let (n, k) = (self.m.n(), self.m.k());
        let u = self.u_forward();
        let ret = vector_expr(n + k, &{
            let mut v: Vec<TokenStream> = Vec::with_capacity(n + k);
            let (mut j, mut a) = (0usize, 0usize);
            for i in 0..n {
                if self.m.independent.contains(&i) {
                    v.push(quote!(__nh_rdot[#j]));
                    j += 1;
                } else {
                    v.push(quote!(__nh_sdot[#a]));
                    a += 1;
                }
            }
            v.extend((0..k).map(|b| quote!(__nh_rdd[#b])));
            v
        });
        Method {
            doc: "ẋ for the state x = [q, ṙ]: ẋ = [q̇(q, ṙ), r̈], with the dependent velocities from the constraints.".into(),
            body: quote! {
                let __nh_q = x.fixed_rows::<#n>(0).into_owned();
                let __nh_rdot = x.fixed_rows::<#k>(#n).into_owned();
                let __nh_sdot = self.dependent_velocities(&__nh_q, &__nh_rdot);
                let __nh_rdd = self.accelerations(t, &__nh_q, &__nh_rdot #u);
                #ret
            },
        }
    }
}

impl Bodies for Derived<'_> {
    fn method(&mut self, name: &str) -> Method {
        let u_doc = if self.m.inputs.is_empty() {
            ""
        } else {
            "\n\n`u` holds the inputs in declared order."
        };
        match name {
            "dependent_velocities" => self.dependent_velocities_method(),
            "accelerations" => {
                let (used, other) = match self.route {
                    Route::Curvature => (self.stats.ops_curvature, self.stats.ops_multiplier),
                    Route::Multiplier => (self.stats.ops_multiplier, self.stats.ops_curvature),
                };
                let other = if other == 0 {
                    "the curvature route is derived for k ≤ 6 or with `outputs { routes }`"
                        .to_string()
                } else {
                    format!("the other route needs {other}")
                };
                let doc = format!(
                    "The reduced equations of motion: r̈, the accelerations of the independent coordinates (in the order of [`Self::INDEPENDENT`]) at time `t`, coordinates `q` and independent velocities `rdot`.{u_doc}\n\nDerived by {}; {used} operations after common-subexpression elimination ({other}). The k × k reduced mass matrix is factorised as LDLᵀ, unrolled, with its structural zeros pruned.",
                    route_doc(self.route),
                );
                self.accelerations(self.route, doc)
            }
            "accelerations_multiplier_route" | "accelerations_curvature_route"
                if (name == "accelerations_multiplier_route")
                    == (self.route == Route::Multiplier) =>
            {
                let u = self.u_forward();
                Method {
                    doc: format!(
                        "r̈ by {}, the route [`Self::accelerations`] uses ({} operations).",
                        route_doc(self.route),
                        match self.route {
                            Route::Multiplier => self.stats.ops_multiplier,
                            Route::Curvature => self.stats.ops_curvature,
                        }
                    ),
                    body: quote! { self.accelerations(t, q, rdot #u) },
                }
            }
            "accelerations_curvature_route" if self.is_large() => {
                self.curvature_route_from_reduced()
            }
            "accelerations_multiplier_route" => {
                let doc = format!(
                    "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
                    route_doc(Route::Multiplier),
                    self.stats.ops_multiplier
                );
                self.accelerations(Route::Multiplier, doc)
            }
            "accelerations_curvature_route" => {
                let doc = format!(
                    "r̈ by {} ({} operations). Agrees with [`Self::accelerations`] to rounding.",
                    route_doc(Route::Curvature),
                    self.stats.ops_curvature
                );
                self.accelerations(Route::Curvature, doc)
            }
            "reduced_system" => self.reduced_system_method(),
            "multipliers" => self.multipliers_method(),
            "curvature" => self.curvature_method(),
            "energy" => self.energy_method(),
            "constraint_matrix" => self.constraint_matrix_method(),
            "mass_matrix" => self.mass_matrix_method(),
            "jacobian" if self.m.outputs.linearization => {
                // the linearisation's A is this Jacobian: one copy of the code
                let u = if self.m.inputs.is_empty() {
                    quote!()
                } else {
                    quote!(, u)
                };
                self.stats.derived.push("jacobian");
                Method {
                    doc: "The Jacobian ∂f/∂x of the first-order system x = [q, ṙ] ↦ [q̇, r̈]: the matrix A of [`Self::linearization`], derived symbolically through the reduced solve.".into(),
                    body: quote! { self.linearization(t, x #u).0 },
                }
            }
            "jacobian" => self.jacobian_method(),
            "linearization" => self.linearization_method(),
            // "rhs": q̇ and r̈ from their methods, inlined (one copy of the
            // code; measured as fast as a fused body)
            _ => self.rhs_method(),
        }
    }

    fn hoisting(&mut self) -> (usize, TokenStream) {
        let blocks = &self.hoist_blocks;
        (self.hoist_len, quote!(#(#blocks)*))
    }

    fn route_consts(&mut self) -> TokenStream {
        let (om, oc) = (self.stats.ops_multiplier, self.stats.ops_curvature);
        let chosen = match self.route {
            Route::Multiplier => "multiplier",
            Route::Curvature => "curvature",
        };
        self.stats.derived.push("routes");
        quote! {
            /// Operations (after CSE) of r̈ by the multiplier route (5.9).
            pub const OPS_MULTIPLIER_ROUTE: usize = #om;
            /// Operations (after CSE) of r̈ by the curvature route (5.20).
            pub const OPS_CURVATURE_ROUTE: usize = #oc;
            /// The route [`Self::accelerations`] uses: `"multiplier"` or `"curvature"`.
            pub const ROUTE: &'static str = #chosen;
        }
    }
}

/// The shape of the API for a definition, as far as it could be parsed
/// (used for the stand-in of a system with errors).
pub fn shape_of(def: &SystemDef) -> Shape<'_> {
    let coords: Vec<Ident> = def
        .coordinates
        .as_ref()
        .map(|c| c.1.clone())
        .unwrap_or_default();
    let mut dependent: Vec<usize> = Vec::new();
    if let Some((_, list)) = &def.constraints {
        for c in list {
            if let crate::parse::Expr::Call { func, arg, .. } = &c.lhs
                && func == "dot"
                && let crate::parse::Expr::Name(id) = &**arg
                && let Some(i) = coords.iter().position(|x| x == id)
                && !dependent.contains(&i)
            {
                dependent.push(i);
            }
        }
    }
    dependent.sort_unstable();
    let independent = (0..coords.len())
        .filter(|i| !dependent.contains(i))
        .collect();
    let mut outputs = crate::lower::Outputs::default();
    if let Some((_, list)) = &def.outputs {
        for o in list {
            outputs.set(&o.to_string());
        }
    }
    // an unknown or malformed parameter list leaves no fields: fine for a stand-in
    Shape {
        attrs: &def.attrs,
        krate: &def.krate,
        vis: &def.vis,
        name: &def.name,
        params: def
            .parameters
            .as_ref()
            .map(|p| p.1.clone())
            .unwrap_or_default(),
        coords: coords
            .iter()
            .map(|c| syn::ext::IdentExt::unraw(c).to_string())
            .collect(),
        inputs: def
            .inputs
            .as_ref()
            .map(|p| {
                p.1.iter()
                    .map(|c| syn::ext::IdentExt::unraw(c).to_string())
                    .collect()
            })
            .unwrap_or_default(),
        independent,
        dependent,
        outputs,
        integrable: false,
    }
}

/// Builds the whole expansion for a lowered model.
pub fn generate(def: &SystemDef, mut m: Model, cx: &mut Ctxt) -> (TokenStream, Stats) {
    let (n, k) = (m.n(), m.k());
    let mut stats = Stats {
        name: def.name.to_string(),
        ..Stats::default()
    };
    let name = &def.name;
    let _ = crate::emit::take_unrepresentable();
    let outputs_span = def
        .outputs
        .as_ref()
        .map(|o| o.0.span())
        .unwrap_or(name.span());

    // ---- derivations: both routes (to choose), and the requested outputs
    let mult = m.multiplier_route();
    let curv = m.curvature();
    // the curvature route pays for small systems (its closed forms); beyond
    // CURVATURE_ROUTE_MAX_K independent coordinates it is derived only when
    // `routes` asks for it, and `accelerations` takes the multiplier route
    let both_routes = m.outputs.routes || m.k() <= CURVATURE_ROUTE_MAX_K;
    let mut croute = if both_routes {
        m.curvature_route(&curv)
    } else {
        m.reduced_mass_only(&curv)
    };
    stats.derived.extend([
        if both_routes {
            "accelerations (both routes)"
        } else {
            "accelerations (multiplier route)"
        },
        "curvature terms",
    ]);
    let (integrable, proved) = integrability(&m, &curv);
    stats.integrable = integrable;
    stats.integrable_proved = proved;

    if m.engine.overflowed() {
        cx.error_at(
            name.span(),
            "the derivation grew beyond the engine's limits (expression swell): simplify the Lagrangian or the constraints, or split the system",
        );
        return (TokenStream::new(), stats);
    }
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
    let energy = if m.outputs.energy {
        let en = m.energy();
        if m.engine.depends_on(en, m.t_sym) {
            cx.error_at(outputs_span, "output `energy` needs a Lagrangian that does not depend on time `t` explicitly: remove `energy` from `outputs`");
        }
        Some(en)
    } else {
        None
    };
    if m.outputs.mass_matrix {
        let varying = mult.mass.iter().flatten().any(|&e| {
            m.vel_syms.iter().any(|&v| m.engine.depends_on(e, v)) || m.engine.depends_on(e, m.t_sym)
        });
        if varying {
            cx.error_at(outputs_span, "output `mass_matrix` needs a Lagrangian quadratic in the velocities with time-independent coefficients (the method takes only `q`)");
        }
    }
    if !cx.is_empty() {
        return (TokenStream::new(), stats);
    }

    // ---- the two routes for accelerations, measured by estimated cost
    let args_v = Args::vectors(n, k);
    let mut d1 = bound_dag(&m, &args_v);
    let mn = multiplier_nodes(&mut d1, &m, &mult);
    let mut d2 = bound_dag(&m, &args_v);
    let (mut rdd2, piv2) = if both_routes {
        curvature_nodes(&mut d2, &m, &croute)
    } else {
        (Vec::new(), Vec::new())
    };
    // the same route with the reduced system solved symbolically, if cheaper
    let (cmass, crhs) = (croute.mass.clone(), croute.rhs.clone());
    if both_routes
        && piv2.iter().all(|&p| p != ZERO_NODE)
        && let Some(sol) = m.solve_symbolic(&cmass, &crhs)
    {
        let mut d3 = bound_dag(&m, &args_v);
        let x3 = exprs(&mut d3, &m, &sol);
        if d3.cost_estimate(&x3) < d2.cost_estimate(&rdd2) {
            croute.solution = Some(sol);
            d2 = d3;
            rdd2 = x3;
        }
    }
    if mn.pivots.iter().chain(&piv2).any(|&x| x == ZERO_NODE) {
        cx.error_at(
            name.span(),
            "the reduced mass matrix is structurally singular: some combination of independent velocities carries no kinetic energy; check the Lagrangian and the choice of dependent coordinates",
        );
        return (TokenStream::new(), stats);
    }
    stats.ops_multiplier = d1.op_count(&mn.rdd);
    stats.ops_curvature = d2.op_count(&rdd2);
    stats.cost_multiplier = d1.cost_estimate(&mn.rdd);
    stats.cost_curvature = d2.cost_estimate(&rdd2);
    let route = if both_routes && stats.cost_curvature <= stats.cost_multiplier {
        Route::Curvature
    } else {
        Route::Multiplier
    };
    stats.route = Some(route);
    let chosen = match route {
        Route::Multiplier => (d1, mn.rdd),
        Route::Curvature => (d2, rdd2),
    };

    let mut shape = shape_of(def);
    shape.integrable = integrable;
    shape.outputs = m.outputs.clone();
    let mut bodies = Derived {
        m: &mut m,
        mult,
        curv,
        croute,
        route,
        stats: &mut stats,
        energy,
        hoist_blocks: Vec::new(),
        hoist_len: 0,
        hoist_seen: rustc_hash::FxHashMap::default(),
        chosen: Some(chosen),
    };
    let mut tokens = crate::api::expand(&shape, &mut bodies);
    if integrable && m.p() > 0 {
        tokens.extend(integrability_warning(
            def,
            m.constraints_span.unwrap_or(name.span()),
            proved,
        ));
    }
    if let Some(c) = crate::emit::take_unrepresentable() {
        let msg = format!(
            "the generated code needs the constant {} (after exact simplification), which is beyond the range of `f64` (about ±1.8e308): rescale the units or the parameters",
            c.sci()
        );
        match m.huge_constant {
            Some(r) => cx.error(r, msg),
            None => cx.error_at(name.span(), msg),
        }
        return (TokenStream::new(), stats);
    }
    stats.graph_size = m.engine.num_exprs();
    stats.derivatives = m.engine.counters.derivatives;

    (tokens, stats)
}

/// Whether the constraints are integrable (all B^b_αβ ≡ 0), and whether that
/// was proved symbolically. An entry whose canonical form is not zero is
/// evaluated at 16 random points in double-double arithmetic (about 32
/// digits): any point where it exceeds 1e-24 of the sum of its terms' sizes
/// proves it nonzero; an entry below that at every point is taken as zero (an
/// identity the canonical form does not know, such as an angle-addition
/// formula). A genuinely nonholonomic system would have to cancel to 24
/// digits at 16 random points to be called integrable.
fn integrability(m: &Model, curv: &[Vec<Vec<ExprId>>]) -> (bool, bool) {
    use crate::sym::dd::Dd;
    let entries: Vec<ExprId> = curv
        .iter()
        .flatten()
        .flatten()
        .copied()
        .filter(|&b| b != ZERO)
        .collect();
    if entries.is_empty() {
        return (true, true);
    }
    let mut state = 0x243F_6A88_85A3_08D3u64; // deterministic: the same verdict every build
    let mut next = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        ((state.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64) / (1u64 << 53) as f64
    };
    let mut vals = vec![Dd::ZERO; m.engine.num_symbols()];
    let mut points = 0;
    for _ in 0..64 {
        if points == 16 {
            break;
        }
        for v in vals.iter_mut() {
            *v = Dd::from_f64(0.3 + 1.1 * next()); // positive: keeps sqrt and ln arguments valid
        }
        vals[m.pi_sym.index()] = Dd::PI;
        let mut usable = true;
        for &b in &entries {
            let (v, scale) = m.engine.eval_with_scale(b, &vals);
            if !v.is_finite() || !scale.is_finite() {
                usable = false;
                break;
            }
            if v.abs().to_f64() > 1e-24 * scale.to_f64() {
                return (false, false);
            }
        }
        if usable {
            points += 1;
        }
    }
    (points == 16, false)
}

/// A compile-time warning on stable Rust (the deprecation-note technique):
/// a deprecated constant used at the span of the `constraints` keyword.
fn integrability_warning(def: &SystemDef, span: proc_macro2::Span, proved: bool) -> TokenStream {
    let how = if proved {
        "every curvature coefficient B^b_αβ of (5.21) vanishes identically"
    } else {
        "every curvature coefficient B^b_αβ of (5.21) evaluates to zero (to 1e-24 of its terms, in 32-digit arithmetic) at 16 random points, though the simplifier could not prove it"
    };
    let note = format!(
        "the constraints of `{}` are integrable: {how}, so they are holonomic in disguise. Integrate them and eliminate the dependent coordinates (a smaller system with no constraints), or keep them: the equations of motion are still correct. `{}::INTEGRABLE` is `true`.",
        def.name, def.name
    );
    let item = proc_macro2::Ident::new("integrable_constraints", span);
    let inherited = crate::attrs::inherited(&def.attrs);
    quote::quote_spanned! {span=>
        #(#inherited)*
        const _: () = {
            #[deprecated(note = #note)]
            #[allow(non_upper_case_globals)]
            const integrable_constraints: () = ();
            let _ = #item;
        };
    }
}

/// Lines of code the way a pretty-printer lays them out: one per statement,
/// item, attribute and brace.
pub fn count_lines(tokens: &TokenStream) -> usize {
    let mut lines = 0;
    for tt in tokens.clone() {
        match tt {
            proc_macro2::TokenTree::Punct(p) if p.as_char() == ';' || p.as_char() == '#' => {
                lines += 1
            }
            proc_macro2::TokenTree::Group(g) if g.delimiter() == proc_macro2::Delimiter::Brace => {
                lines += 2 + count_lines(&g.stream())
            }
            _ => {}
        }
    }
    lines
}
