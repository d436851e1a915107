//! Name resolution and lowering of the surface syntax into the symbolic
//! engine: the Lagrangian, forces and constraints become expressions in the
//! coordinates, velocities, parameters, inputs and time, and every misuse of
//! a name is reported at its token.

pub(crate) mod atlas;
pub(crate) mod bodies;
pub(crate) mod constraints;
mod contacts;
pub(crate) mod euler_charts;
mod expressions;
mod functions;
mod generators;
pub(crate) mod linear;
pub(crate) mod values;
mod velocities;

use crate::check;
use crate::ctxt::{Ctxt, Site, SpanRange};
use crate::model::{Coordinate, Input, Model, Parameter, Partition, Places};
use crate::names;
use crate::parse::{BodyDef, Expr, SystemDef};
use crate::sym::{Engine, ExprId, Rational, SymId, ZERO};
use crate::words::{Constant, Function};
use bodies::BodyState;
use proc_macro2::{Ident, Span};
use rustc_hash::FxHashMap as HashMap;
use values::Value;

mod speeds;

/// The prefix of the names the generated code binds (its fields, locals,
/// helper functions and hidden module): no user name may start with it.
pub const RESERVED_PREFIX: &str = "__nh_";

#[derive(Clone, Copy, Debug)]
enum Binding {
    Param(usize),
    Coord(usize),
    Input(usize),
    Let(usize),
    Speed(usize),
    Body(usize),
    /// A name bound within one expression: a support function's
    /// direction, `x`, `y`, `z` in `support_function: ..`.
    Bound(SymId),
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Place {
    Let,
    Lagrangian,
    Force,
    Constraint,
    Kinematics,
    Body,
}

struct LetInfo {
    value: Option<Value>,
    name: Ident,
}

struct Lowerer<'a> {
    cx: &'a mut Ctxt,
    e: Engine,
    scope: HashMap<String, Binding>,
    params: Vec<Parameter>,
    coords: Vec<Coordinate>,
    inputs: Vec<Input>,
    /// the generalized speeds' symbols, in declared order
    speed_syms: Vec<SymId>,
    lets: Vec<LetInfo>,
    /// the `body` items, lowered on first use
    body_defs: Vec<BodyDef>,
    body_state: Vec<BodyState>,
    t_sym: SymId,
    pi_sym: SymId,
    place: Place,
    /// every `let` name, to tell a use before the definition from a typo
    all_lets: Vec<String>,
    /// names whose declaration failed: uses are not reported again
    poisoned: Vec<String>,
    /// see [`Model::huge_constant`]
    huge_constant: Option<SpanRange>,
    /// see [`Model::description`]
    description: Vec<String>,
    /// the bodies whose kinetic energy the Lagrangian takes, with it
    kinetic: Vec<(crate::model::KineticBody, ExprId)>,
    /// see [`Model::written`]
    written: Vec<ExprId>,
    /// The number of errors recorded when the item whose lowering exceeded
    /// the engine's limits began (see [`Lowerer::at`]).
    abandoned_at: Option<usize>,
}

