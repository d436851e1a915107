//! Name resolution and lowering of the surface syntax into the symbolic
//! engine: the Lagrangian, forces and constraints become expressions in the
//! coordinates, velocities, parameters, inputs and time, and every misuse of
//! a name is reported at its token.

use crate::ctxt::{Ctxt, SpanRange};
use crate::names;
use crate::parse::{BinOp, Expr, SystemDef};
use crate::sym::{Engine, ExprId, Fun, ONE, Rational, SymId, ZERO};
use proc_macro2::{Ident, Span};
use rustc_hash::FxHashMap as HashMap;

/// The functions of the input language.
pub const FUNCTIONS: [&str; 6] = ["sin", "cos", "tan", "exp", "ln", "sqrt"];

/// Names that cannot be declared: the language's own words.
const RESERVED: [&str; 9] = ["t", "pi", "dot", "sin", "cos", "tan", "exp", "ln", "sqrt"];

/// The opt-in outputs (DESIGN §3) plus `routes`.
pub const OUTPUTS: [&str; 8] = [
    "multipliers",
    "curvature",
    "energy",
    "constraint_matrix",
    "mass_matrix",
    "jacobian",
    "linearization",
    "routes",
];

/// Which opt-in outputs a system asked for.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    /// `multipliers`
    pub multipliers: bool,
    /// `curvature`
    pub curvature: bool,
    /// `energy`
    pub energy: bool,
    /// `constraint_matrix`
    pub constraint_matrix: bool,
    /// `mass_matrix`
    pub mass_matrix: bool,
    /// `jacobian`
    pub jacobian: bool,
    /// `linearization`: A = ∂f/∂x and B = ∂f/∂u
    pub linearization: bool,
    /// `routes`: both derivation routes as separate methods
    pub routes: bool,
}

impl Outputs {
    /// Sets the flag of output `name`; `Some(previous)` if the name is known.
    pub fn set(&mut self, name: &str) -> Option<bool> {
        let flag = match name {
            "multipliers" => &mut self.multipliers,
            "curvature" => &mut self.curvature,
            "energy" => &mut self.energy,
            "constraint_matrix" => &mut self.constraint_matrix,
            "mass_matrix" => &mut self.mass_matrix,
            "jacobian" => &mut self.jacobian,
            "linearization" => &mut self.linearization,
            "routes" => &mut self.routes,
            _ => return None,
        };
        Some(std::mem::replace(flag, true))
    }
}

/// A system after lowering: everything the mechanics needs, as symbols and
/// expressions of one engine.
pub struct Model {
    /// The engine holding every expression below.
    pub engine: Engine,
    /// Parameter names in declared order.
    pub params: Vec<Ident>,
    /// Coordinate names in declared order (THE coordinate order).
    pub coords: Vec<Ident>,
    /// Input names.
    pub inputs: Vec<Ident>,
    /// Symbols of the parameters.
    pub param_syms: Vec<SymId>,
    /// Symbols of the coordinates.
    pub coord_syms: Vec<SymId>,
    /// Symbols of the velocities (same order).
    pub vel_syms: Vec<SymId>,
    /// Symbols of the inputs.
    pub input_syms: Vec<SymId>,
    /// Time.
    pub t_sym: SymId,
    /// π.
    pub pi_sym: SymId,
    /// L(q, q̇, t).
    pub lagrangian: ExprId,
    /// Q_j per coordinate (zero where none is given).
    pub forces: Vec<ExprId>,
    /// Indices of the independent coordinates r, ascending.
    pub independent: Vec<usize>,
    /// Indices of the dependent coordinates s, ascending.
    pub dependent: Vec<usize>,
    /// ṡ_a as written (a linear form in ṙ), per dependent coordinate in `dependent` order.
    pub dependent_velocity: Vec<ExprId>,
    /// A^a_α (p × k): minus the coefficient of ṙ_α in the constraint of s_a.
    pub a_matrix: Vec<Vec<ExprId>>,
    /// Requested outputs.
    pub outputs: Outputs,
    /// Span of the `constraints` keyword, if any (for diagnostics).
    pub constraints_span: Option<Span>,
    /// The first subexpression of the input whose value is a constant beyond
    /// the range of `f64` (where an error about such a constant in the
    /// generated code points).
    pub huge_constant: Option<SpanRange>,
}

