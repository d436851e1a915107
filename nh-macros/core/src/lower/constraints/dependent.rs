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
use crate::words::RollingField;
use proc_macro2::Ident;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

impl Lowerer<'_> {
    /// Whether a block of dependent-velocity coefficients is singular at
    /// every point.
    pub(in crate::lower) fn generically_singular(&mut self, block: &[Vec<ExprId>]) -> bool {
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
        // the explicit rows made implicit keep their written coordinate
        let pins: Vec<Option<usize>> = (implicit.iter())
            .map(|&a| {
                rows[a]
                    .pinned
                    .and_then(|s| free.iter().position(|&f| f == s))
            })
            .collect();
        if let Some((kw, names)) = &def.dependent {
            let names = with_pins(names, &pins, free, kw, self);
            return self.named_dependent(def, (kw, &names), rows, implicit, free, coef);
        }
        match self.automatic(def, free, coef, &pins) {
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

    /// The automatic choice: [`Lowerer::rule`] with the headings of the
    /// wheels (see [`Lowerer::rolling_headings`]).
    fn automatic(
        &mut self,
        def: &SystemDef,
        free: &[usize],
        coef: &[Vec<ExprId>],
        pins: &[Option<usize>],
    ) -> Result<Vec<usize>, usize> {
        let headings = self.rolling_headings(def, free);
        self.rule(coef, &headings, pins)
    }

    /// For each free coordinate (indices into `free`), whether the heading
    /// of a wheel depends on it: of a body that rolls on an axle (a
    /// `rolls(..)` line with `axle: ..`, a disc or a torus; not a sphere),
    /// the angle of the first factor of its orientation, when that factor
    /// turns about the vertical z. The rule prefers these as dependent
    /// coordinates, so that a vehicle's heading follows from its wheels
    /// and the wheels' rates stay independent.
    fn rolling_headings(&mut self, def: &SystemDef, free: &[usize]) -> Vec<bool> {
        let mut angles = Vec::new();
        for r in &def.rolling {
            let on_axle =
                (r.fields.iter()).any(|f| RollingField::of(&f.name) == Some(RollingField::Axle));
            if !on_axle {
                continue;
            }
            let Some(body) = self.body(&r.body) else {
                continue;
            };
            if let Some((rotation, _)) = &body.rotation
                && let Some(&(2, angle)) = rotation.factors.first()
            {
                angles.push(angle);
            }
        }
        (free.iter())
            .map(|&i| {
                let q = self.coords[i].position;
                angles.iter().any(|&a| self.e.depends_on(a, q))
            })
            .collect()
    }

    /// The rule of DESIGN §9 on the rows `coef` (coefficients of the free
    /// velocities): rows in order; for each, the candidates are the
    /// coordinates not yet dependent with a nonzero coefficient, those with
    /// a nonzero constant coefficient first (declared order), then the
    /// others from the last declared backwards, those a wheel's heading
    /// depends on (`headings`, per free coordinate) before the rest; the
    /// first that keeps the leading block generically nonsingular is
    /// taken, and where a row has none left, the search goes back to the
    /// rows before it (see [`Lowerer::first_order`]). `Err(a)`: no choice
    /// found, and the first row that had no candidate left is `a`.
    fn rule(
        &mut self,
        coef: &[Vec<ExprId>],
        headings: &[bool],
        pins: &[Option<usize>],
    ) -> Result<Vec<usize>, usize> {
        let prefs: Vec<Vec<usize>> = (coef.iter().zip(pins))
            .map(|(row, pin)| {
                if let Some(j) = *pin {
                    return vec![j];
                }
                let mut with_constant: Vec<usize> = Vec::new();
                let mut others: Vec<usize> = Vec::new();
                for (j, &c) in row.iter().enumerate() {
                    if c == ZERO {
                        continue;
                    }
                    match self.e.as_constant(c) {
                        Some(_) => with_constant.push(j),
                        None => others.push(j),
                    }
                }
                others.reverse();
                // a stable sort: the headings first, each part backwards
                others.sort_by_key(|&j| !headings[j]);
                with_constant.extend(others);
                with_constant
            })
            .collect();
        self.first_order(coef, &prefs)
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

    /// The dependent coordinates named in `def`'s `dependent { .. }` (its
    /// keyword and names), checked.
    fn named_dependent(
        &mut self,
        def: &SystemDef,
        (kw, names): (&Ident, &[Ident]),
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
            None => match self.automatic(def, free, coef, &vec![None; coef.len()]) {
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
    /// nonsingular, if there is one: [`Lowerer::first_order`] with the
    /// names tried as the rule tries candidates (a nonzero constant
    /// coefficient first, then another nonzero one, then the rest; within
    /// each, the name listed for the row first, then the listed order).
    /// With p ≤ [`MAX_IMPLICIT`](super::MAX_IMPLICIT) names there are at
    /// most 2^p sets of columns to test. The order found is checked as
    /// written lists are.
    fn reorder(&mut self, coef: &[Vec<ExprId>], names: &[usize]) -> Option<Vec<usize>> {
        let prefs: Vec<Vec<usize>> = (0..names.len())
            .map(|a| {
                let class = |j: usize| match coef[a][j] {
                    ZERO => 2,
                    c if self.e.as_constant(c).is_some() => 0,
                    _ => 1,
                };
                let mut p = names.to_vec();
                // a stable sort: the listed order within each class
                p.sort_by_key(|&j| (class(j), j != names[a]));
                p
            })
            .collect();
        let order = self.first_order(coef, &prefs).ok()?;
        self.first_singular(coef, &order).is_none().then_some(order)
    }

    /// The first list, in the order of the preferences `prefs` (for each
    /// row of `coef`, its candidate columns, most preferred first), of one
    /// column per row whose every leading block is generically
    /// nonsingular: a depth-first search, row by row, that takes the first
    /// candidate not yet taken that keeps the block nonsingular, and goes
    /// back to the row before when a row has none. Where no row runs out,
    /// this is the greedy choice, with the same blocks tested. The
    /// singularity of a leading block depends only on the set of its
    /// columns, and so whether a list can be completed: both are
    /// remembered by set, and past the first dead end at most
    /// [`BACKTRACK_TESTS`] more blocks are tested. `Err(a)`: none found;
    /// `a` is the first row that had no candidate left.
    fn first_order(
        &mut self,
        coef: &[Vec<ExprId>],
        prefs: &[Vec<usize>],
    ) -> Result<Vec<usize>, usize> {
        let mut search = Search {
            tests_left: BACKTRACK_TESTS,
            ..Search::default()
        };
        let mut order = Vec::with_capacity(prefs.len());
        if self.extend_order(coef, prefs, &mut order, &mut search) {
            Ok(order)
        } else {
            Err(search.first_dead.unwrap_or(0))
        }
    }

    /// Extends `order` (a column for each of the first rows) to every row
    /// (see [`Lowerer::first_order`]); whether it could.
    fn extend_order(
        &mut self,
        coef: &[Vec<ExprId>],
        prefs: &[Vec<usize>],
        order: &mut Vec<usize>,
        search: &mut Search,
    ) -> bool {
        let a = order.len();
        if a == prefs.len() {
            return true;
        }
        let set = sorted(order);
        if search.exhausted || search.dead.contains(&set) {
            return false;
        }
        for &j in &prefs[a] {
            if order.contains(&j) {
                continue;
            }
            order.push(j);
            let key = sorted(order);
            let singular = match search.singular.get(&key) {
                Some(&s) => s,
                None if search.first_dead.is_some() && search.tests_left == 0 => {
                    search.exhausted = true;
                    order.pop();
                    return false;
                }
                None => {
                    if search.first_dead.is_some() {
                        search.tests_left -= 1;
                    }
                    let s = self.leading_block_singular(coef, order);
                    search.singular.insert(key, s);
                    s
                }
            };
            if !singular && self.extend_order(coef, prefs, order, search) {
                return true;
            }
            order.pop();
            if search.exhausted {
                return false;
            }
        }
        search.first_dead.get_or_insert(a);
        search.dead.insert(set);
        false
    }
}

/// The blocks [`Lowerer::first_order`] may test past its first dead end.
const BACKTRACK_TESTS: usize = 512;

/// What [`Lowerer::first_order`] remembers, by the set of columns (a
/// sorted list): whether the leading block in them is singular, and the
/// sets that no list completes; and the first row that had no candidate
/// left, the tests left past it, whether they ran out.
#[derive(Default)]
struct Search {
    singular: HashMap<Vec<usize>, bool>,
    dead: HashSet<Vec<usize>>,
    first_dead: Option<usize>,
    tests_left: usize,
    exhausted: bool,
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

/// `names` of `dependent { .. }` with the written coordinate of each
/// explicit row made implicit (`pins`, indices into `free`) put in its
/// row's place, when the list names one coordinate per other row: such a
/// row was explicit when the list was written.
fn with_pins(
    names: &[Ident],
    pins: &[Option<usize>],
    free: &[usize],
    kw: &Ident,
    lw: &Lowerer<'_>,
) -> Vec<Ident> {
    let pinned = pins.iter().filter(|p| p.is_some()).count();
    if pinned == 0 || names.len() + pinned != pins.len() {
        return names.to_vec();
    }
    let mut rest = names.iter();
    (pins.iter())
        .filter_map(|pin| match pin {
            Some(j) => Some(Ident::new(&lw.coords[free[*j]].name.to_string(), kw.span())),
            None => rest.next().cloned(),
        })
        .collect()
}
