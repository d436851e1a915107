//! Derivatives of the equations of motion on the graph: the Jacobian's
//! columns through the reduced solve, total derivatives through the
//! constraints, the velocity rows.

use super::graph::{Args, bound_dag};
use super::methods::Derived;
use super::multipliers::multiplier_nodes;
use super::nodes::{exprs, matrix, vector_expr};
use super::routes::Route;
use crate::algebra;
use crate::algebra::ldlt::{self, Updates};
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Formulation;
use crate::sym::{ExprId, SymId, ZERO};
use proc_macro2::TokenStream;
use quote::quote;

/// The form the residual R = f − (Cᵀ M C) r̈ of (5.9) is differentiated in.
#[derive(Clone, Copy)]
pub(crate) enum Residual {
    /// −Cᵀ (M q̈ + h) at q̈ = C r̈ + acc_bias: Kane's equations at given
    /// accelerations, each body's rate O(k) per column.
    Regrouped,
    /// The rates of Cᵀ M C and f, then ∂f − (∂Cᵀ M C) r̈: cheaper when k is
    /// small and the bodies' sums are long (the bicycle).
    Projected,
}

/// ∂f − (∂A) r̈ from the rates of A's upper triangle `(a, b)` pairs
/// followed by f's.
fn projected_rates(
    d: &mut Dag,
    rates: &[Node],
    upper: &[(usize, usize)],
    rdd: &[Node],
) -> Vec<Node> {
    let k = rdd.len();
    let (dm_upper, df) = rates.split_at(upper.len());
    let mut dm = vec![vec![ZERO_NODE; k]; k];
    for (&(a, b), &x) in upper.iter().zip(dm_upper) {
        dm[a][b] = x;
        dm[b][a] = x;
    }
    (0..k)
        .map(|a| {
            let moved = algebra::dot(d, (0..k).map(|b| (dm[a][b], rdd[b])));
            d.sub(df[a], moved)
        })
        .collect()
}

impl Derived<'_, '_> {
    /// Is the chosen route's r̈ large enough that methods needing it call
    /// [`accelerations`] instead of repeating its code? (Small systems keep
    /// one fused body per method: their shared work is a few operations.)
    pub(crate) fn is_large(&self) -> bool {
        self.stats.is_large(self.route())
    }

