//! Lowering of `speeds { .. }` and `kinematics { .. }` (DESIGN §9): the
//! kinematic relation q̇ = S(q, t) u + σ(q, t), one line per coordinate,
//! checked to be linear in the speeds with S of full column rank.

use super::{Lowerer, Place};
use crate::model::Speeds;
use crate::parse::SystemDef;
use crate::sym::ExprId;
use crate::words::Block;

/// Random points at which the rank of S is evaluated.
const RANK_POINTS: usize = 8;

impl Lowerer<'_> {
    /// The speeds and kinematics of a system written in generalized speeds;
    /// `None` (with the errors recorded) for any other system or a malformed one.
    pub(super) fn lower_speeds(&mut self, def: &SystemDef) -> Option<Speeds> {
        let (speeds_kw, names) = match (&def.speeds, &def.kinematics) {
            (None, None) => return None,
            // a list of speeds that did not parse: already reported
            (None, Some(_)) if def.rejected.names_of(Block::Speeds).is_some() => return None,
            (None, Some((kw, _))) => {
                self.cx.error_at(kw.span(), "`kinematics` without `speeds`: declare the generalized speeds the right sides use, e.g. `speeds { v, omega }`");
                return None;
            }
            (Some((kw, _)), None) => {
                self.cx.error_at(kw.span(), "`speeds` without `kinematics`: give every coordinate's velocity in the speeds, e.g. `kinematics { dot(x) = v*cos(theta); dot(theta) = omega; }`");
                return None;
            }
            (Some((kw, names)), Some(_)) => (kw, names),
        };
        if let Some((ckw, _)) = &def.constraints {
            self.cx.error_at(ckw.span(), "a system in generalized speeds has no `constraints` block: the kinematics q̇ = S(q, t) u + σ(q, t) already keep the velocities in the allowed ones; build the constraints into `kinematics`, or remove `speeds` and `kinematics`");
            return None;
        }
        if names.is_empty() {
            self.cx.error_at(
                speeds_kw.span(),
                "`speeds` is empty: a system needs at least one generalized speed",
            );
            return None;
        }
        let velocities = self.lower_kinematics(def)?;
        let speeds = Speeds {
            span: speeds_kw.span(),
            names: names.clone(),
            syms: self.speed_syms.clone(),
            velocities,
        };
        self.check_rank(&speeds);
        Some(speeds)
    }

    /// q̇_i per coordinate from `kinematics`: each coordinate exactly once,
    /// right sides free of velocities and linear in the speeds.
    fn lower_kinematics(&mut self, def: &SystemDef) -> Option<Vec<ExprId>> {
        let (kw, list) = def.kinematics.as_ref()?;
        let n = self.coords.len();
        let mut given: Vec<Option<ExprId>> = vec![None; n];
        let mut seen = vec![false; n];
        let mut ok = true;
        for line in list {
            let Some(i) = self.velocity_lhs(&line.lhs, "the left side of a line of `kinematics` must be `dot(q)` for a coordinate `q`: write `dot(q) = s1(q)*u1 + ..`") else {
                ok = false;
                continue;
            };
            let name = self.coords[i].name.clone();
            if seen[i] {
                self.cx.error(line.lhs.range(), format!("`dot({name})` is given twice in `kinematics`: each coordinate has exactly one line `dot({name}) = ..`; merge them"));
                ok = false;
                continue;
            }
            seen[i] = true;
            self.place = Place::Kinematics;
            let Some(v) = self.lower(&line.rhs, 0) else {
                ok = false;
                continue;
            };
            if let Some(j) = (0..n).find(|&j| self.e.depends_on(v, self.coords[j].velocity)) {
                let at = self
                    .find_velocity_use(&line.rhs, j)
                    .unwrap_or(line.rhs.range());
                self.cx.error(at, format!("the kinematics of `{name}` uses the velocity `dot({})`: a right side of `kinematics` is written in the coordinates, the speeds and `t` only (q̇ = S(q, t) u + σ(q, t))", self.coords[j].name));
                ok = false;
                continue;
            }
            if !self.linear_in_speeds(v) {
                let term = super::top_level_terms(&line.rhs)
                    .into_iter()
                    .find(|t| self.lower(t, 0).is_some_and(|x| !self.linear_in_speeds(x)));
                let at = term.map_or(line.rhs.range(), |t| t.range());
                let text = term.map_or(String::new(), |t| format!(" (`{}`)", t.to_source()));
                self.cx.error(at, format!("the kinematics of `{name}` is not linear in the speeds{text}: write `dot({name}) = s1(q, t)*u1 + s2(q, t)*u2 + .. + σ(q, t)`, each term one speed to the first power times a function of the coordinates and time, or none"));
                ok = false;
                continue;
            }
            given[i] = Some(v);
        }
        let missing: Vec<String> = (0..n)
            .filter(|&i| !seen[i])
            .map(|i| format!("`dot({}) = ..;`", self.coords[i].name))
            .collect();
        // a line that did not parse may be the missing one: no news
        if !missing.is_empty() && def.rejected.kinematics_lines == 0 {
            self.cx.error_at(
                kw.span(),
                format!(
                    "`kinematics` must give the velocity of every coordinate in the speeds; add {}",
                    missing.join(", ")
                ),
            );
            return None;
        }
        if !ok || !missing.is_empty() {
            return None;
        }
        given.into_iter().collect()
    }

    /// Whether `v` is affine in the speeds: no coefficient ∂v/∂u_a depends
    /// on a speed.
    fn linear_in_speeds(&mut self, v: ExprId) -> bool {
        let syms = self.speed_syms.clone();
        syms.iter().all(|&a| {
            let c = self.e.diff(v, a);
            !syms.iter().any(|&b| self.e.depends_on(c, b))
        })
    }

    /// S = ∂q̇/∂u has full column rank at generic points: its rank at
    /// random points (the largest found) must be k, else an error at `speeds`.
    fn check_rank(&mut self, speeds: &Speeds) {
        let (n, k) = (speeds.velocities.len(), speeds.syms.len());
        let s: Vec<Vec<ExprId>> = speeds
            .velocities
            .iter()
            .map(|&w| speeds.syms.iter().map(|&u| self.e.diff(w, u)).collect())
            .collect();
        let mut rng = crate::sym::Rng::new(0x5EED_5EED_0C0F_FEE5);
        let mut vals = vec![0.0f64; self.e.num_symbols()];
        let mut rank = 0;
        for _ in 0..RANK_POINTS {
            for v in vals.iter_mut() {
                *v = 0.3 + 1.1 * rng.next_f64();
            }
            vals[self.pi_sym.index()] = std::f64::consts::PI;
            let m: Vec<Vec<f64>> = s
                .iter()
                .map(|row| row.iter().map(|&x| self.e.eval(x, &vals)).collect())
                .collect();
            rank = rank.max(numeric_rank(m));
            if rank == k {
                return;
            }
        }
        let list = speeds
            .names
            .iter()
            .map(|u| format!("`{u}`"))
            .collect::<Vec<_>>()
            .join(", ");
        self.cx.error_at(speeds.span, format!("the speeds {list} are not independent: the matrix S of q̇ = S(q, t) u + σ(q, t) ({n} × {k}) has rank {rank} < {k} at generic points, so the accelerations of the speeds are undetermined; remove a speed or change `kinematics` so that no combination of speeds leaves every q̇ unchanged"));
    }
}

