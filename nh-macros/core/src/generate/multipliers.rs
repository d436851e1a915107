//! The multiplier route on the graph: q̈ = C r̈ + a, the reduced system
//! Cᵀ M C r̈ = −Cᵀ (h + M a) factored by LDLᵀ, with Kane's form of the
//! bodies' terms when the derivation has it.

use super::articulated::Articulated;
use super::kane::body_projection;
use super::nodes::{exprs, matrix, projection};
use crate::algebra;
use crate::algebra::ldlt::{self, Updates};
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Scene;
use crate::mechanics::{BodyTerms, MultiplierRoute};

/// The multiplier route in the graph: returns (r̈, q̈-independent parts) and
/// keeps the mass matrix and bias for the multipliers.
pub(crate) struct MultiplierNodes {
    pub(crate) rdd: Vec<Node>,
    pub(crate) mass: Vec<Vec<Node>>,
    pub(crate) bias: Vec<Node>,
    pub(crate) c: Vec<Vec<Node>>,
    pub(crate) acc_bias: Vec<Node>,
    pub(crate) pivots: Vec<Node>,
    /// Cᵀ M C of (5.9), k × k (symmetric).
    pub(crate) projected_mass: Vec<Vec<Node>>,
    /// The right side of (5.9), −Cᵀ (M acc_bias + h).
    pub(crate) projected_rhs: Vec<Node>,
    /// The LDLᵀ factorisation of Cᵀ M C, reused for derivatives.
    pub(crate) fac: ldlt::Ldlt<Node>,
    /// Whether r̈ is the articulated-body solve.
    pub(crate) by_tree: bool,
    /// The articulated-body factors of Cᵀ M C, where they apply and solve
    /// a right side in fewer operations than `fac` (the derivatives'
    /// columns then take them).
    pub(crate) tree: Option<Articulated>,
    /// The form the projection was built in, for [`MultiplierNodes::residual`].
    pub(crate) form: Projected,
}

/// The form (5.9)'s projection was built in: the expanded Lagrangian's M
/// and h, or Kane's sums body by body with C and acc_bias as they took
/// them (in the heading's frame for a planar pair).
pub(crate) enum Projected {
    Lagrange,
    Kane {
        c: Vec<Vec<Node>>,
        acc_bias: Vec<Node>,
    },
}

pub(crate) fn multiplier_nodes(
    d: &mut Dag,
    m: &Scene<'_>,
    r: &MultiplierRoute,
    kane: Option<&BodyTerms>,
) -> MultiplierNodes {
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
    for (j, &i) in m.independent().iter().enumerate() {
        c[i][j] = ONE_NODE;
    }
    // q̈ = C r̈ + acc_bias, acc_bias_s = −Ȧ ṙ
    let mut acc_bias = vec![ZERO_NODE; n];
    if let Some(bt) = &m.block {
        let columns = super::contacts::velocity_columns(d, m, bt);
        let bias = super::contacts::dependent_bias(d, m, bt);
        for (a, con) in m.constraints.iter().enumerate() {
            for b in 0..k {
                c[con.dependent][b] = columns[b][a];
            }
            acc_bias[con.dependent] = bias[a];
        }
    } else {
        for con in &m.constraints {
            for b in 0..k {
                let x = d.expr(m.engine, con.coefficients[b]);
                c[con.dependent][b] = d.neg(x);
            }
        }
        for (a, &s) in m.dependent().iter().enumerate() {
            acc_bias[s] = d.expr(m.engine, r.dependent_bias[a]);
        }
    }
    // Cᵀ M C r̈ = −Cᵀ (M acc_bias + h)   (5.9)
    // Kane's form where it is cheaper than the expanded Lagrangian's terms
    // (without the expanded terms, Kane's form alone: LAGRANGIAN_TERMS_COMPARED)
    let lagrange = (!r.mass.is_empty()).then(|| projection(d, &mass, &bias, &c, &acc_bias));
    let mut articulated = None;
    let ((mr, f), form) = match kane {
        Some(bt) => {
            let ops = |d: &Dag, (mr, f): &(Vec<Vec<Node>>, Vec<Node>)| {
                let all: Vec<Node> = mr.iter().flatten().chain(f).copied().collect();
                d.op_count(&all)
            };
            let (c, acc_bias) = in_heading(d, m, bt, (&c, &acc_bias));
            let sums = body_projection(d, m, bt, &c, &acc_bias);
            let kane = (sums.mass.clone(), sums.rhs.clone());
            match lagrange {
                Some(lagrange) if ops(d, &lagrange) <= ops(d, &kane) => {
                    (lagrange, Projected::Lagrange)
                }
                _ => {
                    articulated = sums.articulated(d);
                    (kane, Projected::Kane { c, acc_bias })
                }
            }
        }
        // without Kane's form the expanded terms are always derived
        None => (lagrange.unwrap_or_default(), Projected::Lagrange),
    };
    for (a, row) in mr.iter().enumerate() {
        for (b, &x) in row.iter().enumerate().skip(a) {
            d.label(
                x,
                format!("projected mass matrix (Cᵀ M C)[{a}][{b}] of (5.9)"),
            );
        }
    }
    let fac = ldlt::factor(d, &mr, Updates::Kept);
    let (rdd, by_tree) = solved(d, (&fac, articulated.as_ref()), &f);
    let tree = articulated.filter(|a| a.solves_cheaper(d, &fac, k));
    MultiplierNodes {
        rdd,
        mass,
        bias,
        c,
        acc_bias,
        pivots: fac.d.clone(),
        projected_mass: mr,
        projected_rhs: f,
        fac,
        by_tree,
        tree,
        form,
    }
}

