//! Symbolic solution of the small square systems of DESIGN §9 (the block of
//! dependent velocities, the Jacobian of the projection): Cramer's rule up to
//! [`CRAMER_MAX`] rows, sparse Gaussian elimination beyond.

use crate::sym::{Engine, ExprId, ONE, ZERO};

/// The largest block solved by Cramer's rule (its closed forms are small);
/// larger blocks are eliminated.
pub const CRAMER_MAX: usize = 3;

/// The solution of m X = [w_1 | .. | w_k].
pub struct Solved {
    /// X, one vector per right side, in the order of the unknowns.
    pub x: Vec<Vec<ExprId>>,
    /// det m: by Laplace expansion up to [`CRAMER_MAX`] rows, else the
    /// product of the elimination's pivots with the sign of their
    /// permutation (zero if no structurally nonzero pivot was left).
    pub det: ExprId,
}

/// The determinant of a square matrix (see [`Solved::det`]).
pub fn det(e: &mut Engine, m: &[Vec<ExprId>]) -> ExprId {
    if m.len() <= CRAMER_MAX {
        laplace(e, m)
    } else {
        solve(e, m, &[]).det
    }
}

/// m X = [w_1 | .. | w_k] solved, each w_j given by its entries: by Cramer's
/// rule up to [`CRAMER_MAX`] rows, else by [`eliminate`]. A singular m gives
/// x/0 (Cramer) or zeros (elimination): the callers test `det` first.
pub fn solve(e: &mut Engine, m: &[Vec<ExprId>], w: &[Vec<ExprId>]) -> Solved {
    if m.len() <= CRAMER_MAX {
        let det = laplace(e, m);
        let inv = e.pow(det, crate::sym::Rational::MINUS_ONE);
        let x = w.iter().map(|wj| cramer(e, m, wj, inv)).collect();
        return Solved { x, det };
    }
    eliminate(e, m, w)
}

/// The determinant of a small square matrix (Laplace expansion).
fn laplace(e: &mut Engine, m: &[Vec<ExprId>]) -> ExprId {
    match m.len() {
        0 => ONE,
        1 => m[0][0],
        n => {
            let mut parts = Vec::with_capacity(n);
            for j in 0..n {
                if m[0][j] == ZERO {
                    continue;
                }
                let minor: Vec<Vec<ExprId>> = m[1..]
                    .iter()
                    .map(|row| {
                        row.iter()
                            .enumerate()
                            .filter(|&(c, _)| c != j)
                            .map(|(_, &x)| x)
                            .collect()
                    })
                    .collect();
                let d = laplace(e, &minor);
                let t = e.mul(m[0][j], d);
                parts.push(if j % 2 == 0 { t } else { e.neg(t) });
            }
            e.sum(&parts)
        }
    }
}

/// x = m⁻¹ w by Cramer's rule, `inv` = 1/det m.
fn cramer(e: &mut Engine, m: &[Vec<ExprId>], w: &[ExprId], inv: ExprId) -> Vec<ExprId> {
    (0..w.len())
        .map(|j| {
            let mj: Vec<Vec<ExprId>> = m
                .iter()
                .zip(w)
                .map(|(row, &wi)| {
                    let mut row = row.clone();
                    row[j] = wi;
                    row
                })
                .collect();
            let dj = laplace(e, &mj);
            e.mul(dj, inv)
        })
        .collect()
}

/// The next pivot among the rows and columns not yet eliminated: a nonzero
/// constant if there is one, else the structurally nonzero entry of least
/// Markowitz cost (r − 1)(c − 1), r and c the nonzeros of its row and
/// column; ties to fewer terms, then to the first row and column.
fn pivot(
    e: &Engine,
    a: &[Vec<ExprId>],
    row_done: &[bool],
    col_done: &[bool],
) -> Option<(usize, usize)> {
    let n = a.len();
    let live = |i: usize, j: usize| !row_done[i] && !col_done[j] && a[i][j] != ZERO;
    let row_count: Vec<usize> = (0..n)
        .map(|i| (0..n).filter(|&j| live(i, j)).count())
        .collect();
    let col_count: Vec<usize> = (0..n)
        .map(|j| (0..n).filter(|&i| live(i, j)).count())
        .collect();
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter(|&(i, j)| live(i, j))
        .min_by_key(|&(i, j)| {
            let x = a[i][j];
            let cost = (row_count[i] - 1) * (col_count[j] - 1);
            (e.as_constant(x).is_none(), cost, e.num_terms(x), i, j)
        })
}

