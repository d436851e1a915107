//! The bodies of the generated methods, one function each.

use super::graph::{Args, bound_dag, velocity_arg};
use super::methods::Derived;
use super::multipliers::multiplier_nodes;
use super::nodes::{exprs, matrix, vector_expr};
use crate::algebra;
use crate::emit::{Dag, Node, ZERO_NODE};
use crate::sym::{ExprId, SymId, ZERO};
use proc_macro2::TokenStream;
use quote::quote;

impl Derived<'_, '_> {
    /// `dependent_velocities`: ṡ = −A ṙ (5.3).
    pub(crate) fn dependent_velocities_body(&mut self) -> TokenStream {
        let p = self.m.p();
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let outs: Vec<Node> = match self.m.block {
            // solved numerically, bound in the graph
            Some(_) => self
                .m
                .constraints
                .iter()
                .filter_map(|c| d.bound(self.m.coordinates[c.dependent].velocity))
                .collect(),
            None => {
                let sdot: Vec<ExprId> = self.m.constraints.iter().map(|c| c.velocity).collect();
                exprs(&mut d, self.m, &sdot)
            }
        };
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let ret = vector_expr(p, &o);
        let t = if self.m.rheonomic() {
            quote!(t,)
        } else {
            quote!()
        };
        quote! { let _ = (#t q, rdot); #stmts #ret }
    }

    /// `reduced_system`: Mc and f of the curvature route (5.20).
    pub(crate) fn reduced_system_body(&mut self) -> TokenStream {
        let k = self.m.k();
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mass = matrix(&mut d, self.m, &self.dv.reduced.mass);
        let rhs = exprs(&mut d, self.m, &self.dv.reduced.rhs);
        let mut outs: Vec<Node> = mass.iter().flatten().copied().collect();
        outs.extend(&rhs);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let (mo, fo) = o.split_at(k * k);
        let kk = quote!(__nh_private::nalgebra::SMatrix::<T, #k, #k>);
        let f = vector_expr(k, fo);
        quote! { let _ = (t, q, rdot); #stmts (#kk::from_row_slice(&[#(#mo),*]), #f) }
    }

    /// `multipliers`: λ = E_s along the motion (5.10).
    pub(crate) fn multipliers_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mut mn = multiplier_nodes(
            &mut d,
            self.m,
            &self.dv.multiplier_route,
            self.dv.kane.as_ref(),
        );
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
        let qdd = mn.qdd(&mut d);
        let mut lam = Vec::with_capacity(p);
        for (a, &s) in self.m.dependent().iter().enumerate() {
            let acc = mn.euler_lagrange(&mut d, s, &qdd);
            d.label(acc, format!("λ{a} = E_(s{a}) (5.10)"));
            lam.push(acc);
        }
        let (stmts, o) = self.emit_hoisted(&d, &lam);
        let ret = vector_expr(p, &o);
        quote! { let _ = (t, q, rdot); #prologue #stmts #ret }
    }

    /// `curvature`: the coefficients B of (5.21).
    pub(crate) fn curvature_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let mut nodes = Vec::new();
        let mut places = Vec::new();
        for (b, mat) in self.dv.curvature.iter().enumerate() {
            for al in 0..k {
                for be in (al + 1)..k {
                    if mat[al][be] != ZERO {
                        let x = d.expr(self.m.engine, mat[al][be]);
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
        quote! {
            let _ = q;
            #stmts
            let #mutable __nh_b: [#kk; #p] = [#kk_expr::zeros(); #p];
            #sets
            __nh_b
        }
    }

    /// `energy`: E = Σ q̇ ∂L/∂q̇ − L.
    pub(crate) fn energy_body(&mut self) -> TokenStream {
        let args = Args::vectors(self.m);
        let en = self.dv.energy.unwrap_or(ZERO);
        let mut d = bound_dag(self.m, &args);
        let node = d.expr(self.m.engine, en);
        let (stmts, o) = self.emit_hoisted(&d, &[node]);
        let v = &o[0];
        let vel = velocity_arg(self.m);
        quote! { let _ = (q, #vel); #stmts #v }
    }

    /// `momenta` (p_k = ∂Lc/∂ṙ_k, 5.35) or, with `rates`,
    /// `momentum_rates` (ṗ_k, 5.36) of the cyclic coordinates.
    pub(crate) fn momenta_body(&mut self, rates: bool) -> TokenStream {
        let exprs_of = |m: &crate::mechanics::Momenta| match rates {
            true => m.rates.clone(),
            false => m.momenta.clone(),
        };
        let values = self.dv.momenta.as_ref().map(exprs_of).unwrap_or_default();
        self.vector_of_motion(&values)
    }

    /// `symmetry_momenta` or, with `rates`, `symmetry_momentum_rates`.
    pub(crate) fn symmetry_momenta_body(&mut self, rates: bool) -> TokenStream {
        let values: Vec<ExprId> = (self.dv.symmetries.iter())
            .map(|s| if rates { s.rate } else { s.momentum })
            .collect();
        self.vector_of_motion(&values)
    }

    /// `declared_momenta` (`rates`: `declared_momentum_rates`).
    pub(crate) fn declared_momenta_body(&mut self, rates: bool) -> TokenStream {
        let values: Vec<ExprId> = (self.dv.declared_momenta.iter())
            .map(|s| if rates { s.rate } else { s.momentum })
            .collect();
        self.vector_of_motion(&values)
    }

    /// The body of a method of the motion (`t, q, rdot`) returning the
    /// vector of `values`.
    fn vector_of_motion(&mut self, values: &[ExprId]) -> TokenStream {
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let outs = exprs(&mut d, self.m, values);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let ret = vector_expr(values.len(), &o);
        quote! { let _ = (t, q, rdot); #stmts #ret }
    }

    /// `constraint_matrix`: A of (5.3).
    pub(crate) fn constraint_matrix_body(&mut self) -> TokenStream {
        let (k, p) = (self.m.k(), self.m.p());
        let flat: Vec<ExprId> = self
            .m
            .constraints
            .iter()
            .flat_map(|c| c.coefficients.iter().copied())
            .collect();
        self.matrix_of_q(p, k, &flat)
    }

    /// `contact_points`: the rolling contacts' points, one per column.
    pub(crate) fn contact_points_body(&mut self) -> TokenStream {
        let c = self.m.contacts.len();
        let flat: Vec<ExprId> = (0..3)
            .flat_map(|i| self.m.contacts.iter().map(move |p| p[i]))
            .collect();
        self.matrix_of_q(3, c, &flat)
    }

    /// `mass_matrix`: ∂²L/∂q̇∂q̇.
    pub(crate) fn mass_matrix_body(&mut self) -> TokenStream {
        let n = self.m.n();
        let mass = &self.dv.multiplier_route.mass;
        let flat: Vec<ExprId> = mass.iter().flatten().copied().collect();
        self.matrix_of_q(n, n, &flat)
    }

    /// A method of `q` returning the `rows` × `cols` matrix of the entries
    /// `flat`, row by row.
    pub(crate) fn matrix_of_q(&mut self, rows: usize, cols: usize, flat: &[ExprId]) -> TokenStream {
        let args = Args::vectors(self.m);
        let mut d = bound_dag(self.m, &args);
        let nodes = exprs(&mut d, self.m, flat);
        let (stmts, o) = self.emit_hoisted(&d, &nodes);
        let ty = quote!(__nh_private::nalgebra::SMatrix::<T, #rows, #cols>);
        quote! { let _ = q; #stmts #ty::from_row_slice(&[#(#o),*]) }
    }

    /// `jacobian`: ∂f/∂x of the first-order system.
    pub(crate) fn jacobian_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let dim = n + k;
        let args_x = Args::state(self.m).moving();
        let mut d = bound_dag(self.m, &args_x);
        let vars = self.state_vars();
        let jac = self.derivative_columns(&mut d, &vars);
        let flat: Vec<Node> = jac.iter().flatten().copied().collect();
        self.stats.jacobian_ops = Some(d.op_count(&flat));
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        quote! { let _ = (t, x); #u #stmts #dd::from_row_slice(&[#(#o),*]) }
    }

    /// `time_derivative`: ∂f/∂t at fixed x (zero, not derived, for an
    /// autonomous system).
    pub(crate) fn time_derivative_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let u = if self.m.inputs.is_empty() {
            quote!()
        } else {
            quote!(let _ = u;)
        };
        if self.m.autonomous() {
            return quote! { let _ = (t, x); #u __nh_private::nalgebra::SVector::<T, #dim>::zeros() };
        }
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let column = self.derivative_columns(&mut d, &[self.m.time]);
        let flat: Vec<Node> = column.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let ret = vector_expr(dim, &o);
        quote! { let _ = (t, x); #u #stmts #ret }
    }

    /// The symbols of the parameters of `sensitivities`, in their order.
    pub(crate) fn sensitivity_syms(&self) -> Vec<SymId> {
        self.sensitivity_params
            .iter()
            .filter_map(|p| self.m.parameters.iter().find(|q| q.name == *p))
            .map(|p| p.sym)
            .collect()
    }

    /// `parameter_jacobian`: ∂f/∂p.
    pub(crate) fn parameter_jacobian_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let vars = self.sensitivity_syms();
        let cols = self.derivative_columns(&mut d, &vars);
        let flat: Vec<Node> = cols.iter().flatten().copied().collect();
        let (stmts, o) = self.emit_hoisted(&d, &flat);
        let p = vars.len();
        let dp = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #p>);
        quote! { let _ = (t, x); #stmts #dp::from_row_slice(&[#(#o),*]) }
    }

    /// `variational_rhs`: f, (∂f/∂x) S_p + ∂f/∂p and (∂f/∂x) S_x0 in one
    /// graph: the products are sums over the entries of ∂f/∂x that are not
    /// structurally zero, and every value is computed once.
    pub(crate) fn variational_rhs_body(&mut self) -> TokenStream {
        let dim = self.m.n() + self.m.k();
        let mut d = bound_dag(self.m, &Args::state(self.m).moving());
        let state = self.state_vars();
        let params = self.sensitivity_syms();
        let p = params.len();
        let mut vars = state.clone();
        vars.extend(&params);
        let cols = self.derivative_columns(&mut d, &vars);
        let mut outs = self.rhs_nodes(&mut d);
        let s_p: Vec<Vec<Node>> = (0..dim)
            .map(|i| (0..p).map(|j| d.leaf(quote!(s_p[(#i, #j)]))).collect())
            .collect();
        let s_x0: Vec<Vec<Node>> = (0..dim)
            .map(|i| (0..dim).map(|j| d.leaf(quote!(s_x0[(#i, #j)]))).collect())
            .collect();
        for (sens, bias) in [(&s_p, true), (&s_x0, false)] {
            let width = sens.first().map_or(0, Vec::len);
            for row in &cols {
                for j in 0..width {
                    let init = if bias { row[dim + j] } else { ZERO_NODE };
                    let pairs = (0..dim).map(|i| (row[i], sens[i][j]));
                    outs.push(algebra::dot_from(&mut d, init, pairs));
                }
            }
        }
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let (f, rest) = o.split_at(dim);
        let (dsp, dsx) = rest.split_at(dim * p);
        let xty = vector_expr(dim, f);
        let dp = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #p>);
        let dd = quote!(__nh_private::nalgebra::SMatrix::<T, #dim, #dim>);
        quote! {
            let _ = (t, x, s_p, s_x0);
            #stmts
            (#xty, #dp::from_row_slice(&[#(#dsp),*]), #dd::from_row_slice(&[#(#dsx),*]))
        }
    }

    /// f = [q̇, r̈] as nodes of `d` (bound to the state).
    pub(crate) fn rhs_nodes(&mut self, d: &mut Dag) -> Vec<Node> {
        let mut f: Vec<Node> = self
            .m
            .coordinates
            .iter()
            .map(|c| d.bound(c.velocity).unwrap_or(ZERO_NODE))
            .collect();
        f.extend(self.acc_nodes(d, self.route()));
        f
    }

    /// `linearization`: A = ∂f/∂x and B = ∂f/∂u.
    pub(crate) fn linearization_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let (dim, m_in) = (n + k, self.m.inputs.len());
        let args_x = Args::state(self.m).moving();
        let mut d = bound_dag(self.m, &args_x);
        let mut vars = self.state_vars();
        vars.extend(self.m.inputs.iter().map(|u| u.sym));
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
        quote! { let _ = (t, x); #u #stmts (#dd::from_row_slice(&[#(#ao),*]), #du::from_row_slice(&[#(#bo),*])) }
    }

    /// The runtime's `rhs`: q̇ and r̈ from their inlined methods.
    pub(crate) fn rhs_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let u = self.u_forward();
        let t = if self.m.rheonomic() {
            quote!(t,)
        } else {
            quote!()
        };
        let ret = vector_expr(n + k, &{
            let mut v: Vec<TokenStream> = Vec::with_capacity(n + k);
            let (mut j, mut a) = (0usize, 0usize);
            for i in 0..n {
                if self.m.independent().contains(&i) {
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
        quote! {
            let __nh_q = x.fixed_rows::<#n>(0).into_owned();
            let __nh_rdot = x.fixed_rows::<#k>(#n).into_owned();
            let __nh_sdot = self.dependent_velocities(#t &__nh_q, &__nh_rdot);
            let __nh_rdd = self.accelerations(t, &__nh_q, &__nh_rdot #u);
            #ret
        }
    }
}
