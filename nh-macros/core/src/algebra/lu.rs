//! Square systems and determinants: Gaussian elimination (an LU
//! factorisation) with its pivots given or chosen as it goes, right sides
//! carried along or substituted later; the Laplace expansion and Cramer's
//! rule for small systems.
//!
//! The elimination keeps the sparsity: a step updates only the rows with a
//! nonzero in its pivot column, and in them only the columns where the
//! pivot row is nonzero, so structural zeros cost nothing on either carrier.

use super::Carrier;

/// A matrix factored by elimination.
pub struct Lu<V> {
    /// The steps (pivot row, pivot column), in order.
    pub pivots: Vec<(usize, usize)>,
    /// Per step, the rows it eliminated from and their multipliers.
    multipliers: Vec<Vec<(usize, V)>>,
    /// The matrix eliminated: the pivot row of each step is a row of U.
    upper: Vec<Vec<V>>,
}

impl<V> Lu<V> {
    /// Whether every row found a pivot (else the matrix is structurally
    /// singular for the rule that chose them).
    pub fn complete(&self) -> bool {
        self.pivots.len() == self.upper.len()
    }
}

/// The order of the terms Σ u_pj x_j of a back substitution.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Order {
    /// By column, ascending.
    Columns,
    /// In the order of the pivots (the unknowns as they were found).
    Pivots,
}

/// The rows and columns of a matrix not eliminated yet.
pub struct Left<'a> {
    /// Per row, whether it was a pivot row.
    pub row_done: &'a [bool],
    /// Per column, whether it was a pivot column.
    pub col_done: &'a [bool],
}

/// `a` (n × n) factored by elimination, `next` choosing each step's pivot
/// (row, column) from the matrix so far and the rows and columns left
/// (`None`: no pivot left, and the factorisation stops [incomplete]); the
/// right sides `carried` (each n entries) are eliminated along, row by row
/// after the row of the matrix. Per step: 1/pivot; per row below with a
/// nonzero in the pivot column, its multiplier, its updates in the columns
/// left where the pivot row is nonzero, then its entry in the pivot column
/// set to zero.
///
/// [incomplete]: Lu::complete
pub fn factor<C: Carrier>(
    c: &mut C,
    mut a: Vec<Vec<C::Value>>,
    mut next: impl FnMut(&C, &[Vec<C::Value>], Left) -> Option<(usize, usize)>,
    carried: &mut [Vec<C::Value>],
) -> Lu<C::Value> {
    let n = a.len();
    let (mut row_done, mut col_done) = (vec![false; n], vec![false; n]);
    let mut pivots = Vec::with_capacity(n);
    let mut multipliers = Vec::with_capacity(n);
    while pivots.len() < n {
        let left = Left {
            row_done: &row_done,
            col_done: &col_done,
        };
        let Some((p, col)) = next(c, &a, left) else {
            break;
        };
        row_done[p] = true;
        col_done[col] = true;
        pivots.push((p, col));
        let inv = c.recip(a[p][col]);
        let below: Vec<usize> = (0..n)
            .filter(|&i| !row_done[i] && !c.is_zero(a[i][col]))
            .collect();
        let across: Vec<usize> = (0..n)
            .filter(|&j| !col_done[j] && !c.is_zero(a[p][j]))
            .collect();
        let mut step = Vec::with_capacity(below.len());
        for i in below {
            let f = c.mul(a[i][col], inv);
            for &j in &across {
                let t = c.mul(f, a[p][j]);
                a[i][j] = c.sub(a[i][j], t);
            }
            a[i][col] = C::ZERO;
            for b in carried.iter_mut() {
                eliminate_entry(c, b, (p, i), f);
            }
            step.push((i, f));
        }
        multipliers.push(step);
    }
    Lu {
        pivots,
        multipliers,
        upper: a,
    }
}

/// `a` factored with the steps `pivots` (row, column) given, one per row.
pub fn factor_at<C: Carrier>(
    c: &mut C,
    a: Vec<Vec<C::Value>>,
    pivots: &[(usize, usize)],
) -> Lu<C::Value> {
    let mut steps = pivots.iter().copied();
    factor(c, a, |_, _, _| steps.next(), &mut [])
}

/// b_i −= f b_p for the pivot row p and a row i below it (nothing if b_p
/// is zero).
fn eliminate_entry<C: Carrier>(c: &mut C, b: &mut [C::Value], (p, i): (usize, usize), f: C::Value) {
    if !c.is_zero(b[p]) {
        let t = c.mul(f, b[p]);
        b[i] = c.sub(b[i], t);
    }
}

