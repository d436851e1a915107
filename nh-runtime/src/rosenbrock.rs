//! The stepping code of the L-stable Rosenbrock–Wanner methods for stiff
//! problems, written once over their tableaus (`rodas_tableau.rs`): RODAS4
//! ([`Rodas4`](crate::Rodas4), after Hairer's `RODAS`) and Rodas5P
//! ([`Rodas5P`](crate::Rodas5P), Steinebach 2023), each in its own file.

use core::marker::PhantomData;

use nalgebra::{RealField, SMatrix, SVector};

use crate::Stats;
use crate::jacobian::{JacobianSource, Linearised, time_derivative};
use crate::linalg::{all_finite_matrix, factor, solve};
use crate::method::{Failure, Method, Pi, counted};
use crate::numeric::{all_finite, all_finite_in, c};
use crate::rodas_tableau::Scheme;
use crate::step::Poly;
use crate::tolerance::{Tolerance, error_norm};

/// The state of a Rosenbrock method `K` with `S` stages at an accepted
/// point (derivative, Jacobian, `∂f/∂t`, the rounding carry of the state)
/// and the stages of the last trial.
pub(crate) struct Rodas<J, T, K, const D: usize, const S: usize> {
    src: J,
    f0: SVector<T, D>,
    jac: SMatrix<T, D, D>,
    /// The LU factors of the iteration matrix `I/(hγ) − J` of the last
    /// trial, and their row permutation.
    lu: SMatrix<T, D, D>,
    perm: [usize; D],
    ft: SVector<T, D>,
    u: [SVector<T, D>; S],
    x_new: SVector<T, D>,
    f_new: SVector<T, D>,
    /// The accepted state `x` and the part `carry` of the exact sum
    /// `x_prev + Δx` that rounding `x` dropped (compensated summation): the
    /// next step adds it back. Valid only while the driver hands back this
    /// very `x`.
    x: SVector<T, D>,
    carry: SVector<T, D>,
    /// The rounding carry of the last trial's `x_new`.
    carry_new: SVector<T, D>,
    dense: Poly<T, D>,
    scheme: PhantomData<K>,
}

impl<J, T, K, const D: usize, const S: usize> Rodas<J, T, K, D, S>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
    K: Scheme<S>,
{
    pub(crate) fn new(src: J) -> Self {
        Rodas {
            src,
            f0: SVector::zeros(),
            jac: SMatrix::zeros(),
            lu: SMatrix::zeros(),
            perm: [0; D],
            ft: SVector::zeros(),
            u: [SVector::zeros(); S],
            x_new: SVector::zeros(),
            f_new: SVector::zeros(),
            x: SVector::zeros(),
            carry: SVector::zeros(),
            carry_new: SVector::zeros(),
            dense: Poly::from_monomial(&[]),
            scheme: PhantomData,
        }
    }

    /// The Jacobian and `∂f/∂t` at the accepted point `(t, x)`.
    fn linearise(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.src
            .jacobian(t, x, &self.f0, self.jac.as_mut_slice(), stats);
        self.ft = time_derivative(&self.src, t, x, &self.f0, stats);
        if all_finite_matrix(&self.jac) && all_finite(&self.ft) {
            Ok(())
        } else {
            Err(Failure::NonFinite)
        }
    }

    /// The right-hand side of stage `i`'s linear system:
    /// `f_i + Σ_{j<i} (c_ij/h) U_j + h γ_i ∂f/∂t`.
    #[inline(always)]
    fn stage_rhs(&self, i: usize, f: SVector<T, D>, h: T, inv_h: T) -> SVector<T, D> {
        let tab = &K::TABLEAU;
        let mut b = f;
        if i > 0 {
            let mut coupling = self.u[0] * c::<T>(tab.c[i][0]);
            for j in 1..i {
                coupling += self.u[j] * c::<T>(tab.c[i][j]);
            }
            b += coupling * inv_h;
        }
        if tab.gamma_row[i] != 0.0 {
            b += self.ft * (h * c::<T>(tab.gamma_row[i]));
        }
        b
    }
}

/// `x + δ` rounded, and the rounding error (Knuth's TwoSum, exact in binary
/// floating point), componentwise.
#[inline(always)]
fn two_sum<T: RealField + Copy, const D: usize>(
    x: &SVector<T, D>,
    delta: &SVector<T, D>,
) -> (SVector<T, D>, SVector<T, D>) {
    let sum = x + delta;
    let mut err = SVector::<T, D>::zeros();
    for i in 0..D {
        let bv = sum[i] - x[i];
        err[i] = (x[i] - (sum[i] - bv)) + (delta[i] - bv);
    }
    (sum, err)
}

