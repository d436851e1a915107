//! Rigid bodies (DESIGN §10): the functions of vectors and rotations, the
//! angular velocity of a rotation from Ṙ Rᵀ, the kinetic energy of a body.

use super::values::{
    Mat3, Rotation, Value, Vec3, chain_omega, cross3, dot3, elementary, inverse, mat_mat, mat_vec,
    transpose,
};
use super::{Binding, Lowerer, Place};
use crate::ctxt::SpanRange;
use crate::parse::{BodyDef, Expr, Field};
use crate::sym::{Engine, ExprId, Rational, SymId, ZERO};
use crate::words::{BodyField, Function, Word};
use proc_macro2::Ident;
use std::rc::Rc;

/// A body, lowered: world components, body-axis inertia.
pub(crate) struct Body {
    /// The mass.
    pub(crate) mass: ExprId,
    /// The centre of mass, world components.
    pub(crate) centre: Vec3,
    /// Orientation (body → world) and inertia about the centre of mass in
    /// body axes, for a body that is not a point mass.
    pub(crate) rotation: Option<(Rc<Rotation>, Mat3)>,
    /// The body components of its angular velocity (zero for a point mass).
    pub(crate) omega_body: Vec3,
}

/// The state of a body's lowering (bodies are lowered on first use).
#[derive(Clone)]
pub(crate) enum BodyState {
    Pending,
    Busy,
    Done(Option<Rc<Body>>),
}