/// A right side eliminated as the matrix was (L⁻¹ b), step by step.
pub fn forward<C: Carrier>(c: &mut C, lu: &Lu<C::Value>, b: &mut [C::Value]) {
    for (&(p, _), step) in lu.pivots.iter().zip(&lu.multipliers) {
        for &(i, f) in step {
            eliminate_entry(c, b, (p, i), f);
        }
    }
}

/// x with U x = b for each eliminated right side b (see [`forward`]), by
/// back substitution from the last pivot: x_col = (b_p − Σ u_pj x_j)/u_pcol,
/// the terms in `order`, those with u_pj zero left out. The pivots' steps
/// are taken in turn, all the right sides at each.
pub fn back<C: Carrier>(
    c: &mut C,
    lu: &Lu<C::Value>,
    rhs: &[Vec<C::Value>],
    order: Order,
) -> Vec<Vec<C::Value>> {
    let n = lu.upper.len();
    let mut x = vec![vec![C::ZERO; n]; rhs.len()];
    for (s, &(p, col)) in lu.pivots.iter().enumerate().rev() {
        let u = &lu.upper[p];
        let inv = c.recip(u[col]);
        let terms: Vec<usize> = match order {
            Order::Columns => (0..n).filter(|&j| j != col).collect(),
            Order::Pivots => lu.pivots[s + 1..].iter().map(|&(_, j)| j).collect(),
        };
        for (b, xb) in rhs.iter().zip(&mut x) {
            let mut acc = c.begin_sum();
            c.plus(&mut acc, b[p]);
            for &j in &terms {
                if c.is_zero(u[j]) {
                    continue;
                }
                let t = c.mul(u[j], xb[j]);
                c.minus(&mut acc, t);
            }
            let v = c.total(acc);
            xb[col] = c.mul(v, inv);
        }
    }
    x
}

/// x with A x = b for the factored A: [`forward`], then [`back`].
pub fn solve<C: Carrier>(
    c: &mut C,
    lu: &Lu<C::Value>,
    mut b: Vec<C::Value>,
    order: Order,
) -> Vec<C::Value> {
    forward(c, lu, &mut b);
    let x = back(c, lu, std::slice::from_ref(&b), order);
    x.into_iter().next().unwrap_or_default()
}

/// det A: the product of the pivots, in order, after the sign of their
/// permutation row ↦ column (−1 or 1 first); zero if the factorisation is
/// incomplete.
pub fn det<C: Carrier>(c: &mut C, lu: &Lu<C::Value>) -> C::Value {
    if !lu.complete() {
        return C::ZERO;
    }
    let mut det = if permutation_is_odd(&lu.pivots) {
        c.int(-1)
    } else {
        C::ONE
    };
    for &(p, col) in &lu.pivots {
        det = c.mul(det, lu.upper[p][col]);
    }
    det
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

/// The determinant of a small square matrix by Laplace expansion along its
/// first row (zero entries skipped), the cofactors' terms summed with
/// alternating signs.
pub fn laplace<C: Carrier>(c: &mut C, m: &[Vec<C::Value>]) -> C::Value {
    match m.len() {
        0 => C::ONE,
        1 => m[0][0],
        n => {
            let mut s = c.begin_sum();
            for j in 0..n {
                if c.is_zero(m[0][j]) {
                    continue;
                }
                let minor: Vec<Vec<C::Value>> = m[1..]
                    .iter()
                    .map(|row| {
                        row.iter()
                            .enumerate()
                            .filter(|&(k, _)| k != j)
                            .map(|(_, &x)| x)
                            .collect()
                    })
                    .collect();
                let d = laplace(c, &minor);
                let t = c.mul(m[0][j], d);
                if j % 2 == 0 {
                    c.plus(&mut s, t);
                } else {
                    c.minus(&mut s, t);
                }
            }
            c.total(s)
        }
    }
}

/// x = m⁻¹ w by Cramer's rule, `inv` = 1/det m: x_j = det(m with column j
/// replaced by w) · inv.
pub fn cramer<C: Carrier>(
    c: &mut C,
    m: &[Vec<C::Value>],
    w: &[C::Value],
    inv: C::Value,
) -> Vec<C::Value> {
    (0..w.len())
        .map(|j| {
            let mj: Vec<Vec<C::Value>> = m
                .iter()
                .zip(w)
                .map(|(row, &wi)| {
                    let mut row = row.clone();
                    row[j] = wi;
                    row
                })
                .collect();
            let dj = laplace(c, &mj);
            c.mul(dj, inv)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn permutation_parity() {
        use super::permutation_is_odd;
        assert!(!permutation_is_odd(&[(0, 0), (1, 1), (2, 2)]));
        assert!(permutation_is_odd(&[(0, 1), (1, 0), (2, 2)]));
        assert!(!permutation_is_odd(&[(2, 0), (0, 1), (1, 2)]));
    }
}
