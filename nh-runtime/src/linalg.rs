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
        let column_k = &a[k];
        let (mut p, mut max) = (k, column_k[k].abs());
        // (Index loops here and below: the iterator forms cost ~70 and ~470
        // more instructions per factorisation at D = 8.)
        #[allow(clippy::needless_range_loop)]
        for i in k + 1..D {
            let v = column_k[i].abs();
            if v > max {
                (p, max) = (i, v);
            }
        }
        // `0·max` is 0 for a finite `max` and NaN otherwise (cheaper than
        // `is_finite` on a generic `T`).
        if !(max * T::zero() == T::zero() && max > T::zero()) {
            return false;
        }
        if p != k {
            for column in a.iter_mut() {
                column.swap(p, k);
            }
            perm.swap(p, k);
        }
        // The multipliers l_i = a_ik / a_kk below the pivot, and a copy of
        // them with zeros on and above row k: the update of each column
        // then runs over whole columns (a fixed-length loop the compiler
        // unrolls and vectorises); rows ≤ k subtract 0 and keep their value
        // (up to the sign of a zero).
        let pivot = a[k][k];
        let mut l = [T::zero(); D];
        let column_k = &mut a[k];
        #[allow(clippy::manual_memcpy)] // (divides, then copies)
        for i in k + 1..D {
            column_k[i] /= pivot;
            l[i] = column_k[i];
        }
        for column_j in a.iter_mut().skip(k + 1) {
            let akj = column_j[k];
            for (aij, &li) in column_j.iter_mut().zip(&l) {
                *aij -= li * akj;
            }
        }
    }
    all_finite_columns(a)
}

/// Whether every entry of the `D×D` matrix `m` is finite.
pub(crate) fn all_finite_matrix<T: RealField + Copy, const D: usize>(m: &SMatrix<T, D, D>) -> bool {
    all_finite_columns(columns::<T, D>(m.as_slice()))
}

/// Whether every entry of the columns `a` is finite, without a branch per
/// entry (`0·v` is 0 for a finite `v` and NaN otherwise).
#[inline]
pub(crate) fn all_finite_columns<T: RealField + Copy, const D: usize>(a: &[[T; D]]) -> bool {
    let mut zero = [T::zero(); D];
    for column in a {
        for (z, &v) in zero.iter_mut().zip(column) {
            *z += v * T::zero();
        }
    }
    zero.iter().fold(T::zero(), |sum, &z| sum + z) == T::zero()
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
    // Forward substitution column by column: each x_i receives the same
    // subtractions in the same order (j ascending) as row by row.
    for (j, column) in lu.iter().enumerate() {
        let xj = x[j];
        for i in j + 1..D {
            x[i] -= column[i] * xj;
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
