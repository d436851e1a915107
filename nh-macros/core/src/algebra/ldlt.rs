//! Symmetric systems m x = f by an LDLᵀ factorisation without pivoting:
//! L unit lower triangular, D the pivots. On the graph structural zeros of
//! m cost no operations (its folds drop every product with a zero and every
//! sum with a zero term); in the engine a zero pivot is exact, and the
//! factorisation can stop at it ([`solve_nonsingular`]).

use super::Carrier;

/// An LDLᵀ factorisation.
pub struct Ldlt<V> {
    /// L below the diagonal (the unit diagonal implied).
    l: Vec<Vec<V>>,
    /// The pivots D.
    pub d: Vec<V>,
    /// 1/D.
    dinv: Vec<V>,
}

/// How an update l_ir d_r l_jr of the factorisation is formed.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Updates {
    /// l_ir · (l_jr d_r), with l_jr d_r kept from column r (the value
    /// before its division by d_r): one product a term, where each product
    /// is an operation of the code (the graph's form).
    Kept,
    /// (l_ir l_jr) · d_r, formed from L and D (the engine's form).
    Formed,
}

/// The LDLᵀ factorisation of the symmetric `m` (its lower triangle is
/// read), every pivot taken: a zero pivot gives 1/0, and the caller tests
/// the pivots [`Ldlt::d`].
pub fn factor<C: Carrier>(c: &mut C, m: &[Vec<C::Value>], updates: Updates) -> Ldlt<C::Value> {
    factor_until(c, m, updates, false).0
}

/// The factorisation as [`factor`], stopped at the first zero pivot
/// (nothing is built past it) when `stop`; whether every pivot was taken.
fn factor_until<C: Carrier>(
    c: &mut C,
    m: &[Vec<C::Value>],
    updates: Updates,
    stop: bool,
) -> (Ldlt<C::Value>, bool) {
    let k = m.len();
    let mut l = vec![vec![C::ZERO; k]; k];
    // L·D below the diagonal: l_ij d_j, the value before the division
    let mut ld = vec![vec![C::ZERO; k]; k];
    let mut d = vec![C::ZERO; k];
    let mut dinv = vec![C::ZERO; k];
    for j in 0..k {
        let mut dj = m[j][j];
        for r in 0..j {
            let t = update(c, updates, l[j][r], l[j][r], d[r], ld[j][r]);
            dj = c.sub(dj, t);
        }
        if stop && c.is_zero(dj) {
            return (Ldlt { l, d, dinv }, false);
        }
        d[j] = dj;
        dinv[j] = c.recip(dj);
        for i in (j + 1)..k {
            let mut v = m[i][j];
            for r in 0..j {
                let t = update(c, updates, l[i][r], l[j][r], d[r], ld[j][r]);
                v = c.sub(v, t);
            }
            ld[i][j] = v;
            l[i][j] = c.mul(v, dinv[j]);
        }
    }
    (Ldlt { l, d, dinv }, true)
}

/// The update l_i d_r l_j of a factorisation (`kept`: l_j d_r, kept from
/// column r).
fn update<C: Carrier>(
    c: &mut C,
    updates: Updates,
    l_i: C::Value,
    l_j: C::Value,
    d_r: C::Value,
    kept: C::Value,
) -> C::Value {
    match updates {
        Updates::Kept => c.mul(l_i, kept),
        Updates::Formed => {
            let t = c.mul(l_i, l_j);
            c.mul(t, d_r)
        }
    }
}

/// x with L D Lᵀ x = f: forward substitution L y = f, then
/// Lᵀ x = D⁻¹ y from the last unknown (one more right side costs only the
/// substitutions).
pub fn solve<C: Carrier>(c: &mut C, fac: &Ldlt<C::Value>, f: &[C::Value]) -> Vec<C::Value> {
    let k = f.len();
    let mut y = vec![C::ZERO; k];
    for i in 0..k {
        let mut v = f[i];
        for r in 0..i {
            let t = c.mul(fac.l[i][r], y[r]);
            v = c.sub(v, t);
        }
        y[i] = v;
    }
    let mut x = vec![C::ZERO; k];
    for i in (0..k).rev() {
        let mut v = c.mul(y[i], fac.dinv[i]);
        for r in (i + 1)..k {
            let t = c.mul(fac.l[r][i], x[r]);
            v = c.sub(v, t);
        }
        x[i] = v;
    }
    x
}

/// m x = f solved by [`factor`] and [`solve`]; x and the pivots D (a
/// structurally zero pivot: m is singular, and x divides by zero).
pub fn solve_symmetric<C: Carrier>(
    c: &mut C,
    m: &[Vec<C::Value>],
    f: &[C::Value],
    updates: Updates,
) -> (Vec<C::Value>, Vec<C::Value>) {
    let fac = factor(c, m, updates);
    let x = solve(c, &fac, f);
    (x, fac.d)
}

/// m x = f solved by [`factor`] and [`solve`], or `None` at the first zero
/// pivot, before anything is built past it.
pub fn solve_nonsingular<C: Carrier>(
    c: &mut C,
    m: &[Vec<C::Value>],
    f: &[C::Value],
    updates: Updates,
) -> Option<Vec<C::Value>> {
    let (fac, complete) = factor_until(c, m, updates, true);
    complete.then(|| solve(c, &fac, f))
}