/// The names declared so far, each with what it was declared as.
struct Declarations {
    scope: HashMap<String, Binding>,
    declared: HashMap<String, (&'static str, Span)>,
    poisoned: Vec<String>,
}

impl Declarations {
    /// Declares `id` as `binding` (a `kind` for messages); false, after an
    /// error, for a reserved word or a name declared before.
    fn declare(&mut self, cx: &mut Ctxt, id: &Ident, kind: &'static str) -> bool {
        let s = id.to_string();
        if crate::words::is_reserved(&s) {
            let what = match (Constant::of(id), Function::of(id)) {
                (Some(Constant::Time), _) => "`t` is time",
                (Some(Constant::Pi), _) => "`pi` is the constant π",
                (_, Some(Function::Dot)) => "`dot` is the time derivative",
                _ => "it is a function of the language",
            };
            cx.error_at(
                id.span(),
                format!("`{s}` cannot be used as {kind} name: {what}; choose another name"),
            );
            return false;
        }
        if s.starts_with(RESERVED_PREFIX) {
            // declared all the same: its uses raise no follow-up errors
            cx.error_at(
                id.span(),
                format!("`{s}` cannot be used as {kind} name: names starting with `{RESERVED_PREFIX}` are reserved for the code the macro generates; choose another name"),
            );
        }
        if let Some((prev_kind, prev_span)) = self.declared.get(&s) {
            // names are canonical (`r#x` is `x`); say so if one was written raw
            let raw = !s.starts_with("r#")
                && [id.span(), *prev_span]
                    .iter()
                    .any(|sp| sp.source_text().is_some_and(|t| t.starts_with("r#")));
            let same = if raw {
                format!(" (`r#{s}` and `{s}` are one name, as in Rust)")
            } else {
                String::new()
            };
            cx.error_at(
                id.span(),
                format!("`{s}` is already declared as {prev_kind}{same}; every parameter, coordinate, input and `let` needs its own name"),
            );
            // uses of an ambiguous name are not reported again
            self.poisoned.push(s);
            return false;
        }
        self.declared.insert(s, (kind, id.span()));
        true
    }

