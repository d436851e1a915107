//! Differential tests of the generated code against the independent reference
//! data in `tests/data/refdata/` (SymPy + 40-digit mpmath; see the README there).
//!
//! The seven systems below are written exactly as a user would write them: the
//! Lagrangians are the `infix` strings of the JSON files pasted verbatim, the
//! constraints are `dot(s_a) = -sum_alpha A[a][alpha] * dot(r_alpha)` built
//! from the JSON's `A`, and the coordinates are declared in the JSON's `order`
//! (independent first, then dependent).
//!
//! Checked per system:
//! * `reference_states`: `dependent_velocities`, `accelerations`, `multipliers`,
//!   `curvature` (listed entries, antisymmetry, every other entry exactly 0),
//!   `energy`, `constraint_matrix` (`-A rdot = sdot`, entries vs the JSON infix),
//!   and the `OdeSystem` right-hand side, at all 20 states (1e-10 relative);
//! * `mass_matrix_matches_lagrangian`: `mass_matrix` vs the Hessian of the JSON
//!   Lagrangian in the velocities (evaluated with a small infix interpreter);
//! * `routes_agree`: multiplier route, curvature route and `accelerations`
//!   agree to 1e-12 at the reference states and at 200 random states;
//! * `euler_lagrange`: the generated r̈, s̈ (finite difference of
//!   `dependent_velocities` along the motion, also compared with the JSON
//!   `sddot`) and λ satisfy the unreduced Euler–Lagrange equations
//!   `EL(L) = Cᵀ λ`, `C = [A | I]`, with `EL(L)` built from the generated
//!   `mass_matrix` and the potential `V(q) = energy(q, 0)`;
//! * `metadata`: `COORDINATES`, `INDEPENDENT`, `DEPENDENT`, `N`, `K`, `P`,
//!   `STATE_DIM`, `INTEGRABLE` vs the JSON.
//!
//! Plus `f32_accelerations_*`: the same systems instantiated with `T = f32`.
use std::collections::HashMap;

use nonholonomic::prelude::*;
use serde_json::Value;

#[path = "common/refdata_json.rs"]
mod refdata_json;
use refdata_json::{arr, load, num, vector};