/// r̈ from (5.9): by the articulated-body recursion where it applies and
/// takes fewer operations than the LDLᵀ solve (or, under
/// [`super::with_composite_inertias`], wherever it applies), else by the
/// LDLᵀ factors `fac`; each labelled. Whether it is the articulated one.
fn solved(
    d: &mut Dag,
    (fac, articulated): (&ldlt::Ldlt<Node>, Option<&Articulated>),
    f: &[Node],
) -> (Vec<Node>, bool) {
    let dense = ldlt::solve(d, fac, f);
    let tree = articulated.map(|a| a.solve(d, f));
    if let Some(tree) = tree.filter(|t| super::articulated::preferred(d, t, &dense)) {
        for (a, &v) in tree.iter().enumerate() {
            d.label(
                v,
                format!("r̈{a}: (5.9) solved by the articulated-body recursion"),
            );
        }
        return (tree, true);
    }
    for (a, &v) in dense.iter().enumerate() {
        d.label(v, format!("r̈{a}: (5.9) solved by LDLᵀ"));
    }
    (dense, false)
}

/// C and acc_bias for Kane's sums: with a planar pair (x, y), its rows
/// those of u = R_z(−ψ)(ẋ, ẏ) and u̇ (see [`planar_columns`]).
pub(crate) fn in_heading(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &crate::mechanics::BodyTerms,
    (c, acc_bias): (&[Vec<Node>], &[Node]),
) -> (Vec<Vec<Node>>, Vec<Node>) {
    let (mut c, mut acc_bias) = (c.to_vec(), acc_bias.to_vec());
    if let (Some(planar), Some(block)) = (bt.planar, &m.block) {
        let columns = super::contacts::velocity_columns_in_heading(d, m, block);
        let bias = super::contacts::dependent_bias_in_heading(d, m, block);
        for (a, con) in m.constraints.iter().enumerate() {
            if planar.contains(&con.dependent) {
                for (b, col) in columns.iter().enumerate() {
                    c[con.dependent][b] = col[a];
                }
                acc_bias[con.dependent] = bias[a];
            }
        }
    }
    (c, acc_bias)
}

impl MultiplierNodes {
    /// x with (Cᵀ M C) x = `rhs`, by the factors that solve it in fewer
    /// operations (the derivatives' columns).
    pub(crate) fn solve(&self, d: &mut Dag, rhs: &[Node]) -> Vec<Node> {
        match &self.tree {
            Some(tree) => tree.solve(d, rhs),
            None => ldlt::solve(d, &self.fac, rhs),
        }
    }

    /// q̈ = C r̈ + acc_bias at these nodes' r̈.
    pub(crate) fn qdd(&self, d: &mut Dag) -> Vec<Node> {
        (0..self.c.len())
            .map(|i| {
                let pairs = self.c[i].iter().copied().zip(self.rdd.iter().copied());
                algebra::dot_from(d, self.acc_bias[i], pairs)
            })
            .collect()
    }