    /// Declares `id` and binds it in scope if that succeeded.
    fn bind(&mut self, cx: &mut Ctxt, id: &Ident, kind: &'static str, binding: Binding) {
        if self.declare(cx, id, kind) {
            self.scope.insert(id.to_string(), binding);
        }
    }
}

/// The names of one declaration list (`parameters`, `coordinates`, ..).
fn declared_names(list: &Option<(Ident, Vec<Ident>)>) -> Vec<Ident> {
    list.as_ref().map(|p| p.1.clone()).unwrap_or_default()
}

/// Lowers a parsed system: the model and the engine holding its
/// expressions. Returns `None` when errors make a model meaningless; all
/// errors are in `cx`.
pub fn lower(def: &SystemDef, cx: &mut Ctxt) -> Option<(Model, Engine)> {
    lower_in(def, cx, Engine::new())
}

/// [`lower`] into the fresh engine `e` (with its limits set).
pub fn lower_in(def: &SystemDef, cx: &mut Ctxt, e: Engine) -> Option<(Model, Engine)> {
    check::coordinates_declared(def, cx);
    let (mut lw, let_ok) = Lowerer::declare(def, cx, e);
    lw.lower_lets(def, &let_ok);
    let lagrangian = lw.lower_lagrangian(def);
    lw.lower_forces(def);
    let symmetries = (def.symmetries.iter())
        .flat_map(|(_, list)| lw.lower_generators(list, generators::Declared::Symmetries))
        .collect();
    let momentum_directions = (def.momenta.iter())
        .flat_map(|(_, list)| lw.lower_generators(list, generators::Declared::Momenta))
        .collect();
    let mut lowered = lw.at(
        def.keyword_range(def.constraints.as_ref()),
        "solving the constraints for the dependent velocities",
        |lw| lw.lower_constraints(def),
    );
    let dependent: Vec<usize> = lowered.constraints.iter().map(|c| c.dependent).collect();
    let constraint_atlas = !lowered.atlas.is_empty();
    let charts = lw.at(
        SpanRange::single(def.name.span()),
        "finding the charts of the free rotation",
        |lw| lw.euler_charts(def, &dependent, &mut lowered.chart, constraint_atlas),
    );
    if let Some(charts) = charts {
        lowered.atlas = (charts.into_iter())
            .map(|(euler, singular)| atlas::Chart {
                dependent: dependent.clone(),
                singular,
                euler: Some(euler),
            })
            .collect();
    }
    for text in &lowered.implied {
        lw.description.push(format!(
            "- `{text}`: implied by the constraint rows before it (as for two wheels on one axle), so dropped: it has no dependent coordinate and no multiplier"
        ));
    }
    let kinematics = def.keyword_range(def.kinematics.as_ref());
    let speeds = lw.at(kinematics, "expanding the kinematics", |lw| {
        lw.lower_speeds(def)
    });
    lw.lower_unused_bodies();
    lw.report_limits(def);
    let outputs = check::outputs(def, lw.cx);
    check::outputs_for_form(def, lw.cx);
    let lagrangian = lagrangian?;
    if !lw.cx.is_empty() {
        return None;
    }
    let places = Places {
        lagrangian: def.lagrangians[0].1.range(),
        constraints: def.keyword_range(def.constraints.as_ref()),
    };
    let (lagrangian, kinetic) = lw.at(
        places.lagrangian,
        "splitting the Lagrangian into the bodies' kinetic energies",
        |lw| lw.kinetic_split(lagrangian),
    );
    let bodies = bodies::folded_terms(kinetic.as_ref());
    let forces = lw.coords.iter().map(|c| c.force);
    let kinematics = speeds.iter().flat_map(|s| s.velocities.iter().copied());
    let written: Vec<ExprId> = std::iter::once(lagrangian)
        .chain(bodies)
        .chain(forces)
        .chain(std::mem::take(&mut lw.written))
        .chain(kinematics)
        .collect();
    let mut constraints = lowered.constraints;
    let points = lw.points();
    let partition = match speeds {
        Some(_) => Partition::of(0, &mut constraints),
        None => Partition::of(lw.coords.len(), &mut constraints),
    };
    let model = Model {
        symmetries,
        momentum_directions,
        parameters: lw.params,
        coordinates: lw.coords,
        inputs: lw.inputs,
        time: lw.t_sym,
        pi: lw.pi_sym,
        lagrangian_folded: lagrangian,
        constraints,
        partition,
        outputs,
        speeds,
        homogeneous: lowered.homogeneous,
        affine: lowered.affine,
        chart: lowered.chart,
        atlas: lowered.atlas,
        constraints_span: def.constraints.as_ref().map(|c| c.0.span()),
        description: lw.description,
        contacts: lowered.contacts,
        velocity_rows: lowered.velocity_rows,
        contact_kinematics: lowered.contact_kinematics,
        points,
        row_contacts: lowered.row_contacts,
        huge_constant: lw.huge_constant,
        kinetic,
        places,
        written,
    };
    Some((model, lw.e))
}

impl<'a> Lowerer<'a> {
    /// Declares every name of the system (reporting duplicates, shadowing
    /// and reserved words) and creates their symbols; with, per `let`,
    /// whether its declaration succeeded.
    fn declare(def: &SystemDef, cx: &'a mut Ctxt, mut e: Engine) -> (Lowerer<'a>, Vec<bool>) {
        let t_sym = e.symbol(Constant::Time.name());
        let pi_sym = e.symbol(Constant::Pi.name());
        let mut names = Declarations {
            scope: HashMap::default(),
            declared: HashMap::default(),
            poisoned: def.poisoned.iter().map(|p| p.to_string()).collect(),
        };
        let mut params = Vec::new();
        for (i, p) in declared_names(&def.parameters).into_iter().enumerate() {
            names.bind(cx, &p, "a parameter", Binding::Param(i));
            let sym = e.symbol(&p.to_string());
            params.push(Parameter { name: p, sym });
        }
        let coord_names = declared_names(&def.coordinates);
        let mut positions = Vec::new();
        for (i, c) in coord_names.iter().enumerate() {
            names.bind(cx, c, "a coordinate", Binding::Coord(i));
            positions.push(e.symbol(&c.to_string()));
        }
        let coords = coord_names
            .into_iter()
            .zip(positions)
            .map(|(name, position)| Coordinate {
                velocity: e.symbol(&format!("dot({name})")),
                name,
                position,
                force: ZERO,
            })
            .collect();
        let mut inputs = Vec::new();
        for (i, u) in declared_names(&def.inputs).into_iter().enumerate() {
            names.bind(cx, &u, "an input", Binding::Input(i));
            let sym = e.symbol(&u.to_string());
            inputs.push(Input { name: u, sym });
        }
        let mut speed_syms = Vec::new();
        for (i, u) in declared_names(&def.speeds).into_iter().enumerate() {
            names.bind(cx, &u, "a speed", Binding::Speed(i));
            speed_syms.push(e.symbol(&u.to_string()));
        }
        for (i, b) in def.bodies.iter().enumerate() {
            names.bind(cx, &b.name, "a body", Binding::Body(i));
        }
        let let_ok = def
            .lets
            .iter()
            .map(|l| names.declare(cx, &l.name, "a `let`"))
            .collect();
        let Declarations {
            mut scope,
            poisoned,
            ..
        } = names;
        for p in &poisoned {
            scope.remove(p);
        }
        let lw = Lowerer {
            cx,
            e,
            scope,
            params,
            coords,
            inputs,
            speed_syms,
            lets: Vec::new(),
            body_defs: def.bodies.clone(),
            body_state: vec![BodyState::Pending; def.bodies.len()],
            t_sym,
            pi_sym,
            place: Place::Let,
            all_lets: def.lets.iter().map(|l| l.name.to_string()).collect(),
            poisoned,
            huge_constant: None,
            description: Vec::new(),
            kinetic: Vec::new(),
            written: Vec::new(),
            abandoned_at: None,
        };
        (lw, let_ok)
    }