impl Lowerer<'_> {
    /// A call of a vector, rotation or body function; `None` inside
    /// `Some` after an error, `None` if `f` is not one of them.
    pub(super) fn lower_vector_call(
        &mut self,
        f: Function,
        args: &[Expr],
        range: SpanRange,
        depth: usize,
    ) -> Option<Option<Value>> {
        let arity = match f {
            Function::Dot | Function::Cross => 2,
            Function::Diag => 3,
            _ if f.of_vectors() => 1,
            _ => return None,
        };
        if args.len() != arity {
            let what = if arity == 1 {
                "one argument".to_string()
            } else {
                format!("{arity} arguments")
            };
            self.cx.error(range, format!("`{f}` takes {what}"));
            return Some(None);
        }
        if f == Function::KineticEnergy {
            return Some(self.kinetic_energy_of(&args[0]).map(Value::Scalar));
        }
        let vals: Vec<Option<Value>> = args
            .iter()
            .map(|a| self.lower_value(a, depth + 1))
            .collect();
        let vals: Vec<Value> = match vals.into_iter().collect::<Option<_>>() {
            Some(v) => v,
            None => return Some(None),
        };
        Some(self.apply_vector_function(f, vals, args))
    }

    fn apply_vector_function(
        &mut self,
        f: Function,
        mut vals: Vec<Value>,
        args: &[Expr],
    ) -> Option<Value> {
        let arg = |i: usize| &args[i];
        match f {
            Function::Dot | Function::Cross => {
                let b = vals.pop()?;
                let a = vals.pop()?;
                let what = format!("each argument of `{f}` must be a vector");
                let a = self.vector_of(a, arg(0), &what);
                let b = self.vector_of(b, arg(1), &what);
                let (a, b) = (a?, b?);
                Some(if f == Function::Dot {
                    Value::Scalar(dot3(&mut self.e, a, b))
                } else {
                    Value::Vector(cross3(&mut self.e, a, b))
                })
            }
            Function::Norm => {
                let v = self.vector_of(
                    vals.pop()?,
                    arg(0),
                    "the argument of `norm` must be a vector",
                )?;
                let n2 = dot3(&mut self.e, v, v);
                Some(Value::Scalar(self.e.pow(n2, Rational::new(1, 2)?)))
            }
            Function::Transpose => match vals.pop()? {
                Value::Rotation(r) => Some(Value::Rotation(Rc::new(inverse(&mut self.e, &r)))),
                Value::Matrix(m) => Some(Value::Matrix(transpose(&m))),
                other => {
                    self.cx.error(
                        arg(0).range(),
                        format!(
                            "`transpose` takes a rotation or a matrix, but `{}` is {}",
                            super::short(arg(0).to_source()),
                            other.kind()
                        ),
                    );
                    None
                }
            },
            Function::RotX | Function::RotY | Function::RotZ => {
                let angle = self.scalar_of(vals.pop()?, arg(0))?;
                if !self.position_like(angle, arg(0), "the angle of a rotation") {
                    return None;
                }
                let k = f.rotation_axis()?;
                let matrix = elementary(&mut self.e, k, angle);
                Some(Value::Rotation(Rc::new(Rotation {
                    matrix,
                    factors: vec![(k, angle)],
                })))
            }
            Function::Diag => {
                let mut m = [[ZERO; 3]; 3];
                for (i, v) in vals.into_iter().enumerate() {
                    m[i][i] = self.scalar_of(v, arg(i))?;
                }
                Some(Value::Matrix(m))
            }
            _ => {
                let world = f == Function::Omega;
                let r = self.rotation_of(vals.pop()?, arg(0), &format!("the argument of `{f}`"))?;
                Some(Value::Vector(self.angular_velocity(&r, world)))
            }
        }
    }

    /// Whether `v` is free of velocities and inputs (a position, an
    /// angle), else an error at `x`.
    pub(super) fn position_like(&mut self, v: ExprId, x: &Expr, what: &str) -> bool {
        let fs = self.e.free_symbols(v).to_vec();
        let culprit = if self.coords.iter().any(|c| fs.contains(&c.velocity)) {
            Some("a velocity")
        } else if self.inputs.iter().any(|u| fs.contains(&u.sym)) {
            Some("an input")
        } else {
            None
        };
        if let Some(c) = culprit {
            self.cx.error(
                x.range(),
                format!(
                    "{what} depends on the coordinates and time only, but `{}` contains {c}",
                    super::short(x.to_source())
                ),
            );
            return false;
        }
        true
    }

    /// The total time derivative of a velocity-free expression: Σ ∂e/∂q_i q̇_i + ∂e/∂t.
    pub(super) fn time_derivative(&mut self, v: ExprId) -> ExprId {
        let state: Vec<(SymId, SymId)> = (self.coords.iter())
            .map(|c| (c.position, c.velocity))
            .collect();
        time_derivative(&mut self.e, &state, self.t_sym, v)
    }

    /// The angular velocity of a rotation, world (`world`) or body
    /// components. Each elementary factor's ω is read off its Ṙ Rᵀ (skew
    /// by construction); the factors combine by the product rule,
    /// d(AB)/dt (AB)ᵀ = ȦAᵀ + A (ḂBᵀ) Aᵀ: world ω = Σ_i F₁⋯F_{i−1} ω_i,
    /// body ω = Σ_i (F_{i+1}⋯F_n)ᵀ ω_i.
    pub(crate) fn angular_velocity(&mut self, r: &Rotation, world: bool) -> Vec3 {
        let own: Vec<Vec3> = r
            .factors
            .iter()
            .map(|&(k, a)| self.factor_omega(k, a))
            .collect();
        chain_omega(&mut self.e, &r.factors, &own, world)
    }

    /// ω of one elementary rotation, from the skew matrix Ṙ Rᵀ.
    fn factor_omega(&mut self, k: usize, angle: ExprId) -> Vec3 {
        let m = elementary(&mut self.e, k, angle);
        let rdot: Mat3 = m.map(|row| row.map(|x| self.time_derivative(x)));
        let w = mat_mat(&mut self.e, &rdot, &transpose(&m));
        [w[2][1], w[0][2], w[1][0]]
    }

    /// The rotation of a body's orientation, looked up for ω.
    pub(super) fn body(&mut self, id: &Ident) -> Option<Rc<Body>> {
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        let Some(Binding::Body(i)) = self.scope.get(&s).copied() else {
            let what = match self.scope.get(&s) {
                Some(Binding::Let(_)) => format!("`{s}` is a `let`, not a body"),
                Some(_) => format!("`{s}` is not a body"),
                None => format!("unknown body `{s}`"),
            };
            let bodies: Vec<String> = self.body_defs.iter().map(|b| b.name.to_string()).collect();
            let refs: Vec<&str> = bodies.iter().map(|b| b.as_str()).collect();
            let hint = crate::names::suggest(&s, &refs);
            let known = match bodies.as_slice() {
                [] => "declare a body with `body NAME { mass: .., centre: .., orientation: .., inertia: .. }`".to_string(),
                list => format!("the bodies are {}", list.iter().map(|b| format!("`{b}`")).collect::<Vec<_>>().join(", ")),
            };
            self.cx
                .error_at(id.span(), format!("{what}{hint}: {known}"));
            return None;
        };
        match self.body_state[i].clone() {
            BodyState::Done(b) => b,
            BodyState::Busy => {
                self.cx.error_at(
                    id.span(),
                    format!("body `{s}` is used in its own definition"),
                );
                None
            }
            BodyState::Pending => {
                self.body_state[i] = BodyState::Busy;
                let def = self.body_defs[i].clone();
                let range = SpanRange::single(def.name.span());
                let task = format!("expanding body `{}`", def.name);
                let b = self.at(range, task, |lw| lw.lower_body(&def)).map(Rc::new);
                self.body_state[i] = BodyState::Done(b.clone());
                b
            }
        }
    }

    /// A line of the struct's docs for a `let` that is not a scalar.
    pub(super) fn describe_let(&mut self, l: &crate::parse::Let, v: &Value) {
        if let Value::Scalar(_) = v {
            return;
        }
        let kind = v.kind().trim_start_matches("a ");
        self.description.push(format!(
            "- `{}` ({kind}) = `{}`",
            l.name,
            l.value.to_source()
        ));
    }

    /// Components as text for the docs, shortened past 240 characters.
    pub(super) fn show3(&self, v: Vec3) -> String {
        let parts: Vec<String> = v.iter().map(|&c| self.e.display_capped(c, 240)).collect();
        let text = format!("({})", parts.join(", "));
        if text.chars().count() <= 240 {
            return text;
        }
        let head: String = text.chars().take(237).collect();
        format!("{head}...")
    }

    /// Lowers every body not used yet, so that its errors are reported.
    pub(super) fn lower_unused_bodies(&mut self) {
        for i in 0..self.body_defs.len() {
            if matches!(self.body_state[i], BodyState::Pending) {
                let name = self.body_defs[i].name.clone();
                if self.scope.contains_key(&name.to_string()) {
                    let _ = self.body(&name);
                }
            }
        }
    }

    /// The fields of a body, checked and lowered.
    fn lower_body(&mut self, def: &BodyDef) -> Option<Body> {
        let saved = std::mem::replace(&mut self.place, Place::Body);
        let Some(fields) = self.fields::<BodyField>(&def.fields, "a body", &def.name, None) else {
            self.place = saved;
            return None;
        };
        let get = |n: BodyField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        // a field that did not parse: a missing or unpaired field is no news
        let mut ok = !def.rejected_fields;
        for required in [BodyField::Mass, BodyField::Centre] {
            if get(required).is_none() && !def.rejected_fields {
                ok = false;
                self.cx.error_at(def.name.span(), format!("body `{}` has no `{required}`: write `body {} {{ mass: m, centre: C, orientation: R, inertia: I }}` (orientation and inertia may be left out together for a point mass)", def.name, def.name));
            }
        }
        let mass =
            get(BodyField::Mass).and_then(|x| self.lower_position_scalar(x, "the mass of a body"));
        let centre = get(BodyField::Centre)
            .and_then(|x| self.lower_position_vector(x, "the centre of mass"));
        let rotation = match (get(BodyField::Orientation), get(BodyField::Inertia)) {
            (None, None) => Some(None),
            (Some(r), Some(i)) => {
                let rot = self
                    .lower_value(r, 0)
                    .and_then(|v| self.rotation_of(v, r, "the orientation of a body"));
                let inertia = self.lower_inertia(i);
                Some(rot.zip(inertia))
            }
            (_, _) if def.rejected_fields => None,
            (one, _) => {
                let (have, missing) = if one.is_some() {
                    (BodyField::Orientation, BodyField::Inertia)
                } else {
                    (BodyField::Inertia, BodyField::Orientation)
                };
                self.cx.error_at(def.name.span(), format!("body `{}` has an `{have}` but no `{missing}`: a rigid body needs both (a point mass neither)", def.name));
                None
            }
        };
        self.place = saved;
        let rotation = rotation?;
        if !ok {
            return None;
        }
        let (mass, centre) = (mass?, centre?);
        let rotation = match rotation {
            Some(r) => Some(r),
            None if get(BodyField::Orientation).is_some() => return None,
            None => None,
        };
        let omega_body = match &rotation {
            Some((r, _)) => self.angular_velocity(r, false),
            None => [ZERO; 3],
        };
        self.describe_body(def, &fields, rotation.is_some().then_some(omega_body));
        Some(Body {
            mass,
            centre,
            rotation,
            omega_body,
        })
    }

    /// The line of the struct's docs for a body: its fields as written and
    /// its body angular velocity.
    fn describe_body(
        &mut self,
        def: &BodyDef,
        fields: &[(BodyField, &Expr)],
        omega_body: Option<Vec3>,
    ) {
        let get = |n: BodyField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let src = |n: BodyField| get(n).map(|x| x.to_source()).unwrap_or_default();
        let mut line = format!(
            "- body `{}`: mass `{}`, centre of mass `{}`",
            def.name,
            src(BodyField::Mass),
            src(BodyField::Centre)
        );
        match omega_body {
            Some(w) => {
                line.push_str(&format!(", orientation `{}`, inertia `{}` (body axes); kinetic energy T = ½ m |ċ|² + ½ ω_bᵀ I ω_b with the body angular velocity ω_b = {}", src(BodyField::Orientation), src(BodyField::Inertia), self.show3(w)));
            }
            None => line.push_str("; kinetic energy T = ½ m |ċ|² (a point mass)"),
        }
        self.description.push(line);
    }

    /// A vector field that must be free of velocities and inputs.
    pub(super) fn lower_position_vector(&mut self, x: &Expr, what: &str) -> Option<Vec3> {
        let v = self.lower_value(x, 0)?;
        let v = self.vector_of(v, x, &format!("{what} must be a vector"))?;
        v.iter()
            .all(|&c| self.position_like(c, x, what))
            .then_some(v)
    }

    /// A scalar field that must be free of velocities and inputs.
    fn lower_position_scalar(&mut self, x: &Expr, what: &str) -> Option<ExprId> {
        let v = self.lower(x, 0)?;
        self.position_like(v, x, what).then_some(v)
    }

    /// The inertia tensor: a symmetric 3×3 matrix free of velocities.
    fn lower_inertia(&mut self, x: &Expr) -> Option<Mat3> {
        let v = self.lower_value(x, 0)?;
        let m = match v {
            Value::Matrix(m) => m,
            other => {
                self.cx.error(x.range(), format!("the inertia of a body is a 3×3 matrix, but `{}` is {}: write `diag(I1, I2, I3)` for principal axes or `[[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]]`", super::short(x.to_source()), other.kind()));
                return None;
            }
        };
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if m[i][j] != m[j][i] {
                let (a, b) = (self.e.display(m[i][j]), self.e.display(m[j][i]));
                let at = entry_range(x, i, j).unwrap_or(x.range());
                self.cx.error(at, format!("the inertia tensor is not symmetric: entry ({}, {}) is `{}` but ({}, {}) is `{}`; an inertia tensor has I_ij = I_ji", i + 1, j + 1, super::short(a), j + 1, i + 1, super::short(b)));
                return None;
            }
        }
        let all_ok = m
            .iter()
            .flatten()
            .all(|&c| self.position_like(c, x, "the inertia tensor"));
        all_ok.then_some(m)
    }

    /// Named fields checked against the words of kind `W` (`center` is
    /// `centre`): unknown and repeated ones reported; the known ones
    /// returned. `equation` is the one field that may be written as an
    /// equation (`on: z = h(x, y)`), if any.
    pub(super) fn fields<'f, W: Word>(
        &mut self,
        fields: &'f [Field],
        what: &str,
        owner: &Ident,
        equation: Option<W>,
    ) -> Option<Vec<(W, &'f Expr)>> {
        let mut out: Vec<(W, &Expr)> = Vec::new();
        let mut unknown = false;
        for f in fields {
            let n = f.name.to_string();
            let Some(field) = W::parse(&n) else {
                let hint = W::suggest(&n);
                let list: Vec<String> =
                    W::all().iter().map(|a| format!("`{}`", a.name())).collect();
                self.cx.error_at(
                    f.name.span(),
                    format!(
                        "unknown field `{n}`{hint} of {what} `{owner}`: the fields are {}",
                        list.join(", ")
                    ),
                );
                unknown = true;
                continue;
            };
            if let Some(rhs) = &f.equals
                && equation != Some(field)
            {
                let allowed = match equation {
                    Some(w) => format!(" (only `{w}` takes one, a surface `{w}: z = h(x, y)`)"),
                    None => String::new(),
                };
                self.cx.error(
                    rhs.range(),
                    format!("`{field}` of {what} `{owner}` takes a value, not an equation{allowed}: write `{field}: value`"),
                );
                unknown = true;
                continue;
            }
            if out.iter().any(|o| o.0 == field) {
                self.cx.error_at(
                    f.name.span(),
                    format!("`{field}` is given twice for `{owner}`: remove one"),
                );
            } else {
                out.push((field, &f.value));
            }
        }
        // with a field misspelled, a missing one is no news
        (!unknown).then_some(out)
    }

    /// `kinetic_energy(body)`: ½ m |Ċ|² + ½ ω_bᵀ I ω_b, ω_b the body
    /// components of the body's angular velocity. In the Lagrangian, a body
    /// whose expansion would be large ([`FOLD_TERMS`]) stays one symbol
    /// there (see [`KineticBody::folded`](crate::model::KineticBody)).
    fn kinetic_energy_of(&mut self, x: &Expr) -> Option<ExprId> {
        let Expr::Name(id) = x else {
            self.cx.error(
                x.range(),
                "`kinetic_energy` takes the name of a body: `kinetic_energy(wheel)`",
            );
            return None;
        };
        let b = self.body(id)?;
        let body = crate::model::KineticBody {
            mass: b.mass,
            centre: b.centre,
            rotation: b.rotation.as_ref().map(|(_, i)| (b.omega_body, *i)),
            orientation: b.rotation.as_ref().map(|(r, _)| r.matrix),
            heading: b
                .rotation
                .as_ref()
                .and_then(|(r, _)| match r.factors.first() {
                    Some(&(2, angle)) => Some(angle),
                    _ => None,
                }),
            spin: b.rotation.as_ref().and_then(|(r, i)| {
                let &(k, angle) = r.factors.last()?;
                axisymmetric(i, k).then_some((k, angle))
            }),
            factors: b
                .rotation
                .as_ref()
                .map_or(Vec::new(), |(r, _)| r.factors.clone()),
            folded: None,
        };
        if !matches!(self.place, Place::Lagrangian) {
            return self.kinetic_energy(&body);
        }
        let (t, body) = match self.large(&body) {
            true => {
                let s = self.e.symbol(&format!("kinetic_energy({id})"));
                let folded = Some(s);
                (self.e.sym(s), crate::model::KineticBody { folded, ..body })
            }
            false => (self.kinetic_energy(&body)?, body),
        };
        self.kinetic.push((body, t));
        Some(t)
    }

    /// A body's kinetic energy, expanded.
    fn kinetic_energy(&mut self, body: &crate::model::KineticBody) -> Option<ExprId> {
        let state: Vec<(SymId, SymId)> = (self.coords.iter())
            .map(|c| (c.position, c.velocity))
            .collect();
        kinetic_energy(&mut self.e, (&state, self.t_sym), body)
    }

    /// Whether a body's kinetic energy would be large expanded: its
    /// centre's and angular velocity's components have more than
    /// [`FOLD_TERMS`] terms together.
    fn large(&self, body: &crate::model::KineticBody) -> bool {
        let omega = body.rotation.iter().flat_map(|r| r.0);
        let terms: usize = (body.centre.into_iter().chain(omega))
            .map(|x| self.e.num_terms(x))
            .sum();
        terms > FOLD.with(|f| f.get())
    }

    /// L = Σ_b T_b + L_rest over the bodies whose kinetic energy the
    /// Lagrangian took, when there are any and each is a rigid body of the
    /// form Kane's terms assume: its centre and every angle of its
    /// orientation free of t (Ċ = Σ ∂C/∂q q̇, each factor's rate Σ ∂θ/∂q q̇),
    /// its mass and inertia constant (free of the coordinates and t).
    /// Otherwise the Lagrangian's own Euler–Lagrange terms are derived, and
    /// the kinetic energies folded into symbols are expanded in it: the
    /// Lagrangian returned is the one the model keeps.
    pub(super) fn kinetic_split(
        &mut self,
        lagrangian: ExprId,
    ) -> (ExprId, Option<crate::model::KineticSplit>) {
        let kinetic = std::mem::take(&mut self.kinetic);
        let t = self.t_sym;
        let state: Vec<SymId> = (self.coords.iter())
            .flat_map(|c| [c.position, c.velocity])
            .chain([t])
            .collect();
        let varies = |x: ExprId| state.iter().any(|&s| self.e.depends_on(x, s));
        let not_kane = kinetic.iter().any(|(b, _)| {
            let omega = b.rotation.iter().flat_map(|r| r.0);
            let angles = b.factors.iter().map(|f| f.1);
            let timed = (b.centre.iter().copied())
                .chain(omega)
                .chain(angles)
                .any(|x| self.e.depends_on(x, t));
            let inertia = b.rotation.iter().flat_map(|r| r.1.into_iter().flatten());
            timed || std::iter::once(b.mass).chain(inertia).any(varies)
        });
        let mut rest = lagrangian;
        for (_, t) in &kinetic {
            rest = self.e.sub(rest, *t);
        }
        let folded: Vec<SymId> = kinetic.iter().filter_map(|(b, _)| b.folded).collect();
        let stray = folded.iter().any(|&s| self.e.depends_on(rest, s));
        if kinetic.is_empty() || not_kane || stray {
            return (self.unfolded(lagrangian, &kinetic), None);
        }
        let bodies = kinetic.into_iter().map(|(b, _)| b).collect();
        (
            lagrangian,
            Some(crate::model::KineticSplit { bodies, rest }),
        )
    }

    /// `lagrangian` with the kinetic energies folded into symbols expanded.
    fn unfolded(
        &mut self,
        lagrangian: ExprId,
        kinetic: &[(crate::model::KineticBody, ExprId)],
    ) -> ExprId {
        let mut map = rustc_hash::FxHashMap::default();
        for (b, _) in kinetic {
            if let Some(s) = b.folded {
                let t = self.kinetic_energy(b).unwrap_or(ZERO);
                map.insert(s, t);
            }
        }
        match map.is_empty() {
            true => lagrangian,
            false => self.e.subst(lagrangian, &map, &mut Default::default()),
        }
    }
}