#[derive(Clone, Copy, Debug)]
enum Binding {
    Param(usize),
    Coord(usize),
    Input(usize),
    Let(usize),
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Place {
    Let,
    Lagrangian,
    Force,
    Constraint,
}

struct LetInfo {
    value: Option<ExprId>,
    name: Ident,
}

struct Lowerer<'a> {
    cx: &'a mut Ctxt,
    e: Engine,
    scope: HashMap<String, Binding>,
    param_syms: Vec<SymId>,
    coord_syms: Vec<SymId>,
    vel_syms: Vec<SymId>,
    input_syms: Vec<SymId>,
    lets: Vec<LetInfo>,
    t_sym: SymId,
    pi_sym: SymId,
    place: Place,
    /// every `let` name, to tell a use before the definition from a typo
    all_lets: Vec<String>,
    /// names whose declaration failed: uses are not reported again
    poisoned: Vec<String>,
    /// see [`Model::huge_constant`]
    huge_constant: Option<SpanRange>,
}

/// Lowers a parsed system. Returns `None` when errors make a model
/// meaningless; all errors are in `cx`.
pub fn lower(def: &SystemDef, cx: &mut Ctxt) -> Option<Model> {
    let mut e = Engine::new();
    let t_sym = e.symbol("t");
    let pi_sym = e.symbol("pi");
    let params: Vec<Ident> = def
        .parameters
        .as_ref()
        .map(|p| p.1.clone())
        .unwrap_or_default();
    let coords: Vec<Ident> = def
        .coordinates
        .as_ref()
        .map(|p| p.1.clone())
        .unwrap_or_default();
    let inputs: Vec<Ident> = def.inputs.as_ref().map(|p| p.1.clone()).unwrap_or_default();
    if def.coordinates.is_none() {
        cx.error_at(
            def.name.span(),
            "missing `coordinates { .. }`: list the generalized coordinates, e.g. `coordinates { x, y, theta }`",
        );
    } else if coords.is_empty() {
        cx.error_at(
            def.coordinates
                .as_ref()
                .map(|c| c.0.span())
                .unwrap_or(def.name.span()),
            "`coordinates` is empty: a system needs at least one coordinate",
        );
    }

    // declarations: duplicates, shadowing and reserved words
    let mut scope: HashMap<String, Binding> = HashMap::default();
    let mut declared: HashMap<String, (&'static str, Span)> = HashMap::default();
    let mut poisoned: Vec<String> = def.poisoned.iter().map(|p| p.to_string()).collect();
    let mut declare = |cx: &mut Ctxt, id: &Ident, kind: &'static str| -> bool {
        let s = id.to_string();
        if RESERVED.contains(&s.as_str()) {
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
        if let Some((prev_kind, prev_span)) = declared.get(&s) {
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
            poisoned.push(s);
            return false;
        }
        declared.insert(s, (kind, id.span()));
        true
    };
    let mut param_syms = Vec::new();
    for (i, p) in params.iter().enumerate() {
        if declare(cx, p, "a parameter") {
            scope.insert(p.to_string(), Binding::Param(i));
        }
        param_syms.push(e.symbol(&p.to_string()));
    }
    let mut coord_syms = Vec::new();
    let mut vel_syms = Vec::new();
    for (i, c) in coords.iter().enumerate() {
        if declare(cx, c, "a coordinate") {
            scope.insert(c.to_string(), Binding::Coord(i));
        }
        coord_syms.push(e.symbol(&c.to_string()));
    }
    for c in &coords {
        vel_syms.push(e.symbol(&format!("dot({c})")));
    }
    let mut input_syms = Vec::new();
    for (i, u) in inputs.iter().enumerate() {
        if declare(cx, u, "an input") {
            scope.insert(u.to_string(), Binding::Input(i));
        }
        input_syms.push(e.symbol(&u.to_string()));
    }
    let let_names: Vec<Ident> = def.lets.iter().map(|l| l.name.clone()).collect();
    let mut let_ok = Vec::new();
    for l in &let_names {
        let_ok.push(declare(cx, l, "a `let`"));
    }

    for p in &poisoned {
        scope.remove(p);
    }
    let mut lw = Lowerer {
        cx,
        e,
        scope,
        param_syms,
        coord_syms,
        vel_syms,
        input_syms,
        lets: Vec::new(),
        t_sym,
        pi_sym,
        place: Place::Let,
        all_lets: let_names.iter().map(|l| l.to_string()).collect(),
        poisoned,
        huge_constant: None,
    };

    // lets, in order: later ones may use earlier ones
    for (i, l) in def.lets.iter().enumerate() {
        lw.place = Place::Let;
        let v = lw.lower(&l.value, 0);
        lw.lets.push(LetInfo {
            value: v,
            name: l.name.clone(),
        });
        if let_ok[i] {
            lw.scope.insert(l.name.to_string(), Binding::Let(i));
        }
    }

    // the Lagrangian: exactly one
    let mut lagrangian = None;
    match def.lagrangians.as_slice() {
        [] if def.lagrangian_written => {} // it failed to parse: already reported
        [] => lw.cx.error_at(
            def.name.span(),
            "missing `lagrangian = ..;`: give the Lagrangian L = T - V in terms of the coordinates and `dot(q)` velocities",
        ),
        [(_, expr), rest @ ..] => {
            for (kw, _) in rest {
                lw.cx.error_at(kw.span(), "duplicate `lagrangian`: a system has exactly one Lagrangian; combine the terms into one expression");
            }
            lw.place = Place::Lagrangian;
            lagrangian = lw.lower(expr, 0);
        }
    }

    // forces
    let n = coords.len();
    let mut forces = vec![ZERO; n];
    let mut force_seen: Vec<Option<Span>> = vec![None; n];
    if let Some((_, list)) = &def.forces {
        for f in list {
            lw.place = Place::Force;
            let v = lw.lower(&f.value, 0);
            match lw.scope.get(&f.coordinate.to_string()) {
                _ if lw.poisoned.contains(&f.coordinate.to_string()) => {}
                Some(Binding::Coord(i)) => {
                    let i = *i;
                    if force_seen[i].is_some() {
                        lw.cx.error_at(f.coordinate.span(), format!("a second force on `{}`: write the sum of the forces on one coordinate as one expression", f.coordinate));
                    } else if let Some(v) = v {
                        forces[i] = v;
                        force_seen[i] = Some(f.coordinate.span());
                    }
                }
                _ => {
                    let cands: Vec<String> = coords.iter().map(|c| c.to_string()).collect();
                    let refs: Vec<&str> = cands.iter().map(|s| s.as_str()).collect();
                    let hint = names::suggest(&f.coordinate.to_string(), &refs);
                    lw.cx.error_at(
                        f.coordinate.span(),
                        format!("`{}` is not a coordinate{hint}: a force is given as `coordinate: Q;` for one of {}", f.coordinate, list_names(&coords)),
                    );
                }
            }
        }
    }

    // constraints
    let mut dep_of: Vec<Option<usize>> = vec![None; n]; // coordinate -> constraint index
    let mut constraint_rhs: Vec<(usize, ExprId, &crate::parse::Constraint)> = Vec::new();
    let constraints_span = def.constraints.as_ref().map(|c| c.0.span());
    if let Some((_, list)) = &def.constraints {
        for (ci, c) in list.iter().enumerate() {
            let Some(s) = lw.constraint_lhs(&c.lhs, &coords) else {
                continue;
            };
            if let Some(prev) = dep_of[s] {
                let _ = prev;
                lw.cx.error(
                    c.lhs.range(),
                    format!("`{}` is constrained twice: each dependent coordinate has exactly one constraint `dot({}) = ..`; merge them or choose another dependent coordinate", coords[s], coords[s]),
                );
                continue;
            }
            dep_of[s] = Some(ci);
            lw.place = Place::Constraint;
            if let Some(v) = lw.lower(&c.rhs, 0) {
                constraint_rhs.push((s, v, c));
            }
        }
    }
    let dependent: Vec<usize> = (0..n).filter(|&i| dep_of[i].is_some()).collect();
    let independent: Vec<usize> = (0..n).filter(|&i| dep_of[i].is_none()).collect();
    if n > 0 && independent.is_empty() {
        lw.cx.error_at(
            constraints_span.unwrap_or(def.name.span()),
            "every coordinate is constrained: no independent coordinate is left; a system needs at least one coordinate that is not on the left side of a constraint",
        );
    }

    // constraint right sides: linear and homogeneous in the independent velocities
    let mut a_matrix = vec![vec![ZERO; independent.len()]; dependent.len()];
    let mut dependent_velocity = vec![ZERO; dependent.len()];
    let analysable = if independent.is_empty() {
        &[][..]
    } else {
        &constraint_rhs[..]
    };
    for (s, rhs, c) in analysable {
        let a = dependent.iter().position(|d| d == s).unwrap_or(0);
        if let Some(row) = lw.analyse_constraint(*s, *rhs, c, &coords, &dependent, &independent) {
            a_matrix[a] = row;
            dependent_velocity[a] = *rhs;
        }
    }

    // outputs
    let mut outputs = Outputs::default();
    if let Some((_, list)) = &def.outputs {
        for o in list {
            let name = o.to_string();
            match outputs.set(&name) {
                Some(true) => lw.cx.error_at(
                    o.span(),
                    format!("output `{name}` is listed twice: remove one"),
                ),
                Some(false) => {}
                None => {
                    let hint = names::suggest(&name, &OUTPUTS);
                    lw.cx.error_at(
                        o.span(),
                        format!(
                            "unknown output `{name}`{hint}; the outputs are {}",
                            OUTPUTS.map(|s| format!("`{s}`")).join(", ")
                        ),
                    );
                }
            }
        }
    }

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
    Some(Model {
        engine: lw.e,
        params,
        coords,
        inputs,
        param_syms: lw.param_syms,
        coord_syms: lw.coord_syms,
        vel_syms: lw.vel_syms,
        input_syms: lw.input_syms,
        t_sym: lw.t_sym,
        pi_sym: lw.pi_sym,
        lagrangian,
        forces,
        independent,
        dependent,
        dependent_velocity,
        a_matrix,
        outputs,
        constraints_span,
        huge_constant: lw.huge_constant,
    })
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

fn list_names(ids: &[Ident]) -> String {
    ids.iter()
        .map(|i| format!("`{i}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Lowerer<'_> {
    fn known_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.scope.keys().cloned().collect();
        v.push("t".into());
        v.push("pi".into());
        v.sort();
        v
    }

    /// Lowers a surface expression; `None` after recording an error.
    fn lower(&mut self, x: &Expr, depth: usize) -> Option<ExprId> {
        let v = self.lower_inner(x, depth)?;
        if self.huge_constant.is_none()
            && let Some(c) = self.e.as_constant(v)
            && !c.to_f64().is_finite()
        {
            self.huge_constant = Some(x.range());
        }
        Some(v)
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
            None => short(self.e.display(v)),
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

    fn lower_inner(&mut self, x: &Expr, depth: usize) -> Option<ExprId> {
        if depth > crate::parse::MAX_DEPTH {
            self.cx.error(
                x.range(),
                "expression nested too deeply: split it into `let` items",
            );
            return None;
        }
        match x {
            Expr::Num(q, _) => Some(self.e.constant(*q)),
            Expr::Name(id) => self.lower_name(id),
            Expr::Neg(inner, _) => {
                let v = self.lower(inner, depth + 1)?;
                Some(self.e.neg(v))
            }
            Expr::Chain { first, rest } => {
                // every operand is lowered, so that all their errors are reported
                let mut acc = self.lower(first, depth + 1);
                for (op, op_span, operand) in rest {
                    let v = self.lower(operand, depth + 1);
                    acc = match (acc, v) {
                        (Some(a), Some(v)) => match op {
                            BinOp::Add => Some(self.e.add(a, v)),
                            BinOp::Sub => Some(self.e.sub(a, v)),
                            BinOp::Mul => Some(self.e.mul(a, v)),
                            BinOp::Div if v == ZERO => {
                                let at = SpanRange {
                                    first: *op_span,
                                    last: operand.range().last,
                                };
                                let msg = if matches!(operand, Expr::Num(..)) {
                                    "division by zero".to_string()
                                } else {
                                    format!(
                                        "division by zero: `{}` is 0",
                                        short(operand.to_source())
                                    )
                                };
                                self.cx.error(at, msg);
                                None
                            }
                            BinOp::Div => Some(self.e.div(a, v)),
                            BinOp::Pow => None,
                        },
                        _ => None,
                    };
                }
                acc
            }
            Expr::Pow { base, exp, .. } => {
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
                                "0 to a symbolic power is undefined here (it is exp(b·ln 0), and ln 0 = −∞)".to_string()
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
            Expr::Call { func, arg, range } => self.lower_call(func, arg, *range, depth),
        }
    }

    fn lower_name(&mut self, id: &Ident) -> Option<ExprId> {
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        match self.scope.get(&s).copied() {
            Some(Binding::Param(i)) => Some(self.e.sym(self.param_syms[i])),
            Some(Binding::Coord(i)) => Some(self.e.sym(self.coord_syms[i])),
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
                    _ => {}
                }
                Some(self.e.sym(self.input_syms[i]))
            }
            Some(Binding::Let(i)) => {
                let v = self.lets[i].value?;
                if self.place == Place::Lagrangian
                    && self.input_syms.iter().any(|&u| self.e.depends_on(v, u))
                {
                    self.cx.error_at(id.span(), format!("`{s}` depends on an input, and inputs cannot appear in the Lagrangian: put actuation in `forces`"));
                    return None;
                }
                Some(v)
            }
            None => match s.as_str() {
                "t" => {
                    if self.place == Place::Constraint {
                        self.cx.error_at(id.span(), "time-dependent (rheonomic) constraints are not supported: a constraint may depend on the coordinates only");
                        return None;
                    }
                    Some(self.e.sym(self.t_sym))
                }
                "pi" => Some(self.e.sym(self.pi_sym)),
                _ if FUNCTIONS.contains(&s.as_str()) || s == "dot" => {
                    self.cx.error_at(
                        id.span(),
                        format!("`{s}` is a function: call it with an argument, as in `{s}(x)`"),
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
        arg: &Expr,
        range: SpanRange,
        depth: usize,
    ) -> Option<ExprId> {
        let f = func.to_string();
        if f == "dot" {
            return self.lower_dot(arg, range);
        }
        let fun = match f.as_str() {
            "sin" => Some(Fun::Sin),
            "cos" => Some(Fun::Cos),
            "tan" => Some(Fun::Tan),
            "exp" => Some(Fun::Exp),
            "ln" => Some(Fun::Ln),
            "sqrt" => None,
            _ => {
                let mut cands: Vec<&str> = FUNCTIONS.to_vec();
                cands.push("dot");
                let hint = names::suggest(&f, &cands);
                let extra = if f == "log" {
                    " (the natural logarithm is `ln`)"
                } else {
                    ""
                };
                self.cx.error_at(
                    func.span(),
                    format!("unknown function `{f}`{hint}{extra}; the functions are `sin`, `cos`, `tan`, `exp`, `ln`, `sqrt` and `dot` (time derivative)"),
                );
                // still lower the argument to find errors inside it
                let _ = self.lower(arg, depth + 1);
                return None;
            }
        };
        let a = self.lower(arg, depth + 1)?;
        // a constant outside the function's domain
        use std::cmp::Ordering::{Equal, Less};
        let domain = match (fun, self.constant_sign(a)) {
            (None, Some(Less)) => Some(format!(
                "`sqrt` of a negative constant is not a real number{}",
                self.value_note(arg, a)
            )),
            (Some(Fun::Ln), Some(Equal)) => {
                Some("`ln(0)` is undefined (the logarithm tends to −∞ at 0)".to_string())
            }
            (Some(Fun::Ln), Some(Less)) => Some(format!(
                "`ln` of a negative constant is not a real number{}",
                self.value_note(arg, a)
            )),
            (Some(Fun::Tan), _) => self
                .pi_multiple(a)
                .and_then(|c| c.checked_sub(Rational::new(1, 2)?))
                .filter(|d| d.is_integer())
                .map(|_| {
                    format!(
                        "`tan` is undefined at odd multiples of π/2 (its cosine is 0){}",
                        self.value_note(arg, a)
                    )
                }),
            _ => None,
        };
        if let Some(msg) = domain {
            self.cx.error(range, msg);
            return None;
        }
        Some(match fun {
            Some(fun) => self.e.func(fun, a),
            None => self.e.pow(a, Rational::new(1, 2).unwrap_or(Rational::ONE)),
        })
    }

    fn lower_dot(&mut self, arg: &Expr, range: SpanRange) -> Option<ExprId> {
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
            Some(Binding::Coord(i)) => Some(self.e.sym(self.vel_syms[i])),
            Some(Binding::Let(i)) => {
                let v = self.lets[i].value?;
                let name = self.lets[i].name.clone();
                let fs = self.e.free_symbols(v).to_vec();
                if self.vel_syms.iter().any(|vs| fs.contains(vs)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` contains velocities, and its time derivative would need accelerations; `dot` applies to velocity-free `let`s only"));
                    return None;
                }
                if self.input_syms.iter().any(|u| fs.contains(u)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` depends on an input, whose time derivative is unknown"));
                    return None;
                }
                // total derivative by the chain rule: Σ ∂/∂q_i q̇_i + ∂/∂t
                let mut parts = Vec::new();
                for i in 0..self.coord_syms.len() {
                    let d = self.e.diff(v, self.coord_syms[i]);
                    if d != ZERO {
                        let vel = self.e.sym(self.vel_syms[i]);
                        parts.push(self.e.mul(d, vel));
                    }
                }
                let dt = self.e.diff(v, self.t_sym);
                parts.push(dt);
                Some(self.e.sum(&parts))
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

    /// The dependent coordinate of a constraint's left side `dot(s)`.
    fn constraint_lhs(&mut self, lhs: &Expr, coords: &[Ident]) -> Option<usize> {
        let msg = "the left side of a constraint must be `dot(s)` for a coordinate `s`, which becomes dependent: write `dot(s) = a1(q)*dot(r1) + ..`";
        match lhs {
            Expr::Call { func, arg, .. } if func == "dot" => match &**arg {
                Expr::Name(id) if self.poisoned.contains(&id.to_string()) => None,
                Expr::Name(id) => match self.scope.get(&id.to_string()) {
                    Some(Binding::Coord(i)) => Some(*i),
                    _ => {
                        let cands: Vec<String> = coords.iter().map(|c| c.to_string()).collect();
                        let refs: Vec<&str> = cands.iter().map(|s| s.as_str()).collect();
                        let hint = names::suggest(&id.to_string(), &refs);
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

    /// Checks a constraint's right side and returns its row of A.
    fn analyse_constraint(
        &mut self,
        s: usize,
        rhs: ExprId,
        c: &crate::parse::Constraint,
        coords: &[Ident],
        dependent: &[usize],
        independent: &[usize],
    ) -> Option<Vec<ExprId>> {
        let sname = &coords[s];
        let form = "a constraint must have the form `dot(s) = a1(q)*dot(r1) + a2(q)*dot(r2) + ..`, linear and homogeneous in the velocities of the independent coordinates";
        // dependent velocities on the right side
        for &d in dependent {
            if self.e.depends_on(rhs, self.vel_syms[d]) {
                let culprit = self.find_velocity_use(&c.rhs, d).unwrap_or(c.rhs.range());
                if d == s {
                    self.cx.error(culprit, format!("`dot({sname})` appears on both sides of its own constraint, so the constraint cannot be solved for it at a generic point; move the term to the left and divide by its coefficient"));
                } else {
                    self.cx.error(culprit, format!("the constraint for `{sname}` uses `dot({})`, the velocity of a dependent coordinate; substitute its constraint so that the right side has only independent velocities", coords[d]));
                }
                return None;
            }
        }
        // every term: exactly one independent velocity to the first power
        let terms = self.e.terms(rhs).to_vec();
        let mut ok = true;
        for (m, _) in &terms {
            let factors = self.e.factors(*m).to_vec();
            let mut vel_count = 0;
            let mut nonlinear = false;
            for (a, ex) in &factors {
                let syms = self.e.atom_symbols(*a).to_vec();
                let has_vel = independent
                    .iter()
                    .any(|&i| syms.contains(&self.vel_syms[i]));
                if !has_vel {
                    continue;
                }
                match self.e.atom(*a) {
                    crate::sym::Atom::Sym(_) if ex.is_one() => vel_count += 1,
                    _ => nonlinear = true,
                }
            }
            if nonlinear || vel_count != 1 {
                ok = false;
            }
        }
        if !ok {
            // locate the offending top-level term in the source
            let mut reported = false;
            for term in top_level_terms(&c.rhs) {
                let Some(v) = self.lower(term, 0) else {
                    continue;
                };
                let kind = self.term_kind(v, independent);
                match kind {
                    TermKind::Linear => {}
                    TermKind::Affine => {
                        let text = term.to_source();
                        self.cx.error(
                            term.range(),
                            format!("the constraint for `{sname}` has a term without any velocity, `{text}` (an affine term: ṡ would not vanish with the independent velocities); {form}"),
                        );
                        reported = true;
                    }
                    TermKind::Nonlinear => {
                        let (culprit, why) = self
                            .find_nonlinear(term, independent)
                            .unwrap_or((term, "is not linear in the velocities"));
                        let text = culprit.to_source();
                        self.cx.error(
                            culprit.range(),
                            format!("the constraint for `{sname}` is not linear in the velocities: `{text}` {why}; {form}"),
                        );
                        reported = true;
                    }
                }
            }
            if !reported {
                self.cx.error(c.rhs.range(), format!("the constraint for `{sname}` is not linear and homogeneous in the velocities once expanded; {form}"));
            }
            return None;
        }
        let mut row = Vec::with_capacity(independent.len());
        for &i in independent {
            let coef = self.e.diff(rhs, self.vel_syms[i]);
            row.push(self.e.neg(coef));
        }
        let _ = ONE;
        Some(row)
    }

    fn term_kind(&mut self, v: ExprId, independent: &[usize]) -> TermKind {
        let mut kind = TermKind::Linear;
        let terms = self.e.terms(v).to_vec();
        if terms.is_empty() {
            return TermKind::Linear;
        }
        for (m, _) in terms {
            let mut count = 0;
            for (a, ex) in self.e.factors(m).to_vec() {
                let syms = self.e.atom_symbols(a).to_vec();
                if !independent
                    .iter()
                    .any(|&i| syms.contains(&self.vel_syms[i]))
                {
                    continue;
                }
                match self.e.atom(a) {
                    crate::sym::Atom::Sym(_) if ex.is_one() => count += 1,
                    _ => count += 2,
                }
            }
            if count > 1 {
                return TermKind::Nonlinear;
            }
            if count == 0 {
                kind = TermKind::Affine;
            }
        }
        kind
    }

    fn has_velocity(&mut self, x: &Expr, independent: &[usize]) -> bool {
        match self.lower(x, 0) {
            Some(v) => independent
                .iter()
                .any(|&i| self.e.depends_on(v, self.vel_syms[i])),
            None => false,
        }
    }

    /// The smallest subexpression that makes a term nonlinear in the
    /// velocities, and what is wrong with it.
    fn find_nonlinear<'e>(
        &mut self,
        x: &'e Expr,
        independent: &[usize],
    ) -> Option<(&'e Expr, &'static str)> {
        match x {
            Expr::Neg(inner, _) => self.find_nonlinear(inner, independent),
            Expr::Chain { first, rest } if !x.is_sum() => {
                // a product: two factors with velocities, or one in a denominator
                let mut with_velocity: Vec<&Expr> = Vec::new();
                if self.has_velocity(first, independent) {
                    with_velocity.push(first);
                }
                for (op, _, f) in rest {
                    if self.has_velocity(f, independent) {
                        if *op == BinOp::Div {
                            return Some((f, "divides by a velocity"));
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
                    [_, ..] => Some((x, "multiplies velocities together")),
                }
            }
            Expr::Pow { base, .. } => {
                if self.has_velocity(base, independent) {
                    Some((x, "is a power of a velocity"))
                } else if self.has_velocity(x, independent) {
                    Some((x, "has a velocity in an exponent"))
                } else {
                    None
                }
            }
            Expr::Call { func, .. } if func == "dot" => None,
            Expr::Call { .. } => {
                if self.has_velocity(x, independent) {
                    Some((x, "has a velocity inside a function"))
                } else {
                    None
                }
            }
            _ => None,
        }
    }

    /// Where the velocity of coordinate `d` is used in `x` (depth first, left to right).
    fn find_velocity_use(&mut self, x: &Expr, d: usize) -> Option<SpanRange> {
        let mut stack = vec![x];
        while let Some(x) = stack.pop() {
            match x {
                Expr::Call { func, arg, range } if func == "dot" => {
                    if let Expr::Name(id) = &**arg
                        && self
                            .scope
                            .get(&id.to_string())
                            .is_some_and(|b| matches!(b, Binding::Coord(i) if *i == d))
                    {
                        return Some(*range);
                    }
                }
                Expr::Call { arg, .. } => stack.push(arg),
                Expr::Neg(inner, _) => stack.push(inner),
                Expr::Chain { first, rest } => {
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
}

enum TermKind {
    Linear,
    Affine,
    Nonlinear,
}

/// The top-level additive terms of an expression (through `+`, `-` and unary minus).
fn top_level_terms(x: &Expr) -> Vec<&Expr> {
    let mut out = Vec::new();
    let mut stack = vec![x];
    while let Some(x) = stack.pop() {
        match x {
            Expr::Chain { first, rest } if x.is_sum() => {
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
