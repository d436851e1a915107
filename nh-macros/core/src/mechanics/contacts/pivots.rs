//! The static pivots of a block of velocity rows solved in the generated
//! code (DESIGN §9): an elimination order chosen at expansion, by the sizes
//! of the entries at two test states and by what each step costs.

/// What an entry of the block is, for the cost of eliminating with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Entry {
    /// Identically zero: nothing to eliminate.
    Zero,
    /// A number (a column of a planar pair is e_x or e_y): a pivot needs no
    /// division, a multiplier no product.
    Constant,
    /// Depends on the state or the parameters.
    Varying,
}

/// A pivot must be at least this fraction of the largest entry left in its
/// column at the operating point (threshold partial pivoting: each step
/// grows the entries by at most 1 + 1/THRESHOLD).
const THRESHOLD: f64 = 0.1;

/// What a pivot costs, compared in order: not a constant, Markowitz's
/// count, minus its size relative to its column.
type Cost = (bool, usize, f64);

/// The block as the pivot search sees it: the kinds of its entries and
/// their values at the coordinates' zero and at a random state.
pub struct Block {
    /// The kind of each entry, p × p.
    pub kinds: Vec<Vec<Entry>>,
    /// The entries at the coordinates' zero (the usual operating point).
    pub at_zero: Vec<Vec<f64>>,
    /// The entries at a random state.
    pub at_random: Vec<Vec<f64>>,
}

impl Block {
    /// The elimination steps (pivot row, column), in order: at each step,
    /// among the entries within [`THRESHOLD`] of their column's largest at
    /// the operating point (at the random state if none is) and nonzero at
    /// the other state, a constant entry first, then the fewest updates
    /// (Markowitz's count (r − 1)(c − 1) of the nonzeros left in the
    /// entry's row and column), then the largest relative to its column.
    /// `None` if some column has no usable pivot at either state.
    pub fn elimination_order(mut self) -> Option<Vec<(usize, usize)>> {
        let p = self.kinds.len();
        let (mut rows, mut cols) = (vec![true; p], vec![true; p]);
        let mut steps = Vec::with_capacity(p);
        for _ in 0..p {
            let (r, j) = self
                .best(&rows, &cols, true)
                .or_else(|| self.best(&rows, &cols, false))?;
            rows[r] = false;
            cols[j] = false;
            self.eliminate(r, j, &rows, &cols);
            steps.push((r, j));
        }
        Some(steps)
    }

    /// The best pivot left, judged by size at the operating point (`zero`)
    /// or at the random state, and nonzero at the other.
    fn best(&self, rows: &[bool], cols: &[bool], zero: bool) -> Option<(usize, usize)> {
        let (judged, other) = if zero {
            (&self.at_zero, &self.at_random)
        } else {
            (&self.at_random, &self.at_zero)
        };
        let left = |v: &[bool]| (0..v.len()).filter(|&i| v[i]).collect::<Vec<_>>();
        let (rows, cols) = (left(rows), left(cols));
        let count = |it: &mut dyn Iterator<Item = Entry>| it.filter(|&k| k != Entry::Zero).count();
        let mut best: Option<(Cost, (usize, usize))> = None;
        for &j in &cols {
            let largest = rows.iter().map(|&i| judged[i][j].abs()).fold(0.0, f64::max);
            let in_col = count(&mut rows.iter().map(|&i| self.kinds[i][j]));
            for &i in &rows {
                let (x, y) = (judged[i][j].abs(), other[i][j].abs());
                let usable = x.is_finite() && x > 1e-9 && x >= THRESHOLD * largest;
                if self.kinds[i][j] == Entry::Zero || !usable || !(zero || y > 1e-12) {
                    continue;
                }
                let in_row = count(&mut cols.iter().map(|&c| self.kinds[i][c]));
                let key = (
                    self.kinds[i][j] != Entry::Constant,
                    (in_row - 1) * (in_col - 1),
                    -x / largest,
                );
                if best.is_none_or(|(b, _)| key < b) {
                    best = Some((key, (i, j)));
                }
            }
        }
        best.map(|(_, at)| at)
    }