/// The terms of the bodies whose kinetic energies are folded: the poles of
/// a folded kinetic energy are those of its mass, centre, ω_b and inertia.
pub(crate) fn folded_terms(kinetic: Option<&crate::model::KineticSplit>) -> Vec<ExprId> {
    let folded = kinetic.iter().flat_map(|k| &k.bodies);
    let folded = folded.filter(|b| b.folded.is_some());
    folded
        .flat_map(|b| {
            let rotation = b
                .rotation
                .iter()
                .flat_map(|(w, i)| w.iter().chain(i.iter().flatten()));
            let centre = b.centre.iter().chain(rotation).chain([&b.mass]);
            centre.copied().collect::<Vec<_>>()
        })
        .collect()
}

/// The total time derivative Σ ∂v/∂q_i q̇_i + ∂v/∂t of a velocity-free
/// expression, with `state` the (position, velocity) symbols of the
/// coordinates and `t` time's.
pub(crate) fn time_derivative(
    e: &mut Engine,
    state: &[(SymId, SymId)],
    t: SymId,
    v: ExprId,
) -> ExprId {
    let mut parts = Vec::new();
    for &(q, qdot) in state {
        let d = e.diff(v, q);
        if d != ZERO {
            let vel = e.sym(qdot);
            parts.push(e.mul(d, vel));
        }
    }
    parts.push(e.diff(v, t));
    e.sum(&parts)
}

