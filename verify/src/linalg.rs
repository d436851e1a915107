//! Small dense linear algebra over any [`Scalar`]: LU with partial
//! pivoting, and the choice of linearly independent rows.

use crate::Scalar;

/// A dense matrix as rows.
pub type Matrix<S> = Vec<Vec<S>>;

fn mag<S: Scalar>(x: S) -> f64 {
    x.to_f64().abs()
}

/// Solves `a x = b` for several right sides (the columns of `b`) by LU
/// with partial pivoting; `None` if a pivot is below `1e-14` of the
/// largest entry of `a` (singular to working precision). Also returns the
/// ratio of the largest to the smallest pivot, a cheap condition estimate.
pub fn solve<S: Scalar>(a: &Matrix<S>, b: &Matrix<S>) -> Option<(Matrix<S>, f64)> {
    let n = a.len();
    let mut m = a.clone();
    let mut r = b.clone();
    let scale = m.iter().flatten().map(|&x| mag(x)).fold(0.0, f64::max);
    let (mut big, mut small) = (0.0f64, f64::INFINITY);
    for col in 0..n {
        let p = (col..n).max_by(|&i, &j| mag(m[i][col]).total_cmp(&mag(m[j][col])))?;
        let piv = mag(m[p][col]);
        if piv.is_nan() || piv <= 1e-14 * scale {
            return None;
        }
        big = big.max(piv);
        small = small.min(piv);
        m.swap(col, p);
        r.swap(col, p);
        for i in col + 1..n {
            let f = m[i][col] / m[col][col];
            for j in col..n {
                m[i][j] = m[i][j] - f * m[col][j];
            }
            for j in 0..r[i].len() {
                r[i][j] = r[i][j] - f * r[col][j];
            }
        }
    }
    for col in (0..n).rev() {
        for j in 0..r[col].len() {
            let mut s = r[col][j];
            for k in col + 1..n {
                s = s - m[col][k] * r[k][j];
            }
            r[col][j] = s / m[col][col];
        }
    }
    Some((r, big / small))
}

/// The rows of `rows` (each `[c | b]`) that are linearly independent in
/// their first `n` entries, in order, by Gram–Schmidt against the rows
/// kept before: a row whose coefficients leave a residual below `tol` of
/// their size is implied, and a row whose coefficients are below `tol` of
/// the largest row's vanishes (rounding of an identically zero row).
/// `Err(a)` if row `a`'s coefficients are implied
/// but its last entries are not (contradicting rows).
pub fn independent_rows<S: Scalar>(
    rows: &Matrix<S>,
    n: usize,
    tol: f64,
) -> Result<Vec<usize>, usize> {
    let scale = rows.iter().map(|r| norm(&r[..n])).fold(0.0, f64::max);
    let mut basis: Vec<Vec<S>> = Vec::new();
    let mut kept = Vec::new();
    for (a, row) in rows.iter().enumerate() {
        let mut res = row.clone();
        for e in &basis {
            let mut dot = S::zero();
            for i in 0..n {
                dot = dot + res[i] * e[i];
            }
            for (x, y) in res.iter_mut().zip(e) {
                *x = *x - dot * *y;
            }
        }
        let size = norm(&row[..n]);
        let left = norm(&res[..n]);
        if left > tol * size && size > tol * scale {
            let inv = S::one() / S::from_f64(left);
            // one more pass keeps the basis orthonormal in double-double
            let mut e: Vec<S> = res.iter().map(|&x| x * inv).collect();
            let len = norm(&e[..n]);
            let inv = S::one() / S::from_f64(len);
            e.iter_mut().for_each(|x| *x = *x * inv);
            basis.push(e);
            kept.push(a);
        } else if norm(&res[n..]) > tol * (size + norm(&row[n..])).max(1.0) {
            return Err(a);
        }
    }
    Ok(kept)
}

/// The 2-norm condition number λ_max/λ_min of a symmetric positive
/// definite matrix in `f64`: 30 steps of the power iteration on it and on
/// its inverse (LU); infinite if it is singular or not positive.
pub fn spd_condition<S: Scalar>(a: &Matrix<S>) -> f64 {
    let m: Matrix<f64> = a
        .iter()
        .map(|r| r.iter().map(|x| x.to_f64()).collect())
        .collect();
    let n = m.len();
    if n == 0 {
        return 1.0;
    }
    let times = |v: &[f64]| -> Vec<f64> {
        m.iter()
            .map(|r| r.iter().zip(v).map(|(x, y)| x * y).sum())
            .collect()
    };
    let unit = |v: Vec<f64>| -> (Vec<f64>, f64) {
        let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        (v.iter().map(|x| x / len).collect(), len)
    };
    let start: Vec<f64> = (0..n).map(|i| 1.0 + 0.1 * i as f64).collect();
    let (mut v, mut big) = unit(start.clone());
    for _ in 0..30 {
        (v, big) = unit(times(&v));
    }
    let (mut w, mut inv) = unit(start);
    for _ in 0..30 {
        let col: Matrix<f64> = w.iter().map(|&x| vec![x]).collect();
        let Some((x, _)) = solve(&m, &col) else {
            return f64::INFINITY;
        };
        (w, inv) = unit(x.iter().map(|r| r[0]).collect());
    }
    if big.is_finite() && inv.is_finite() && inv > 0.0 {
        big * inv
    } else {
        f64::INFINITY
    }
}

/// |det a| / Π‖row‖ in `f64`: 1 for orthogonal rows, 0 for a singular
/// matrix (Hadamard's ratio), the conditioning of a chart of dependent
/// velocities.
pub fn hadamard_ratio<S: Scalar>(a: &Matrix<S>) -> f64 {
    let n = a.len();
    let mut m: Vec<Vec<f64>> = a
        .iter()
        .map(|r| r.iter().map(|x| x.to_f64()).collect())
        .collect();
    let mut ratio = 1.0;
    for row in &m {
        let len = row.iter().map(|x| x * x).sum::<f64>().sqrt();
        if len == 0.0 {
            return 0.0;
        }
        ratio /= len;
    }
    for col in 0..n {
        let Some(p) = (col..n).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs())) else {
            return 0.0;
        };
        m.swap(col, p);
        let piv = m[col][col];
        if piv == 0.0 {
            return 0.0;
        }
        ratio *= piv.abs();
        for i in col + 1..n {
            let f = m[i][col] / piv;
            for j in col..n {
                m[i][j] -= f * m[col][j];
            }
        }
    }
    ratio
}

fn norm<S: Scalar>(v: &[S]) -> f64 {
    v.iter().map(|&x| mag(x) * mag(x)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_and_finds_implied_rows() {
        let a = vec![vec![0.0, 2.0], vec![3.0, 1.0]];
        let b = vec![vec![2.0], vec![4.0]];
        let (x, _) = solve(&a, &b).unwrap();
        assert!((x[0][0] - 1.0).abs() < 1e-15 && (x[1][0] - 1.0).abs() < 1e-15);
        let rows = vec![
            vec![1.0, 1.0, 0.5],
            vec![2.0, 2.0, 1.0],
            vec![0.0, 1.0, 0.0],
        ];
        assert_eq!(independent_rows(&rows, 2, 1e-10), Ok(vec![0, 2]));
        let bad = vec![vec![1.0, 1.0, 0.5], vec![2.0, 2.0, 0.0]];
        assert_eq!(independent_rows(&bad, 2, 1e-10), Err(1));
        assert!(solve(&vec![vec![1.0, 2.0], vec![2.0, 4.0]], &b).is_none());
    }
}
