//! The atlas of a system's charts (DESIGN §9.3). A chart is a choice of
//! the coordinates the implicit and holonomic rows are solved for; it is
//! singular where the block of their coefficients, c_s, is. The rows are
//! regular where c has full rank, that is where *some* block of p of its
//! columns is nonsingular, so the charts of every nonsingular block cover
//! every regular point. The atlas keeps a few of them: the system's own
//! chart first, then, greedily, the chart that is best (largest Hadamard
//! ratio) at the points where every chart taken so far is singular and the
//! rows are not, found numerically by Gauss–Newton from random starts, until
//! no such point is found or [`MAX_CHARTS`] are taken.

use super::Lowerer;
use super::linear;
use crate::sym::{Engine, ExprId, Rng, ZERO};

/// The most charts an atlas holds (the system's own included).
pub const MAX_CHARTS: usize = 4;
/// Most candidate blocks examined (the first ones in column order).
const MAX_CANDIDATES: usize = 512;
/// Random starts of the search for common singular points.
const STARTS: u64 = 8;
/// Gauss–Newton iterations per start.
const ITERATIONS: usize = 20;
/// A Hadamard ratio at least this large: the rows are regular there.
const REGULAR: f64 = 1e-3;

/// One chart of the atlas.
#[derive(Clone, Debug)]
pub struct Chart {
    /// The coordinates (indices in q) the implicit and holonomic rows are
    /// solved for, in the rows' order.
    pub dependent: Vec<usize>,
    /// det c_s of the chart as text: the chart is singular where it
    /// vanishes.
    pub singular: String,
    /// The sequence a free rotation is read in, in a chart of its angles
    /// (DESIGN §9.4); `None` in a chart of the constraints.
    pub euler: Option<super::euler_charts::EulerChart>,
}

/// The rows' coefficients evaluated at points that differ in the
/// coordinates and time only (the parameters at fixed random values).
struct Numeric<'e> {
    e: &'e Engine,
    coef: &'e [Vec<ExprId>],
    /// The holonomic constraints f(q, t) = 0: the points searched are on them.
    holonomic: &'e [ExprId],
    base: Vec<f64>,
    /// The symbols varied: the coordinates' positions, then time.
    varied: Vec<usize>,
}

impl Numeric<'_> {
    /// c at the point whose varied symbols are `z`; `None` if not finite.
    fn matrix(&self, z: &[f64]) -> Option<Vec<Vec<f64>>> {
        let mut vals = self.base.clone();
        for (&s, &v) in self.varied.iter().zip(z) {
            vals[s] = v;
        }
        let mut memo = crate::sym::EvalMemo::default();
        let m: Vec<Vec<f64>> = self
            .coef
            .iter()
            .map(|row| {
                row.iter()
                    .map(|&c| {
                        if c == ZERO {
                            0.0
                        } else {
                            self.e.eval_memo(c, &vals, &mut memo)
                        }
                    })
                    .collect()
            })
            .collect();
        m.iter().flatten().all(|v| v.is_finite()).then_some(m)
    }

    /// The holonomic constraints' values at `z`.
    fn holonomic_at(&self, z: &[f64]) -> Vec<f64> {
        let mut vals = self.base.clone();
        for (&s, &v) in self.varied.iter().zip(z) {
            vals[s] = v;
        }
        let mut memo = crate::sym::EvalMemo::default();
        (self.holonomic.iter())
            .map(|&f| self.e.eval_memo(f, &vals, &mut memo))
            .collect()
    }

    /// The ratios of `charts` and the holonomic constraints' values at
    /// `z`: what vanishes on the common singular set of the charts on the
    /// constraint manifold.
    fn residuals(&self, charts: &[Vec<usize>], z: &[f64]) -> Vec<f64> {
        let mut r = self.ratios(charts, z);
        r.extend(self.holonomic_at(z));
        r
    }

    /// The signed ratios of `charts` at `z` (zeros where not finite).
    fn ratios(&self, charts: &[Vec<usize>], z: &[f64]) -> Vec<f64> {
        match self.matrix(z) {
            Some(m) => charts.iter().map(|s| hadamard(&m, s)).collect(),
            None => vec![f64::NAN; charts.len()],
        }
    }
}

/// det(c_s)/Π_a ‖c_a‖ of the columns `cols` of `m` (0 for a zero row).
fn hadamard(m: &[Vec<f64>], cols: &[usize]) -> f64 {
    let block: Vec<Vec<f64>> = m
        .iter()
        .map(|row| cols.iter().map(|&j| row[j]).collect())
        .collect();
    let mut ratio = det(block);
    for row in m {
        let norm = row.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            return 0.0;
        }
        ratio /= norm;
    }
    ratio
}

