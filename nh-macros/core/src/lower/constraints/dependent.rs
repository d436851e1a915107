//! The dependent coordinates of the implicit and holonomic rows (DESIGN §9):
//! those of `dependent { .. }`, checked, else the documented rule. A list
//! that cannot work is one error, at the name where it fails, that says
//! why (the coordinate is not in its constraint, or the block is singular)
//! and which list works: the same coordinates in another order if one
//! does, else the rule's choice.

use super::{Binding, Lowerer, Row, SystemDef, linear};
use crate::ctxt::SpanRange;
use crate::model::ConstraintKind;
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, ZERO};
use proc_macro2::Ident;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

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
        match self.rule(coef) {
            Ok(chosen) => Some(chosen),
            Err(a) => {
                self.no_candidate(rows[implicit[a]].src.range());
                None
            }
        }
    }

    /// The error of a row that no velocity not already dependent can be
    /// solved for (the rows are dependent, whatever the choice).
    fn no_candidate(&mut self, at: SpanRange) {
        self.cx.error(at, "this constraint cannot be solved for any velocity not already dependent: with the constraints before it, its block of dependent velocities is singular at every point (it repeats or combines them, or involves only dependent coordinates); remove it or rewrite it");
    }

    /// The rule of DESIGN §9 on the rows `coef` (coefficients of the free
    /// velocities): rows in order; for each, the candidates are the
    /// coordinates not yet dependent with a nonzero coefficient, those with
    /// a nonzero constant coefficient first (declared order), then the
    /// others from the last declared backwards; the first that keeps the
    /// leading block generically nonsingular is taken. `Err(a)`: row `a`
    /// has no candidate.
    fn rule(&mut self, coef: &[Vec<ExprId>]) -> Result<Vec<usize>, usize> {
        let mut chosen: Vec<usize> = Vec::new();
        for (a, row) in coef.iter().enumerate() {
            let mut with_constant: Vec<usize> = Vec::new();
            let mut others: Vec<usize> = Vec::new();
            for (j, &c) in row.iter().enumerate() {
                if chosen.contains(&j) || c == ZERO {
                    continue;
                }
                match self.e.as_constant(c) {
                    Some(_) => with_constant.push(j),
                    None => others.push(j),
                }
            }
            others.reverse();
            let pick = with_constant.into_iter().chain(others).find(|&j| {
                let cols: Vec<usize> = chosen.iter().copied().chain([j]).collect();
                !self.leading_block_singular(coef, &cols)
            });
            match pick {
                Some(j) => chosen.push(j),
                None => return Err(a),
            }
        }
        Ok(chosen)
    }

    /// Whether the leading block of `coef`, its first `cols.len()` rows in
    /// the columns `cols` (in that order), is singular at every point.
    fn leading_block_singular(&mut self, coef: &[Vec<ExprId>], cols: &[usize]) -> bool {
        let block: Vec<Vec<ExprId>> = coef[..cols.len()]
            .iter()
            .map(|row| cols.iter().map(|&c| row[c]).collect())
            .collect();
        self.generically_singular(&block)
    }

    /// The first row `a` whose leading block in the columns `order[..=a]`
    /// is singular at every point: where the list `order` fails.
    fn first_singular(&mut self, coef: &[Vec<ExprId>], order: &[usize]) -> Option<usize> {
        (0..order.len()).find(|&a| self.leading_block_singular(coef, &order[..=a]))
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
        let Some(a) = self.first_singular(coef, &chosen) else {
            return Some(chosen);
        };
        // the list cannot work: the cause at row a, and a list that works
        let fix = match self.reorder(coef, &chosen) {
            Some(order) => format!(
                "write `{}`: the same coordinates in an order that works",
                self.dependent_list(free, &order)
            ),
            None => match self.rule(coef) {
                Ok(rule) => format!(
                    "no order of `{}` works: write `{}` (the automatic choice), or leave `dependent` out",
                    (names.iter().map(|n| n.to_string()))
                        .collect::<Vec<_>>()
                        .join(", "),
                    self.dependent_list(free, &rule)
                ),
                Err(b) => {
                    // no choice works: the constraints are at fault, not the list
                    self.no_candidate(rows[implicit[b]].src.range());
                    return None;
                }
            },
        };
        let row = &rows[implicit[a]];
        let which = format!(
            "the {} implicit or holonomic constraint, `{}`",
            ordinal(a + 1),
            super::short(row.src.text())
        );
        let name = &names[a];
        let cause = if coef[a][chosen[a]] == ZERO {
            let what = match row.kind {
                ConstraintKind::Holonomic => format!("`{name}`"),
                _ => format!("`dot({name})`"),
            };
            // written, it has the velocity: the explicit rows cancel it
            let velocity = self.coords[free[chosen[a]]].velocity;
            let substituted = if self.e.depends_on(row.value, velocity) {
                ", once the explicit constraints are substituted into it"
            } else {
                ""
            };
            format!(
                "{what} does not appear in {which}{substituted}, which `dependent {{ .. }}` pairs with `{name}` (it lists one coordinate per such constraint, in the constraints' order)"
            )
        } else {
            format!(
                "{which}, cannot be solved for `dot({name})`, which `dependent {{ .. }}` pairs with it: with the constraints before it, the block of dependent velocities is singular at every point"
            )
        };
        self.cx.error_at(name.span(), format!("{cause}; {fix}"));
        None
    }

    /// `dependent { .. }` with the coordinates `order` (indices into
    /// `free`), for a message.
    fn dependent_list(&self, free: &[usize], order: &[usize]) -> String {
        let names: Vec<String> = order
            .iter()
            .map(|&j| self.coords[free[j]].name.to_string())
            .collect();
        format!("dependent {{ {} }}", names.join(", "))
    }

    /// An order of the coordinates `names` (indices into `free`, one per
    /// row of `coef`) whose every leading block is generically
    /// nonsingular, if there is one: a search over the orders, row by row,
    /// that tries the names as the rule does (a nonzero constant
    /// coefficient first, then another nonzero one, then the rest; within
    /// each, the name listed for the row first, then the listed order). The
    /// singularity of a leading block depends only on the set of its
    /// columns, and so whether an order can be completed: both are
    /// remembered by set, so at most 2^p blocks are tested for p rows
    /// (p ≤ [`MAX_IMPLICIT`](super::MAX_IMPLICIT)). The order found is
    /// checked as written lists are.
    fn reorder(&mut self, coef: &[Vec<ExprId>], names: &[usize]) -> Option<Vec<usize>> {
        let mut search = Search::default();
        let mut order = Vec::with_capacity(names.len());
        if !self.extend_order(coef, names, &mut order, &mut search) {
            return None;
        }
        self.first_singular(coef, &order).is_none().then_some(order)
    }

    /// Extends the order `order` of some of `names` to all of them (see
    /// [`Lowerer::reorder`]); whether it could.
    fn extend_order(
        &mut self,
        coef: &[Vec<ExprId>],
        names: &[usize],
        order: &mut Vec<usize>,
        search: &mut Search,
    ) -> bool {
        let a = order.len();
        if a == names.len() {
            return true;
        }
        let set = sorted(order);
        if search.dead.contains(&set) {
            return false;
        }
        let mut candidates: Vec<usize> = (names.iter().copied())
            .filter(|j| !order.contains(j))
            .collect();
        // as the rule orders them: a nonzero constant coefficient first,
        // then another nonzero one, then the rest; within each, the name
        // listed for this row, then the listed order (a stable sort)
        let class = |e: &crate::sym::Engine, j: usize| match coef[a][j] {
            ZERO => 2,
            c if e.as_constant(c).is_some() => 0,
            _ => 1,
        };
        candidates.sort_by_key(|&j| (class(&self.e, j), j != names[a]));
        for j in candidates {
            order.push(j);
            let key = sorted(order);
            let singular = match search.singular.get(&key) {
                Some(&s) => s,
                None => {
                    let s = self.leading_block_singular(coef, order);
                    search.singular.insert(key, s);
                    s
                }
            };
            if !singular && self.extend_order(coef, names, order, search) {
                return true;
            }
            order.pop();
        }
        search.dead.insert(set);
        false
    }
}

/// What [`Lowerer::reorder`] remembers, by the set of columns (sorted):
/// whether the leading block in them is singular, and the sets no order
/// of the remaining names completes.
#[derive(Default)]
struct Search {
    singular: HashMap<Vec<usize>, bool>,
    dead: HashSet<Vec<usize>>,
}

/// A set of columns as its sorted list.
fn sorted(cols: &[usize]) -> Vec<usize> {
    let mut s = cols.to_vec();
    s.sort_unstable();
    s
}

/// "1st", "2nd", "3rd", "4th", ..
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}
