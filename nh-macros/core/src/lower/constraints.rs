//! The constraints of DESIGN §9: each is classified (explicit, implicit or
//! holonomic), the dependent coordinates of the implicit and holonomic ones
//! are chosen (`dependent { .. }` or the documented rule), and every
//! dependent velocity is solved for: ṡ = −A ṙ − β.

mod dependent;

use super::linear;
use super::{Binding, Lowerer, Place};
use crate::ctxt::SpanRange;
use crate::model::{Constraint, ConstraintKind};
use crate::parse::{self, ContactKind, Expr, RollingDef, SystemDef};
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, Rational, SymId, ZERO};
use crate::words::Function;
use rustc_hash::FxHashMap as HashMap;

/// The most implicit and holonomic constraints a system may have: their
/// block of dependent velocities is solved symbolically (Cramer's rule up to
/// [`CRAMER_MAX`](super::linear::CRAMER_MAX) rows, sparse elimination beyond).
pub const MAX_IMPLICIT: usize = 8;

/// The constraints after lowering.
#[derive(Default)]
pub struct Lowered {
    /// One per dependent coordinate, solved.
    pub constraints: Vec<Constraint>,
    /// See [`crate::model::Model::chart`].
    pub chart: Option<ExprId>,
    /// See [`crate::model::Model::homogeneous`].
    pub homogeneous: bool,
    /// See [`crate::model::Model::affine`].
    pub affine: bool,
    /// See [`crate::model::Model::contacts`].
    pub contacts: Vec<[ExprId; 3]>,
    /// See [`crate::model::Model::velocity_rows`].
    pub velocity_rows: Vec<ExprId>,
    /// See [`crate::model::Model::contact_kinematics`].
    pub contact_kinematics: Vec<crate::model::ContactKinematics>,
    /// See [`crate::model::Model::row_contacts`].
    pub row_contacts: Vec<Option<(usize, usize)>>,
    /// Per velocity row, the index of its `rolls(..)` line in the
    /// definition and the component, if it is one's.
    row_sources: Vec<Option<(usize, usize)>>,
    /// The rows of `rolls(..)` lines implied by the rows before them, which
    /// were dropped (their text).
    pub implied: Vec<String>,
    /// See [`crate::model::Model::atlas`].
    pub atlas: Vec<super::atlas::Chart>,
}

/// What the no-slip rows of a `rolls(..)` line say.
const NO_SLIP_X: &str = "no slip along x";
/// See [`NO_SLIP_X`].
const NO_SLIP_Y: &str = "no slip along y";
/// What the rail's row of a `rolls(.., rail: d)` line says.
const ON_RAIL: &str = "on the rail";
/// What the velocity row of a `rolls(.., rail: d)` line says.
const NO_SLIP_RAIL: &str = "no slip along the rail";
/// What the rows of a `rolls(.., on: z = h(x, y), contact: [u, v])` line
/// that place the contact point say.
const AT_CONTACT_X: &str = "the contact point's x is the first coordinate of `contact`";
/// See [`AT_CONTACT_X`].
const AT_CONTACT_Y: &str = "the contact point's y is the second coordinate of `contact`";
/// What the row of a `slides(..)` line says.
const ON_THE_SURFACE: &str = "the point on the surface";
/// What the row of a `skates(..)` line says.
const NO_SKID: &str = "no velocity across the blade";

/// Where a constraint row comes from.
#[derive(Clone, Copy)]
enum Source<'d> {
    /// An equation as written.
    Written(&'d parse::Constraint),
    /// A row of a `rolls(..)` line (and what the row says).
    Rolling(&'d RollingDef, &'static str),
}