/// A body's kinetic energy ½ m |Ċ|² + ½ ω_bᵀ I ω_b, expanded, with
/// `(state, t)` as for [`time_derivative`].
pub(crate) fn kinetic_energy(
    e: &mut Engine,
    (state, t): (&[(SymId, SymId)], SymId),
    body: &crate::model::KineticBody,
) -> Option<ExprId> {
    let v = body.centre.map(|c| time_derivative(e, state, t, c));
    let v2 = dot3(e, v, v);
    let half = e.constant(Rational::new(1, 2)?);
    let m_half = e.mul(half, body.mass);
    let mut energy = e.mul(m_half, v2);
    if let Some((w, inertia)) = &body.rotation {
        let iw = mat_vec(e, inertia, *w);
        let rot = dot3(e, *w, iw);
        let rot = e.mul(half, rot);
        energy = e.add(energy, rot);
    }
    Some(energy)
}

/// A body's kinetic energy stays one symbol in the Lagrangian when its
/// centre's and angular velocity's components have more than this many
/// terms together: the links of a chain, whose expanded kinetic energies
/// grow with the square of their sizes and which Kane's form of the
/// multiplier route (DESIGN §10) does not need. Expanded where an output
/// or a route takes the Lagrangian itself (`Scene::lagrangian`).
pub(crate) const FOLD_TERMS: usize = 256;

