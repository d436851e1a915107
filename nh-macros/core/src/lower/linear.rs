//! Symbolic solution of the small square systems of DESIGN §9 (the block of
//! dependent velocities, the Jacobian of the projection): Cramer's rule up to
//! [`CRAMER_MAX`] rows, sparse Gaussian elimination beyond.

use crate::algebra::lu::{self, Left, Order, cramer, laplace};
use crate::sym::{Engine, ExprId, ZERO};

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

/// The next pivot among the rows and columns not yet eliminated: a nonzero
/// constant if there is one, else the structurally nonzero entry of least
/// Markowitz cost (r − 1)(c − 1), r and c the nonzeros of its row and
/// column; ties to fewer terms, then to the first row and column.
fn pivot(e: &Engine, a: &[Vec<ExprId>], left: Left) -> Option<(usize, usize)> {
    let n = a.len();
    let live = |i: usize, j: usize| !left.row_done[i] && !left.col_done[j] && a[i][j] != ZERO;
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

/// m X = [w_1 | .. | w_k] by Gaussian elimination that keeps the sparsity
/// ([`lu::factor`]): pivots by [`pivot`], the right sides carried along,
/// so no inverse is formed, then back substitution by column. Long
/// products stay atoms in the engine, so the entries grow additively.
fn eliminate(e: &mut Engine, m: &[Vec<ExprId>], w: &[Vec<ExprId>]) -> Solved {
    let n = m.len();
    let mut r = w.to_vec();
    let lu = lu::factor(e, m.to_vec(), pivot, &mut r);
    if !lu.complete() {
        let x = vec![vec![ZERO; n]; w.len()];
        return Solved { x, det: ZERO };
    }
    let x = lu::back(e, &lu, &r, Order::Columns);
    let det = lu::det(e, &lu);
    Solved { x, det }
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
    use crate::sym::random_points::vanish_at_random_points;
    use crate::sym::{Fun, ONE};

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
}
