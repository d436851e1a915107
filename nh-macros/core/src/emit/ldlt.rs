//! Symmetric linear systems solved in the graph by an LDLᵀ factorisation, so
//! that structural zeros of the matrix cost no operations.

use super::{Dag, Node, ONE_NODE, ZERO_NODE};

/// An LDLᵀ factorisation held as graph nodes.
pub struct Ldlt {
    l: Vec<Vec<Node>>,
    /// The pivots D.
    pub d: Vec<Node>,
    dinv: Vec<Node>,
}

impl Dag {
    /// Solves the symmetric system `m x = f` by an LDLᵀ factorisation without
    /// pivoting, built in the graph so structural zeros cost nothing. Returns
    /// x and the pivots D (for singularity checks: a constant-zero pivot means
    /// the matrix is structurally singular).
    pub fn solve_symmetric(&mut self, m: &[Vec<Node>], f: &[Node]) -> (Vec<Node>, Vec<Node>) {
        let fac = self.factor_symmetric(m);
        let x = self.solve_factored(&fac, f);
        (x, fac.d)
    }

    /// The LDLᵀ factorisation of a symmetric matrix, in the graph.
    pub fn factor_symmetric(&mut self, m: &[Vec<Node>]) -> Ldlt {
        let k = m.len();
        let mut l = vec![vec![ZERO_NODE; k]; k]; // unit lower triangular
        let mut ld = vec![vec![ZERO_NODE; k]; k]; // L·D below the diagonal
        let mut d = vec![ZERO_NODE; k];
        let mut dinv = vec![ZERO_NODE; k];
        for j in 0..k {
            let mut dj = m[j][j];
            for r in 0..j {
                let t = self.mul(l[j][r], ld[j][r]);
                dj = self.sub(dj, t);
            }
            d[j] = dj;
            dinv[j] = self.div(ONE_NODE, dj);
            for i in (j + 1)..k {
                let mut v = m[i][j];
                for r in 0..j {
                    let t = self.mul(l[i][r], ld[j][r]);
                    v = self.sub(v, t);
                }
                ld[i][j] = v;
                l[i][j] = self.mul(v, dinv[j]);
            }
        }
        Ldlt { l, d, dinv }
    }

    /// Solves with a factorisation from [`Dag::factor_symmetric`] (one more
    /// right side costs only the substitutions).
    pub fn solve_factored(&mut self, fac: &Ldlt, f: &[Node]) -> Vec<Node> {
        let k = f.len();
        // forward substitution L y = f
        let mut y = vec![ZERO_NODE; k];
        for i in 0..k {
            let mut v = f[i];
            for r in 0..i {
                let t = self.mul(fac.l[i][r], y[r]);
                v = self.sub(v, t);
            }
            y[i] = v;
        }
        // D z = y, Lᵀ x = z
        let mut x = vec![ZERO_NODE; k];
        for i in (0..k).rev() {
            let mut v = self.mul(y[i], fac.dinv[i]);
            for r in (i + 1)..k {
                let t = self.mul(fac.l[r][i], x[r]);
                v = self.sub(v, t);
            }
            x[i] = v;
        }
        x
    }
}