    /// The residual of (5.9) at these nodes' r̈, f − (Cᵀ M C) r̈ regrouped
    /// as −Cᵀ (M q̈ + h) with q̈ = C r̈ + acc_bias: Kane's equations at given
    /// accelerations (inverse dynamics), body by body where the route took
    /// Kane's form. Zero at the solution; its rates at fixed r̈ give the
    /// Jacobian's columns, ∂r̈/∂z = (Cᵀ M C)⁻¹ ∂R/∂z, each body's part in
    /// O(k) operations per column where Cᵀ M C's rates would take O(k²).
    pub(crate) fn residual(
        &self,
        d: &mut Dag,
        m: &Scene<'_>,
        kane: Option<&BodyTerms>,
    ) -> Vec<Node> {
        match (&self.form, kane) {
            (Projected::Kane { c, acc_bias }, Some(bt)) => {
                let qdd: Vec<Node> = (0..c.len())
                    .map(|i| {
                        let pairs = c[i].iter().copied().zip(self.rdd.iter().copied());
                        algebra::dot_from(d, acc_bias[i], pairs)
                    })
                    .collect();
                body_projection(d, m, bt, c, &qdd).rhs
            }
            _ => {
                let qdd = self.qdd(d);
                projection(d, &self.mass, &self.bias, &self.c, &qdd).1
            }
        }
    }

    /// The Euler–Lagrange term E_i = (M q̈ + h)_i (3.9) at accelerations `qdd`.
    pub(crate) fn euler_lagrange(&self, d: &mut Dag, i: usize, qdd: &[Node]) -> Node {
        let pairs = self.mass[i].iter().copied().zip(qdd.iter().copied());
        algebra::dot_from(d, self.bias[i], pairs)
    }
}

#[cfg(test)]
mod tests {
    use super::multiplier_nodes;
    use crate::generate::graph::{Args, bound_dag};
    use crate::mechanics::Scene;
    use crate::testing::{DISC, DISC_BY_HAND, SLED, close, lowered, node_value, without_ydot};

    /// The multiplier route on the graph gives the sled's closed form
    /// (ẍ = −tan θ θ̇ ẋ, θ̈ = 0: the speed along the blade is constant).
    #[test]
    fn the_sleds_accelerations_by_the_multiplier_route() {
        let (model, mut engine) = lowered(SLED);
        let mut scene = Scene::new(&model, &mut engine);
        let dv = crate::mechanics::derive(&mut scene, false);
        let mut d = bound_dag(&scene, &Args::vectors(&scene));
        let mn = multiplier_nodes(&mut d, &scene, &dv.multiplier_route, dv.kane.as_ref());
        let at = without_ydot();
        let xdd = node_value(&model, &d, mn.rdd[0], &at);
        assert!(close(xdd, -(0.3f64.tan()) * -1.1 * 0.7), "{xdd}");
        assert_eq!(node_value(&model, &d, mn.rdd[1], &at), 0.0);
    }

    /// Kane's form of the disc written as a body (generate/kane) gives the
    /// accelerations of the same disc's Lagrangian written out by hand.
    #[test]
    fn kanes_form_of_the_disc_agrees_with_its_written_out_lagrangian() {
        let at = [
            ("theta", 0.4),
            ("phi", -0.7),
            ("psi", 0.25),
            ("x", 0.1),
            ("y", 0.2),
            ("dot(theta)", 1.3),
            ("dot(phi)", -0.6),
            ("dot(psi)", 0.45),
            ("m", 1.5),
            ("R", 0.3),
            ("g", 9.81),
        ];
        let rdd = |src: &str| {
            let (model, mut engine) = lowered(src);
            let mut scene = Scene::new(&model, &mut engine);
            let dv = crate::mechanics::derive(&mut scene, false);
            assert_eq!(dv.kane.is_some(), src == DISC);
            let mut d = bound_dag(&scene, &Args::vectors(&scene));
            let mn = multiplier_nodes(&mut d, &scene, &dv.multiplier_route, dv.kane.as_ref());
            let v: Vec<f64> = mn
                .rdd
                .iter()
                .map(|&n| node_value(&model, &d, n, &at))
                .collect();
            v
        };
        let (kane, plain) = (rdd(DISC), rdd(DISC_BY_HAND));
        for (a, b) in kane.iter().zip(&plain) {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "{kane:?} against {plain:?}"
            );
        }
    }
}