impl<J, T, K, const D: usize, const S: usize> Method<T, D> for Rodas<J, T, K, D, S>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
    K: Scheme<S>,
{
    const ORDER: u32 = K::ORDER;
    const PI: Pi = K::PI;
    /// `50·eps` (1.1e-14 in `f64`): below, the rounding of the stage
    /// combinations (coefficients up to about 100) sets the error, not the
    /// tolerance.
    const MIN_RTOL_EPS: Option<f64> = Some(50.0);

    fn rhs(&self, t: T, x: &SVector<T, D>) -> SVector<T, D> {
        self.src.rhs(t, x)
    }

    fn start(&mut self, t: T, x: &SVector<T, D>, stats: &mut Stats) -> Result<(), Failure> {
        self.f0 = counted(self.src.rhs(t, x), stats)?;
        self.x = *x;
        self.carry = SVector::zeros();
        self.linearise(t, x, stats)
    }

    fn slope(&self) -> Option<&SVector<T, D>> {
        Some(&self.f0)
    }

    /// The stages with the step `t_new − t` (exact in floating point) rather
    /// than `h`, so that the step integrated is the step the clock takes.
    fn attempt(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        _h: T,
        t_new: T,
        tol: &Tolerance<T, D>,
        stats: &mut Stats,
    ) -> Result<T, Failure> {
        let tab = &K::TABLEAU;
        let h = t_new - t;
        // The iteration matrix I/(hγ) − J and its LU decomposition.
        let fac = T::one() / (h * c(tab.gamma));
        stats.lu_decompositions += 1;
        // (`δ_ij·fac − J_ij` as `I·fac − J` computes it, zeros' signs too.)
        let (m, jac) = (self.lu.as_mut_slice(), self.jac.as_slice());
        for (m, &jac) in m.iter_mut().zip(jac) {
            *m = T::zero() * fac - jac;
        }
        for i in 0..D {
            self.lu[(i, i)] = fac - self.jac[(i, i)];
        }
        if !factor::<T, D>(self.lu.as_mut_slice(), &mut self.perm) {
            return Err(Failure::Singular);
        }
        let inv_h = T::one() / h;
        let b = self.stage_rhs(0, self.f0, h, inv_h);
        self.u[0] = solve(self.lu.as_slice(), &self.perm, &b);
        // `delta`: the argument of the current stage minus x.
        let mut delta = SVector::<T, D>::zeros();
        for i in 1..S {
            if i >= tab.chain {
                delta += self.u[i - 1];
            } else {
                delta = self.u[0] * c::<T>(tab.a[i][0]);
                for j in 1..i {
                    delta += self.u[j] * c::<T>(tab.a[i][j]);
                }
            }
            let ti = if tab.alpha[i] == 1.0 {
                t_new
            } else {
                t + h * c(tab.alpha[i])
            };
            let f = self.src.rhs(ti, &(x + delta));
            let b = self.stage_rhs(i, f, h, inv_h);
            self.u[i] = solve(self.lu.as_slice(), &self.perm, &b);
        }
        stats.rhs_evals += S - 1;
        // x_new = x + Δx, Δx = (last argument − x) + U_S, plus the carry of
        // the previous step when this is the state that step produced.
        let err = self.u[S - 1];
        let mut step = delta + err;
        if *x == self.x {
            step += self.carry;
        }
        (self.x_new, self.carry_new) = two_sum(x, &step);
        if !(all_finite_in(&self.u) && all_finite(&self.x_new)) {
            return Err(Failure::NonFinite);
        }
        Ok(error_norm(&err, x, &self.x_new, tol))
    }

    /// The derivative at the new point (for the next step); a non-finite
    /// one means the step went where the system is undefined.
    fn complete(&mut self, t_new: T, stats: &mut Stats) -> Result<(), Failure> {
        self.f_new = counted(self.src.rhs(t_new, &self.x_new), stats)?;
        Ok(())
    }

    fn x_new(&self) -> &SVector<T, D> {
        &self.x_new
    }

    /// The dense output of RODAS:
    /// `x(θ) = (1−θ) x + θ (x_new + (1−θ)(k1 + θ (k2 + θ k3)))`, as monomials.
    fn build_dense(&mut self, _t: T, x: &SVector<T, D>, _h: T, _stats: &mut Stats) -> bool {
        let tab = &K::TABLEAU;
        let k: [SVector<T, D>; 3] = core::array::from_fn(|r| {
            let mut kr = self.u[0] * c::<T>(tab.dense[r][0]);
            for i in 1..S {
                kr += self.u[i] * c::<T>(tab.dense[r][i]);
            }
            kr
        });
        let chord = self.x_new - x;
        let cubic = [*x, chord + k[0], k[1] - k[0], -k[1]];
        self.dense = if tab.dense[2].iter().all(|&w| w == 0.0) {
            Poly::from_monomial(&cubic)
        } else {
            Poly::from_monomial(&[cubic[0], cubic[1], cubic[2], k[2] - k[1], -k[2]])
        };
        self.dense.is_finite()
    }

    fn dense(&self) -> &Poly<T, D> {
        &self.dense
    }

    fn advance(
        &mut self,
        t: T,
        x: &SVector<T, D>,
        last: bool,
        stats: &mut Stats,
    ) -> Result<(), Failure> {
        self.f0 = self.f_new;
        self.carry = if *x == self.x_new {
            self.carry_new
        } else {
            SVector::zeros()
        };
        self.x = *x;
        if last {
            Ok(())
        } else {
            self.linearise(t, x, stats)
        }
    }
}

impl<J, T, K, const D: usize, const S: usize> Linearised<T, D> for Rodas<J, T, K, D, S>
where
    T: RealField + Copy,
    J: JacobianSource<T, D>,
    K: Scheme<S>,
{
    fn jacobian(&self) -> &SMatrix<T, D, D> {
        &self.jac
    }
}