impl Source<'_> {
    /// The row's text, for messages and docs.
    fn text(&self) -> String {
        match self {
            Source::Written(c) => source_of(c),
            Source::Rolling(r, what) => {
                let kw = match r.kind {
                    ContactKind::Rolls => "rolls",
                    ContactKind::Skates => "skates",
                    ContactKind::Slides => "slides",
                };
                format!("{kw}({}, ..): {what}", r.body)
            }
        }
    }

    /// The index of the `rolls(..)` line in `def` and the component of the
    /// contact point's material velocity the row is (z for the height, whose
    /// rate is that component), for a row of one.
    fn contact_component(&self, def: &SystemDef) -> Option<(usize, usize)> {
        let Source::Rolling(r, what) = self else {
            return None;
        };
        let line = def.rolling.iter().position(|x| std::ptr::eq(x, *r))?;
        let comp = match *what {
            NO_SLIP_X => 0,
            NO_SLIP_Y => 1,
            _ => 2,
        };
        Some((line, comp))
    }

    /// The range to point at.
    fn range(&self) -> SpanRange {
        match self {
            Source::Written(c) => range_of(c),
            Source::Rolling(r, _) => r.range,
        }
    }
}

/// See [`Lowerer::row_block`].
struct RowBlock {
    explicit_deps: Vec<usize>,
    implicit: Vec<usize>,
    free: Vec<usize>,
    coef: Vec<Vec<ExprId>>,
    bias: Vec<ExprId>,
}

/// A constraint as written and lowered, before solving.
struct Row<'d> {
    src: Source<'d>,
    kind: ConstraintKind,
    /// The dependent coordinate of an explicit row.
    explicit: Option<usize>,
    /// The explicit row's right side, or lhs − rhs (a velocity row: for a
    /// holonomic constraint, the time derivative of f).
    value: ExprId,
    /// f of a holonomic row.
    holonomic: Option<ExprId>,
    /// The written `dot(s)` of an explicit row with a denominator that can
    /// vanish, made implicit with its denominators cleared (DESIGN §9.3):
    /// the system's own chart solves it for s.
    pinned: Option<usize>,
}

/// A constraint's text as written, shortened for messages and docs.
fn source_of(c: &parse::Constraint) -> String {
    format!("{} = {}", c.lhs.to_source(), c.rhs.to_source())
}

/// The range of a whole constraint.
fn range_of(c: &parse::Constraint) -> SpanRange {
    let (l, r) = (c.lhs.range(), c.rhs.range());
    SpanRange {
        first: l.first,
        last: r.last,
    }
}

