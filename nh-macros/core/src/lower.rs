//! Name resolution and lowering of the surface syntax into the symbolic
//! engine: the Lagrangian, forces and constraints become expressions in the
//! coordinates, velocities, parameters, inputs and time, and every misuse of
//! a name is reported at its token.

mod bodies;
pub(crate) mod constraints;
mod functions;
pub(crate) mod linear;
pub(crate) mod values;

use crate::check;
use crate::ctxt::{Ctxt, SpanRange};
use crate::model::{Coordinate, Input, Model, Parameter, Partition};
use crate::names;
use crate::parse::{BinOp, BodyDef, Expr, SystemDef};
use crate::sym::{Engine, ExprId, Fun, Rational, SymId, ZERO};
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
            let what = match s.as_str() {
                "t" => "`t` is time",
                "pi" => "`pi` is the constant π",
                "dot" => "`dot` is the time derivative",
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

/// Lowers a parsed system. Returns `None` when errors make a model
/// meaningless; all errors are in `cx`.
pub fn lower(def: &SystemDef, cx: &mut Ctxt) -> Option<Model> {
    check::coordinates_declared(def, cx);
    let (mut lw, let_ok) = Lowerer::declare(def, cx);
    lw.lower_lets(def, &let_ok);
    let lagrangian = lw.lower_lagrangian(def);
    lw.lower_forces(def);
    let lowered = lw.lower_constraints(def);
    for text in &lowered.implied {
        lw.description.push(format!(
            "- `{text}`: implied by the constraint rows before it (as for two wheels on one axle), so dropped: it has no dependent coordinate and no multiplier"
        ));
    }
    let speeds = lw.lower_speeds(def);
    lw.lower_unused_bodies();
    let outputs = check::outputs(def, lw.cx);
    check::outputs_for_form(def, lw.cx);
    if lw.e.overflowed() {
        lw.cx.error_at(
            def.name.span(),
            "an expression grew beyond the engine's limits (too many terms, or a constant power of more than 10000 digits): simplify the input",
        );
    }
    let lagrangian = lagrangian?;
    if !lw.cx.is_empty() {
        return None;
    }
    let kinetic = lw.kinetic_split(lagrangian);
    let forces = lw.coords.iter().map(|c| c.force);
    let kinematics = speeds.iter().flat_map(|s| s.velocities.iter().copied());
    let written: Vec<ExprId> = std::iter::once(lagrangian)
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
    Some(Model {
        engine: lw.e,
        parameters: lw.params,
        coordinates: lw.coords,
        inputs: lw.inputs,
        time: lw.t_sym,
        pi: lw.pi_sym,
        lagrangian,
        constraints,
        partition,
        outputs,
        speeds,
        homogeneous: lowered.homogeneous,
        affine: lowered.affine,
        chart: lowered.chart,
        constraints_span: def.constraints.as_ref().map(|c| c.0.span()),
        description: lw.description,
        contacts: lowered.contacts,
        velocity_rows: lowered.velocity_rows,
        contact_kinematics: lowered.contact_kinematics,
        points,
        contact_chains: Vec::new(),
        row_contacts: lowered.row_contacts,
        block: None,
        huge_constant: lw.huge_constant,
        kinetic,
        written,
    })
}

impl<'a> Lowerer<'a> {
    /// Declares every name of the system (reporting duplicates, shadowing
    /// and reserved words) and creates their symbols; with, per `let`,
    /// whether its declaration succeeded.
    fn declare(def: &SystemDef, cx: &'a mut Ctxt) -> (Lowerer<'a>, Vec<bool>) {
        let mut e = Engine::new();
        let t_sym = e.symbol("t");
        let pi_sym = e.symbol("pi");
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

    /// The `let`s, in order: later ones may use earlier ones.
    fn lower_lets(&mut self, def: &SystemDef, let_ok: &[bool]) {
        for (i, l) in def.lets.iter().enumerate() {
            self.place = Place::Let;
            let v = self.lower_value(&l.value, 0);
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
                self.lower(expr, 0)
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
            let v = self.lower(&f.value, 0);
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
        v.push("t".into());
        v.push("pi".into());
        v.sort();
        v
    }

    /// Lowers a surface expression that must be a scalar; `None` after
    /// recording an error.
    fn lower(&mut self, x: &Expr, depth: usize) -> Option<ExprId> {
        let v = self.lower_value(x, depth)?;
        self.scalar_of(v, x)
    }

    /// Lowers a surface expression of any kind; `None` after recording an error.
    fn lower_value(&mut self, x: &Expr, depth: usize) -> Option<Value> {
        let v = self.lower_inner(x, depth)?;
        let Value::Scalar(v) = v else {
            return Some(v);
        };
        if self.huge_constant.is_none()
            && let Some(c) = self.e.as_constant(v)
            && !c.to_f64().is_finite()
        {
            self.huge_constant = Some(x.range());
        }
        Some(Value::Scalar(v))
    }

    /// The sign of `e` if it is a rational constant times a power of π.
    fn constant_sign(&self, e: ExprId) -> Option<std::cmp::Ordering> {
        if let Some(c) = self.e.as_constant(e) {
            return Some(c.cmp(&Rational::ZERO));
        }
        match self.e.terms(e) {
            [(_, c)] if self.e.free_symbols(e) == [self.pi_sym] => Some(c.cmp(&Rational::ZERO)),
            _ => None,
        }
    }

    /// ": `src` is value" for a message about an argument, if the value
    /// says more than the source text.
    fn value_note(&self, arg: &Expr, v: ExprId) -> String {
        let src = short(arg.to_source());
        let val = match self.e.as_constant(v) {
            Some(c) => show(c),
            None => short(self.e.display_capped(v, 60)),
        };
        if src == val {
            String::new()
        } else {
            format!(": `{src}` is {val}")
        }
    }

    /// The rational `c` if `e` is `c·π`.
    fn pi_multiple(&self, e: ExprId) -> Option<Rational> {
        if self.e.free_symbols(e) != [self.pi_sym] {
            return None;
        }
        let [(m, c)] = self.e.terms(e) else {
            return None;
        };
        match self.e.factors(*m) {
            [(_, k)] if k.is_one() => Some(*c),
            _ => None,
        }
    }

    fn lower_inner(&mut self, x: &Expr, depth: usize) -> Option<Value> {
        if depth > crate::parse::MAX_DEPTH {
            self.cx.error(
                x.range(),
                "expression nested too deeply: split it into `let` items",
            );
            return None;
        }
        match x {
            Expr::Num(q, _) => Some(Value::Scalar(self.e.constant(*q))),
            Expr::Name(id) => self.lower_name(id),
            Expr::Neg(inner, _) => match self.lower_value(inner, depth + 1)? {
                Value::Scalar(v) => Some(Value::Scalar(self.e.neg(v))),
                v => {
                    let minus = Value::Scalar(self.e.int(-1));
                    self.combine(BinOp::Mul, minus, v, x.range(), inner)
                }
            },
            Expr::Chain { first, rest, .. } => self.lower_chain(first, rest, depth),
            Expr::Pow { base, exp, .. } => self.lower_pow(x, base, exp, depth).map(Value::Scalar),
            Expr::Call { func, args, range } => self.lower_call(func, args, *range, depth),
            Expr::Vector { items, range } => self.lower_brackets(items, *range, depth),
            Expr::Component { base, field } => self.lower_component(base, field, depth),
        }
    }

    /// A chain of binary operations of one precedence, left to right.
    fn lower_chain(
        &mut self,
        first: &Expr,
        rest: &[(BinOp, Span, Expr)],
        depth: usize,
    ) -> Option<Value> {
        // every operand is lowered, so that all their errors are reported
        let mut acc = self.lower_value(first, depth + 1);
        for (op, op_span, operand) in rest {
            let v = self.lower_value(operand, depth + 1);
            acc = match (acc, v) {
                (Some(a), Some(v)) => match op {
                    BinOp::Div if matches!(v, Value::Scalar(ZERO)) => {
                        let at = SpanRange {
                            first: *op_span,
                            last: operand.range().last,
                        };
                        let msg = if matches!(operand, Expr::Num(..)) {
                            "division by zero".to_string()
                        } else {
                            format!("division by zero: `{}` is 0", short(operand.to_source()))
                        };
                        self.cx.error(at, msg);
                        None
                    }
                    _ => {
                        let at = first.range().to(operand.range());
                        self.combine(*op, a, v, at, operand)
                    }
                },
                _ => None,
            };
        }
        acc
    }

    /// `base ^ exp`.
    fn lower_pow(&mut self, x: &Expr, base: &Expr, exp: &Expr, depth: usize) -> Option<ExprId> {
        let l = self.lower(base, depth + 1);
        let r = self.lower(exp, depth + 1);
        let (l, r) = (l?, r?);
        let base_const = self.e.as_constant(l);
        Some(match self.e.as_constant(r) {
            Some(q) => {
                if l == ZERO && q.is_zero() {
                    self.cx.error(x.range(), "`0^0` is undefined");
                    return None;
                }
                if l == ZERO && q.is_negative() {
                    self.cx.error(
                        x.range(),
                        format!("division by zero: 0 to the negative power {q}"),
                    );
                    return None;
                }
                if let Some(c) = base_const {
                    if c.is_negative() && !q.is_integer() {
                        self.cx.error(x.range(), format!("a negative constant to a fractional power is not a real number: ({})^({})", show(c), show(q)));
                        return None;
                    }
                    let digits = c.pow_digits(q.floor());
                    if digits > f64::from(Rational::MAX_DIGITS) {
                        self.cx.error(x.range(), format!("this power is too large to compute exactly: it has about {} digits, and the limit is {}", if digits < 1e12 { format!("{digits:.0}") } else { format!("{digits:.1e}") }, Rational::MAX_DIGITS));
                        return None;
                    }
                }
                if q.abs() > Rational::int(64) && base_const.is_none() {
                    self.cx.error(
                        exp.range(),
                        "exponent too large: powers up to 64 are supported",
                    );
                    return None;
                }
                self.e.pow(l, q)
            }
            // a^b = exp(b ln a) for a symbolic exponent
            None => {
                if let Some(c) = base_const
                    && c <= Rational::ZERO
                {
                    let what = if c.is_zero() {
                        "0 to a symbolic power is undefined here (it is exp(b·ln 0), and ln 0 = −∞)"
                            .to_string()
                    } else {
                        format!(
                            "a negative constant to a symbolic power is not a real number: ({})^(..)",
                            show(c)
                        )
                    };
                    self.cx.error(x.range(), what);
                    return None;
                }
                let ln = self.e.func(Fun::Ln, l);
                let p = self.e.mul(r, ln);
                self.e.func(Fun::Exp, p)
            }
        })
    }

    fn lower_name(&mut self, id: &Ident) -> Option<Value> {
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        if let Some(Binding::Let(i)) = self.scope.get(&s).copied() {
            let v = self.lets[i].value.clone()?;
            let inputs: Vec<SymId> = self.inputs.iter().map(|u| u.sym).collect();
            let uses_input = v
                .entries()
                .iter()
                .any(|&x| inputs.iter().any(|&u| self.e.depends_on(x, u)));
            if self.place == Place::Lagrangian && uses_input {
                self.cx.error_at(id.span(), format!("`{s}` depends on an input, and inputs cannot appear in the Lagrangian: put actuation in `forces`"));
                return None;
            }
            return Some(v);
        }
        if let Some(Binding::Body(_)) = self.scope.get(&s) {
            self.cx.error_at(
                id.span(),
                format!(
                    "`{s}` is a body, not a value: its kinetic energy is `kinetic_energy({s})`"
                ),
            );
            return None;
        }
        self.lower_scalar_name(id).map(Value::Scalar)
    }

    fn lower_scalar_name(&mut self, id: &Ident) -> Option<ExprId> {
        let s = id.to_string();
        match self.scope.get(&s).copied() {
            Some(Binding::Param(i)) => Some(self.e.sym(self.params[i].sym)),
            Some(Binding::Coord(i)) => Some(self.e.sym(self.coords[i].position)),
            Some(Binding::Input(i)) => {
                match self.place {
                    Place::Lagrangian => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in the Lagrangian: inputs act through `forces {{ q: ..; }}` (generalized forces), which is where actuation belongs"));
                        return None;
                    }
                    Place::Constraint => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in a constraint: constraints depend on the coordinates only"));
                        return None;
                    }
                    Place::Kinematics => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in `kinematics`: q̇ = S(q, t) u + σ(q, t) depends on the coordinates, the speeds and time only; inputs act through `forces`"));
                        return None;
                    }
                    Place::Body => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in a body or a rolling contact: they enter the Lagrangian and the constraints; inputs act through `forces`"));
                        return None;
                    }
                    _ => {}
                }
                Some(self.e.sym(self.inputs[i].sym))
            }
            Some(Binding::Let(_) | Binding::Body(_)) => None,
            Some(Binding::Speed(i)) => {
                if self.place != Place::Kinematics {
                    self.cx.error_at(id.span(), format!("speed `{s}` can appear only on the right sides of `kinematics`: write the Lagrangian, forces and `let`s with the velocities `dot(q)` of the coordinates (they are substituted by q̇ = S u + σ)"));
                    return None;
                }
                Some(self.e.sym(self.speed_syms[i]))
            }
            None => match s.as_str() {
                "t" => Some(self.e.sym(self.t_sym)),
                "pi" => Some(self.e.sym(self.pi_sym)),
                _ if crate::words::Function::parse(&s).is_some_and(|f| !f.of_vectors()) => {
                    let (args, example) = match s.as_str() {
                        "atan2" => ("two arguments", "atan2(y, x)".to_string()),
                        _ => ("an argument", format!("{s}(x)")),
                    };
                    self.cx.error_at(
                        id.span(),
                        format!("`{s}` is a function: call it with {args}, as in `{example}`"),
                    );
                    None
                }
                _ if self.all_lets.contains(&s) => {
                    self.cx.error_at(
                        id.span(),
                        format!("`{s}` is used before its `let`: a `let` may use only the items above it; move `let {s} = ..;` up"),
                    );
                    None
                }
                _ => {
                    let known = self.known_names();
                    let refs: Vec<&str> = known.iter().map(|k| k.as_str()).collect();
                    let hint = names::suggest(&s, &refs);
                    self.cx.error_at(id.span(), format!("unknown name `{s}`{hint}: declare it in `parameters {{ .. }}`, `coordinates {{ .. }}`, `inputs {{ .. }}` or with an earlier `let`"));
                    None
                }
            },
        }
    }

    fn lower_call(
        &mut self,
        func: &Ident,
        args: &[Expr],
        range: SpanRange,
        depth: usize,
    ) -> Option<Value> {
        let f = func.to_string();
        if f == "dot" && args.len() == 1 {
            return self.lower_dot(&args[0], range);
        }
        if let Some(v) = self.lower_vector_call(func, args, range, depth) {
            return v;
        }
        self.lower_scalar_call(func, args, range, depth)
            .map(Value::Scalar)
    }

    fn lower_dot(&mut self, arg: &Expr, range: SpanRange) -> Option<Value> {
        let id = match arg {
            Expr::Name(id) => id,
            Expr::Call { func, .. } if func == "dot" => {
                self.cx.error(range, "`dot(dot(..))`: second derivatives cannot be written; the equations of motion are derived from the Lagrangian, which needs only velocities `dot(q)`");
                return None;
            }
            _ => {
                self.cx.error(arg.range(), "`dot` takes a coordinate or the name of a `let`; to differentiate an expression, name it first: `let X = ..;` then `dot(X)`");
                return None;
            }
        };
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        match self.scope.get(&s).copied() {
            Some(Binding::Coord(i)) => Some(Value::Scalar(self.e.sym(self.coords[i].velocity))),
            Some(Binding::Let(i)) => {
                let v = self.lets[i].value.clone()?;
                let name = self.lets[i].name.clone();
                let entries = v.entries();
                let mut fs: Vec<SymId> = Vec::new();
                for &x in &entries {
                    fs.extend_from_slice(self.e.free_symbols(x));
                }
                if self.coords.iter().any(|c| fs.contains(&c.velocity)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` contains velocities, and its time derivative would need accelerations; `dot` applies to velocity-free `let`s only"));
                    return None;
                }
                if self.inputs.iter().any(|u| fs.contains(&u.sym)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` depends on an input, whose time derivative is unknown"));
                    return None;
                }
                // total derivative by the chain rule: Σ ∂/∂q_i q̇_i + ∂/∂t
                Some(match v {
                    Value::Scalar(x) => Value::Scalar(self.time_derivative(x)),
                    Value::Vector(x) => Value::Vector(x.map(|c| self.time_derivative(c))),
                    Value::Rotation(r) => {
                        Value::Matrix(r.matrix.map(|row| row.map(|c| self.time_derivative(c))))
                    }
                    Value::Matrix(m) => {
                        Value::Matrix(m.map(|row| row.map(|c| self.time_derivative(c))))
                    }
                })
            }
            Some(Binding::Body(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a body; the velocity of its centre is `dot(C)` of a `let C` for the centre, its angular velocity `omega(R)` of its orientation"));
                None
            }
            Some(Binding::Speed(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a speed; its derivative is what the equations of motion compute, it cannot be written"));
                None
            }
            Some(Binding::Param(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a parameter, constant in time, so its derivative is 0; remove the term"));
                None
            }
            Some(Binding::Input(_)) => {
                self.cx.error(
                    range,
                    format!("`dot({s})`: the time derivative of input `{s}` is unknown"),
                );
                None
            }
            None => {
                if s == "t" {
                    self.cx.error(range, "`dot(t)` is 1: write `1`");
                    return None;
                }
                let known = self.known_names();
                let refs: Vec<&str> = known.iter().map(|k| k.as_str()).collect();
                let hint = names::suggest(&s, &refs);
                self.cx.error_at(id.span(), format!("unknown name `{s}`{hint} in `dot(..)`: `dot` takes a coordinate or a `let` name"));
                None
            }
        }
    }

    /// Where the velocity of coordinate `d` is used in `x` (depth first, left to right).
    fn find_velocity_use(&mut self, x: &Expr, d: usize) -> Option<SpanRange> {
        let mut stack = vec![x];
        while let Some(x) = stack.pop() {
            match x {
                Expr::Call { func, args, range } if func == "dot" && args.len() == 1 => {
                    if let Expr::Name(id) = &args[0]
                        && self
                            .scope
                            .get(&id.to_string())
                            .is_some_and(|b| matches!(b, Binding::Coord(i) if *i == d))
                    {
                        return Some(*range);
                    }
                }
                Expr::Call { args: items, .. } | Expr::Vector { items, .. } => {
                    stack.extend(items.iter().rev())
                }
                Expr::Component { base, .. } => stack.push(base),
                Expr::Neg(inner, _) => stack.push(inner),
                Expr::Chain { first, rest, .. } => {
                    for (_, _, e) in rest.iter().rev() {
                        stack.push(e);
                    }
                    stack.push(first);
                }
                Expr::Pow { base, exp, .. } => {
                    stack.push(exp);
                    stack.push(base);
                }
                Expr::Name(_) | Expr::Num(..) => {}
            }
        }
        None
    }

    /// The coordinate of a left side `dot(q)`; `msg` says what is expected.
    fn velocity_lhs(&mut self, lhs: &Expr, msg: &str) -> Option<usize> {
        match lhs {
            Expr::Call { func, args, .. } if func == "dot" && args.len() == 1 => match &args[0] {
                Expr::Name(id) if self.poisoned.contains(&id.to_string()) => None,
                Expr::Name(id) => match self.scope.get(&id.to_string()) {
                    Some(Binding::Coord(i)) => Some(*i),
                    _ => {
                        let hint = self.coordinate_hint(id);
                        self.cx.error_at(
                            id.span(),
                            format!("`{id}` is not a coordinate{hint}: {msg}"),
                        );
                        None
                    }
                },
                _ => {
                    self.cx.error(lhs.range(), msg);
                    None
                }
            },
            _ => {
                self.cx.error(lhs.range(), msg);
                None
            }
        }
    }

    fn has_velocity(&mut self, x: &Expr, independent: &[usize]) -> bool {
        match self.lower(x, 0) {
            Some(v) => independent
                .iter()
                .any(|&i| self.e.depends_on(v, self.coords[i].velocity)),
            None => false,
        }
    }

    /// The smallest subexpression that makes a term nonlinear in the
    /// velocities, and what is wrong with it.
    fn find_nonlinear<'e>(
        &mut self,
        x: &'e Expr,
        independent: &[usize],
    ) -> Option<(&'e Expr, String)> {
        match x {
            Expr::Neg(inner, _) => self.find_nonlinear(inner, independent),
            Expr::Chain { first, rest, .. } if x.is_sum() => {
                // a parenthesised sum inside a product or a function
                std::iter::once(&**first)
                    .chain(rest.iter().map(|r| &r.2))
                    .find_map(|t| self.find_nonlinear(t, independent))
            }
            Expr::Chain { first, rest, .. } => {
                // a product: two factors with velocities, or one in a denominator
                let mut with_velocity: Vec<&Expr> = Vec::new();
                if self.has_velocity(first, independent) {
                    with_velocity.push(first);
                }
                for (op, _, f) in rest {
                    if self.has_velocity(f, independent) {
                        if *op == BinOp::Div {
                            return Some((f, "divides by a velocity".into()));
                        }
                        with_velocity.push(f);
                    }
                }
                // a factor that is nonlinear by itself (a power, a function) first
                for f in &with_velocity {
                    if let Some(r) = self.find_nonlinear(f, independent) {
                        return Some(r);
                    }
                }
                match with_velocity.as_slice() {
                    [] | [_] => None,
                    [_, ..] => Some((x, "multiplies velocities together".into())),
                }
            }
            Expr::Pow { base, .. } => {
                if self.has_velocity(base, independent) {
                    Some((x, "is a power of a velocity".into()))
                } else if self.has_velocity(x, independent) {
                    Some((x, "has a velocity in an exponent".into()))
                } else {
                    None
                }
            }
            Expr::Call { func, args, .. } if func == "dot" && args.len() == 1 => {
                // `dot(NAME)` of a `let` with velocities is already an error
                None
            }
            Expr::Call { func, args, .. } => {
                if !self.has_velocity(x, independent) {
                    return None;
                }
                let why = match func.to_string().as_str() {
                    "abs" if args.len() == 1 => {
                        let a = args[0].to_source();
                        let minus = match &args[0] {
                            Expr::Call { .. } | Expr::Name(_) => format!("-{a}"),
                            _ => format!("-({a})"),
                        };
                        format!("is the absolute value of a velocity: it is `{a}` where `{a}` ≥ 0 and `{minus}` where it is negative, a different linear constraint for each sign; write the one that holds")
                    }
                    "sqrt" => "is a square root of velocities, which is not linear (the root of a square is an absolute value, `sqrt(dot(x)^2)` = `abs(dot(x))`, and the root of a sum of squares is a speed)".to_string(),
                    "kinetic_energy" => "is a kinetic energy, quadratic in the velocities".to_string(),
                    "omega" | "omega_body" | "cross" | "dot" | "norm" => {
                        "is not linear in the velocities".to_string()
                    }
                    f => format!("has a velocity inside the function `{f}`"),
                };
                Some((x, why))
            }
            Expr::Name(id) => {
                // a `let` with velocities that are not linear
                let Some(Binding::Let(i)) = self.scope.get(&id.to_string()).copied() else {
                    return None;
                };
                let Some(Value::Scalar(v)) = self.lets[i].value.clone() else {
                    return None;
                };
                let moving = independent
                    .iter()
                    .any(|&j| self.e.depends_on(v, self.coords[j].velocity));
                (moving && !self.is_linear_in_velocities(v)).then(|| {
                    (
                        x,
                        format!(
                            "is a `let` that is not linear in the velocities (`{}`)",
                            short(self.e.display_capped(v, 60))
                        ),
                    )
                })
            }
            _ => None,
        }
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
