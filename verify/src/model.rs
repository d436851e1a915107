//! A system in the language, held as a tree: what the generator builds,
//! what [`System::text`] writes in the macro's syntax and what the plain
//! derivation ([`crate::plain`]) evaluates. The tree is the system's
//! meaning as the language defines it (DESIGN §2, §9, §10), independent
//! of the engine.

use std::fmt::Write;

/// A scalar function of the language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fun {
    /// sin.
    Sin,
    /// cos.
    Cos,
    /// tan.
    Tan,
    /// exp.
    Exp,
    /// ln.
    Ln,
    /// sqrt.
    Sqrt,
    /// atan.
    Atan,
    /// asin.
    Asin,
    /// acos.
    Acos,
    /// sinh.
    Sinh,
    /// cosh.
    Cosh,
    /// tanh.
    Tanh,
    /// abs.
    Abs,
}

impl Fun {
    /// The function's name in the language.
    pub fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Exp => "exp",
            Fun::Ln => "ln",
            Fun::Sqrt => "sqrt",
            Fun::Atan => "atan",
            Fun::Asin => "asin",
            Fun::Acos => "acos",
            Fun::Sinh => "sinh",
            Fun::Cosh => "cosh",
            Fun::Tanh => "tanh",
            Fun::Abs => "abs",
        }
    }
}

/// A scalar expression.
#[derive(Clone, Debug)]
pub enum Ex {
    /// p/q (q > 0).
    Num(i64, i64),
    /// π.
    Pi,
    /// A parameter.
    Param(usize),
    /// A coordinate qᵢ.
    Coord(usize),
    /// Its velocity `dot(qᵢ)`.
    Vel(usize),
    /// A generalized speed.
    Speed(usize),
    /// An input.
    Input(usize),
    /// t.
    Time,
    /// A scalar `let`.
    Let(usize),
    /// `dot(L)` of a velocity-free scalar `let`.
    DotLet(usize),
    /// A component (0, 1, 2 for x, y, z) of a vector.
    Comp(Box<Vx>, usize),
    /// A sum.
    Add(Vec<Ex>),
    /// a − b.
    Sub(Box<Ex>, Box<Ex>),
    /// A product.
    Mul(Vec<Ex>),
    /// −a.
    Neg(Box<Ex>),
    /// a / b.
    Div(Box<Ex>, Box<Ex>),
    /// a^(p/q).
    Pow(Box<Ex>, i64, i64),
    /// f(a).
    Call(Fun, Box<Ex>),
    /// atan2(y, x).
    Atan2(Box<Ex>, Box<Ex>),
    /// `kinetic_energy(body)`.
    Kinetic(usize),
}

impl Default for Ex {
    fn default() -> Ex {
        Ex::Num(0, 1)
    }
}

/// A 3-vector expression.
#[derive(Clone, Debug)]
pub enum Vx {
    /// `[a, b, c]`.
    Lit(Box<[Ex; 3]>),
    /// A vector `let`.
    Let(usize),
    /// u + v.
    Add(Box<Vx>, Box<Vx>),
    /// u − v.
    Sub(Box<Vx>, Box<Vx>),
    /// s v.
    Scale(Box<Ex>, Box<Vx>),
    /// R v.
    Rot(Box<Rx>, Box<Vx>),
}

/// A rotation expression.
#[derive(Clone, Debug)]
pub enum Rx {
    /// `rot_x`, `rot_y`, `rot_z` (axis 0, 1, 2) of an angle.
    Elem(usize, Box<Ex>),
    /// A rotation `let`.
    Let(usize),
    /// A product.
    Mul(Box<Rx>, Box<Rx>),
    /// `transpose(R)`.
    Transpose(Box<Rx>),
}

/// The value of a `let`.
#[derive(Clone, Debug)]
pub enum LetValue {
    /// A scalar.
    Scalar(Ex),
    /// A vector.
    Vector(Vx),
    /// A rotation.
    Rotation(Rx),
}

/// A rigid body or point mass.
#[derive(Clone, Debug)]
pub struct Body {
    /// m.
    pub mass: Ex,
    /// The centre of mass, world components.
    pub centre: Vx,
    /// Orientation and inertia about the centre in body axes (symmetric),
    /// or none for a point mass.
    pub rotation: Option<(Rx, [[Ex; 3]; 3])>,
    /// Whether the inertia is written `diag(..)`.
    pub diagonal: bool,
}

