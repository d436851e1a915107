//! Maggi's equations on the generated side (DESIGN §9): the methods whose
//! bodies or documentation differ for a system in generalized speeds (the
//! kinematics, the reaction forces, the mass matrix in the speeds, the
//! runtime's right side, the linearisation and the chart's regularity),
//! dispatched from one place ([`Derived::maggi_method`]).

use super::graph::{Args, bound_dag};
use super::methods::Derived;
use super::nodes::{exprs, matrix, vector_expr};
use crate::algebra;
use crate::algebra::ldlt::{self, Updates};
use crate::api::GeneratedMethod;
use crate::emit::Node;
use crate::mechanics::MaggiTerms;
use crate::model::Output;
use proc_macro2::TokenStream;
use quote::quote;

impl Derived<'_, '_> {
    /// The methods whose bodies or documentation differ for Maggi's
    /// equations; `None` for the others, which are built as for any system.
    pub(crate) fn maggi_method(
        &mut self,
        method: GeneratedMethod,
    ) -> Option<(String, TokenStream)> {
        Some(match method {
            GeneratedMethod::Accelerations => {
                (self.speeds_accelerations_doc(), self.accelerations(self.route()))
            }
            GeneratedMethod::MassMatrix => (
                "The mass matrix in the speeds, Sᵀ M S (the mass matrix of Maggi's equations (Sᵀ M S) u̇ = .., with M = ∂²L/∂q̇∂q̇ and S = ∂q̇/∂u): rows and columns follow [`Self::SPEEDS`].".to_string(),
                self.speeds_mass_matrix_body(),
            ),
            GeneratedMethod::Rhs => (
                "ẋ for the state x = [q, u]: ẋ = [S u + σ, u̇], with u̇ from Maggi's equations.".to_string(),
                self.speeds_rhs_body(),
            ),
            GeneratedMethod::Linearization => (
                "The linearisation of the first-order system ẋ = f(t, x, u), x = [q, u_speeds], at (t, x, u): A = ∂f/∂x and B = ∂f/∂u, derived symbolically through Maggi's equations (as for the Jacobian). For controller design: δẋ ≈ A δx + B δu.".to_string(),
                self.linearization_body(),
            ),
            GeneratedMethod::Jacobian if self.m.outputs.contains(Output::Linearization) => self
                .jacobian_from_linearization(
                    "The Jacobian ∂f/∂x of the first-order system x = [q, u] ↦ [S u + σ, u̇]",
                ),
            GeneratedMethod::Jacobian => {
                let doc = "The Jacobian ∂f/∂x of the first-order system x = [q, u] ↦ [S u + σ, u̇], derived symbolically: the kinematics differentiated directly, u̇ through Maggi's equations, ∂u̇/∂z = (Sᵀ M S)⁻¹ (∂f/∂z − ∂(Sᵀ M S)/∂z u̇) with one factorisation for every column.".to_string();
                (doc, self.jacobian_body())
            }
            _ => return None,
        })
    }

    /// Maggi's terms (only called for a system in generalized speeds).
    pub(crate) fn terms(&self) -> &MaggiTerms {
        self.maggi
            .as_ref()
            .expect("the bodies of a system in generalized speeds have its terms")
    }

    /// The documentation of `accelerations` in generalized speeds.
    pub(super) fn speeds_accelerations_doc(&self) -> String {
        let u_doc = if self.m.inputs.is_empty() {
            ""
        } else {
            "\n\n`u` holds the inputs in declared order."
        };
        let how = if self.dv.reduced.solution.is_some() {
            "solved symbolically (LDLᵀ)"
        } else {
            "solved by an unrolled LDLᵀ factorisation with its structural zeros pruned"
        };
        format!(
            "The equations of motion in generalized speeds: u̇, the rates of the speeds (in the order of [`Self::SPEEDS`]) at time `t`, coordinates `q` and speeds `speeds`.{u_doc}\n\nDerived as Maggi's equations (Sᵀ M S) u̇ = Sᵀ(Q − h − M(Ṡ u + σ̇)) with q̇ = S(q, t) u + σ(q, t) from `kinematics`, M = ∂²L/∂q̇∂q̇ and E = M q̈ + h − Q the Euler–Lagrange terms; the k × k system is {how}; {} operations after common-subexpression elimination.",
            self.stats.ops_curvature
        )
    }