impl Lowerer<'_> {
    /// The constraints, classified, with their dependent coordinates chosen
    /// and their dependent velocities solved for (DESIGN §9).
    pub(super) fn lower_constraints(&mut self, def: &SystemDef) -> Lowered {
        let Some((_, list)) = &def.constraints else {
            return Lowered {
                homogeneous: true,
                ..Lowered::default()
            };
        };
        self.place = Place::Constraint;
        let mut sides = Vec::new();
        let mut wheels = Vec::new();
        let mut contacts = Vec::new();
        let mut kinematics = Vec::new();
        let mut complete = true;
        for i in 0..=list.len() {
            for r in def.rolling.iter().filter(|r| r.position == i) {
                let one_row = match r.kind {
                    ContactKind::Skates => Some((self.skate_row(r), NO_SKID)),
                    ContactKind::Slides => Some((self.slide_row(r), ON_THE_SURFACE)),
                    ContactKind::Rolls => None,
                };
                if let Some((row, what)) = one_row {
                    match row {
                        Some(row) => sides.push((Source::Rolling(r, what), row, ZERO)),
                        None => complete = false,
                    }
                    continue;
                }
                let task = format!("deriving the contact of `{}`", r.body);
                let rows = self.at(r.range, task, |lw| {
                    lw.rolling_rows(r, &mut sides, &mut wheels)
                });
                if let Some((point, kin)) = rows {
                    contacts.push(point);
                    let line = def.rolling.iter().position(|x| std::ptr::eq(x, r));
                    // a body without closed-form kinematics: written rows
                    kinematics.extend(kin.map(|k| (line, k)));
                } else {
                    complete = false;
                }
            }
            let Some(c) = list.get(i) else { break };
            let task = format!("expanding the constraint `{}`", short(source_of(c)));
            let (lhs, rhs) = self.at(range_of(c), task, |lw| {
                (lw.lower(&c.lhs, 0), lw.lower(&c.rhs, 0))
            });
            if let (Some(l), Some(r)) = (lhs, rhs) {
                sides.push((Source::Written(c), l, r));
            } else {
                complete = false;
            }
        }
        let explicit = self.explicit_targets(&sides);
        let mut rows = Vec::new();
        let written = sides.len();
        for ((c, l, r), s) in sides.into_iter().zip(explicit) {
            if let Some(row) = self.classify(c, l, r, s) {
                rows.push(row);
            }
        }
        if !self.cx.is_empty() {
            // errors elsewhere: the stand-in takes the rows' number
            if complete && rows.len() == written && def.rejected.constraint_lines == 0 {
                self.cx.constraint_rows = Some(self.rows_kept(&rows));
            }
            return Lowered::default();
        }
        let Some(mut lowered) = self.solve_rows(def, rows) else {
            return Lowered::default();
        };
        // for the stand-in, should a later stage find errors
        self.cx.constraint_rows = Some(lowered.constraints.len());
        lowered.contacts = contacts;
        // each velocity row of a contact: which contact, which component
        lowered.row_contacts = lowered
            .row_sources
            .iter()
            .map(|src| {
                let (r, comp) = (*src)?;
                let c = kinematics.iter().position(|k| k.0 == Some(r))?;
                Some((c, comp))
            })
            .collect();
        lowered.contact_kinematics = kinematics.into_iter().map(|k| k.1).collect();
        for w in wheels {
            lowered.chart = Some(match lowered.chart {
                Some(c) => self.e.mul(c, w),
                None => w,
            });
        }
        lowered
    }

    /// The rows of a `rolls(..)` line: the contact's height if it is not
    /// identically zero (holonomic), then no slip along x and along y.
    fn rolling_rows<'d>(
        &mut self,
        r: &'d RollingDef,
        sides: &mut Vec<(Source<'d>, ExprId, ExprId)>,
        wheels: &mut Vec<ExprId>,
    ) -> Option<([ExprId; 3], Option<crate::model::ContactKinematics>)> {
        let contact = self.rolling_contact(r)?;
        if let Some([x, y]) = contact.located {
            // on a surface z = h(x, y) no slip comes first: its rows take
            // the centre's x and y, the height z, and the rows that place
            // the contact the contact coordinates, so that the chart ends
            // where the body no longer fits the surface
            let [vx, vy] = contact.velocity;
            sides.push((Source::Rolling(r, NO_SLIP_X), vx, ZERO));
            sides.push((Source::Rolling(r, NO_SLIP_Y), vy, ZERO));
            let h = contact.height.unwrap_or(ZERO);
            let what = "contact with the surface z = h(x, y)";
            sides.push((Source::Rolling(r, what), h, ZERO));
            sides.push((Source::Rolling(r, AT_CONTACT_X), x, ZERO));
            sides.push((Source::Rolling(r, AT_CONTACT_Y), y, ZERO));
            wheels.extend(contact.chart);
            return Some((contact.point, contact.kinematics));
        }
        if let Some(h) = contact.height {
            sides.push((Source::Rolling(r, "contact with the plane z = 0"), h, ZERO));
        }
        if let Some([row, along]) = contact.rail {
            sides.push((Source::Rolling(r, ON_RAIL), row, ZERO));
            sides.push((Source::Rolling(r, NO_SLIP_RAIL), along, ZERO));
        } else {
            let [vx, vy] = contact.velocity;
            sides.push((Source::Rolling(r, NO_SLIP_X), vx, ZERO));
            sides.push((Source::Rolling(r, NO_SLIP_Y), vy, ZERO));
        }
        wheels.extend(contact.chart);
        Some((contact.point, contact.kinematics))
    }

    /// For each constraint, the coordinate it makes dependent if it is
    /// explicit: written `dot(s) = rhs` with ṡ nowhere in rhs, the first such
    /// constraint for s, and no other explicit constraint's ṡ in rhs.
    fn explicit_targets(&mut self, sides: &[(Source<'_>, ExprId, ExprId)]) -> Vec<Option<usize>> {
        let mut out: Vec<Option<usize>> = Vec::with_capacity(sides.len());
        for (c, _, r) in sides {
            let Source::Written(c) = c else {
                out.push(None);
                continue;
            };
            let s = match c.lhs.call1(Function::Dot) {
                Some(Expr::Name(id)) => match self.scope.get(&id.to_string()) {
                    Some(Binding::Coord(i)) => Some(*i),
                    _ => None,
                },
                _ => None,
            };
            let s = s.filter(|&s| {
                !self.e.depends_on(*r, self.coords[s].velocity) && !out.contains(&Some(s))
            });
            out.push(s);
        }
        loop {
            let mut changed = false;
            for a in 0..out.len() {
                if out[a].is_none() {
                    continue;
                }
                let uses_other = out.iter().enumerate().any(|(b, s)| {
                    b != a
                        && s.is_some_and(|s| self.e.depends_on(sides[a].2, self.coords[s].velocity))
                });
                if uses_other {
                    out[a] = None;
                    changed = true;
                }
            }
            if !changed {
                return out;
            }
        }
    }

    /// A constraint's form, after checking that it is linear in the
    /// velocities.
    fn classify<'d>(
        &mut self,
        c: Source<'d>,
        lhs: ExprId,
        rhs: ExprId,
        explicit: Option<usize>,
    ) -> Option<Row<'d>> {
        let mut g = self.e.sub(lhs, rhs);
        // an explicit row that divides by a function of the coordinates is
        // an implicit row with its denominators cleared, solved for s in
        // the system's own chart and for others in the atlas's
        let cleared = explicit.and_then(|_| self.cleared(g));
        if let Some(h) = cleared {
            g = h;
        }
        if let Source::Written(_) = c {
            self.written.push(g);
        }
        let vels: Vec<SymId> = self.coords.iter().map(|c| c.velocity).collect();
        let has_velocity = vels.iter().any(|&v| self.e.depends_on(g, v));
        if !has_velocity {
            // holonomic: its velocity row is df/dt = Σ ∂f/∂q_i q̇_i + ∂f/∂t
            let value = self.time_derivative(g);
            if value == ZERO {
                self.cx.error(c.range(), format!("the constraint `{}` involves no velocity and no coordinate (it is constant): remove it", c.text()));
                return None;
            }
            return Some(Row {
                src: c,
                kind: ConstraintKind::Holonomic,
                explicit: None,
                value,
                holonomic: Some(g),
                pinned: None,
            });
        }
        // a contact's rows are linear by construction
        if matches!(c, Source::Written(_)) && !self.linear_in_velocities(c, g, explicit) {
            return None;
        }
        if cleared.is_some() {
            return Some(Row {
                src: c,
                kind: ConstraintKind::Cleared,
                explicit: None,
                value: g,
                holonomic: None,
                pinned: explicit,
            });
        }
        let (kind, value) = match explicit {
            Some(_) => {
                let b = self.velocity_free_part(rhs);
                let affine = b != ZERO || self.e.depends_on(rhs, self.t_sym);
                let kind = if affine {
                    ConstraintKind::ExplicitAffine
                } else {
                    ConstraintKind::ExplicitVelocity
                };
                (kind, rhs)
            }
            None => (ConstraintKind::Implicit, g),
        };
        Some(Row {
            src: c,
            kind,
            explicit,
            value,
            holonomic: None,
            pinned: None,
        })
    }

    /// `g` times the denominators of its terms that depend on the
    /// coordinates and may vanish (each atom to the highest power it
    /// divides by; `tan` is sin·cos⁻¹), `None` if there are none.
    fn cleared(&mut self, g: ExprId) -> Option<ExprId> {
        let positions: Vec<SymId> = self.coords.iter().map(|c| c.position).collect();
        let mut denominators: Vec<(crate::sym::AtomId, Rational)> = Vec::new();
        for &(m, _) in self.e.terms(g) {
            for &(a, k) in self.e.factors(m) {
                if !k.is_negative() {
                    continue;
                }
                match denominators.iter_mut().find(|d| d.0 == a) {
                    Some(d) => d.1 = d.1.max(k.abs()),
                    None => denominators.push((a, k.abs())),
                }
            }
        }
        let mut product = crate::sym::ONE;
        for (a, k) in denominators {
            let base = self.e.atom_power(a, Rational::ONE);
            let of_coordinates = (self.e.free_symbols(base).iter()).any(|s| positions.contains(s));
            if of_coordinates && !self.e.seen_positive(base) {
                let power = self.e.atom_power(a, k);
                product = self.e.mul(product, power);
            }
        }
        (product != crate::sym::ONE).then(|| self.e.mul(product, g))
    }

    /// `x` with every velocity set to zero.
    fn velocity_free_part(&mut self, x: ExprId) -> ExprId {
        let map: HashMap<SymId, ExprId> = self.coords.iter().map(|c| (c.velocity, ZERO)).collect();
        self.e.subst(x, &map, &mut HashMap::default())
    }

    /// Whether `g` is affine in the velocities: no coefficient ∂g/∂q̇_i
    /// depends on a velocity, and g − Σ_i ∂g/∂q̇_i q̇_i does not either (it
    /// is the velocity-free part; a symbolic remainder in the velocities
    /// must vanish at random points).
    pub(super) fn is_linear_in_velocities(&mut self, g: ExprId) -> bool {
        let vels: Vec<SymId> = self.coords.iter().map(|c| c.velocity).collect();
        let mut parts = vec![g];
        for &v in &vels {
            if !self.e.depends_on(g, v) {
                continue;
            }
            let d = self.e.diff(g, v);
            if vels.iter().any(|&w| self.e.depends_on(d, w)) {
                return false;
            }
            let vs = self.e.sym(v);
            let term = self.e.mul(d, vs);
            parts.push(self.e.neg(term));
        }
        let rest = self.e.sum(&parts);
        if !vels.iter().any(|&w| self.e.depends_on(rest, w)) {
            return true;
        }
        let b = self.velocity_free_part(g);
        let rest = self.e.sub(rest, b);
        rest == ZERO || vanish_at_random_points(&self.e, self.pi_sym, &[rest])
    }

    /// Whether `g` is linear in the velocities after the engine's
    /// simplification: every coefficient ∂g/∂q̇_i is free of velocities, and
    /// so is what is left, g − Σ_i ∂g/∂q̇_i q̇_i. (Second derivatives are not
    /// the test: d/du |u| = sign(u) has a zero derivative, so `abs(dot(x))`
    /// would pass.) Reports the offending term if not.
    fn linear_in_velocities(&mut self, c: Source<'_>, g: ExprId, explicit: Option<usize>) -> bool {
        let linear = self.is_linear_in_velocities(g);
        if linear {
            return true;
        }
        let all: Vec<usize> = (0..self.coords.len()).collect();
        let form = "a constraint must be linear in the velocities, each velocity to the first power times a function of the coordinates and time: `dot(s) = a1(q, t)*dot(r1) + .. + b(q, t)` or `c1(q, t)*dot(q1) + .. = b(q, t)`";
        let who = match explicit {
            Some(s) => format!("the constraint for `{}`", self.coords[s].name),
            None => format!("the constraint `{}`", short(c.text())),
        };
        let sides = match c {
            Source::Written(c) => vec![&c.lhs, &c.rhs],
            Source::Rolling(..) => Vec::new(),
        };
        for side in sides {
            for term in super::top_level_terms(side) {
                // only a term that is itself not linear once simplified
                // (`abs(dot(x))/abs(dot(x))*dot(x)` is `dot(x)`)
                let nonlinear = self
                    .lower(term, 0)
                    .is_some_and(|v| !self.is_linear_in_velocities(v));
                if !nonlinear {
                    continue;
                }
                if let Some((culprit, why)) = self.find_nonlinear(term, &all) {
                    let text = culprit.to_source();
                    self.cx.error(
                        culprit.range(),
                        format!("{who} is not linear in the velocities: `{text}` {why}; {form}"),
                    );
                    return false;
                }
            }
        }
        self.cx.error(
            c.range(),
            format!("{who} is not linear in the velocities once expanded; {form}"),
        );
        false
    }

    /// Chooses the dependent coordinates of the implicit and holonomic rows
    /// and solves every row for its dependent velocity.
    fn solve_rows(&mut self, def: &SystemDef, rows: Vec<Row<'_>>) -> Option<Lowered> {
        let n = self.coords.len();
        let RowBlock {
            explicit_deps,
            implicit,
            free,
            coef,
            bias,
        } = self.row_block(&rows);
        let implied = self.implied_rolling_rows(&rows, &implicit, &coef, &bias);
        if !implied.is_empty() {
            // rows of `rolls(..)` lines that the rows before them imply (two
            // wheels on one axle): dropped, and the rest solved without them
            let texts: Vec<String> = implied.iter().map(|&a| rows[a].src.text()).collect();
            let kept = rows
                .into_iter()
                .enumerate()
                .filter(|(a, _)| !implied.contains(a))
                .map(|(_, r)| r)
                .collect();
            let mut lowered = self.solve_rows(def, kept)?;
            lowered.implied = texts;
            return Some(lowered);
        }
        if implicit.len() > MAX_IMPLICIT {
            let c = rows[implicit[MAX_IMPLICIT]].src;
            self.cx.error(c.range(), format!("at most {MAX_IMPLICIT} constraints may be implicit or holonomic (their block of dependent velocities is solved symbolically): write the others explicitly, `dot(s) = ..`"));
            return None;
        }
        let chosen = self.choose_dependent(def, &rows, &implicit, &free, &coef)?;
        let dependent: Vec<usize> = explicit_deps
            .iter()
            .chain(chosen.iter().map(|&j| &free[j]))
            .copied()
            .collect();
        let independent: Vec<usize> = (0..n).filter(|i| !dependent.contains(i)).collect();
        crate::check::independent_left(
            def,
            n,
            &independent,
            def.constraints.as_ref().map(|c| c.0.span()),
            self.cx,
        );
        if independent.is_empty() {
            return None;
        }
        let (solved, det) = self.solve_block(&coef, &bias, &chosen, &free);
        // a block solved by elimination, with no explicit rows: its rows
        // as written, for the dependent accelerations (see Model::velocity_rows)
        let (velocity_rows, row_sources) =
            if explicit_deps.is_empty() && implicit.len() > linear::CRAMER_MAX {
                implicit
                    .iter()
                    .map(|&a| (rows[a].value, rows[a].src.contact_component(def)))
                    .unzip()
            } else {
                (Vec::new(), Vec::new())
            };
        let chart = (!implicit.is_empty()).then(|| self.regularity(det, &coef));
        let atlas = if implicit.is_empty() || def.one_chart {
            Vec::new()
        } else {
            let holonomic: Vec<ExprId> = rows.iter().filter_map(|r| r.holonomic).collect();
            self.atlas(&coef, &free, &chosen, &holonomic)
        };
        let back: HashMap<SymId, ExprId> = chosen
            .iter()
            .zip(&solved)
            .map(|(&j, &v)| (self.coords[free[j]].velocity, v))
            .collect();
        let mut homogeneous = true;
        let mut affine = false;
        let mut constraints = Vec::with_capacity(rows.len());
        let mut next_implicit = 0;
        for row in &rows {
            let (s, velocity) = match row.explicit {
                Some(s) if back.is_empty() => (s, row.value),
                Some(s) => (s, self.e.subst(row.value, &back, &mut HashMap::default())),
                None => {
                    let j = chosen[next_implicit];
                    next_implicit += 1;
                    (free[j], solved[next_implicit - 1])
                }
            };
            let coefficients = independent
                .iter()
                .map(|&i| {
                    let d = self.e.diff(velocity, self.coords[i].velocity);
                    self.e.neg(d)
                })
                .collect();
            let row_affine = self.velocity_free_part(velocity) != ZERO
                || self.e.depends_on(velocity, self.t_sym);
            affine |= row_affine;
            homogeneous &= row.kind != ConstraintKind::Holonomic && !row_affine;
            constraints.push(Constraint {
                kind: row.kind,
                dependent: s,
                velocity,
                coefficients,
                holonomic: row.holonomic,
                source: row.src.text(),
            });
        }
        Some(Lowered {
            constraints,
            chart,
            homogeneous,
            affine,
            contacts: Vec::new(),
            velocity_rows,
            row_sources,
            atlas,
            ..Lowered::default()
        })
    }

    /// The rows' block: the explicit rows' dependent coordinates, the
    /// implicit and holonomic rows (indices into `rows`), the coordinates
    /// not made dependent by explicit rows, and those rows' coefficients of
    /// their velocities and velocity-free parts, the explicit velocities
    /// substituted.
    fn row_block(&mut self, rows: &[Row<'_>]) -> RowBlock {
        let n = self.coords.len();
        let explicit_deps: Vec<usize> = rows.iter().filter_map(|r| r.explicit).collect();
        let implicit: Vec<usize> = (0..rows.len())
            .filter(|&a| rows[a].explicit.is_none())
            .collect();
        let free: Vec<usize> = (0..n).filter(|i| !explicit_deps.contains(i)).collect();
        // the explicit velocities substituted into the other rows
        let sub: HashMap<SymId, ExprId> = rows
            .iter()
            .filter_map(|r| r.explicit.map(|s| (self.coords[s].velocity, r.value)))
            .collect();
        let mut coef: Vec<Vec<ExprId>> = Vec::new();
        let mut bias = Vec::new();
        for &a in &implicit {
            let v = self.e.subst(rows[a].value, &sub, &mut HashMap::default());
            coef.push(
                free.iter()
                    .map(|&i| self.e.diff(v, self.coords[i].velocity))
                    .collect(),
            );
            bias.push(self.velocity_free_part(v));
        }
        RowBlock {
            explicit_deps,
            implicit,
            free,
            coef,
            bias,
        }
    }

    /// The number of rows kept of a system's complete rows (those implied
    /// by the rows before them dropped): the stand-in's dimensions when
    /// the system has errors elsewhere.
    fn rows_kept(&mut self, rows: &[Row<'_>]) -> usize {
        let block = self.row_block(rows);
        let implied = self.implied_rolling_rows(rows, &block.implicit, &block.coef, &block.bias);
        rows.len() - implied.len()
    }

    /// The implicit block solved, c_s ṡ = −(c_r ṙ + b): the dependent
    /// velocities (in the order of `chosen`) and det c_s. Up to
    /// [`linear::CRAMER_MAX`] rows the right side is one vector, linear in
    /// ṙ; beyond, A and β are eliminated column by column, each entry a
    /// function of q and t only, and ṡ = −A ṙ − β assembled after.
    fn solve_block(
        &mut self,
        coef: &[Vec<ExprId>],
        bias: &[ExprId],
        chosen: &[usize],
        free: &[usize],
    ) -> (Vec<ExprId>, ExprId) {
        let block: Vec<Vec<ExprId>> = coef
            .iter()
            .map(|row| chosen.iter().map(|&j| row[j]).collect())
            .collect();
        let e = &mut self.e;
        if block.len() > linear::CRAMER_MAX {
            // the right sides' columns: −c_r for each ṙ involved, then −b
            let mut velocities = Vec::new();
            let mut columns: Vec<Vec<ExprId>> = Vec::new();
            for (j, &i) in free.iter().enumerate() {
                if !chosen.contains(&j) && coef.iter().any(|row| row[j] != ZERO) {
                    velocities.push(e.sym(self.coords[i].velocity));
                    columns.push(coef.iter().map(|row| e.neg(row[j])).collect());
                }
            }
            columns.push(bias.iter().map(|&b| e.neg(b)).collect());
            let s = linear::solve(e, &block, &columns);
            let solved = (0..block.len())
                .map(|a| {
                    let mut parts = vec![s.x[velocities.len()][a]];
                    for (xk, &v) in s.x.iter().zip(&velocities) {
                        parts.push(e.mul(xk[a], v));
                    }
                    e.sum(&parts)
                })
                .collect();
            return (solved, s.det);
        }
        let w: Vec<ExprId> = (0..block.len())
            .map(|a| {
                let mut parts = vec![bias[a]];
                for (j, &i) in free.iter().enumerate() {
                    if !chosen.contains(&j) && coef[a][j] != ZERO {
                        let v = e.sym(self.coords[i].velocity);
                        parts.push(e.mul(coef[a][j], v));
                    }
                }
                let s = e.sum(&parts);
                e.neg(s)
            })
            .collect();
        let s = linear::solve(e, &block, &[w]);
        (s.x.into_iter().next().unwrap_or_default(), s.det)
    }

    /// det(c_s)/Π_a ‖c_a‖: the signed Hadamard ratio of the implicit rows.
    fn regularity(&mut self, det: ExprId, coef: &[Vec<ExprId>]) -> ExprId {
        let e = &mut self.e;
        let mut parts = vec![det];
        for row in coef {
            let squares: Vec<ExprId> = row.iter().map(|&c| e.mul(c, c)).collect();
            let norm2 = e.sum(&squares);
            parts.push(e.pow(norm2, Rational::new(-1, 2).unwrap_or(Rational::MINUS_ONE)));
        }
        parts
            .into_iter()
            .fold(crate::sym::ONE, |acc, x| e.mul(acc, x))
    }

    /// The rows (indices into `rows`) of `rolls(..)` lines that the
    /// implicit rows before them imply: rows [c_a | b_a] (coefficients of
    /// the free velocities, then the velocity-free part) in the span of the
    /// earlier kept rows at each of 4 random points, to 1e-9 of their size.
    /// A written row is never dropped (the singular block's error says it
    /// repeats others), nor a row whose coefficients are implied but whose
    /// velocity-free part is not (then the rows contradict each other).
    fn implied_rolling_rows(
        &mut self,
        rows: &[Row<'_>],
        implicit: &[usize],
        coef: &[Vec<ExprId>],
        bias: &[ExprId],
    ) -> Vec<usize> {
        if !implicit
            .iter()
            .any(|&a| matches!(rows[a].src, Source::Rolling(..)))
        {
            return Vec::new();
        }
        let points: Vec<Vec<Vec<f64>>> = (0..4u64)
            .map(|k| self.rows_at_random_point(coef, bias, k))
            .collect();
        let mut kept: Vec<usize> = Vec::new();
        let mut implied = Vec::new();
        for (a, &ra) in implicit.iter().enumerate() {
            let candidates = [&kept[..], &[a]].concat();
            let in_span = points
                .iter()
                .all(|m| linear::in_span_numerically(m, &kept, a));
            if in_span && matches!(rows[ra].src, Source::Rolling(..)) {
                implied.push(ra);
            } else {
                kept = candidates;
            }
        }
        implied
    }

    /// The rows [c_a | b_a] at a random point (the `k`-th of a fixed
    /// sequence; every symbol in [0.3, 1.4], π itself).
    fn rows_at_random_point(&self, coef: &[Vec<ExprId>], bias: &[ExprId], k: u64) -> Vec<Vec<f64>> {
        let mut rng = crate::sym::Rng::new(0x9E37_79B9_7F4A_7C15 ^ k);
        let vals = rng.point(self.e.num_symbols(), self.pi_sym);
        coef.iter()
            .zip(bias)
            .map(|(row, &b)| {
                row.iter()
                    .chain([&b])
                    .map(|&x| self.e.eval(x, &vals).to_f64())
                    .collect()
            })
            .collect()
    }
}

/// A text for a message, shortened past 60 characters.
fn short(s: String) -> String {
    super::short(s)
}