    /// The vectors of the `let`s that depend on the coordinates alone
    /// (points of the mechanism, for the chains of DESIGN §10).
    fn points(&self) -> Vec<[ExprId; 3]> {
        let moving = |s: &crate::sym::SymId| {
            *s == self.t_sym
                || self.inputs.iter().any(|u| u.sym == *s)
                || self.coords.iter().any(|c| c.velocity == *s)
        };
        self.lets
            .iter()
            .filter_map(|l| match &l.value {
                Some(Value::Vector(v)) => Some(*v),
                _ => None,
            })
            .filter(|v| {
                v.iter()
                    .all(|&x| !self.e.free_symbols(x).iter().any(moving))
            })
            .collect()
    }

    /// `work`, with the engine's site at `range`, doing `task`. If the
    /// engine's limits are first exceeded in it, the errors recorded from
    /// its start are dropped when the limit is reported (`report_limits`):
    /// they may follow from the meaningless values of the abandoned
    /// derivation (a divisor that came out zero).
    fn at<T>(
        &mut self,
        range: SpanRange,
        task: impl Into<String>,
        work: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let errors = self.cx.len();
        let within = !self.e.overflowed();
        let outer = self.e.enter(Site::new(range, task));
        let r = work(self);
        self.e.leave(outer);
        if within && self.e.overflowed() && self.abandoned_at.is_none() {
            self.abandoned_at = Some(errors);
        }
        r
    }

    /// The error for a limit of the engine exceeded while lowering, in
    /// place of the errors that followed it.
    fn report_limits(&mut self, def: &SystemDef) {
        if let Some(errors) = self.abandoned_at {
            self.cx.truncate(errors);
        }
        check::within_limits(def, &self.e, self.cx);
    }

    /// The `let`s, in order: later ones may use earlier ones.
    fn lower_lets(&mut self, def: &SystemDef, let_ok: &[bool]) {
        for (i, l) in def.lets.iter().enumerate() {
            self.place = Place::Let;
            let range = SpanRange::single(l.name.span()).to(l.value.range());
            let task = format!("expanding `{}`", l.name);
            let v = self.at(range, task, |lw| lw.lower_value(&l.value, 0));
            if let Some(v) = &v {
                self.describe_let(l, v);
            }
            self.lets.push(LetInfo {
                value: v,
                name: l.name.clone(),
            });
            if let_ok[i] {
                self.scope.insert(l.name.to_string(), Binding::Let(i));
            }
        }
    }