std::thread_local! {
    /// The threshold in force on this thread ([`with_fold_terms`]).
    static FOLD: std::cell::Cell<usize> = const { std::cell::Cell::new(FOLD_TERMS) };
}

/// Runs `f` with kinetic energies folded above `terms` terms instead of
/// [`FOLD_TERMS`] on this thread: with 0, every body's kinetic energy in
/// the Lagrangian is folded, which the differential verifier uses to check
/// the folded path on every random system with bodies.
pub fn with_fold_terms<T>(terms: usize, f: impl FnOnce() -> T) -> T {
    let before = FOLD.with(|c| c.replace(terms));
    let out = f();
    FOLD.with(|c| c.set(before));
    out
}

/// Whether an inertia (body axes) is symmetric about axis k: it commutes
/// with every rotation about k.
fn axisymmetric(i: &Mat3, k: usize) -> bool {
    let (a, b) = ((k + 1) % 3, (k + 2) % 3);
    i[a][a] == i[b][b] && [i[a][b], i[a][k], i[b][k]].iter().all(|&x| x == ZERO)
}

/// The range of entry (i, j) of a matrix written `[[..], [..], [..]]`.
fn entry_range(x: &Expr, i: usize, j: usize) -> Option<SpanRange> {
    let Expr::Vector { items: rows, .. } = x else {
        return None;
    };
    match rows.get(i)? {
        Expr::Vector { items, .. } => Some(items.get(j)?.range()),
        _ => None,
    }
}