/// Gaussian elimination with partial pivoting of the small system
/// `a x = b` (`b` may be empty): the upper-triangular factor, the right
/// side carried along, and det a; `None` at a pivot of magnitude `tiny`
/// or less.
fn eliminate(
    mut a: Vec<Vec<f64>>,
    mut b: Vec<f64>,
    tiny: f64,
) -> Option<(Vec<Vec<f64>>, Vec<f64>, f64)> {
    let n = a.len();
    let mut d = 1.0;
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= tiny {
            return None;
        }
        if p != c {
            a.swap(p, c);
            if !b.is_empty() {
                b.swap(p, c);
            }
            d = -d;
        }
        d *= a[c][c];
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            for k in c..n {
                a[r][k] -= f * a[c][k];
            }
            if !b.is_empty() {
                b[r] -= f * b[c];
            }
        }
    }
    Some((a, b, d))
}

/// The determinant of a small matrix (0 for a zero pivot).
fn det(a: Vec<Vec<f64>>) -> f64 {
    eliminate(a, Vec::new(), 0.0).map_or(0.0, |(_, _, d)| d)
}

/// Solves the small system `a x = b`; `None` if a pivot is below 1e-300.
fn solve(a: Vec<Vec<f64>>, b: Vec<f64>) -> Option<Vec<f64>> {
    let (u, b, _) = eliminate(a, b, 1e-300)?;
    let n = b.len();
    let mut x = vec![0.0; n];
    for c in (0..n).rev() {
        let s: f64 = (c + 1..n).map(|k| u[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / u[c][c];
    }
    Some(x)
}

/// The `p`-element subsets of `0..m` in lexicographic order, at most
/// [`MAX_CANDIDATES`] of them, among the columns `allowed`.
fn subsets(allowed: &[usize], p: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut idx: Vec<usize> = (0..p).collect();
    let m = allowed.len();
    if p == 0 || p > m {
        return out;
    }
    loop {
        out.push(idx.iter().map(|&i| allowed[i]).collect());
        if out.len() == MAX_CANDIDATES {
            return out;
        }
        let Some(i) = (0..p).rev().find(|&i| idx[i] != i + m - p) else {
            return out;
        };
        idx[i] += 1;
        for j in i + 1..p {
            idx[j] = idx[j - 1] + 1;
        }
    }
}

/// A point of the common singular set of `charts` near `z` (Gauss–Newton
/// on their ratios, minimal-norm steps); `None` if it does not converge.
fn common_singular_point(
    num: &Numeric<'_>,
    charts: &[Vec<usize>],
    mut z: Vec<f64>,
) -> Option<Vec<f64>> {
    for _ in 0..ITERATIONS {
        let r = num.residuals(charts, &z);
        if r.iter().any(|v| !v.is_finite()) {
            return None;
        }
        if r.iter().all(|v| v.abs() < 1e-10) {
            return Some(z);
        }
        // the Jacobian of the ratios by forward differences
        let jac: Vec<Vec<f64>> = (0..z.len())
            .map(|i| {
                let h = 1e-7 * (1.0 + z[i].abs());
                let mut zi = z.clone();
                zi[i] += h;
                let ri = num.residuals(charts, &zi);
                ri.iter().zip(&r).map(|(a, b)| (a - b) / h).collect()
            })
            .collect();
        let j = r.len();
        // (J Jᵀ + μ I) y = r, Δz = −Jᵀ y
        let gram: Vec<Vec<f64>> = (0..j)
            .map(|a| {
                (0..j)
                    .map(|b| {
                        let s: f64 = jac.iter().map(|col| col[a] * col[b]).sum();
                        s + if a == b { 1e-14 } else { 0.0 }
                    })
                    .collect()
            })
            .collect();
        let y = solve(gram, r)?;
        for (i, col) in jac.iter().enumerate() {
            z[i] -= col.iter().zip(&y).map(|(c, y)| c * y).sum::<f64>();
        }
    }
    None
}

impl Lowerer<'_> {
    /// The atlas of the implicit block `coef` (rows × the coordinates
    /// `free`), whose chart `chosen` (indices into `free`) the system takes:
    /// empty when that chart is never singular (no other is needed), else
    /// that chart and the others, at most [`MAX_CHARTS`].
    pub(super) fn atlas(
        &mut self,
        coef: &[Vec<ExprId>],
        free: &[usize],
        chosen: &[usize],
        holonomic: &[ExprId],
    ) -> Vec<Chart> {
        let p = coef.len();
        let involved: Vec<usize> = (0..free.len())
            .filter(|&j| coef.iter().any(|row| row[j] != ZERO))
            .collect();
        let mut rng = Rng::new(0x5851_F42D_4C95_7F2D);
        let base: Vec<f64> = rng
            .point(self.e.num_symbols(), self.pi_sym)
            .iter()
            .map(|v| v.to_f64())
            .collect();
        let varied: Vec<usize> = self
            .coords
            .iter()
            .map(|c| c.position.index())
            .chain([self.t_sym.index()])
            .collect();
        let num = Numeric {
            e: &self.e,
            coef,
            holonomic,
            base,
            varied,
        };
        let start = |rng: &mut Rng| -> Vec<f64> {
            (0..num.varied.len())
                .map(|_| std::f64::consts::PI * (2.0 * rng.next_f64() - 1.0))
                .collect()
        };
        let probes: Vec<Vec<Vec<f64>>> = (0..3)
            .filter_map(|_| num.matrix(&start(&mut rng)))
            .collect();
        let mut own = chosen.to_vec();
        own.sort_unstable();
        let candidates: Vec<Vec<usize>> = subsets(&involved, p)
            .into_iter()
            .filter(|s| *s == own || probes.iter().any(|m| hadamard(m, s).abs() > 1e-9))
            .collect();
        let mut charts = vec![own];
        while charts.len() < MAX_CHARTS {
            let points: Vec<Vec<f64>> = (0..STARTS)
                .filter_map(|_| common_singular_point(&num, &charts, start(&mut rng)))
                .filter(|z| {
                    let r = num.ratios(&candidates, z);
                    r.iter().any(|v| v.abs() > REGULAR)
                })
                .collect();
            if points.is_empty() {
                break;
            }
            let worst = |s: &Vec<usize>| {
                points
                    .iter()
                    .map(|z| num.ratios(std::slice::from_ref(s), z)[0].abs())
                    .fold(f64::INFINITY, f64::min)
            };
            let scored: Vec<(f64, &Vec<usize>)> = candidates
                .iter()
                .filter(|s| !charts.contains(s))
                .map(|s| (worst(s), s))
                .filter(|(w, _)| w.is_finite() && *w > 0.0)
                .collect();
            let top = scored.iter().map(|c| c.0).fold(0.0, f64::max);
            // among the charts nearly as good as the best there, the one
            // closest to the system's own (fewest coordinates changed)
            let shared = |s: &Vec<usize>| s.iter().filter(|j| charts[0].contains(j)).count();
            let best = scored
                .iter()
                .filter(|c| c.0 >= 0.5 * top)
                .max_by(|a, b| shared(a.1).cmp(&shared(b.1)).then(a.0.total_cmp(&b.0)));
            match best {
                Some((_, s)) => charts.push((*s).clone()),
                None => break,
            }
        }
        if charts.len() == 1 {
            return Vec::new();
        }
        let mut atlas = Vec::with_capacity(charts.len());
        for (c, cols) in charts.iter().enumerate() {
            let ordered = if c == 0 {
                Some(chosen.to_vec())
            } else {
                self.row_order(coef, cols)
            };
            let Some(ordered) = ordered else { continue };
            let block: Vec<Vec<ExprId>> = coef
                .iter()
                .map(|row| ordered.iter().map(|&j| row[j]).collect())
                .collect();
            let singular = if p <= linear::CRAMER_MAX {
                let d = linear::det(&mut self.e, &block);
                format!("{} = 0", self.e.display_capped(d, 160))
            } else {
                format!(
                    "the {p}×{p} block of the coefficients of {} is singular",
                    ordered
                        .iter()
                        .map(|&j| format!("`dot({})`", self.coords[free[j]].name))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            atlas.push(Chart {
                dependent: ordered.iter().map(|&j| free[j]).collect(),
                singular,
                euler: None,
            });
        }
        if atlas.len() < 2 { Vec::new() } else { atlas }
    }

    /// The columns `cols` ordered so that the leading blocks (rows 0..=a,
    /// the first a + 1 columns) are generically nonsingular, as
    /// `dependent { .. }` needs; `None` if no order is.
    fn row_order(&mut self, coef: &[Vec<ExprId>], cols: &[usize]) -> Option<Vec<usize>> {
        let mut order = Vec::new();
        self.extend_chart_order(coef, cols, &mut order)
            .then_some(order)
    }

    /// Backtracking for [`Self::row_order`].
    fn extend_chart_order(
        &mut self,
        coef: &[Vec<ExprId>],
        cols: &[usize],
        order: &mut Vec<usize>,
    ) -> bool {
        let a = order.len();
        if a == cols.len() {
            return true;
        }
        for &j in cols {
            if order.contains(&j) || coef[a][j] == ZERO {
                continue;
            }
            order.push(j);
            let block: Vec<Vec<ExprId>> = coef[..=a]
                .iter()
                .map(|row| order.iter().map(|&c| row[c]).collect())
                .collect();
            if !self.generically_singular(&block) && self.extend_chart_order(coef, cols, order) {
                return true;
            }
            order.pop();
        }
        false
    }
}