/// m X = [w_1 | .. | w_k] by Gaussian elimination that keeps the sparsity:
/// pivots by [`pivot`], only the rows with a nonzero in the pivot column are
/// updated, then back substitution; the right sides are carried along, so
/// no inverse is formed. Long products stay atoms in the engine, so the
/// entries grow additively.
fn eliminate(e: &mut Engine, m: &[Vec<ExprId>], w: &[Vec<ExprId>]) -> Solved {
    let n = m.len();
    let mut a = m.to_vec();
    // the right sides by row
    let mut r: Vec<Vec<ExprId>> = (0..n).map(|i| w.iter().map(|wj| wj[i]).collect()).collect();
    let (mut row_done, mut col_done) = (vec![false; n], vec![false; n]);
    let mut order: Vec<(usize, usize)> = Vec::with_capacity(n);
    while order.len() < n {
        let Some((p, c)) = pivot(e, &a, &row_done, &col_done) else {
            let x = vec![vec![ZERO; n]; w.len()];
            return Solved { x, det: ZERO };
        };
        row_done[p] = true;
        col_done[c] = true;
        order.push((p, c));
        let inv = e.pow(a[p][c], crate::sym::Rational::MINUS_ONE);
        let below: Vec<usize> = (0..n)
            .filter(|&i| !row_done[i] && a[i][c] != ZERO)
            .collect();
        let across: Vec<usize> = (0..n)
            .filter(|&j| !col_done[j] && a[p][j] != ZERO)
            .collect();
        for i in below {
            let f = e.mul(a[i][c], inv);
            for &j in &across {
                let t = e.mul(f, a[p][j]);
                a[i][j] = e.sub(a[i][j], t);
            }
            a[i][c] = ZERO;
            for k in 0..w.len() {
                if r[p][k] != ZERO {
                    let t = e.mul(f, r[p][k]);
                    r[i][k] = e.sub(r[i][k], t);
                }
            }
        }
    }
    // back substitution, last pivot first
    let mut x = vec![vec![ZERO; n]; w.len()];
    for &(p, c) in order.iter().rev() {
        let inv = e.pow(a[p][c], crate::sym::Rational::MINUS_ONE);
        for (k, xk) in x.iter_mut().enumerate() {
            let mut parts = vec![r[p][k]];
            for j in (0..n).filter(|&j| j != c && a[p][j] != ZERO) {
                let t = e.mul(a[p][j], xk[j]);
                parts.push(e.neg(t));
            }
            let s = e.sum(&parts);
            xk[c] = e.mul(s, inv);
        }
    }
    let mut det = if permutation_is_odd(&order) {
        e.int(-1)
    } else {
        ONE
    };
    for &(p, c) in &order {
        det = e.mul(det, a[p][c]);
    }
    Solved { x, det }
}

/// Whether the permutation row ↦ column of the pivots is odd.
fn permutation_is_odd(order: &[(usize, usize)]) -> bool {
    let mut col_of = vec![0; order.len()];
    for &(p, c) in order {
        col_of[p] = c;
    }
    let mut inversions = 0;
    for i in 0..col_of.len() {
        for j in i + 1..col_of.len() {
            if col_of[i] > col_of[j] {
                inversions += 1;
            }
        }
    }
    inversions % 2 == 1
}