    /// `, u` when the system has inputs (to forward them to another method).
    pub(crate) fn u_forward(&self) -> TokenStream {
        if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(, u)
        }
    }

    /// r̈ by the curvature route of a large system: `reduced_system`'s Mc and
    /// f solved by an unrolled LDLᵀ.
    pub(crate) fn curvature_route_from_reduced(&mut self) -> TokenStream {
        let k = self.m.k();
        let u = self.u_forward();
        let mut d = bound_dag(self.m, &Args::vectors(self.m));
        let mass: Vec<Vec<Node>> = (0..k)
            .map(|a| (0..k).map(|b| d.leaf(quote!(__nh_mc[(#a, #b)]))).collect())
            .collect();
        let rhs: Vec<Node> = (0..k).map(|a| d.leaf(quote!(__nh_f[#a]))).collect();
        let (x, _) = ldlt::solve_symmetric(&mut d, &mass, &rhs, Updates::Kept);
        let (stmts, o) = d.emit(&x);
        let ret = vector_expr(k, &o);
        quote! {
            let (__nh_mc, __nh_f) = self.reduced_system(t, q, rdot #u);
            #stmts #ret
        }
    }

    /// The state variables in order: q, then ṙ.
    pub(crate) fn state_vars(&self) -> Vec<SymId> {
        self.m
            .positions()
            .chain(self.m.independent_velocities())
            .collect()
    }

    /// ∂f/∂z for each variable z of `vars`, as rows of f = [q̇, r̈] (n + k
    /// rows, one column per variable): the dependent velocities differentiated
    /// symbolically, r̈ through the reduced solve, ∂r̈/∂z = Mc⁻¹ (∂f/∂z −
    /// (∂Mc/∂z) r̈), with one factorisation for every column.
    pub(crate) fn derivative_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        if let Some(sol) = self.dv.reduced.solution.clone() {
            // r̈ in closed form: differentiate it directly (factors that cancel
            // in r̈, such as the mass, then cancel in its derivatives too)
            let mut out = self.velocity_rows(d, vars);
            for (c, &z) in vars.iter().enumerate() {
                for al in 0..k {
                    let e = self.m.engine.diff(sol[al], z);
                    out[n + al][c] = d.expr(self.m.engine, e);
                }
            }
            return out;
        }
        if self.route() == Route::Multiplier {
            return self.multiplier_columns(d, vars);
        }
        let mass = matrix(d, self.m, &self.dv.reduced.mass);
        let rhs = exprs(d, self.m, &self.dv.reduced.rhs);
        let fac = ldlt::factor(d, &mass, Updates::Kept);
        let rdd = ldlt::solve(d, &fac, &rhs);
        let mut out = self.velocity_rows(d, vars);
        for (c, &z) in vars.iter().enumerate() {
            let mut col_rhs = Vec::with_capacity(k);
            for al in 0..k {
                let df = self.m.engine.diff(self.dv.reduced.rhs[al], z);
                let mut v = d.expr(self.m.engine, df);
                for be in 0..k {
                    let dm = self.m.engine.diff(self.dv.reduced.mass[al][be], z);
                    if dm != ZERO {
                        let dmn = d.expr(self.m.engine, dm);
                        let t = d.mul(dmn, rdd[be]);
                        v = d.sub(v, t);
                    }
                }
                col_rhs.push(v);
            }
            let col = ldlt::solve(d, &fac, &col_rhs);
            for al in 0..k {
                out[n + al][c] = col[al];
            }
        }
        out
    }

    /// ∂f/∂z through the multiplier route: forward through the
    /// accelerations' graph, with R = f − (Cᵀ M C) r̈ in the cheaper (in
    /// operations) of its two forms ([`Residual`]); where every term comes
    /// from the expanded Lagrangian (no bodies' sums, no contacts' block),
    /// the expanded terms differentiated symbolically when that is cheaper
    /// still (a small dense system's symbolic derivatives share more).
    pub(crate) fn multiplier_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let flat = |c: &[Vec<Node>]| -> Vec<Node> { c.iter().flatten().copied().collect() };
        let mut regrouped_dag = d.clone();
        let regrouped = self.forward_columns(&mut regrouped_dag, vars, Residual::Regrouped);
        let mut projected_dag = d.clone();
        let projected = self.forward_columns(&mut projected_dag, vars, Residual::Projected);
        let (mut best_dag, mut best) = (regrouped_dag, regrouped);
        if projected_dag.op_count(&flat(&projected)) < best_dag.op_count(&flat(&best)) {
            (best_dag, best) = (projected_dag, projected);
        }
        if self.dv.kane.is_none() && self.m.block.is_none() {
            let expanded = self.expanded_columns(d, vars);
            if d.op_count(&flat(&expanded)) <= best_dag.op_count(&flat(&best)) {
                return expanded;
            }
        }
        *d = best_dag;
        best
    }

    /// ∂f/∂z through the multiplier route (5.9) by forward differentiation
    /// of its graph. A r̈ = f (A = Cᵀ M C) holds along the motion, so
    /// ∂r̈/∂z = A⁻¹ ∂R/∂z for R = f − A r̈ at the solved r̈ held; ∂R/∂z is
    /// built from the nodes' operands (`Dag::rates`, the dependent velocities
    /// differentiated through the constraints as the nodes they are) in the
    /// `form` given, and the factorisation of r̈'s own solve serves every
    /// column. Nothing of the expanded derivation is differentiated.
    pub(crate) fn forward_columns(
        &mut self,
        d: &mut Dag,
        vars: &[SymId],
        form: Residual,
    ) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let kane = self.dv.kane.as_ref();
        let mn = multiplier_nodes(d, self.m, &self.dv.multiplier_route, kane);
        let upper: Vec<(usize, usize)> = (0..k).flat_map(|a| (a..k).map(move |b| (a, b))).collect();
        let mut roots = match form {
            Residual::Regrouped => mn.residual(d, self.m, kane),
            Residual::Projected => {
                let mut r: Vec<Node> = upper
                    .iter()
                    .map(|&(a, b)| mn.projected_mass[a][b])
                    .collect();
                r.extend(&mn.projected_rhs);
                r
            }
        };
        let width = roots.len();
        // q̇: the independent velocities' leaves and the dependent ones'
        // nodes (C ṙ, sharing C with the accelerations)
        roots.extend((self.m.coordinates.iter()).map(|c| d.bound(c.velocity).unwrap_or(ZERO_NODE)));
        let mut out = vec![vec![ZERO_NODE; vars.len()]; n + k];
        for (col, &z) in vars.iter().enumerate() {
            let Some(seed) = d.bound(z) else { continue };
            let seeds = [(seed, ONE_NODE)].into_iter().collect();
            let rates = d.rates(&roots, &seeds, &mn.rdd);
            let (dr, dq) = rates.split_at(width);
            let dr = match form {
                Residual::Regrouped => dr.to_vec(),
                Residual::Projected => projected_rates(d, dr, &upper, &mn.rdd),
            };
            let x = mn.solve(d, &dr);
            for (i, &v) in dq.iter().enumerate() {
                out[i][col] = v;
            }
            for al in 0..k {
                out[n + al][col] = x[al];
            }
        }
        out
    }

    /// ∂f/∂z through the multiplier route (5.9) from the expanded
    /// derivation's terms, differentiated symbolically: r̈ solves R(z, r̈) = Cᵀ E = 0
    /// with E = M q̈ + h and q̈ = C r̈ + b (b = −Ȧ ṙ), so ∂r̈/∂z =
    /// −(Cᵀ M C)⁻¹ ∂R/∂z at fixed r̈, with the factorisation of r̈'s own solve.
    /// Each ∂/∂z is a total derivative: the dependent velocities ṡ(q, ṙ) in
    /// M, h and b are differentiated through the constraints (5.3).
    pub(crate) fn expanded_columns(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mn = multiplier_nodes(d, self.m, &self.dv.multiplier_route, self.dv.kane.as_ref());
        let qdd = mn.qdd(d);
        let e_nodes: Vec<Node> = (0..n).map(|i| mn.euler_lagrange(d, i, &qdd)).collect();
        let mut out = self.velocity_rows(d, vars);
        for (col, &z) in vars.iter().enumerate() {
            let dsdot: Vec<Node> = (0..self.m.p())
                .map(|a| {
                    let e = self.m.engine.diff(self.m.constraints[a].velocity, z);
                    d.expr(self.m.engine, e)
                })
                .collect();
            // ∂C/∂z: only the rows of the dependent coordinates, −∂A/∂z
            let mut dc = vec![vec![ZERO_NODE; k]; n];
            let dependent = self.m.dependent().to_vec();
            for (a, &s) in dependent.iter().enumerate() {
                for b in 0..k {
                    let e = self.total_diff(d, self.m.constraints[a].coefficients[b], z, &dsdot);
                    dc[s][b] = d.neg(e);
                }
            }
            // ∂q̈/∂z at fixed r̈
            let mut dqdd = vec![ZERO_NODE; n];
            for (a, &s) in dependent.iter().enumerate() {
                let acc = self.total_diff(d, self.dv.multiplier_route.dependent_bias[a], z, &dsdot);
                dqdd[s] = algebra::dot_from(d, acc, (0..k).map(|b| (dc[s][b], mn.rdd[b])));
            }
            // ∂E/∂z = ∂M/∂z q̈ + M ∂q̈/∂z + ∂h/∂z
            let mut de = Vec::with_capacity(n);
            for i in 0..n {
                let mut acc = self.total_diff(d, self.dv.multiplier_route.bias[i], z, &dsdot);
                for j in 0..n {
                    let dm = self.total_diff(d, self.dv.multiplier_route.mass[i][j], z, &dsdot);
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
                let pairs = (0..n).flat_map(|i| [(dc[i][al], e_nodes[i]), (mn.c[i][al], de[i])]);
                let acc = algebra::dot(d, pairs);
                rhs.push(d.neg(acc));
            }
            let x = mn.solve(d, &rhs);
            for al in 0..k {
                out[n + al][col] = x[al];
            }
        }
        out
    }

    /// The total derivative of `e` with respect to `z` as a node: ∂e/∂z plus
    /// Σ_a ∂e/∂ṡ_a ∂ṡ_a/∂z, the dependent velocities ṡ being functions of
    /// q and ṙ through the constraints.
    pub(crate) fn total_diff(&mut self, d: &mut Dag, e: ExprId, z: SymId, dsdot: &[Node]) -> Node {
        let direct = self.m.engine.diff(e, z);
        let mut acc = d.expr(self.m.engine, direct);
        let model = self.m.model;
        for (a, c) in model.constraints.iter().enumerate() {
            if dsdot[a] == ZERO_NODE {
                continue;
            }
            let de = self
                .m
                .engine
                .diff(e, model.coordinates[c.dependent].velocity);
            if de != ZERO {
                let x = d.expr(self.m.engine, de);
                let t = d.mul(x, dsdot[a]);
                acc = d.add(acc, t);
            }
        }
        acc
    }

    /// The rows of q̇ in ∂f/∂z (the first n rows; the other k are zero).
    pub(crate) fn velocity_rows(&mut self, d: &mut Dag, vars: &[SymId]) -> Vec<Vec<Node>> {
        let (n, k) = (self.m.n(), self.m.k());
        let mut out = vec![vec![ZERO_NODE; vars.len()]; n + k];
        if self.formulation == Formulation::Maggi {
            let w = self.m.constrained_qdot();
            for i in 0..n {
                for (c, &z) in vars.iter().enumerate() {
                    let e = self.m.engine.diff(w[i], z);
                    out[i][c] = d.expr(self.m.engine, e);
                }
            }
            return out;
        }
        for i in 0..n {
            match self.m.constraints.iter().find(|c| c.dependent == i) {
                None => {
                    let velocity = self.m.coordinates[i].velocity;
                    if let Some(c) = vars.iter().position(|&z| z == velocity) {
                        out[i][c] = ONE_NODE;
                    }
                }
                Some(con) => {
                    let sdot = con.velocity;
                    for (c, &z) in vars.iter().enumerate() {
                        let e = self.m.engine.diff(sdot, z);
                        out[i][c] = d.expr(self.m.engine, e);
                    }
                }
            }
        }
        out
    }
}