nonholonomic_system! {
    /// Rolling-disc model of the thesis (Lagrangian (6.22) verbatim).
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        lagrangian = m*(R^2*dot(phi)^2*(sin(psi)^2 + 1/4) + 5*R^2*dot(psi)^2/4 + R^2*dot(theta)^2/2 - 2*R*g*cos(psi) - 2*R*(dot(phi)*(dot(x)*cos(phi) + dot(y)*sin(phi))*sin(psi) + dot(psi)*(dot(x)*sin(phi) - dot(y)*cos(phi))*cos(psi)) + dot(x)^2 + dot(y)^2)/2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Chaplygin sled: knife edge at (x, y), heading theta, centre of mass a ahead.
    pub struct ChaplyginSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*((-a*dot(theta)*sin(theta) + dot(x))^2 + (a*dot(theta)*cos(theta) + dot(y))^2)/2;
        constraints {
            dot(y) = tan(theta)*dot(x);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Knife edge on an inclined plane (incline angle alpha).
    pub struct KnifeEdgeIncline {
        parameters { m, J, g, alpha }
        coordinates { x, phi, y }
        lagrangian = J*dot(phi)^2/2 + g*m*x*sin(alpha) + m*(dot(x)^2 + dot(y)^2)/2;
        constraints {
            dot(y) = tan(phi)*dot(x);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Random coupled system 01 (differential testing).
    pub struct Random01 {
        parameters { k1, k2 }
        coordinates { x, y, z, u, v }
        lagrangian = -k2*z^2*cos(z) + dot(u)^2*(k1*cos(u)^2/2 + 3/2) - dot(u)*dot(v)*cos(z)/3 - dot(u)*dot(x)*sin(u)/4 - dot(u)*dot(y)*cos(v)/4 - v^2/6 + dot(v)^2*(sin(y)*cos(v)/4 + 7/4) - dot(v)*dot(x)*cos(u)/2 - 2*dot(v)*dot(z)/5 + dot(x)^2*(y^2*z^2/4 + 2) + 2*dot(x)*dot(y)*sin(y)/5 + dot(y)^2*(sin(x)*cos(u)/4 + 11/4) - dot(y)*dot(z)*cos(v)*cos(x)/3 + dot(z)^2*(sin(x)^2/2 + 3/2);
        constraints {
            dot(u) = 2*v*sin(v)/3*dot(x) - (-3*x^2/2 - 3/2)*dot(y);
            dot(v) = 3*exp(y/3)/2*dot(x) - 1/3*dot(y);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Random coupled system 02 (differential testing).
    pub struct Random02 {
        parameters { k1, k2 }
        coordinates { th, ph, ps, a1 }
        lagrangian = dot(a1)^2*(k1*cos(ps)^2/2 + 5/4) - dot(a1)*dot(ph)/3 - dot(a1)*dot(ps)*sin(a1)/4 + 2*dot(a1)*dot(th)/5 + dot(ph)^2*(sin(ps)^2/2 + 7/4) - 2*dot(ph)*dot(ps)*cos(ps)*cos(th)/5 + ps*th/3 + dot(ps)^2*(k1*cos(ps)^2/2 + 5/4) - th^3/12 - th/4 + dot(th)^2*(k1*cos(ps)^2/2 + 7/4);
        constraints {
            dot(a1) = -(-ph^2 - 1)*dot(th);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Random coupled system 03 (differential testing).
    pub struct Random03 {
        parameters { k1, k2 }
        coordinates { xi, eta, q_1, q_2, r1, s1 }
        lagrangian = dot(eta)^2*(q_2^2/2 + 9/4) - dot(eta)*dot(q_1)/4 - dot(eta)*dot(q_2)*sin(r1)/3 - dot(eta)*dot(r1)/3 - dot(eta)*dot(s1)*cos(eta)*cos(s1)/3 - k2*cos(xi) + dot(q_1)^2*(sin(q_2)*cos(xi)/4 + 5/2) - 2*dot(q_1)*dot(q_2)/5 - 2*dot(q_1)*dot(s1)*cos(s1)*cos(xi)/5 - 2*q_2/5 + 7*dot(q_2)^2/4 - 2*dot(q_2)*dot(r1)*cos(eta)/5 + dot(q_2)*dot(xi)*sin(s1)*cos(eta)/4 + dot(r1)^2*(sin(q_1)^2/2 + 11/4) + 2*dot(r1)*dot(s1)/5 + 7*dot(s1)^2/4 + dot(s1)*dot(xi)*sin(eta)*cos(r1)/4 + dot(xi)^2*(q_2^2/2 + 7/4);
        constraints {
            dot(r1) = 3*s1^2/2*dot(xi) - 2*xi*cos(q_1)*dot(eta) - 1/3*dot(q_1);
            dot(s1) = -1/2*dot(xi) + 2*cos(r1)/3*dot(eta) - (-q_2^2 - 1)*dot(q_2);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

nonholonomic_system! {
    /// Random coupled system 04 (differential testing).
    pub struct Random04 {
        parameters { k1, k2 }
        coordinates { q1, q2, q3 }
        lagrangian = -k2*q1^2*cos(q2) - 2*q1*q2/5 + dot(q1)^2*(q1^4/4 + 3/2) + dot(q1)*dot(q3)*cos(q2)*cos(q3)/2 + dot(q2)^2*(k1*cos(q1)^2/2 + 2) - 2*dot(q2)*dot(q3)*cos(q1)/5 + dot(q3)^2*(q1^2/2 + 3/2);
        constraints {
            dot(q3) = 3*q2^2/2*dot(q1) - cos(q1)/2*dot(q2);
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

// ---------------------------------------------------------------------------
// Reference data access
// ---------------------------------------------------------------------------

fn strings(v: &Value) -> Vec<String> {
    arr(v)
        .iter()
        .map(|s| s.as_str().expect("string").to_owned())
        .collect()
}

fn index(v: &Value) -> usize {
    v.as_u64().expect("index") as usize
}

// ---------------------------------------------------------------------------
// Error bookkeeping
// ---------------------------------------------------------------------------

/// `|a - b| / max(1, |b|)`; infinite if either side is not finite.
fn rel(a: f64, b: f64) -> f64 {
    if a.is_finite() && b.is_finite() {
        (a - b).abs() / b.abs().max(1.0)
    } else {
        f64::INFINITY
    }
}

/// Maximum error per checked quantity, with its tolerance and where it occurred.
struct Errs {
    system: String,
    rows: Vec<(String, f64, f64, String)>,
}

impl Errs {
    fn new(system: &str) -> Self {
        Errs {
            system: system.to_owned(),
            rows: Vec::new(),
        }
    }

    fn record(&mut self, what: &str, tol: f64, err: f64, at: impl FnOnce() -> String) {
        let err = if err.is_nan() { f64::INFINITY } else { err };
        match self.rows.iter_mut().find(|r| r.0 == what) {
            Some(row) => {
                if err > row.1 {
                    row.1 = err;
                    row.3 = at();
                }
            }
            None => self.rows.push((what.to_owned(), err, tol, at())),
        }
    }

    /// Prints all maxima and fails if any exceeds its tolerance.
    fn finish(self) {
        let mut failed = Vec::new();
        for (what, err, tol, at) in &self.rows {
            let ok = err <= tol;
            println!(
                "{:<20} {:<44} max err {:>9.2e} (tol {:.0e}) {} {}",
                self.system,
                what,
                err,
                tol,
                if ok { "ok  " } else { "FAIL" },
                at
            );
            if !ok {
                failed.push(format!("{what}: {err:.3e} > {tol:.0e} at {at}"));
            }
        }
        assert!(
            !self.rows.is_empty(),
            "{}: nothing was checked",
            self.system
        );
        assert!(
            failed.is_empty(),
            "{}: tolerances exceeded:\n  {}",
            self.system,
            failed.join("\n  ")
        );
    }
}

// ---------------------------------------------------------------------------
// A small interpreter for the README's infix grammar (independent of the macro)
// ---------------------------------------------------------------------------

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Op(char),
}

fn tokenize(s: &str) -> Vec<Tok> {
    let c: Vec<char> = s.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        if ch.is_whitespace() {
            i += 1;
        } else if ch.is_ascii_digit() || ch == '.' {
            let start = i;
            while i < c.len() && (c[i].is_ascii_digit() || c[i] == '.') {
                i += 1;
            }
            let text: String = c[start..i].iter().collect();
            out.push(Tok::Num(text.parse().expect("number")));
        } else if ch.is_alphabetic() || ch == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(Tok::Name(c[start..i].iter().collect()));
        } else {
            assert!(
                "+-*/^()".contains(ch),
                "unexpected character {ch:?} in {s:?}"
            );
            out.push(Tok::Op(ch));
            i += 1;
        }
    }
    out
}

/// Values of the names (coordinates, parameters) and of the velocities `dot(q)`.
struct Env {
    names: HashMap<String, f64>,
    dots: HashMap<String, f64>,
}

struct Infix<'a> {
    toks: Vec<Tok>,
    pos: usize,
    env: &'a Env,
}

impl Infix<'_> {
    fn eval(src: &str, env: &Env) -> f64 {
        let mut p = Infix {
            toks: tokenize(src),
            pos: 0,
            env,
        };
        let v = p.expr();
        assert_eq!(p.pos, p.toks.len(), "trailing input in {src:?}");
        v
    }

    fn peek_op(&self, op: char) -> bool {
        self.toks.get(self.pos) == Some(&Tok::Op(op))
    }

    fn expect_op(&mut self, op: char) {
        assert!(self.peek_op(op), "expected {op:?} at token {}", self.pos);
        self.pos += 1;
    }

    fn expr(&mut self) -> f64 {
        let mut v = self.term();
        loop {
            if self.peek_op('+') {
                self.pos += 1;
                v += self.term();
            } else if self.peek_op('-') {
                self.pos += 1;
                v -= self.term();
            } else {
                return v;
            }
        }
    }

    fn term(&mut self) -> f64 {
        let mut v = self.unary();
        loop {
            if self.peek_op('*') {
                self.pos += 1;
                v *= self.unary();
            } else if self.peek_op('/') {
                self.pos += 1;
                v /= self.unary();
            } else {
                return v;
            }
        }
    }

    fn unary(&mut self) -> f64 {
        if self.peek_op('-') {
            self.pos += 1;
            -self.unary()
        } else {
            self.power()
        }
    }

    fn power(&mut self) -> f64 {
        let base = self.primary();
        if self.peek_op('^') {
            self.pos += 1;
            let e = self.unary();
            if e == e.round() && e.abs() < 64.0 {
                base.powi(e as i32)
            } else {
                base.powf(e)
            }
        } else {
            base
        }
    }

    fn primary(&mut self) -> f64 {
        let tok = self.toks[self.pos].clone();
        self.pos += 1;
        match tok {
            Tok::Num(x) => x,
            Tok::Op('(') => {
                let v = self.expr();
                self.expect_op(')');
                v
            }
            Tok::Name(name) if self.peek_op('(') => {
                self.pos += 1;
                if name == "dot" {
                    let Tok::Name(q) = self.toks[self.pos].clone() else {
                        panic!("dot() of a non-name")
                    };
                    self.pos += 1;
                    self.expect_op(')');
                    return *self
                        .env
                        .dots
                        .get(&q)
                        .unwrap_or_else(|| panic!("no velocity for {q}"));
                }
                let x = self.expr();
                self.expect_op(')');
                match name.as_str() {
                    "sin" => x.sin(),
                    "cos" => x.cos(),
                    "tan" => x.tan(),
                    "exp" => x.exp(),
                    "ln" => x.ln(),
                    "sqrt" => x.sqrt(),
                    f => panic!("unknown function {f}"),
                }
            }
            Tok::Name(name) => *self
                .env
                .names
                .get(&name)
                .unwrap_or_else(|| panic!("unknown name {name}")),
            Tok::Op(op) => panic!("unexpected {op:?}"),
        }
    }
}

#[test]
fn infix_interpreter_follows_the_readme_grammar() {
    let env = Env {
        names: [("x".to_owned(), 3.0), ("a".to_owned(), 2.0)].into(),
        dots: [("x".to_owned(), 5.0)].into(),
    };
    let e = |s: &str| Infix::eval(s, &env);
    assert_eq!(e("-x^2"), -9.0);
    assert_eq!(e("2^3^2"), 512.0);
    assert_eq!(e("1/4"), 0.25);
    assert_eq!(e("8/2/2"), 2.0);
    assert_eq!(e("a - x - 1"), -2.0);
    assert_eq!(e("(2/3)^(a)"), 4.0 / 9.0);
    assert_eq!(e("x^(-a)"), 1.0 / 9.0);
    assert_eq!(e("dot(x)^2/2 + a*dot(x)"), 22.5);
    assert_eq!(e("--x"), 3.0);
    assert!((e("sin(x)^2 + cos(x)^2") - 1.0).abs() < 1e-15);
}

// ---------------------------------------------------------------------------
// A uniform view of the generated systems
// ---------------------------------------------------------------------------

/// The generated API of one system (all outputs enabled), for generic checks.
trait Sys<const N: usize, const K: usize, const P: usize, const D: usize>: OdeSystem<f64, D> {
    /// Name of the reference data file.
    const FILE: &'static str;
    /// Bound on |q_i| for random states (tan(theta) systems stay below 1.2).
    const COORD_BOUND: f64;
    fn build(params: &Value) -> Self;
    fn coordinates() -> [&'static str; N];
    fn independent() -> [usize; K];
    fn dependent() -> [usize; P];
    /// `(N, K, P, STATE_DIM)` as generated.
    fn dims() -> (usize, usize, usize, usize);
    fn integrable() -> bool;
    fn sdot(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> SVector<f64, P>;
    fn rddot(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> SVector<f64, K>;
    fn rddot_multiplier(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> SVector<f64, K>;
    fn rddot_curvature(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> SVector<f64, K>;
    fn lambda(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> SVector<f64, P>;
    fn b(&self, q: &SVector<f64, N>) -> [SMatrix<f64, K, K>; P];
    fn e(&self, q: &SVector<f64, N>, rdot: &SVector<f64, K>) -> f64;
    fn a(&self, q: &SVector<f64, N>) -> SMatrix<f64, P, K>;
    fn m(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N>;
}

macro_rules! impl_sys {
    ($ty:ident, $file:literal, bound = $bound:literal,
     n = $n:literal, k = $k:literal, p = $p:literal, params = [$($param:ident),*]) => {
        impl Sys<$n, $k, $p, { $n + $k }> for $ty<f64> {
            const FILE: &'static str = $file;
            const COORD_BOUND: f64 = $bound;
            fn build(params: &Value) -> Self {
                $ty::new($(num(&params[stringify!($param)])),*)
            }
            fn coordinates() -> [&'static str; $n] {
                Self::COORDINATES
            }
            fn independent() -> [usize; $k] {
                Self::INDEPENDENT
            }
            fn dependent() -> [usize; $p] {
                Self::DEPENDENT
            }
            fn dims() -> (usize, usize, usize, usize) {
                (Self::N, Self::K, Self::P, Self::STATE_DIM)
            }
            fn integrable() -> bool {
                Self::INTEGRABLE
            }
            fn sdot(&self, q: &SVector<f64, $n>, rdot: &SVector<f64, $k>) -> SVector<f64, $p> {
                self.dependent_velocities(q, rdot)
            }
            fn rddot(&self, q: &SVector<f64, $n>, rdot: &SVector<f64, $k>) -> SVector<f64, $k> {
                self.accelerations(0.0, q, rdot)
            }
            fn rddot_multiplier(
                &self,
                q: &SVector<f64, $n>,
                rdot: &SVector<f64, $k>,
            ) -> SVector<f64, $k> {
                self.accelerations_multiplier_route(0.0, q, rdot)
            }
            fn rddot_curvature(
                &self,
                q: &SVector<f64, $n>,
                rdot: &SVector<f64, $k>,
            ) -> SVector<f64, $k> {
                self.accelerations_curvature_route(0.0, q, rdot)
            }
            fn lambda(&self, q: &SVector<f64, $n>, rdot: &SVector<f64, $k>) -> SVector<f64, $p> {
                self.multipliers(0.0, q, rdot)
            }
            fn b(&self, q: &SVector<f64, $n>) -> [SMatrix<f64, $k, $k>; $p] {
                self.curvature(q)
            }
            fn e(&self, q: &SVector<f64, $n>, rdot: &SVector<f64, $k>) -> f64 {
                self.energy(q, rdot)
            }
            fn a(&self, q: &SVector<f64, $n>) -> SMatrix<f64, $p, $k> {
                self.constraint_matrix(q)
            }
            fn m(&self, q: &SVector<f64, $n>) -> SMatrix<f64, $n, $n> {
                self.mass_matrix(q)
            }
        }
    };
}

impl_sys!(
    ThesisDisc,
    "thesis_disc",
    bound = 1.5,
    n = 5,
    k = 3,
    p = 2,
    params = [m, R, g]
);
impl_sys!(
    ChaplyginSled,
    "chaplygin_sled",
    bound = 1.15,
    n = 3,
    k = 2,
    p = 1,
    params = [m, J, a]
);
impl_sys!(
    KnifeEdgeIncline,
    "knife_edge_incline",
    bound = 1.15,
    n = 3,
    k = 2,
    p = 1,
    params = [m, J, g, alpha]
);
impl_sys!(
    Random01,
    "random_01",
    bound = 1.5,
    n = 5,
    k = 3,
    p = 2,
    params = [k1, k2]
);
impl_sys!(
    Random02,
    "random_02",
    bound = 1.5,
    n = 4,
    k = 3,
    p = 1,
    params = [k1, k2]
);
impl_sys!(
    Random03,
    "random_03",
    bound = 1.5,
    n = 6,
    k = 4,
    p = 2,
    params = [k1, k2]
);
impl_sys!(
    Random04,
    "random_04",
    bound = 1.5,
    n = 3,
    k = 2,
    p = 1,
    params = [k1, k2]
);

/// One reference state of the JSON.
struct State<const N: usize, const K: usize, const P: usize> {
    q: SVector<f64, N>,
    rdot: SVector<f64, K>,
    sdot: SVector<f64, P>,
    rddot: SVector<f64, K>,
    sddot: SVector<f64, P>,
    lambda: SVector<f64, P>,
    energy: f64,
    /// `(b, alpha, beta, value)` with `alpha < beta`.
    b: Vec<(usize, usize, usize, f64)>,
}

fn states<const N: usize, const K: usize, const P: usize>(data: &Value) -> Vec<State<N, K, P>> {
    let states: Vec<_> = arr(&data["states"])
        .iter()
        .map(|s| State {
            q: vector(&s["q"]),
            rdot: vector(&s["rdot"]),
            sdot: vector(&s["sdot"]),
            rddot: vector(&s["rddot"]),
            sddot: vector(&s["sddot"]),
            lambda: vector(&s["lambda"]),
            energy: num(&s["energy"]),
            b: arr(&s["B"])
                .iter()
                .map(|e| {
                    (
                        index(&e["b"]),
                        index(&e["alpha"]),
                        index(&e["beta"]),
                        num(&e["value"]),
                    )
                })
                .collect(),
        })
        .collect();
    assert_eq!(states.len(), 20, "20 reference states");
    states
}

/// Names (parameters and coordinates) and velocities of a state, for `Infix`.
fn env<const N: usize>(data: &Value, q: &SVector<f64, N>, qdot: &SVector<f64, N>) -> Env {
    let mut names: HashMap<String, f64> = data["parameters"]
        .as_object()
        .expect("parameters")
        .iter()
        .map(|(k, v)| (k.clone(), num(v)))
        .collect();
    let mut dots = HashMap::new();
    for (i, c) in strings(&data["coordinates"]["order"])
        .into_iter()
        .enumerate()
    {
        names.insert(c.clone(), q[i]);
        dots.insert(c, qdot[i]);
    }
    Env { names, dots }
}

/// Full velocity vector (in coordinate order) from the independent and dependent parts.
fn assemble<const N: usize, const K: usize, const P: usize>(
    ind: &[usize; K],
    dep: &[usize; P],
    r: &SVector<f64, K>,
    s: &SVector<f64, P>,
) -> SVector<f64, N> {
    let mut v = SVector::<f64, N>::zeros();
    for (a, &i) in ind.iter().enumerate() {
        v[i] = r[a];
    }
    for (a, &i) in dep.iter().enumerate() {
        v[i] = s[a];
    }
    v
}

/// xorshift64*: a small deterministic PRNG.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn random_states<S, const N: usize, const K: usize, const P: usize, const D: usize>(
    seed: u64,
    count: usize,
) -> Vec<(SVector<f64, N>, SVector<f64, K>)>
where
    S: Sys<N, K, P, D>,
{
    let mut rng = Rng(seed);
    let b = S::COORD_BOUND;
    (0..count)
        .map(|_| {
            let q = SVector::<f64, N>::from_fn(|_, _| rng.uniform(-b, b));
            let r = SVector::<f64, K>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
            (q, r)
        })
        .collect()
}

fn setup<S, const N: usize, const K: usize, const P: usize, const D: usize>() -> (Value, S)
where
    S: Sys<N, K, P, D>,
{
    let data = load(S::FILE);
    let sys = S::build(&data["parameters"]);
    (data, sys)
}

// ---------------------------------------------------------------------------
// The checks
// ---------------------------------------------------------------------------

const TOL: f64 = 1e-10;

fn check_reference_states<S, const N: usize, const K: usize, const P: usize, const D: usize>()
where
    S: Sys<N, K, P, D>,
{
    assert_eq!(D, N + K);
    let (data, sys) = setup::<S, N, K, P, D>();
    let (ind, dep) = (S::independent(), S::dependent());
    let a_infix: Vec<Vec<String>> = arr(&data["constraints"]["A"])
        .iter()
        .map(|row| {
            arr(row)
                .iter()
                .map(|e| e["infix"].as_str().expect("infix").to_owned())
                .collect()
        })
        .collect();
    let mut errs = Errs::new(S::FILE);
    for (i, st) in states::<N, K, P>(&data).iter().enumerate() {
        let at = || format!("state {i}");
        let (q, rdot) = (&st.q, &st.rdot);

        let sdot = sys.sdot(q, rdot);
        for a in 0..P {
            errs.record("dependent_velocities", TOL, rel(sdot[a], st.sdot[a]), at);
        }
        let rdd = sys.rddot(q, rdot);
        for a in 0..K {
            errs.record("accelerations", TOL, rel(rdd[a], st.rddot[a]), at);
        }
        let lam = sys.lambda(q, rdot);
        for a in 0..P {
            errs.record("multipliers", TOL, rel(lam[a], st.lambda[a]), at);
        }
        errs.record("energy", TOL, rel(sys.e(q, rdot), st.energy), at);

        // Constraint matrix: -A rdot = sdot, and each entry vs the JSON infix.
        let a_mat = sys.a(q);
        let minus_a_rdot = -(a_mat * rdot);
        for a in 0..P {
            errs.record(
                "-constraint_matrix*rdot vs sdot",
                TOL,
                rel(minus_a_rdot[a], st.sdot[a]),
                at,
            );
        }
        let env = env(&data, q, &SVector::<f64, N>::zeros());
        for (a, row) in a_infix.iter().enumerate() {
            for (al, src) in row.iter().enumerate() {
                if src == "0" {
                    errs.record(
                        "constraint_matrix zero entries (exact)",
                        0.0,
                        a_mat[(a, al)].abs(),
                        at,
                    );
                } else {
                    let want = Infix::eval(src, &env);
                    errs.record(
                        "constraint_matrix vs A infix",
                        TOL,
                        rel(a_mat[(a, al)], want),
                        at,
                    );
                }
            }
        }

        // Curvature: listed entries, antisymmetry, and exact zeros elsewhere.
        let b = sys.b(q);
        let mut listed = vec![[[false; K]; K]; P];
        for &(bb, al, be, value) in &st.b {
            assert!(al < be && bb < P && be < K, "{}: bad B index", S::FILE);
            listed[bb][al][be] = true;
            errs.record(
                "curvature listed entries",
                TOL,
                rel(b[bb][(al, be)], value),
                at,
            );
            errs.record(
                "curvature antisymmetry",
                TOL,
                rel(b[bb][(be, al)], -value),
                at,
            );
        }
        for (bb, mat) in b.iter().enumerate() {
            for al in 0..K {
                for be in 0..K {
                    if !listed[bb][al.min(be)][al.max(be)] || al == be {
                        errs.record(
                            "curvature unlisted entries (exact 0)",
                            0.0,
                            mat[(al, be)].abs(),
                            at,
                        );
                    }
                }
            }
        }

        // The OdeSystem right-hand side: [qdot (= [rdot, sdot] in order), rddot].
        let x = SVector::<f64, D>::from_fn(|j, _| if j < N { q[j] } else { rdot[j - N] });
        let xdot = sys.rhs(0.0, &x);
        let qdot_ref: SVector<f64, N> = assemble(&ind, &dep, rdot, &st.sdot);
        for j in 0..N {
            errs.record("rhs: qdot", TOL, rel(xdot[j], qdot_ref[j]), at);
        }
        for a in 0..K {
            errs.record("rhs: rddot", TOL, rel(xdot[N + a], st.rddot[a]), at);
        }
    }
    errs.finish();
}

/// `mass_matrix` vs the velocity Hessian of the JSON Lagrangian (which is
/// quadratic in the velocities, so polarisation is exact up to rounding), and
/// `energy` vs `(1/2) qdot^T M qdot + V` with `V = -L(q, 0)` from the JSON.
fn check_mass_matrix<S, const N: usize, const K: usize, const P: usize, const D: usize>()
where
    S: Sys<N, K, P, D>,
{
    let (data, sys) = setup::<S, N, K, P, D>();
    let lagrangian = data["lagrangian"]["infix"].as_str().expect("infix");
    let mut errs = Errs::new(S::FILE);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut points: Vec<SVector<f64, N>> = states::<N, K, P>(&data).iter().map(|s| s.q).collect();
    let bound = S::COORD_BOUND;
    points.extend((0..20).map(|_| SVector::<f64, N>::from_fn(|_, _| rng.uniform(-bound, bound))));
    for (i, q) in points.iter().enumerate() {
        let at = || format!("point {i}");
        let l = |v: SVector<f64, N>| Infix::eval(lagrangian, &env(&data, q, &v));
        let e = |i: usize| SVector::<f64, N>::from_fn(|j, _| if i == j { 1.0 } else { 0.0 });
        let m = sys.m(q);
        let l0 = l(SVector::zeros());
        for r in 0..N {
            for c in 0..N {
                let want = l(e(r) + e(c)) - l(e(r)) - l(e(c)) + l0;
                errs.record("mass_matrix vs Hessian of L", TOL, rel(m[(r, c)], want), at);
            }
        }
        // Potential: energy at zero velocity is V = -L(q, 0).
        errs.record(
            "energy(q, 0) vs -L(q, 0)",
            TOL,
            rel(sys.e(q, &SVector::zeros()), -l0),
            at,
        );
    }
    errs.finish();
}

fn check_routes<S, const N: usize, const K: usize, const P: usize, const D: usize>()
where
    S: Sys<N, K, P, D>,
{
    const ROUTE_TOL: f64 = 1e-12;
    let (data, sys) = setup::<S, N, K, P, D>();
    let mut errs = Errs::new(S::FILE);
    let mut points: Vec<_> = states::<N, K, P>(&data)
        .iter()
        .map(|s| (s.q, s.rdot))
        .collect();
    let n_ref = points.len();
    points.extend(random_states::<S, N, K, P, D>(0x5EED_0000_0000_0001, 200));
    for (i, (q, rdot)) in points.iter().enumerate() {
        let at = || {
            if i < n_ref {
                format!("reference state {i}")
            } else {
                format!(
                    "random state {}: q={:?} rdot={:?}",
                    i - n_ref,
                    q.as_slice(),
                    rdot.as_slice()
                )
            }
        };
        let acc = sys.rddot(q, rdot);
        let mult = sys.rddot_multiplier(q, rdot);
        let curv = sys.rddot_curvature(q, rdot);
        for a in 0..K {
            errs.record(
                "multiplier route vs curvature route",
                ROUTE_TOL,
                rel(mult[a], curv[a]),
                at,
            );
            errs.record(
                "accelerations vs multiplier route",
                ROUTE_TOL,
                rel(acc[a], mult[a]),
                at,
            );
            errs.record(
                "accelerations vs curvature route",
                ROUTE_TOL,
                rel(acc[a], curv[a]),
                at,
            );
        }
    }
    errs.finish();
}

/// The generated r̈, s̈ and λ satisfy `EL(L) = Cᵀλ`, `C = [A | I]`, where
/// `EL_j = (M q̈)_j + Σ_ik ∂_k M_ji q̇_k q̇_i − ½ q̇ᵀ ∂_j M q̇ + ∂_j V`, with
/// `∂M`, `∂V` by central differences of `mass_matrix` and of
/// `V(q) = energy(q, 0)`, and `s̈` by a central difference in time of
/// `dependent_velocities` along the motion (also compared with the JSON s̈).
fn check_euler_lagrange<S, const N: usize, const K: usize, const P: usize, const D: usize>()
where
    S: Sys<N, K, P, D>,
{
    const FD_TOL: f64 = 1e-6;
    let h = 1e-5;
    let (data, sys) = setup::<S, N, K, P, D>();
    let (ind, dep) = (S::independent(), S::dependent());
    let mut errs = Errs::new(S::FILE);
    let refs = states::<N, K, P>(&data);
    let mut points: Vec<_> = refs.iter().map(|s| (s.q, s.rdot)).collect();
    points.extend(random_states::<S, N, K, P, D>(0xE1E1_2345_6789_ABCD, 50));
    let unit = |k: usize| SVector::<f64, N>::from_fn(|j, _| if j == k { h } else { 0.0 });
    let potential = |q: &SVector<f64, N>| sys.e(q, &SVector::zeros());
    for (i, (q, rdot)) in points.iter().enumerate() {
        let at = || {
            format!(
                "{} state {i}",
                if i < refs.len() {
                    "reference"
                } else {
                    "random"
                }
            )
        };
        let sdot = sys.sdot(q, rdot);
        let rdd = sys.rddot(q, rdot);
        let lam = sys.lambda(q, rdot);
        let a_mat = sys.a(q);
        let qdot: SVector<f64, N> = assemble(&ind, &dep, rdot, &sdot);
        let sdd = (sys.sdot(&(q + qdot * h), &(rdot + rdd * h))
            - sys.sdot(&(q - qdot * h), &(rdot - rdd * h)))
            / (2.0 * h);
        if let Some(st) = refs.get(i) {
            for a in 0..P {
                errs.record(
                    "sddot (finite difference) vs JSON",
                    FD_TOL,
                    rel(sdd[a], st.sddot[a]),
                    at,
                );
            }
        }
        let qdd: SVector<f64, N> = assemble(&ind, &dep, &rdd, &sdd);
        let m = sys.m(q);
        let dm: Vec<SMatrix<f64, N, N>> = (0..N)
            .map(|k| (sys.m(&(q + unit(k))) - sys.m(&(q - unit(k)))) / (2.0 * h))
            .collect();
        let inertia = m * qdd;
        let mut mdot_qdot = SVector::<f64, N>::zeros();
        for (k, dmk) in dm.iter().enumerate() {
            mdot_qdot += dmk * qdot * qdot[k];
        }
        // Cᵀλ with C = [A | I].
        let mut c_t_lambda = SVector::<f64, N>::zeros();
        for (al, &j) in ind.iter().enumerate() {
            c_t_lambda[j] = (0..P).map(|a| a_mat[(a, al)] * lam[a]).sum();
        }
        for (a, &j) in dep.iter().enumerate() {
            c_t_lambda[j] = lam[a];
        }
        for j in 0..N {
            let quad = 0.5 * qdot.dot(&(dm[j] * qdot));
            let dv = (potential(&(q + unit(j))) - potential(&(q - unit(j)))) / (2.0 * h);
            let el = inertia[j] + mdot_qdot[j] - quad + dv;
            let scale = [1.0, inertia[j], mdot_qdot[j], quad, dv, c_t_lambda[j]]
                .iter()
                .fold(0.0f64, |s, x| s.max(x.abs()));
            errs.record(
                "EL(L) - C^T lambda (relative)",
                FD_TOL,
                (el - c_t_lambda[j]).abs() / scale,
                at,
            );
        }
    }
    errs.finish();
}

fn check_metadata<S, const N: usize, const K: usize, const P: usize, const D: usize>()
where
    S: Sys<N, K, P, D>,
{
    let data = load(S::FILE);
    let c = &data["coordinates"];
    let order = strings(&c["order"]);
    let pos = |name: &String| order.iter().position(|o| o == name).expect("in order");
    let independent: Vec<usize> = strings(&c["independent"]).iter().map(pos).collect();
    let dependent: Vec<usize> = strings(&c["dependent"]).iter().map(pos).collect();
    assert_eq!(S::coordinates().to_vec(), order, "{}: COORDINATES", S::FILE);
    assert_eq!(
        S::independent().to_vec(),
        independent,
        "{}: INDEPENDENT",
        S::FILE
    );
    assert_eq!(S::dependent().to_vec(), dependent, "{}: DEPENDENT", S::FILE);
    assert_eq!(
        S::dims(),
        (N, K, P, N + K),
        "{}: N, K, P, STATE_DIM",
        S::FILE
    );
    assert_eq!((N, K, P), (order.len(), independent.len(), dependent.len()));
    if let Some(h) = data.get("holonomic") {
        assert_eq!(h.as_bool(), Some(false), "{}: JSON holonomic", S::FILE);
    }
    assert!(
        !S::integrable(),
        "{}: INTEGRABLE must be false (nonzero curvature)",
        S::FILE
    );
    // The curvature entries' names agree with the generated index lists.
    for e in arr(&data["curvature_nonzero"]) {
        let names = strings(&e["names"]);
        let coords = S::coordinates();
        assert_eq!(names[0], coords[S::dependent()[index(&e["b"])]]);
        assert_eq!(names[1], coords[S::independent()[index(&e["alpha"])]]);
        assert_eq!(names[2], coords[S::independent()[index(&e["beta"])]]);
    }
    println!(
        "{:<20} COORDINATES {:?} INDEPENDENT {:?} DEPENDENT {:?} INTEGRABLE {}",
        S::FILE,
        S::coordinates(),
        S::independent(),
        S::dependent(),
        S::integrable()
    );
}

macro_rules! system_tests {
    ($module:ident, $ty:ident) => {
        mod $module {
            use super::*;

            #[test]
            fn reference_states() {
                check_reference_states::<$ty<f64>, _, _, _, _>();
            }

            #[test]
            fn mass_matrix_matches_lagrangian() {
                check_mass_matrix::<$ty<f64>, _, _, _, _>();
            }

            #[test]
            fn routes_agree() {
                check_routes::<$ty<f64>, _, _, _, _>();
            }

            #[test]
            fn euler_lagrange() {
                check_euler_lagrange::<$ty<f64>, _, _, _, _>();
            }

            #[test]
            fn metadata() {
                check_metadata::<$ty<f64>, _, _, _, _>();
            }
        }
    };
}

system_tests!(thesis_disc, ThesisDisc);
system_tests!(chaplygin_sled, ChaplyginSled);
system_tests!(knife_edge_incline, KnifeEdgeIncline);
system_tests!(random_01, Random01);
system_tests!(random_02, Random02);
system_tests!(random_03, Random03);
system_tests!(random_04, Random04);

// ---------------------------------------------------------------------------
// f32
// ---------------------------------------------------------------------------

fn check_f32<const N: usize, const K: usize>(
    file: &str,
    acc: impl Fn(&Value, &SVector<f32, N>, &SVector<f32, K>) -> SVector<f32, K>,
) {
    let data = load(file);
    let params = &data["parameters"];
    let mut errs = Errs::new(file);
    for (i, s) in arr(&data["states"]).iter().enumerate() {
        let q: SVector<f64, N> = vector(&s["q"]);
        let rdot: SVector<f64, K> = vector(&s["rdot"]);
        let want: SVector<f64, K> = vector(&s["rddot"]);
        let got = acc(params, &q.cast::<f32>(), &rdot.cast::<f32>());
        for a in 0..K {
            errs.record(
                "f32 accelerations",
                1e-4,
                rel(f64::from(got[a]), want[a]),
                || format!("state {i}"),
            );
        }
    }
    errs.finish();
}

fn p32(params: &Value, name: &str) -> f32 {
    num(&params[name]) as f32
}

#[test]
fn f32_accelerations_thesis_disc() {
    check_f32::<5, 3>("thesis_disc", |p, q, r| {
        ThesisDisc::<f32>::new(p32(p, "m"), p32(p, "R"), p32(p, "g")).accelerations(0.0, q, r)
    });
}

#[test]
fn f32_accelerations_random_03() {
    check_f32::<6, 4>("random_03", |p, q, r| {
        Random03::<f32>::new(p32(p, "k1"), p32(p, "k2")).accelerations(0.0, q, r)
    });
}
