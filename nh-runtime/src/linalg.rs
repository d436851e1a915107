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
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        for k in 0..D {
            // Partial pivoting: the largest entry of column k at or below k.
            let mut p = k;
            let mut max = a[(k, k)].abs();
            for i in k + 1..D {
                let v = a[(i, k)].abs();
                if v > max {
                    max = v;
                    p = i;
                }
            }
            if !(max.is_finite() && max > T::zero()) {
                return None;
            }
            if p != k {
                a.swap_rows(p, k);
                perm.swap(p, k);
            }
            let pivot = a[(k, k)];
            for i in k + 1..D {
                let l = a[(i, k)] / pivot;
                a[(i, k)] = l;
                for j in k + 1..D {
                    let akj = a[(k, j)];
                    a[(i, j)] -= l * akj;
                }
            }
        }
        if !a.iter().all(|v| v.is_finite()) {
            return None;
        }
        Some(Self { lu: a, perm })
    }

    /// Solves `A x = b`.
    pub(crate) fn solve(&self, b: &SVector<T, D>) -> SVector<T, D> {
        let mut x = SVector::<T, D>::from_fn(|i, _| b[self.perm[i]]);
        for i in 0..D {
            for j in 0..i {
                let lij = self.lu[(i, j)];
                let xj = x[j];
                x[i] -= lij * xj;
            }
        }
        for i in (0..D).rev() {
            for j in i + 1..D {
                let uij = self.lu[(i, j)];
                let xj = x[j];
                x[i] -= uij * xj;
            }
            x[i] /= self.lu[(i, i)];
        }
        x
    }
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
