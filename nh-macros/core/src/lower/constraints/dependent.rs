//! The dependent coordinates of the implicit and holonomic rows (DESIGN §9):
//! those of `dependent { .. }`, checked, else the documented rule.

use super::{Binding, Lowerer, Row, SystemDef, linear};
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, ZERO};
use proc_macro2::Ident;

impl Lowerer<'_> {
    /// Whether a block of dependent-velocity coefficients is singular at
    /// every point.
    fn generically_singular(&mut self, block: &[Vec<ExprId>]) -> bool {
        let d = linear::det(&mut self.e, block);
        d == ZERO || vanish_at_random_points(&self.e, self.pi_sym, &[d])
    }

    /// For each implicit row, the index in `free` of its dependent
    /// coordinate: from `dependent { .. }`, else by the rule of DESIGN §9.
    pub(super) fn choose_dependent(
        &mut self,
        def: &SystemDef,
        rows: &[Row<'_>],
        implicit: &[usize],
        free: &[usize],
        coef: &[Vec<ExprId>],
    ) -> Option<Vec<usize>> {
        if let Some((kw, names)) = &def.dependent {
            return self.named_dependent(kw, names, rows, implicit, free, coef);
        }
        let mut chosen: Vec<usize> = Vec::new();
        for (a, &ra) in implicit.iter().enumerate() {
            let mut with_constant: Vec<usize> = Vec::new();
            let mut others: Vec<usize> = Vec::new();
            for j in 0..free.len() {
                if chosen.contains(&j) || coef[a][j] == ZERO {
                    continue;
                }
                match self.e.as_constant(coef[a][j]) {
                    Some(_) => with_constant.push(j),
                    None => others.push(j),
                }
            }
            others.reverse();
            let pick = with_constant.into_iter().chain(others).find(|&j| {
                let cols: Vec<usize> = chosen.iter().copied().chain([j]).collect();
                let block: Vec<Vec<ExprId>> = coef[..=a]
                    .iter()
                    .map(|row| cols.iter().map(|&c| row[c]).collect())
                    .collect();
                !self.generically_singular(&block)
            });
            match pick {
                Some(j) => chosen.push(j),
                None => {
                    self.cx.error(rows[ra].src.range(), "this constraint cannot be solved for any velocity not already dependent: with the constraints before it, its block of dependent velocities is singular at every point (it repeats or combines them, or involves only dependent coordinates); remove it or rewrite it");
                    return None;
                }
            }
        }
        Some(chosen)
    }

    /// The dependent coordinates named in `dependent { .. }`, checked.
    fn named_dependent(
        &mut self,
        kw: &Ident,
        names: &[Ident],
        rows: &[Row<'_>],
        implicit: &[usize],
        free: &[usize],
        coef: &[Vec<ExprId>],
    ) -> Option<Vec<usize>> {
        let mut chosen = Vec::new();
        for id in names {
            let j = match self.scope.get(&id.to_string()) {
                Some(Binding::Coord(i)) => free.iter().position(|f| f == i),
                _ => {
                    let hint = self.coordinate_hint(id);
                    self.cx.error_at(id.span(), format!("`{id}` is not a coordinate{hint}: `dependent {{ .. }}` lists the coordinates the implicit and holonomic constraints are solved for"));
                    return None;
                }
            };
            let involved = j.filter(|&j| coef.iter().any(|row| row[j] != ZERO));
            match involved {
                Some(j) if chosen.contains(&j) => {
                    self.cx.error_at(
                        id.span(),
                        format!("`{id}` is listed twice in `dependent`: remove one"),
                    );
                    return None;
                }
                Some(j) => chosen.push(j),
                None => {
                    self.cx.error_at(id.span(), format!("`{id}` appears in no implicit or holonomic constraint (or is made dependent by an explicit constraint `dot({id}) = ..`), so none can be solved for it: list a coordinate whose velocity such a constraint involves"));
                    return None;
                }
            }
        }
        if chosen.len() != implicit.len() {
            let count = |n: usize, one: &str, many: &str| {
                format!("{n} {}", if n == 1 { one } else { many })
            };
            self.cx.error_at(kw.span(), format!("`dependent` lists {}, but {} implicit or holonomic: list exactly one dependent coordinate per such constraint, in their order", count(chosen.len(), "coordinate", "coordinates"), count(implicit.len(), "constraint is", "constraints are")));
            return None;
        }
        for a in 0..implicit.len() {
            let block: Vec<Vec<ExprId>> = coef[..=a]
                .iter()
                .map(|row| chosen[..=a].iter().map(|&c| row[c]).collect())
                .collect();
            if self.generically_singular(&block) {
                let name = &self.coords[free[chosen[a]]].name;
                self.cx.error(rows[implicit[a]].src.range(), format!("this constraint cannot be solved for `dot({name})` (named in `dependent`): with the constraints before it, the block of dependent velocities is singular at every point; list another coordinate in `dependent`"));
                return None;
            }
        }
        Some(chosen)
    }
}