/// Whether row `a` of `m` lies in the span of the rows `basis` (numbers at
/// one point): its residual after least-squares projection onto them, by
/// modified Gram–Schmidt, is at most 1e-9 of its size. A non-finite entry
/// answers `false`.
pub(crate) fn in_span_numerically(m: &[Vec<f64>], basis: &[usize], a: usize) -> bool {
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut ortho: Vec<Vec<f64>> = Vec::with_capacity(basis.len());
    for &b in basis {
        let mut v = m[b].clone();
        for u in &ortho {
            let d: f64 = v.iter().zip(u).map(|(x, y)| x * y).sum();
            v.iter_mut().zip(u).for_each(|(x, y)| *x -= d * y);
        }
        let n = norm(&v);
        if n > 0.0 {
            ortho.push(v.iter().map(|x| x / n).collect());
        }
    }
    let size = norm(&m[a]);
    let mut r = m[a].clone();
    for u in &ortho {
        let d: f64 = r.iter().zip(u).map(|(x, y)| x * y).sum();
        r.iter_mut().zip(u).for_each(|(x, y)| *x -= d * y);
    }
    size.is_finite() && norm(&r) <= 1e-9 * size
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_row_in_the_span_of_others_is_found_numerically() {
        let m = vec![
            vec![1.0, 2.0, 0.0, 0.5],
            vec![0.0, 1.0, 3.0, 0.0],
            vec![2.0, 5.0, 3.0, 1.0],
            vec![2.0, 5.0, 3.0, 1.0 + 1e-6],
        ];
        assert!(super::in_span_numerically(&m, &[0, 1], 2));
        assert!(!super::in_span_numerically(&m, &[0, 1], 3));
        assert!(!super::in_span_numerically(&m, &[0], 1));
        assert!(!super::in_span_numerically(&m, &[], 0));
    }

    use super::*;
    use crate::sym::Fun;
    use crate::sym::random_points::vanish_at_random_points;

    /// A 5×5 block with constants, trigonometric entries and zeros.
    fn block(e: &mut Engine) -> (Vec<Vec<ExprId>>, crate::sym::SymId) {
        let pi = e.symbol("pi");
        let q: Vec<ExprId> = (0..5)
            .map(|i| {
                let s = e.symbol(&format!("q{i}"));
                e.sym(s)
            })
            .collect();
        let c0 = e.func(Fun::Cos, q[0]);
        let s1 = e.func(Fun::Sin, q[1]);
        let two = e.int(2);
        let m = vec![
            vec![q[2], ZERO, c0, ONE, ZERO],
            vec![ZERO, s1, ZERO, q[3], q[0]],
            vec![c0, q[4], two, ZERO, ZERO],
            vec![ONE, ZERO, ZERO, s1, q[1]],
            vec![q[3], ZERO, q[2], ZERO, c0],
        ];
        (m, pi)
    }

    #[test]
    fn elimination_solves_and_its_pivots_give_the_determinant() {
        let mut e = Engine::new();
        let (m, pi) = block(&mut e);
        let w: Vec<ExprId> = (0..5).map(|i| e.int(i as i128 + 1)).collect();
        let s = solve(&mut e, &m, std::slice::from_ref(&w));
        // m x − w vanishes
        let mut residuals = Vec::new();
        for (row, &wi) in m.iter().zip(&w) {
            let terms: Vec<ExprId> = row
                .iter()
                .zip(&s.x[0])
                .map(|(&a, &x)| e.mul(a, x))
                .collect();
            let lhs = e.sum(&terms);
            residuals.push(e.sub(lhs, wi));
        }
        assert!(vanish_at_random_points(&e, pi, &residuals));
        // the pivots' product is the Laplace determinant
        let d = laplace(&mut e, &m);
        let diff = e.sub(s.det, d);
        assert!(vanish_at_random_points(&e, pi, &[diff]));
        assert!(!vanish_at_random_points(&e, pi, &[s.det]));
    }

    #[test]
    fn a_structurally_singular_block_has_zero_determinant() {
        let mut e = Engine::new();
        let (mut m, _) = block(&mut e);
        for row in &mut m {
            row[1] = ZERO;
        }
        assert_eq!(det(&mut e, &m), ZERO);
    }

    #[test]
    fn permutation_parity() {
        assert!(!permutation_is_odd(&[(0, 0), (1, 1), (2, 2)]));
        assert!(permutation_is_odd(&[(0, 1), (1, 0), (2, 2)]));
        assert!(!permutation_is_odd(&[(2, 0), (0, 1), (1, 2)]));
    }
}
