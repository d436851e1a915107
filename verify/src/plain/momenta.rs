//! The momenta of the independent coordinates and their rates, plainly:
//! with C the matrix of the constrained velocities (q̇ = C ṙ: the identity
//! on ṙ, −A on ṡ), p = Cᵀ ∂L/∂q̇ is ∂Lc/∂ṙ (5.35), and along the
//! Lagrange–d'Alembert motion d/dt ∂L/∂q̇ = ∂L/∂q + Q + cᵀμ with c C = 0,
//! so ṗ = Ċᵀ ∂L/∂q̇ + Cᵀ(∂L/∂q + Q). Nothing here forms Lc, the curvature
//! B or (5.36); Ȧ comes from differentiating c_s A = c_r along q̇.
//!
//! Whether a coordinate is cyclic is measured the same way: ∂Lc/∂r_k and
//! ∂Q/∂r_k at the constrained velocities, by moving r_k with ṙ held and ṡ
//! following A.

use super::{Plain, Scalar};
use crate::jet::{Eps, Jet};
use crate::linalg::{self, Matrix};

/// The chart of dependent velocities a motion was solved in.
pub(super) struct Chart<'c, S> {
    /// The dependent coordinates, in `DEPENDENT` order.
    pub dependent: &'c [usize],
    /// The independent ones.
    pub independent: &'c [usize],
    /// The rows kept (independent ones), in the order of `cs`'s rows.
    pub kept: &'c [usize],
    /// c_s of the kept rows.
    pub cs: &'c Matrix<S>,
    /// A = c_s⁻¹ c_r (ṡ = −A ṙ for homogeneous rows).
    pub a: &'c Matrix<S>,
}

impl<S: Scalar> Plain<'_, S> {
    /// ∂L/∂q̇ (`velocities`) or ∂L/∂q at (q, q̇, t).
    fn gradient(&self, q: &[S], qd: &[S], t: S, velocities: bool) -> Vec<S> {
        let base = self.at(q, qd, &[], t);
        (0..self.n)
            .map(|i| {
                let mut at = base.clone();
                let x = if velocities {
                    &mut at.qd[i]
                } else {
                    &mut at.q[i]
                };
                *x = x.plus_eps(Eps::One, &Jet::constant(S::one()));
                self.lagrangian(&at).part(1)
            })
            .collect()
    }

    /// Σ_j ∂c/∂q_j d_j: the rows' coefficients differentiated along d.
    fn row_slopes(&self, q: &[S], t: S, d: &[S]) -> Matrix<S> {
        let zero = vec![S::zero(); self.n];
        let mut base = self.at(q, &zero, &[], t);
        for (x, &dj) in base.q.iter_mut().zip(d) {
            *x = x.plus_eps(Eps::Two, &Jet::constant(dj));
        }
        let mut out: Matrix<S> = Vec::new();
        for i in 0..self.n {
            let mut at = base.clone();
            at.qd[i] = Jet::seeded(S::zero(), Eps::One, S::one());
            let rows = self.eval.rows(&at);
            out.resize(rows.len(), vec![S::zero(); self.n]);
            for (a, r) in rows.iter().enumerate() {
                out[a][i] = r.part(3);
            }
        }
        out
    }

    /// A differentiated along d: c_s⁻¹ (∂c_r − ∂c_s A), from c_s A = c_r.
    fn matrix_slope(&self, q: &[S], t: S, d: &[S], ch: &Chart<'_, S>) -> Option<Matrix<S>> {
        if ch.kept.is_empty() {
            return Some(Vec::new());
        }
        let dc = self.row_slopes(q, t, d);
        let rhs: Matrix<S> = (ch.kept.iter())
            .map(|&a| {
                let row = &dc[a];
                (ch.independent.iter().enumerate())
                    .map(|(j, &r)| {
                        (ch.dependent.iter().enumerate())
                            .fold(row[r], |acc, (b, &s)| acc - row[s] * ch.a[b][j])
                    })
                    .collect()
            })
            .collect();
        linalg::solve(ch.cs, &rhs).map(|(x, _)| x)
    }

    /// (p, ṗ) of every independent coordinate at (q, q̇), q̇ on the
    /// homogeneous, time-independent constraints of `ch`.
    pub(super) fn momenta(
        &self,
        q: &[S],
        qd: &[S],
        t: S,
        ch: &Chart<'_, S>,
    ) -> Option<(Vec<S>, Vec<S>)> {
        let g = self.gradient(q, qd, t, true);
        let forces = self.forces(&self.at(q, qd, &[], t));
        let f: Vec<S> = (self.gradient(q, qd, t, false).iter().zip(&forces))
            .map(|(&l, &q)| l + q)
            .collect();
        let adot = self.matrix_slope(q, t, qd, ch)?;
        // Cᵀv: v_r − Σ_a v_s A^a_j
        let project = |v: &[S], a: &Matrix<S>, j: usize, r: usize| {
            (ch.dependent.iter().enumerate()).fold(v[r], |acc, (b, &s)| acc - v[s] * a[b][j])
        };
        let mut p = Vec::new();
        let mut rates = Vec::new();
        for (j, &r) in ch.independent.iter().enumerate() {
            p.push(project(&g, ch.a, j, r));
            // Ċᵀ ∂L/∂q̇ = −Σ_a ∂L/∂ṡ_a Ȧ^a_j
            let turning = (ch.dependent.iter().enumerate())
                .fold(S::zero(), |acc, (b, &s)| acc - g[s] * adot[b][j]);
            rates.push(project(&f, ch.a, j, r) + turning);
        }
        Some((p, rates))
    }

    /// For each independent coordinate r_k, the larger of |∂Lc/∂r_k| and
    /// every |∂Q_i/∂r_k| at the constrained velocities of `rdot` (infinite
    /// where c_s is singular): zero where r_k is cyclic.
    pub(super) fn cyclic_slopes(
        &self,
        q: &[S],
        qd: &[S],
        t: S,
        rdot: &[S],
        ch: &Chart<'_, S>,
    ) -> Vec<f64> {
        let base = self.at(q, qd, &[], t);
        let mut out = Vec::new();
        for &r in ch.independent {
            let mut d = vec![S::zero(); self.n];
            d[r] = S::one();
            let Some(da) = self.matrix_slope(q, t, &d, ch) else {
                out.push(f64::INFINITY);
                continue;
            };
            let mut at = base.clone();
            at.q[r] = at.q[r].plus_eps(Eps::One, &Jet::constant(S::one()));
            for (a, &s) in ch.dependent.iter().enumerate() {
                // ṡ = −A ṙ moves with r_k
                let ds =
                    (rdot.iter().enumerate()).fold(S::zero(), |acc, (j, &v)| acc - da[a][j] * v);
                at.qd[s] = at.qd[s].plus_eps(Eps::One, &Jet::constant(ds));
            }
            let forces = (self.eval.sys.forces.iter())
                .map(|(_, f)| self.eval.ex(f, &at).part(1).to_f64().abs());
            let slope = forces.fold(self.lagrangian(&at).part(1).to_f64().abs(), f64::max);
            out.push(slope);
        }
        out
    }
}