/// A constraint line.
#[derive(Clone, Debug)]
pub enum Constraint {
    /// `dot(s) = rhs`.
    Explicit {
        /// s.
        s: usize,
        /// The right side.
        rhs: Ex,
    },
    /// `lhs = rhs`, with velocities: linear in them.
    Implicit {
        /// Left side.
        lhs: Ex,
        /// Right side.
        rhs: Ex,
    },
    /// `lhs = rhs` without velocities.
    Holonomic {
        /// Left side.
        lhs: Ex,
        /// Right side.
        rhs: Ex,
    },
    /// `rolls(body, radius: r[, axle: a][, tube: ρ][, centre: G])`.
    Rolls {
        /// The body.
        body: usize,
        /// r.
        radius: Ex,
        /// The axle in body axes (none: a sphere).
        axle: Option<[i64; 3]>,
        /// ρ for a torus.
        tube: Option<Ex>,
        /// The geometric centre, if not the centre of mass.
        centre: Option<Vx>,
    },
}

/// A system in generalized speeds: one kinematic line per coordinate.
#[derive(Clone, Debug)]
pub struct Speeds {
    /// The speeds' names.
    pub names: Vec<String>,
    /// `dot(qᵢ) = wᵢ(q, u, t)`.
    pub kinematics: Vec<Ex>,
}

/// A whole system.
#[derive(Clone, Debug)]
pub struct System {
    /// The struct's name.
    pub name: String,
    /// Parameter names.
    pub params: Vec<String>,
    /// Coordinate names.
    pub coords: Vec<String>,
    /// Input names.
    pub inputs: Vec<String>,
    /// The `let`s, in order.
    pub lets: Vec<(String, LetValue)>,
    /// The bodies, with their names.
    pub bodies: Vec<(String, Body)>,
    /// L.
    pub lagrangian: Ex,
    /// Generalized forces (coordinate, Q).
    pub forces: Vec<(usize, Ex)>,
    /// The constraint lines.
    pub constraints: Vec<Constraint>,
    /// `dependent { .. }`, if written.
    pub dependent: Option<Vec<usize>>,
    /// `speeds` and `kinematics`, if the system is written in speeds.
    pub speeds: Option<Speeds>,
    /// `outputs { .. }`.
    pub outputs: Vec<&'static str>,
}

impl System {
    /// Whether `e` depends on t, through `let`s and bodies too.
    pub fn timed(&self, e: &Ex) -> bool {
        match e {
            Ex::Time => true,
            Ex::Let(i) | Ex::DotLet(i) => self.let_timed(*i),
            Ex::Comp(v, _) => self.vx_timed(v),
            Ex::Add(v) | Ex::Mul(v) => v.iter().any(|x| self.timed(x)),
            Ex::Sub(a, b) | Ex::Div(a, b) | Ex::Atan2(a, b) => self.timed(a) || self.timed(b),
            Ex::Neg(a) | Ex::Pow(a, ..) | Ex::Call(_, a) => self.timed(a),
            Ex::Kinetic(b) => self.body_timed(*b),
            _ => false,
        }
    }

    fn let_timed(&self, i: usize) -> bool {
        match &self.lets[i].1 {
            LetValue::Scalar(x) => self.timed(x),
            LetValue::Vector(v) => self.vx_timed(v),
            LetValue::Rotation(r) => self.rx_timed(r),
        }
    }

    /// Whether a vector depends on t.
    pub fn vx_timed(&self, v: &Vx) -> bool {
        match v {
            Vx::Lit(c) => c.iter().any(|x| self.timed(x)),
            Vx::Let(i) => self.let_timed(*i),
            Vx::Add(a, b) | Vx::Sub(a, b) => self.vx_timed(a) || self.vx_timed(b),
            Vx::Scale(s, v) => self.timed(s) || self.vx_timed(v),
            Vx::Rot(r, v) => self.rx_timed(r) || self.vx_timed(v),
        }
    }

    /// Whether a rotation depends on t.
    pub fn rx_timed(&self, r: &Rx) -> bool {
        match r {
            Rx::Elem(_, a) => self.timed(a),
            Rx::Let(i) => self.let_timed(*i),
            Rx::Mul(a, b) => self.rx_timed(a) || self.rx_timed(b),
            Rx::Transpose(a) => self.rx_timed(a),
        }
    }

    /// Whether a body's fields depend on t.
    pub fn body_timed(&self, b: usize) -> bool {
        let b = &self.bodies[b].1;
        self.timed(&b.mass)
            || self.vx_timed(&b.centre)
            || b.rotation
                .as_ref()
                .is_some_and(|(r, i)| self.rx_timed(r) || i.iter().flatten().any(|x| self.timed(x)))
    }