    /// One step of the elimination with pivot (r, j), on the kinds and on
    /// the values at both states.
    fn eliminate(&mut self, r: usize, j: usize, rows: &[bool], cols: &[bool]) {
        let p = rows.len();
        let below: Vec<usize> = (0..p)
            .filter(|&i| rows[i] && self.kinds[i][j] != Entry::Zero)
            .collect();
        let along: Vec<usize> = (0..p)
            .filter(|&c| cols[c] && self.kinds[r][c] != Entry::Zero)
            .collect();
        for i in below {
            for &c in &along {
                let all_constant = [self.kinds[i][j], self.kinds[r][j], self.kinds[r][c]]
                    .iter()
                    .all(|&k| k == Entry::Constant)
                    && self.kinds[i][c] != Entry::Varying;
                self.kinds[i][c] = if all_constant {
                    Entry::Constant
                } else {
                    Entry::Varying
                };
            }
            self.kinds[i][j] = Entry::Zero;
            for a in [&mut self.at_zero, &mut self.at_random] {
                let piv = a[r][j];
                if piv == 0.0 || !piv.is_finite() {
                    continue;
                }
                let f = a[i][j] / piv;
                for c in (0..p).filter(|&c| cols[c]) {
                    a[i][c] -= f * a[r][c];
                }
                a[i][j] = 0.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Block, Entry};
    use Entry::{Constant as C, Varying as V, Zero as Z};

    #[test]
    fn constant_pivots_go_first_and_fill_is_avoided() {
        // the bicycle's block at the coordinates' zero: columns yaw, pitch,
        // front wheel, u_x, u_y; rows rear x, rear y, height, front x, front y
        let kinds = vec![
            vec![V, V, Z, C, Z],
            vec![V, V, Z, Z, C],
            vec![Z, V, Z, Z, Z],
            vec![V, V, V, C, Z],
            vec![V, V, V, Z, C],
        ];
        let at_zero = vec![
            vec![0.0, -1.08, 0.0, 1.0, 0.0],
            vec![0.0, 0.0, 0.0, 0.0, 1.0],
            vec![0.0, -0.91, 0.0, 0.0, 0.0],
            vec![0.0, -1.08, -0.52, 1.0, 0.0],
            vec![0.91, 0.0, 0.0, 0.0, 1.0],
        ];
        let at_random = vec![
            vec![0.3, -1.12, 0.0, 1.0, 0.0],
            vec![0.2, 0.1, 0.0, 0.0, 1.0],
            vec![0.0, -0.02, 0.0, 0.0, 0.0],
            vec![0.6, -1.32, -1.10, 1.0, 0.0],
            vec![0.02, 0.01, 0.48, 0.0, 1.0],
        ];
        let order = Block {
            kinds,
            at_zero,
            at_random,
        }
        .elimination_order()
        .unwrap();
        // u_x and u_y by the rear contact's rows (pivot 1, no division),
        // then pitch by the height row (a single entry in its row), then
        // yaw and the front wheel by what is left of the front rows
        assert_eq!(order, vec![(0, 3), (1, 4), (2, 1), (4, 0), (3, 2)]);
    }

    #[test]
    fn a_small_pivot_is_passed_over_and_a_singular_block_has_none() {
        let block = |at_zero: Vec<Vec<f64>>| Block {
            kinds: vec![vec![V, V], vec![V, V]],
            at_random: at_zero.clone(),
            at_zero,
        };
        // (0, 0) would cost the same as (1, 0) but is 1e-3 of its column
        let order = block(vec![vec![1e-3, 1.0], vec![1.0, 1.0]]).elimination_order();
        assert_eq!(order.unwrap()[0], (1, 0));
        assert!(
            block(vec![vec![1.0, 1.0], vec![1.0, 1.0]])
                .elimination_order()
                .is_none()
        );
    }
}
