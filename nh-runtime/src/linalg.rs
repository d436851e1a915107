//! A small stack-allocated LU decomposition with partial pivoting.
//!
//! nalgebra's `lu()` needs `DimMin` bounds that generic `const D: usize`
//! code cannot state on stable Rust, so the implicit methods use this one.

use nalgebra::{RealField, SMatrix, SVector};

/// `P A = L U` of a `D×D` matrix, stored compactly (unit lower triangle of
/// `L` below the diagonal, `U` on and above it) with the row permutation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lu<T, const D: usize> {
    lu: SMatrix<T, D, D>,
    perm: [usize; D],
}

impl<T: RealField + Copy, const D: usize> Lu<T, D> {
    /// Factorises `a`; `None` if a pivot is zero or anything is non-finite
    /// (the matrix is singular to working precision, or garbage).
    pub(crate) fn new(mut a: SMatrix<T, D, D>) -> Option<Self> {
        let mut perm = [0usize; D];
        factor::<T, D>(a.as_mut_slice(), &mut perm).then_some(Self { lu: a, perm })
    }

    /// Solves `A x = b`.
    pub(crate) fn solve(&self, b: &SVector<T, D>) -> SVector<T, D> {
        solve(self.lu.as_slice(), &self.perm, b)
    }
}

/// The first `D` columns of the column-major slice `a` (`D·D` entries) as
/// arrays, so that indexing them needs no bounds checks.
fn columns<T, const D: usize>(a: &[T]) -> &[[T; D]] {
    &a.as_chunks::<D>().0[..D]
}

/// [`columns`], mutably.
fn columns_mut<T, const D: usize>(a: &mut [T]) -> &mut [[T; D]] {
    &mut a.as_chunks_mut::<D>().0[..D]
}

/// Factorises the `D×D` column-major matrix `a` in place into `P A = L U`
/// with partial pivoting (whole rows are exchanged); `false` if a pivot is
/// zero or anything is non-finite.
pub(crate) fn factor<T: RealField + Copy, const D: usize>(a: &mut [T], perm: &mut [usize]) -> bool {
    let a = columns_mut::<T, D>(a);
    let perm = &mut perm[..D];
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    for k in 0..D {
        // Partial pivoting: the largest entry of column k at or below k.
        let mut p = k;
        let mut max = a[k][k].abs();
        for (i, v) in a[k].iter().enumerate().skip(k + 1) {
            if v.abs() > max {
                max = v.abs();
                p = i;
            }
        }
        if !(max.is_finite() && max > T::zero()) {
            return false;
        }
        if p != k {
            for column in a.iter_mut() {
                column.swap(p, k);
            }
            perm.swap(p, k);
        }
        let (left, right) = a.split_at_mut(k + 1);
        let column_k = &mut left[k];
        let pivot = column_k[k];
        for l in &mut column_k[k + 1..] {
            *l /= pivot;
        }
        for column_j in right {
            let akj = column_j[k];
            for (aij, &l) in column_j[k + 1..].iter_mut().zip(&column_k[k + 1..]) {
                *aij -= l * akj;
            }
        }
    }
    a.iter().flatten().all(|v| v.is_finite())
}

/// Solves `A x = b` with the factors of [`factor`].
pub(crate) fn solve<T: RealField + Copy, const D: usize>(
    lu: &[T],
    perm: &[usize],
    b: &SVector<T, D>,
) -> SVector<T, D> {
    let lu = columns::<T, D>(lu);
    let perm = &perm[..D];
    let mut x = SVector::<T, D>::from_fn(|i, _| b[perm[i]]);
    for i in 0..D {
        for j in 0..i {
            let xj = x[j];
            x[i] -= lu[j][i] * xj;
        }
    }
    for i in (0..D).rev() {
        for j in i + 1..D {
            let xj = x[j];
            x[i] -= lu[j][i] * xj;
        }
        x[i] /= lu[i][i];
    }
    x
}

/// `A v` for the `D×D` column-major matrix `a`.
#[cfg(feature = "alloc")]
pub(crate) fn matvec<T: RealField + Copy, const D: usize>(
    a: &[T],
    v: &SVector<T, D>,
) -> SVector<T, D> {
    let mut y = SVector::<T, D>::zeros();
    for (column, &vj) in a.chunks_exact(D.max(1)).zip(v.iter()) {
        for (yi, &aij) in y.iter_mut().zip(column) {
            *yi += aij * vj;
        }
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn solves_with_pivoting() {
        // A zero leading entry forces a row exchange.
        let a = Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let b = Vector3::new(1.0, 2.0, 3.0);
        let x = Lu::new(a).unwrap().solve(&b);
        assert!((a * x - b).amax() < 1e-14, "{x}");
    }

    #[test]
    fn singular_and_non_finite_are_rejected() {
        let a = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(a).is_none());
        let mut b = Matrix3::<f64>::identity();
        b[(2, 1)] = f64::NAN;
        assert!(Lu::new(b).is_none());
    }
}