    /// Whether some constraint or kinematic line depends on t.
    pub fn timed_rows(&self) -> bool {
        let rows = self.constraints.iter().any(|c| match c {
            Constraint::Explicit { rhs, .. } => self.timed(rhs),
            Constraint::Implicit { lhs, rhs } | Constraint::Holonomic { lhs, rhs } => {
                self.timed(lhs) || self.timed(rhs)
            }
            Constraint::Rolls { body, centre, .. } => {
                self.body_timed(*body) || centre.as_ref().is_some_and(|g| self.vx_timed(g))
            }
        });
        let kin =
            (self.speeds.as_ref()).is_some_and(|s| s.kinematics.iter().any(|w| self.timed(w)));
        rows || kin
    }

    /// The macro's input: `pub struct Name { .. }`.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let list = |v: &[String]| v.join(", ");
        let _ = writeln!(s, "pub struct {} {{", self.name);
        if !self.params.is_empty() {
            let _ = writeln!(s, "    parameters {{ {} }}", list(&self.params));
        }
        let _ = writeln!(s, "    coordinates {{ {} }}", list(&self.coords));
        if !self.inputs.is_empty() {
            let _ = writeln!(s, "    inputs {{ {} }}", list(&self.inputs));
        }
        for (name, v) in &self.lets {
            let value = match v {
                LetValue::Scalar(e) => self.ex(e),
                LetValue::Vector(v) => self.vx(v),
                LetValue::Rotation(r) => self.rx(r),
            };
            let _ = writeln!(s, "    let {name} = {value};");
        }
        for (name, b) in &self.bodies {
            let _ = writeln!(s, "    {}", self.body_text(name, b));
        }
        let _ = writeln!(s, "    lagrangian = {};", self.ex(&self.lagrangian));
        if !self.forces.is_empty() {
            let lines: Vec<String> = (self.forces.iter())
                .map(|(i, q)| format!("{}: {};", self.coords[*i], self.ex(q)))
                .collect();
            let _ = writeln!(s, "    forces {{ {} }}", lines.join(" "));
        }
        if !self.constraints.is_empty() {
            let lines: Vec<String> = self
                .constraints
                .iter()
                .map(|c| self.constraint_text(c))
                .collect();
            let _ = writeln!(
                s,
                "    constraints {{\n        {}\n    }}",
                lines.join("\n        ")
            );
        }
        if let Some(d) = &self.dependent {
            let names: Vec<String> = d.iter().map(|&i| self.coords[i].clone()).collect();
            let _ = writeln!(s, "    dependent {{ {} }}", list(&names));
        }
        if let Some(sp) = &self.speeds {
            let _ = writeln!(s, "    speeds {{ {} }}", list(&sp.names));
            let lines: Vec<String> = (sp.kinematics.iter().enumerate())
                .map(|(i, w)| format!("dot({}) = {};", self.coords[i], self.ex(w)))
                .collect();
            let _ = writeln!(
                s,
                "    kinematics {{\n        {}\n    }}",
                lines.join("\n        ")
            );
        }
        if !self.outputs.is_empty() {
            let _ = writeln!(s, "    outputs {{ {} }}", self.outputs.join(", "));
        }
        s.push('}');
        s
    }

    fn body_text(&self, name: &str, b: &Body) -> String {
        let mut s = format!(
            "body {name} {{ mass: {}, centre: {}",
            self.ex(&b.mass),
            self.vx(&b.centre)
        );
        if let Some((r, i)) = &b.rotation {
            let inertia = if b.diagonal {
                format!(
                    "diag({}, {}, {})",
                    self.ex(&i[0][0]),
                    self.ex(&i[1][1]),
                    self.ex(&i[2][2])
                )
            } else {
                let rows: Vec<String> = (i.iter())
                    .map(|row| {
                        format!(
                            "[{}]",
                            row.iter()
                                .map(|e| self.ex(e))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    })
                    .collect();
                format!("[{}]", rows.join(", "))
            };
            let _ = write!(s, ", orientation: {}, inertia: {inertia}", self.rx(r));
        }
        s.push_str(" }");
        s
    }

    fn constraint_text(&self, c: &Constraint) -> String {
        match c {
            Constraint::Explicit { s, rhs } => {
                format!("dot({}) = {};", self.coords[*s], self.ex(rhs))
            }
            Constraint::Implicit { lhs, rhs } | Constraint::Holonomic { lhs, rhs } => {
                format!("{} = {};", self.ex(lhs), self.ex(rhs))
            }
            Constraint::Rolls {
                body,
                radius,
                axle,
                tube,
                centre,
            } => {
                let mut s = format!(
                    "rolls({}, radius: {}",
                    self.bodies[*body].0,
                    self.ex(radius)
                );
                if let Some(a) = axle {
                    let _ = write!(s, ", axle: [{}, {}, {}]", a[0], a[1], a[2]);
                }
                if let Some(t) = tube {
                    let _ = write!(s, ", tube: {}", self.ex(t));
                }
                if let Some(g) = centre {
                    let _ = write!(s, ", centre: {}", self.vx(g));
                }
                s.push_str(");");
                s
            }
        }
    }

    /// A scalar expression in the language (fully parenthesised where
    /// precedence could matter).
    pub fn ex(&self, e: &Ex) -> String {
        match e {
            Ex::Num(p, 1) if *p >= 0 => p.to_string(),
            Ex::Num(p, 1) => format!("({p})"),
            Ex::Num(p, q) => format!("({p}/{q})"),
            Ex::Pi => "pi".into(),
            Ex::Param(i) => self.params[*i].clone(),
            Ex::Coord(i) => self.coords[*i].clone(),
            Ex::Vel(i) => format!("dot({})", self.coords[*i]),
            Ex::Speed(i) => self
                .speeds
                .as_ref()
                .map_or("?".into(), |s| s.names[*i].clone()),
            Ex::Input(i) => self.inputs[*i].clone(),
            Ex::Time => "t".into(),
            Ex::Let(i) => self.lets[*i].0.clone(),
            Ex::DotLet(i) => format!("dot({})", self.lets[*i].0),
            Ex::Comp(v, k) => match &**v {
                Vx::Let(i) => format!("{}.{}", self.lets[*i].0, ["x", "y", "z"][*k]),
                other => format!("({}).{}", self.vx(other), ["x", "y", "z"][*k]),
            },
            Ex::Add(v) => format!(
                "({})",
                v.iter().map(|x| self.ex(x)).collect::<Vec<_>>().join(" + ")
            ),
            Ex::Sub(a, b) => format!("({} - {})", self.ex(a), self.ex(b)),
            Ex::Mul(v) => format!(
                "({})",
                v.iter().map(|x| self.ex(x)).collect::<Vec<_>>().join("*")
            ),
            Ex::Neg(a) => format!("(-{})", self.ex(a)),
            Ex::Div(a, b) => format!("({}/{})", self.ex(a), self.ex(b)),
            Ex::Pow(a, p, 1) => format!("{}^{p}", self.ex(a)),
            Ex::Pow(a, p, q) => format!("{}^({p}/{q})", self.ex(a)),
            Ex::Call(f, a) => format!("{}({})", f.name(), self.ex(a)),
            Ex::Atan2(y, x) => format!("atan2({}, {})", self.ex(y), self.ex(x)),
            Ex::Kinetic(b) => format!("kinetic_energy({})", self.bodies[*b].0),
        }
    }

    /// A vector expression in the language.
    pub fn vx(&self, v: &Vx) -> String {
        match v {
            Vx::Lit(c) => format!(
                "[{}, {}, {}]",
                self.ex(&c[0]),
                self.ex(&c[1]),
                self.ex(&c[2])
            ),
            Vx::Let(i) => self.lets[*i].0.clone(),
            Vx::Add(a, b) => format!("({} + {})", self.vx(a), self.vx(b)),
            Vx::Sub(a, b) => format!("({} - {})", self.vx(a), self.vx(b)),
            Vx::Scale(s, v) => format!("({}*{})", self.ex(s), self.vx(v)),
            Vx::Rot(r, v) => format!("({}*{})", self.rx(r), self.vx(v)),
        }
    }

    /// Rewrites the rotation written `own` (`rot_z(q1)*rot_y(q2)*rot_x(q3)`,
    /// a `let` or a body's orientation) with its factors about `axes`,
    /// keeping their angles: the same rotation read in another sequence
    /// (DESIGN §9.4). Whether it was found.
    pub fn rewrite_rotation(&mut self, own: &str, axes: [usize; 3]) -> bool {
        fn set_axes(r: &mut Rx, axes: &mut std::slice::Iter<'_, usize>) {
            match r {
                Rx::Elem(k, _) => {
                    if let Some(&a) = axes.next() {
                        *k = a;
                    }
                }
                Rx::Mul(a, b) => {
                    set_axes(a, axes);
                    set_axes(b, axes);
                }
                Rx::Let(_) | Rx::Transpose(_) => {}
            }
        }
        let found = (0..self.lets.len())
            .find(|&i| matches!(&self.lets[i].1, LetValue::Rotation(r) if self.rx(r) == own));
        if let Some(i) = found
            && let LetValue::Rotation(r) = &mut self.lets[i].1
        {
            set_axes(r, &mut axes.iter());
            return true;
        }
        let found = (0..self.bodies.len())
            .find(|&i| matches!(&self.bodies[i].1.rotation, Some((r, _)) if self.rx(r) == own));
        if let Some(i) = found
            && let Some((r, _)) = &mut self.bodies[i].1.rotation
        {
            set_axes(r, &mut axes.iter());
            return true;
        }
        false
    }

    /// A rotation expression in the language.
    pub fn rx(&self, r: &Rx) -> String {
        match r {
            Rx::Elem(k, a) => format!("{}({})", ["rot_x", "rot_y", "rot_z"][*k], self.ex(a)),
            Rx::Let(i) => self.lets[*i].0.clone(),
            Rx::Mul(a, b) => format!("{}*{}", self.rx(a), self.rx(b)),
            Rx::Transpose(a) => format!("transpose({})", self.rx(a)),
        }
    }
}