/// The rank of a matrix by Gaussian elimination with partial pivoting,
/// pivots below 1e-9 of the largest entry counted as zero (0 for a matrix
/// with an entry that is not finite).
fn numeric_rank(mut m: Vec<Vec<f64>>) -> usize {
    let rows = m.len();
    let cols = m.first().map_or(0, |r| r.len());
    if m.iter().flatten().any(|x| !x.is_finite()) {
        return 0; // a point outside the domain of S: no evidence of rank
    }
    let scale = m.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
    if scale == 0.0 {
        return 0;
    }
    let mut rank = 0;
    for c in 0..cols {
        let Some(p) = (rank..rows).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs())) else {
            break;
        };
        if m[p][c].abs() <= 1e-9 * scale {
            continue;
        }
        m.swap(rank, p);
        for r in (rank + 1)..rows {
            let f = m[r][c] / m[rank][c];
            for j in c..cols {
                m[r][j] -= f * m[rank][j];
            }
        }
        rank += 1;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::numeric_rank;

    #[test]
    fn rank_by_elimination() {
        assert_eq!(
            numeric_rank(vec![vec![1.0, 0.0], vec![0.0, 2.0], vec![3.0, 1.0]]),
            2
        );
        // the second column is twice the first
        assert_eq!(
            numeric_rank(vec![vec![1.0, 2.0], vec![0.5, 1.0], vec![-3.0, -6.0]]),
            1
        );
        // below 1e-9 of the largest entry counts as zero
        assert_eq!(
            numeric_rank(vec![vec![1.0, 1.0], vec![1.0, 1.0 + 1e-12]]),
            1
        );
        assert_eq!(numeric_rank(vec![vec![0.0, 0.0], vec![0.0, 0.0]]), 0);
        assert_eq!(numeric_rank(vec![vec![f64::NAN, 1.0]]), 0);
    }
}
