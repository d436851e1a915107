//! The runtime hooks of systems with implicit or holonomic constraints
//! (DESIGN §9): the chart regularity of the dependent-velocity block, the
//! residual of the holonomic constraints, and the projection onto them by
//! Newton's method on their dependent coordinates.

use super::graph::{Args, bound_dag};
use crate::emit::{Dag, Node};
use crate::lower::linear;
use crate::mechanics::Scene;
use crate::sym::ExprId;
use proc_macro2::TokenStream;
use quote::quote;

/// Newton iterations of the projection before it fails.
const NEWTON_ITERATIONS: usize = 8;

/// The trait methods `chart_regularity`, `constraint_residual` and
/// `project` for state type `xty`; nothing for a system whose constraints
/// are all explicit (its per-step cost is unchanged).
pub fn methods(m: &mut Scene<'_>, xty: &TokenStream) -> TokenStream {
    let Some(chart) = m.chart else {
        return quote!();
    };
    let args = Args::state(m);
    let mut d = bound_dag(m, &args);
    let node = d.expr(m.engine, chart);
    let (stmts, o) = d.emit(&[node]);
    let rho = &o[0];
    let mut out = quote! {
        /// The signed Hadamard ratio det(c_s)/Π‖c_a‖ of the block of
        /// dependent velocities of the implicit and holonomic constraints:
        /// in [−1, 1], zero where the chart of dependent coordinates is
        /// singular.
        #[inline]
        fn chart_regularity(&self, t: T, x: &#xty) -> ::core::option::Option<T> {
            let _ = (t, x);
            #stmts
            ::core::option::Option::Some(#rho)
        }
    };
    let holonomic = m.holonomic();
    if !holonomic.is_empty() {
        out.extend(projection(m, &args, &holonomic, xty));
    }
    out
}

/// `constraint_residual` and `project` for the holonomic constraints
/// (dependent coordinate, f).
fn projection(
    m: &mut Scene<'_>,
    args: &Args,
    holonomic: &[(usize, ExprId)],
    xty: &TokenStream,
) -> TokenStream {
    let p = holonomic.len();
    let f: Vec<ExprId> = holonomic.iter().map(|&(_, f)| f).collect();
    let (residual, step) = newton_step(m, holonomic);
    // the scale of f: the sum of the sizes of its terms, so that a
    // constraint with constant terms (a wheel's radius) has a scale at q = 0
    let mut scale_terms = Vec::new();
    for &fa in &f {
        let terms = m.engine.terms(fa).to_vec();
        for (mono, c) in terms {
            scale_terms.push(m.engine.term(mono, c));
        }
    }
    let mut d = bound_dag(m, args);
    let f_nodes: Vec<Node> = f.iter().map(|&e| d.expr(m.engine, e)).collect();
    for (&s, &n) in residual.iter().zip(&f_nodes) {
        d.bind(s, n);
    }
    let step = match step {
        Ok(step) => step.iter().map(|&e| d.expr(m.engine, e)).collect(),
        Err(jac) => newton_step_on_graph(m, &mut d, &jac, &f_nodes),
    };
    let mut outs = f_nodes;
    outs.extend(step);
    for e in &scale_terms {
        outs.push(d.expr(m.engine, *e));
    }
    let (stmts, o) = d.emit(&outs);
    let (fo, rest) = o.split_at(p);
    let (so, scale) = rest.split_at(p);
    let updates = holonomic
        .iter()
        .enumerate()
        .map(|(a, &(s, _))| quote!(x[#s] += step[#a];));
    let residuals = {
        let mut d = bound_dag(m, args);
        let outs: Vec<Node> = f.iter().map(|&e| d.expr(m.engine, e)).collect();
        let (s, o) = d.emit(&outs);
        quote!({ #s [#(#o),*] })
    };
    let iterations = NEWTON_ITERATIONS;
    quote! {
        /// The largest |f_i(q, t)| of the holonomic constraints.
        #[inline]
        fn constraint_residual(&self, t: T, x: &#xty) -> ::core::option::Option<T> {
            let _ = (t, x);
            let __nh_f: [T; #p] = #residuals;
            let mut __nh_r = T::zero();
            for v in __nh_f {
                let a = v.abs();
                if !(a <= __nh_r) {
                    __nh_r = a;
                }
            }
            ::core::option::Option::Some(__nh_r)
        }

        /// Newton's method on the dependent coordinates of the holonomic
        /// constraints, at most 8 iterations, to 4 ε of the size of f's
        /// terms, Σ|term| (finite), and on while each step still halves the
        /// residual.
        #[inline]
        fn project(
            &self,
            t: T,
            x: &mut #xty,
        ) -> ::core::result::Result<bool, __nh_private::nh_runtime::ProjectionFailure<T>> {
            let __nh_newton = |x: &#xty| -> (T, T, [T; #p]) {
                let _ = (t, x);
                #stmts
                let mut res = T::zero();
                for v in [#(#fo),*] {
                    let a = v.abs();
                    if !(a <= res) {
                        res = a;
                    }
                }
                let mut scale = T::zero();
                for v in [#(#scale),*] {
                    scale += v.abs();
                }
                // a state that overflowed (a step through a singular
                // Jacobian) has no finite tolerance and never converges
                let mut tol = T::default_epsilon() * Self::__nh_c(4.0) * scale;
                if !tol.is_finite() {
                    tol = -T::one();
                }
                (res, tol, [#(#so),*])
            };
            // converged once within the tolerance and no longer halving
            // the residual (a state within it is left alone)
            let mut changed = false;
            let mut last = T::zero();
            for i in 0..#iterations {
                let (res, tol, step) = __nh_newton(x);
                if res <= tol && (i == 0 || res + res >= last) {
                    return ::core::result::Result::Ok(changed);
                }
                last = res;
                #(#updates)*
                changed = true;
            }
            let (res, tol, _) = __nh_newton(x);
            if res <= tol {
                ::core::result::Result::Ok(changed)
            } else {
                ::core::result::Result::Err(__nh_private::nh_runtime::ProjectionFailure { residual: res })
            }
        }
    }
}

/// Newton's step Δs as expressions of the symbols φ, or the Jacobian J of
/// the rows for [`newton_step_on_graph`] when its symbolic solve passes the
/// engine's limits.
type Step = Result<Vec<ExprId>, Vec<Vec<ExprId>>>;

/// Newton's step on the dependent coordinates s of the holonomic rows f,
/// Δs = −J⁻¹ φ with J = ∂f/∂s, in symbols φ for the values of f (bound to
/// them where the step is evaluated): solved for f's terms instead, the
/// step distributes them over det J and cancels to their round-off over
/// it, which stalls Newton above its tolerance where J is nearly singular
/// (a ball where a surface curves almost as much as it). `Err(J)` when the
/// symbolic solve passes the engine's limits ([`newton_step_on_graph`]).
fn newton_step(m: &mut Scene<'_>, holonomic: &[(usize, ExprId)]) -> (Vec<crate::sym::SymId>, Step) {
    let jac: Vec<Vec<ExprId>> = holonomic
        .iter()
        .map(|&(_, fa)| {
            holonomic
                .iter()
                .map(|&(s, _)| m.engine.diff(fa, m.coordinates[s].position))
                .collect()
        })
        .collect();
    let residual: Vec<crate::sym::SymId> = (0..holonomic.len())
        .map(|a| m.engine.symbol(&format!("__nh_residual_{a}")))
        .collect();
    let minus_f: Vec<ExprId> = (residual.iter())
        .map(|&s| {
            let x = m.engine.sym(s);
            m.engine.neg(x)
        })
        .collect();
    let step = m
        .engine
        .attempt(|e| linear::solve(e, &jac, &[minus_f]).x.remove(0));
    (residual, step.ok_or(jac))
}

/// Newton's step on the graph, Δs = −J⁻¹ φ by Cramer's rule over the nodes
/// (`φ` the nodes of f): for the rows whose symbolic solve passes the
/// engine's limits (a random system's constants grew past 10,000 digits in
/// it), where the graph forms no product.
fn newton_step_on_graph(
    m: &Scene<'_>,
    d: &mut Dag,
    jac: &[Vec<ExprId>],
    phi: &[Node],
) -> Vec<Node> {
    let jac: Vec<Vec<Node>> = (jac.iter())
        .map(|row| row.iter().map(|&x| d.expr(m.engine, x)).collect())
        .collect();
    let minus_phi: Vec<Node> = phi.iter().map(|&x| d.neg(x)).collect();
    let det = crate::algebra::lu::laplace(d, &jac);
    let inv = d.div(crate::emit::ONE_NODE, det);
    crate::algebra::lu::cramer(d, &jac, &minus_phi, inv)
}