/// The system's expressions as Python source for SymPy (the independent
/// check of the plain derivation, `data/sympy_reference.py`): parameters
/// `P[i]`, coordinates `q[i]`, velocities `qd[i]`, speeds `w[i]`, inputs
/// `U[i]`, `t`; a scalar `let` `L('name')`, its total time derivative
/// `D('name')`, a vector or rotation `let` `L('name')` (a 3 × 1 or 3 × 3
/// matrix), `KE('body')` a body's kinetic energy; components `v[k]`.
impl System {
    /// A scalar expression in Python.
    pub fn py(&self, e: &Ex) -> String {
        let list = |v: &[Ex], op: &str| v.iter().map(|x| self.py(x)).collect::<Vec<_>>().join(op);
        match e {
            Ex::Num(p, q) => format!("Rational({p}, {q})"),
            Ex::Pi => "pi".into(),
            Ex::Param(i) => format!("P[{i}]"),
            Ex::Coord(i) => format!("q[{i}]"),
            Ex::Vel(i) => format!("qd[{i}]"),
            Ex::Speed(i) => format!("w[{i}]"),
            Ex::Input(i) => format!("U[{i}]"),
            Ex::Time => "t".into(),
            Ex::Let(i) => format!("L('{}')", self.lets[*i].0),
            Ex::DotLet(i) => format!("D('{}')", self.lets[*i].0),
            Ex::Comp(v, k) => format!("({})[{k}]", self.py_v(v)),
            Ex::Add(v) => format!("({})", list(v, " + ")),
            Ex::Sub(a, b) => format!("({} - {})", self.py(a), self.py(b)),
            Ex::Mul(v) => format!("({})", list(v, "*")),
            Ex::Neg(a) => format!("(-{})", self.py(a)),
            Ex::Div(a, b) => format!("({}/{})", self.py(a), self.py(b)),
            Ex::Pow(a, p, q) => format!("(({})**Rational({p}, {q}))", self.py(a)),
            Ex::Call(Fun::Ln, a) => format!("log({})", self.py(a)),
            Ex::Call(Fun::Abs, a) => format!("Abs({})", self.py(a)),
            Ex::Call(f, a) => format!("{}({})", f.name(), self.py(a)),
            Ex::Atan2(y, x) => format!("atan2({}, {})", self.py(y), self.py(x)),
            Ex::Kinetic(b) => format!("KE('{}')", self.bodies[*b].0),
        }
    }