    /// `velocities`: q̇ = S u + σ.
    pub(super) fn velocities_body(&mut self) -> TokenStream {
        let n = self.m.n();
        let mut d = bound_dag(self.m, &Args::vectors(self.m));
        let w = self.m.constrained_qdot();
        let outs = exprs(&mut d, self.m, &w);
        let (stmts, o) = self.emit_hoisted(&d, &outs);
        let ret = vector_expr(n, &o);
        quote! { let _ = (t, q, speeds); #stmts #ret }
    }

    /// `reaction_forces`: E − Q = M (S u̇ + a) + h, with u̇ from `accelerations`.
    pub(super) fn reaction_forces_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let mut d = bound_dag(self.m, &Args::vectors(self.m));
        let udot: Vec<Node> = (0..k).map(|b| d.leaf(quote!(__nh_udot[#b]))).collect();
        let t = self.terms();
        let (mass, bias, s, acc) = (
            t.mass.clone(),
            t.bias.clone(),
            t.s.clone(),
            t.acc_bias.clone(),
        );
        let mass = matrix(&mut d, self.m, &mass);
        let bias = exprs(&mut d, self.m, &bias);
        let s = matrix(&mut d, self.m, &s);
        let acc = exprs(&mut d, self.m, &acc);
        // q̈ = S u̇ + a
        let qdd: Vec<Node> = (0..n)
            .map(|i| algebra::dot_from(&mut d, acc[i], (0..k).map(|b| (s[i][b], udot[b]))))
            .collect();
        let out: Vec<Node> = (0..n)
            .map(|i| {
                let r = algebra::dot_from(&mut d, bias[i], (0..n).map(|j| (mass[i][j], qdd[j])));
                d.label(r, format!("reaction force {i}: (M q̈ + h)_{i}, E − Q (3.9)"));
                r
            })
            .collect();
        let (stmts, o) = self.emit_hoisted(&d, &out);
        let ret = vector_expr(n, &o);
        let u = self.u_forward();
        quote! {
            let __nh_udot = self.accelerations(t, q, speeds #u);
            #stmts #ret
        }
    }

    /// `mass_matrix` in generalized speeds: Sᵀ M S.
    pub(super) fn speeds_mass_matrix_body(&mut self) -> TokenStream {
        let k = self.m.k();
        let flat: Vec<_> = self.dv.reduced.mass.iter().flatten().copied().collect();
        self.matrix_of_q(k, k, &flat)
    }

    /// The runtime's `rhs`: [S u + σ, u̇] from `velocities` and `accelerations`.
    pub(super) fn speeds_rhs_body(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let u = self.u_forward();
        let items: Vec<TokenStream> = (0..n)
            .map(|i| quote!(__nh_qdot[#i]))
            .chain((0..k).map(|b| quote!(__nh_udot[#b])))
            .collect();
        let ret = vector_expr(n + k, &items);
        quote! {
            let __nh_q = x.fixed_rows::<#n>(0).into_owned();
            let __nh_u = x.fixed_rows::<#k>(#n).into_owned();
            let __nh_qdot = self.velocities(t, &__nh_q, &__nh_u);
            let __nh_udot = self.accelerations(t, &__nh_q, &__nh_u #u);
            #ret
        }
    }

    /// The runtime's `chart_regularity`: the Hadamard ratio det(Sᵀ M S) /
    /// Π (Sᵀ M S)_aa, from the pivots of its LDLᵀ factorisation. In (0, 1]
    /// where Sᵀ M S is positive definite; it tends to 0 where the speeds
    /// lose rank.
    pub(super) fn chart_regularity(&mut self) -> TokenStream {
        let (n, k) = (self.m.n(), self.m.k());
        let dim = n + k;
        let mut d = bound_dag(self.m, &Args::state(self.m));
        let mass = matrix(&mut d, self.m, &self.dv.reduced.mass);
        let fac = ldlt::factor(&mut d, &mass, Updates::Kept);
        let mut ratio = crate::emit::ONE_NODE;
        for (a, &p) in fac.d.iter().enumerate() {
            let r = d.div(p, mass[a][a]);
            ratio = d.mul(ratio, r);
        }
        d.label(
            ratio,
            "Hadamard ratio det(Sᵀ M S) / Π diag: 1 for orthogonal speeds, → 0 at a loss of rank",
        );
        let (stmts, o) = self.emit_hoisted(&d, &[ratio]);
        let v = &o[0];
        let xty = crate::api::svector(dim);
        quote! {
            /// The regularity of the speeds' chart: the Hadamard ratio
            /// det(Sᵀ M S) / Π (Sᵀ M S)_aa of the mass matrix in the speeds,
            /// in (0, 1] where it is positive definite and tending to 0 where
            /// the speeds lose rank (the runtime then ends the run).
            #[inline]
            fn chart_regularity(&self, t: T, x: &#xty) -> ::core::option::Option<T> {
                let _ = (t, x);
                #stmts
                ::core::option::Option::Some(#v)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::{SLED, SLED_SPEEDS};

    /// The methods that differ for Maggi's equations are dispatched to this
    /// room for a system in speeds, and only for it.
    #[test]
    fn maggis_methods_are_dispatched_for_speeds_only() {
        let with = |src: &str, outputs: &str| {
            let src = src.replacen(
                "lagrangian",
                &format!("outputs {{ {outputs} }}\n    lagrangian"),
                1,
            );
            crate::expand(src.parse().expect("lexes")).to_string()
        };
        let speeds = with(SLED_SPEEDS, "mass_matrix, jacobian");
        assert!(speeds.contains("Derived as Maggi's equations"));
        assert!(speeds.contains("The mass matrix in the speeds, Sᵀ M S"));
        assert!(speeds.contains("derived symbolically: the kinematics differentiated directly"));
        let sled = with(SLED, "mass_matrix, jacobian");
        assert!(!sled.contains("Maggi"));
    }
}