    /// The Lagrangian: exactly one.
    fn lower_lagrangian(&mut self, def: &SystemDef) -> Option<ExprId> {
        match def.lagrangians.as_slice() {
            [] if def.lagrangian_written => None, // it failed to parse: already reported
            [] => {
                self.cx.error_at(
                    def.name.span(),
                    "missing `lagrangian = ..;`: give the Lagrangian L = T - V in terms of the coordinates and `dot(q)` velocities",
                );
                None
            }
            [(_, expr), rest @ ..] => {
                for (kw, _) in rest {
                    self.cx.error_at(kw.span(), "duplicate `lagrangian`: a system has exactly one Lagrangian; combine the terms into one expression");
                }
                self.place = Place::Lagrangian;
                self.at(expr.range(), "expanding the Lagrangian", |lw| {
                    lw.lower(expr, 0)
                })
            }
        }
    }

    /// The generalized forces, into the coordinates they act on.
    fn lower_forces(&mut self, def: &SystemDef) {
        let Some((_, list)) = &def.forces else {
            return;
        };
        let mut seen = vec![false; self.coords.len()];
        for f in list {
            self.place = Place::Force;
            let range = SpanRange::single(f.coordinate.span()).to(f.value.range());
            let task = format!("expanding the force on `{}`", f.coordinate);
            let v = self.at(range, task, |lw| lw.lower(&f.value, 0));
            match self.scope.get(&f.coordinate.to_string()) {
                _ if self.poisoned.contains(&f.coordinate.to_string()) => {}
                Some(Binding::Coord(i)) => {
                    let i = *i;
                    if seen[i] {
                        self.cx.error_at(f.coordinate.span(), format!("a second force on `{}`: write the sum of the forces on one coordinate as one expression", f.coordinate));
                    } else if let Some(v) = v {
                        self.coords[i].force = v;
                        seen[i] = true;
                    }
                }
                _ => {
                    let hint = self.coordinate_hint(&f.coordinate);
                    let all = list_names(self.coords.iter().map(|c| &c.name));
                    self.cx.error_at(
                        f.coordinate.span(),
                        format!("`{}` is not a coordinate{hint}: a force is given as `coordinate: Q;` for one of {all}", f.coordinate),
                    );
                }
            }
        }
    }

    /// " (did you mean ..?)" for a name that should be a coordinate.
    fn coordinate_hint(&self, id: &Ident) -> String {
        let cands: Vec<String> = self.coords.iter().map(|c| c.name.to_string()).collect();
        let refs: Vec<&str> = cands.iter().map(|s| s.as_str()).collect();
        names::suggest(&id.to_string(), &refs)
    }
}
/// A text for a message, shortened past 60 characters.
fn short(s: String) -> String {
    if s.chars().count() <= 60 {
        return s;
    }
    let head: String = s.chars().take(57).collect();
    format!("{head}...")
}

/// A constant for a message: exact if short, else in scientific form.
fn show(c: Rational) -> String {
    let s = c.to_string();
    if s.len() <= 40 {
        s
    } else {
        format!("≈{}", c.sci())
    }
}

fn list_names<'i>(ids: impl Iterator<Item = &'i Ident>) -> String {
    ids.map(|i| format!("`{i}`")).collect::<Vec<_>>().join(", ")
}

impl Lowerer<'_> {
    fn known_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.scope.keys().cloned().collect();
        v.extend(Constant::ALL.map(|c| c.name().to_string()));
        v.sort();
        v
    }

    /// Lowers a surface expression that must be a scalar; `None` after
    /// recording an error.
    fn lower(&mut self, x: &Expr, depth: usize) -> Option<ExprId> {
        let v = self.lower_value(x, depth)?;
        self.scalar_of(v, x)
    }
}

/// The top-level additive terms of an expression (through `+`, `-` and unary minus).
fn top_level_terms(x: &Expr) -> Vec<&Expr> {
    let mut out = Vec::new();
    let mut stack = vec![x];
    while let Some(x) = stack.pop() {
        match x {
            Expr::Chain { first, rest, .. } if x.is_sum() => {
                for (_, _, e) in rest.iter().rev() {
                    stack.push(e);
                }
                stack.push(first);
            }
            Expr::Neg(inner, _) => stack.push(inner),
            _ => out.push(x),
        }
    }
    out
}