    /// A vector expression in Python (a 3 × 1 SymPy matrix).
    pub fn py_v(&self, v: &Vx) -> String {
        match v {
            Vx::Lit(c) => format!(
                "Matrix([{}, {}, {}])",
                self.py(&c[0]),
                self.py(&c[1]),
                self.py(&c[2])
            ),
            Vx::Let(i) => format!("L('{}')", self.lets[*i].0),
            Vx::Add(a, b) => format!("({} + {})", self.py_v(a), self.py_v(b)),
            Vx::Sub(a, b) => format!("({} - {})", self.py_v(a), self.py_v(b)),
            Vx::Scale(s, v) => format!("({}*{})", self.py(s), self.py_v(v)),
            Vx::Rot(r, v) => format!("({}*{})", self.py_r(r), self.py_v(v)),
        }
    }

    /// A rotation expression in Python (a 3 × 3 SymPy matrix).
    pub fn py_r(&self, r: &Rx) -> String {
        match r {
            Rx::Elem(k, a) => format!("{}({})", ["rot_x", "rot_y", "rot_z"][*k], self.py(a)),
            Rx::Let(i) => format!("L('{}')", self.lets[*i].0),
            Rx::Mul(a, b) => format!("({}*{})", self.py_r(a), self.py_r(b)),
            Rx::Transpose(a) => format!("({}).T", self.py_r(a)),
        }
    }
}
