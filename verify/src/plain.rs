//! The plain derivation of a [`System`], numerically and independently of
//! the engine: the Lagrangian as the language defines it (a body's kinetic
//! energy ½ m|Ċ|² + ½ ω_bᵀIω_b with ω_b from RᵀṘ, `dot(X)` the total time
//! derivative), its Euler–Lagrange terms E = M q̈ + h − Q by hyper-dual
//! differentiation, every constraint as a velocity row g(q, q̇, t) = c q̇ + b
//! (a holonomic f as ḟ; a rolling contact as the height of its contact
//! point and the horizontal velocity of the material point there), and
//! the Lagrange–d'Alembert equations with the rows adjoined by
//! multipliers, M q̈ − cᵀμ = −h, c q̈ = −ċ q̇ − ḃ, solved as one linear
//! system. Nothing here knows the engine's routes, Kane's form, frames,
//! pivots or chosen rows.

mod declared;
mod momenta;

pub use declared::Direction;

use crate::Scalar;
use crate::jet::{Eps, Jet};
use crate::linalg::{self, Matrix};
use crate::model::{Body, Constraint, Ex, Fun, LetValue, Rx, System, Vx};

type V3<S> = [Jet<S>; 3];
type M3<S> = [[Jet<S>; 3]; 3];

/// The numbers a state is evaluated at.
#[derive(Clone, Debug)]
pub struct Point<S> {
    /// Parameter values.
    pub params: Vec<S>,
    /// Input values.
    pub inputs: Vec<S>,
    /// t.
    pub t: S,
    /// q.
    pub q: Vec<S>,
    /// The independent velocities ṙ (or the speeds u).
    pub v: Vec<S>,
}

/// The motion at a state by the plain derivation.
#[derive(Clone, Debug)]
pub struct Motion<S> {
    /// Every velocity q̇ (from the speeds' kinematics, or ṙ with ṡ solved).
    pub qdot: Vec<S>,
    /// The dependent velocities ṡ (constraints), in `DEPENDENT` order.
    pub sdot: Vec<S>,
    /// r̈ (or u̇ for a system in speeds).
    pub accelerations: Vec<S>,
    /// λ = E_s (5.10), in `DEPENDENT` order.
    pub multipliers: Vec<S>,
    /// Σ q̇ ∂L/∂q̇ − L.
    pub energy: S,
    /// ∂²L/∂q̇², n × n.
    pub mass: Matrix<S>,
    /// A with ṡ = −A ṙ − β (p × k), for constraints.
    pub constraint_matrix: Matrix<S>,
    /// The largest-to-smallest pivot ratio of the final solve.
    pub condition: f64,
    /// The Hadamard ratio |det c_s| / Π‖c_a‖ of the chart of dependent
    /// velocities the expansion chose (1 without constraints): how far the
    /// state is from that chart's singularity.
    pub chart: f64,
    /// The condition number of the reduced mass matrix Cᵀ M C (Sᵀ M S in
    /// speeds), which every route solves.
    pub reduced_condition: f64,
    /// The momentum ∂Lc/∂ṙ_k of every independent coordinate (5.35), in
    /// `INDEPENDENT` order (empty in speeds).
    pub momenta: Vec<S>,
    /// Their rates along the motion, for homogeneous, time-independent
    /// constraints (see `plain/momenta.rs`).
    pub momentum_rates: Vec<S>,
    /// For each independent coordinate, the larger of |∂Lc/∂r_k| and
    /// |∂Q_i/∂r_k|: zero where it is cyclic.
    pub cyclic_slopes: Vec<f64>,
    /// Every acceleration q̈ (empty for a system in speeds).
    pub qdd: Vec<S>,
}

/// Why the plain derivation has no answer at a state.
#[derive(Clone, Debug, PartialEq)]
pub enum Unsolvable {
    /// The constraints keep another number of independent rows than the
    /// expansion has dependent coordinates.
    RowCount {
        /// Independent rows found.
        rows: usize,
        /// Dependent coordinates of the expansion.
        dependent: usize,
    },
    /// Row `0` contradicts the rows before it.
    Contradiction(usize),
    /// A linear system is singular at this state.
    Singular(&'static str),
}

/// Where an expression is evaluated: every value a hyper-dual number.
#[derive(Clone)]
struct At<S> {
    q: Vec<Jet<S>>,
    qd: Vec<Jet<S>>,
    u: Vec<Jet<S>>,
    t: Jet<S>,
}

impl<S: Scalar> At<S> {
    fn constant(p: &[S]) -> Vec<Jet<S>> {
        p.iter().map(|&x| Jet::constant(x)).collect()
    }

    /// q + ε₃q̇, t + ε₃: an expression evaluated here carries its total
    /// time derivative in ε₃.
    fn moving(&self) -> At<S> {
        let q = (self.q.iter().zip(&self.qd)).map(|(q, v)| q.plus_eps(Eps::Three, v));
        At {
            q: q.collect(),
            qd: self.qd.clone(),
            u: self.u.clone(),
            t: self.t.plus_eps(Eps::Three, &Jet::constant(S::one())),
        }
    }
}

struct Eval<'a, S> {
    sys: &'a System,
    params: Vec<Jet<S>>,
    inputs: Vec<Jet<S>>,
}

impl<S: Scalar> Eval<'_, S> {
    fn ex(&self, e: &Ex, at: &At<S>) -> Jet<S> {
        match e {
            Ex::Num(p, q) => Jet::constant(S::from_f64(*p as f64) / S::from_f64(*q as f64)),
            Ex::Pi => Jet::constant(S::pi()),
            Ex::Param(i) => self.params[*i],
            Ex::Coord(i) => at.q[*i],
            Ex::Vel(i) => at.qd[*i],
            Ex::Speed(i) => at.u[*i],
            Ex::Input(i) => self.inputs[*i],
            Ex::Time => at.t,
            Ex::Let(i) => match &self.sys.lets[*i].1 {
                LetValue::Scalar(x) => self.ex(x, at),
                _ => panic!("a scalar `let` expected"),
            },
            Ex::DotLet(i) => match &self.sys.lets[*i].1 {
                LetValue::Scalar(x) => self.ex(x, &at.moving()).along(Eps::Three),
                _ => panic!("a scalar `let` expected"),
            },
            Ex::Comp(v, k) => self.vx(v, at)[*k],
            Ex::Add(v) => v
                .iter()
                .fold(Jet::constant(S::zero()), |a, x| a + self.ex(x, at)),
            Ex::Sub(a, b) => self.ex(a, at) - self.ex(b, at),
            Ex::Mul(v) => v
                .iter()
                .fold(Jet::constant(S::one()), |a, x| a * self.ex(x, at)),
            Ex::Neg(a) => -self.ex(a, at),
            Ex::Div(a, b) => self.ex(a, at) / self.ex(b, at),
            Ex::Pow(a, p, 1) => self.ex(a, at).powi(*p as i32),
            Ex::Pow(a, p, q) => self
                .ex(a, at)
                .powc(S::from_f64(*p as f64) / S::from_f64(*q as f64)),
            Ex::Call(f, a) => call(*f, self.ex(a, at)),
            Ex::Atan2(y, x) => self.ex(y, at).atan2(&self.ex(x, at)),
            Ex::Kinetic(b) => self.kinetic(&self.sys.bodies[*b].1, at),
        }
    }

    fn vx(&self, v: &Vx, at: &At<S>) -> V3<S> {
        match v {
            Vx::Lit(c) => [self.ex(&c[0], at), self.ex(&c[1], at), self.ex(&c[2], at)],
            Vx::Let(i) => match &self.sys.lets[*i].1 {
                LetValue::Vector(x) => self.vx(x, at),
                _ => panic!("a vector `let` expected"),
            },
            Vx::Add(a, b) => add3(self.vx(a, at), self.vx(b, at)),
            Vx::Sub(a, b) => sub3(self.vx(a, at), self.vx(b, at)),
            Vx::Scale(s, v) => {
                let s = self.ex(s, at);
                self.vx(v, at).map(|x| s * x)
            }
            Vx::Rot(r, v) => mat_vec(&self.rx(r, at), &self.vx(v, at)),
        }
    }

    fn rx(&self, r: &Rx, at: &At<S>) -> M3<S> {
        match r {
            Rx::Elem(k, a) => elementary(*k, self.ex(a, at)),
            Rx::Let(i) => match &self.sys.lets[*i].1 {
                LetValue::Rotation(x) => self.rx(x, at),
                _ => panic!("a rotation `let` expected"),
            },
            Rx::Mul(a, b) => mat_mat(&self.rx(a, at), &self.rx(b, at)),
            Rx::Transpose(a) => transpose(&self.rx(a, at)),
        }
    }

    /// A vector's value and total time derivative.
    fn vx_rate(&self, v: &Vx, at: &At<S>) -> (V3<S>, V3<S>) {
        let m = self.vx(v, &at.moving());
        (
            m.map(|x| x.without(Eps::Three)),
            m.map(|x| x.along(Eps::Three)),
        )
    }

    /// A rotation's value and total time derivative.
    fn rx_rate(&self, r: &Rx, at: &At<S>) -> (M3<S>, M3<S>) {
        let m = self.rx(r, &at.moving());
        (
            m.map(|row| row.map(|x| x.without(Eps::Three))),
            m.map(|row| row.map(|x| x.along(Eps::Three))),
        )
    }

    /// ½ m |Ċ|² + ½ ω_bᵀ I ω_b, ω_b the axial vector of RᵀṘ.
    fn kinetic(&self, b: &Body, at: &At<S>) -> Jet<S> {
        let half = Jet::constant(S::from_f64(0.5));
        let (_, cdot) = self.vx_rate(&b.centre, at);
        let mut t = half * self.ex(&b.mass, at) * dot3(&cdot, &cdot);
        if let Some((r, inertia)) = &b.rotation {
            let (rm, rdot) = self.rx_rate(r, at);
            let w = axial(&mat_mat(&transpose(&rm), &rdot));
            let i: M3<S> = [0, 1, 2].map(|r| [0, 1, 2].map(|c| self.ex(&inertia[r][c], at)));
            t = t + half * dot3(&w, &mat_vec(&i, &w));
        }
        t
    }

    /// The velocity rows g(q, q̇, t) of every constraint line, in order; a
    /// contact gives the rate of its contact point's height, then the x and
    /// y components of the material velocity at the contact point.
    fn rows(&self, at: &At<S>) -> Vec<Jet<S>> {
        let mut out = Vec::new();
        for c in &self.sys.constraints {
            match c {
                Constraint::Explicit { s, rhs } => out.push(at.qd[*s] - self.ex(rhs, at)),
                Constraint::Implicit { lhs, rhs } => out.push(self.ex(lhs, at) - self.ex(rhs, at)),
                Constraint::Holonomic { lhs, rhs } => {
                    let m = at.moving();
                    out.push((self.ex(lhs, &m) - self.ex(rhs, &m)).along(Eps::Three));
                }
                Constraint::Rolls { .. } => out.extend(self.contact_rows(c, at)),
            }
        }
        out
    }

    fn contact_rows(&self, c: &Constraint, at: &At<S>) -> [Jet<S>; 3] {
        let Constraint::Rolls {
            body,
            radius,
            axle,
            tube,
            centre,
        } = c
        else {
            unreachable!()
        };
        let b = &self.sys.bodies[*body].1;
        let Some((r, _)) = &b.rotation else {
            panic!("a rolling body has an orientation")
        };
        let centre = centre.as_ref().unwrap_or(&b.centre);
        // evaluated moving: value and rate of every part at once
        let m = at.moving();
        let g = self.vx(centre, &m);
        let rm = self.rx(r, &m);
        let (rv, rdot) = (
            rm.map(|row| row.map(|x| x.without(Eps::Three))),
            rm.map(|row| row.map(|x| x.along(Eps::Three))),
        );
        let radius = self.ex(radius, &m);
        let tube = tube
            .as_ref()
            .map_or(Jet::constant(S::zero()), |x| self.ex(x, &m));
        let ez = [
            Jet::constant(S::zero()),
            Jet::constant(S::zero()),
            Jet::constant(S::one()),
        ];
        let w = match axle {
            None => ez,
            Some(a) => {
                let a = a.map(|x| Jet::constant(S::from_f64(x as f64)));
                let len = dot3(&a, &a).sqrt();
                let n = mat_vec(&rm, &a).map(|x| x / len);
                let s = (Jet::constant(S::one()) - n[2] * n[2]).sqrt();
                [0, 1, 2].map(|i| (ez[i] - n[2] * n[i]) / s)
            }
        };
        // P − G = −r w − ρ e_z, as a function of the moving state
        let arm = [0, 1, 2].map(|i| -(radius * w[i]) - tube * ez[i]);
        let height = g[2] + arm[2];
        let omega = axial(&mat_mat(&rdot, &transpose(&rv)));
        let arm_now = arm.map(|x| x.without(Eps::Three));
        let vel = add3(g.map(|x| x.along(Eps::Three)), cross(&omega, &arm_now));
        [height.along(Eps::Three), vel[0], vel[1]]
    }
}

fn call<S: Scalar>(f: Fun, a: Jet<S>) -> Jet<S> {
    match f {
        Fun::Sin => a.sin(),
        Fun::Cos => a.cos(),
        Fun::Tan => {
            let (s, c) = a.sin_cos();
            s / c
        }
        Fun::Exp => a.exp(),
        Fun::Ln => a.ln(),
        Fun::Sqrt => a.sqrt(),
        Fun::Atan => a.atan(),
        Fun::Asin => a.asin(),
        Fun::Acos => a.acos(),
        Fun::Sinh => a.sinh(),
        Fun::Cosh => a.cosh(),
        Fun::Tanh => a.tanh(),
        Fun::Abs => a.abs(),
    }
}

fn elementary<S: Scalar>(k: usize, angle: Jet<S>) -> M3<S> {
    let (s, c) = angle.sin_cos();
    let (zero, one) = (Jet::constant(S::zero()), Jet::constant(S::one()));
    let mut m = [[zero; 3]; 3];
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    m[k][k] = one;
    m[i][i] = c;
    m[j][j] = c;
    m[i][j] = -s;
    m[j][i] = s;
    m
}

fn add3<S: Scalar>(a: V3<S>, b: V3<S>) -> V3<S> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub3<S: Scalar>(a: V3<S>, b: V3<S>) -> V3<S> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot3<S: Scalar>(a: &V3<S>, b: &V3<S>) -> Jet<S> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn mat_vec<S: Scalar>(m: &M3<S>, v: &V3<S>) -> V3<S> {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn mat_mat<S: Scalar>(a: &M3<S>, b: &M3<S>) -> M3<S> {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j]))
}

fn transpose<S: Scalar>(m: &M3<S>) -> M3<S> {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[j][i]))
}

/// The axial vector w of a skew matrix W (W v = w × v).
fn axial<S: Scalar>(w: &M3<S>) -> V3<S> {
    [w[2][1], w[0][2], w[1][0]]
}

/// The condition number of Cᵀ M C, C = [I; −A] in the rows of r and s.
fn reduced_condition<S: Scalar>(mass: &Matrix<S>, a: &Matrix<S>, dependent: &[usize]) -> f64 {
    let n = mass.len();
    let independent: Vec<usize> = (0..n).filter(|i| !dependent.contains(i)).collect();
    let k = independent.len();
    let mut c = vec![vec![S::zero(); k]; n];
    for (j, &r) in independent.iter().enumerate() {
        c[r][j] = S::one();
    }
    for (row, &s) in dependent.iter().enumerate() {
        for j in 0..k {
            c[s][j] = -a[row][j];
        }
    }
    let mc: Matrix<S> = (0..k)
        .map(|x| {
            (0..k)
                .map(|y| {
                    let mut acc = S::zero();
                    for i in 0..n {
                        for j in 0..n {
                            acc = acc + c[i][x] * mass[i][j] * c[j][y];
                        }
                    }
                    acc
                })
                .collect()
        })
        .collect();
    linalg::spd_condition(&mc)
}

/// The plain derivation of one system.
pub struct Plain<'a, S> {
    eval: Eval<'a, S>,
    n: usize,
}

impl<'a, S: Scalar> Plain<'a, S> {
    /// The system with the parameter and input values of `p`.
    pub fn new(sys: &'a System, p: &Point<S>) -> Self {
        Plain {
            eval: Eval {
                sys,
                params: At::constant(&p.params),
                inputs: At::constant(&p.inputs),
            },
            n: sys.coords.len(),
        }
    }

    fn at(&self, q: &[S], qd: &[S], u: &[S], t: S) -> At<S> {
        At {
            q: At::constant(q),
            qd: At::constant(qd),
            u: At::constant(u),
            t: Jet::constant(t),
        }
    }

    fn lagrangian(&self, at: &At<S>) -> Jet<S> {
        self.eval.ex(&self.eval.sys.lagrangian, at)
    }

    /// M = ∂²L/∂q̇² and h (E = M q̈ + h, forces included) at (q, q̇, t).
    fn euler_lagrange(&self, q: &[S], qd: &[S], u: &[S], t: S) -> (Matrix<S>, Vec<S>) {
        let n = self.n;
        let base = self.at(q, qd, u, t);
        let mut mass = vec![vec![S::zero(); n]; n];
        for i in 0..n {
            for j in i..n {
                let mut at = base.clone();
                at.qd[i] = at.qd[i].plus_eps(Eps::One, &Jet::constant(S::one()));
                at.qd[j] = at.qd[j].plus_eps(Eps::Two, &Jet::constant(S::one()));
                let m = self.lagrangian(&at).part(3);
                mass[i][j] = m;
                mass[j][i] = m;
            }
        }
        // Σ ∂²L/∂q̇_j∂q_i q̇_i + ∂²L/∂q̇_j∂t: ε₂ moves (q, t) along (q̇, 1)
        let mut moving = base.clone();
        for i in 0..n {
            moving.q[i] = moving.q[i].plus_eps(Eps::Two, &Jet::constant(qd[i]));
        }
        moving.t = moving.t.plus_eps(Eps::Two, &Jet::constant(S::one()));
        let forces = self.forces(&base);
        let bias = (0..n)
            .map(|j| {
                let mut at = moving.clone();
                at.qd[j] = at.qd[j].plus_eps(Eps::One, &Jet::constant(S::one()));
                let mixed = self.lagrangian(&at).part(3);
                let mut at = base.clone();
                at.q[j] = at.q[j].plus_eps(Eps::One, &Jet::constant(S::one()));
                let dq = self.lagrangian(&at).part(1);
                mixed - dq - forces[j]
            })
            .collect();
        (mass, bias)
    }

    fn forces(&self, at: &At<S>) -> Vec<S> {
        let mut q = vec![S::zero(); self.n];
        for (i, f) in &self.eval.sys.forces {
            q[*i] = q[*i] + self.eval.ex(f, at).value();
        }
        q
    }

    /// The rows' coefficients c (rows × n) and velocity-free parts b at (q, t).
    fn row_parts(&self, q: &[S], u: &[S], t: S) -> (Matrix<S>, Vec<S>) {
        let zero = vec![S::zero(); self.n];
        let base = self.at(q, &zero, u, t);
        let b: Vec<S> = self.eval.rows(&base).iter().map(|r| r.value()).collect();
        let mut c = vec![vec![S::zero(); self.n]; b.len()];
        for i in 0..self.n {
            let mut at = base.clone();
            at.qd[i] = Jet::seeded(S::zero(), Eps::One, S::one());
            for (a, r) in self.eval.rows(&at).iter().enumerate() {
                c[a][i] = r.part(1);
            }
        }
        (c, b)
    }

    /// ċ q̇ + ḃ: the rows' rates along the motion with q̇ held.
    fn row_rates(&self, q: &[S], qd: &[S], u: &[S], t: S) -> Vec<S> {
        let mut at = self.at(q, qd, u, t);
        for i in 0..self.n {
            at.q[i] = at.q[i].plus_eps(Eps::One, &Jet::constant(qd[i]));
        }
        at.t = at.t.plus_eps(Eps::One, &Jet::constant(S::one()));
        self.eval.rows(&at).iter().map(|r| r.part(1)).collect()
    }

    /// The energy Σ q̇ ∂L/∂q̇ − L.
    fn energy(&self, q: &[S], qd: &[S], u: &[S], t: S) -> S {
        let mut at = self.at(q, qd, u, t);
        for i in 0..self.n {
            at.qd[i] = at.qd[i].plus_eps(Eps::One, &Jet::constant(qd[i]));
        }
        let l = self.lagrangian(&at);
        l.part(1) - l.value()
    }

    /// The motion of a system with constraints at `p`, its dependent
    /// coordinates those of the expansion.
    pub fn motion(&self, p: &Point<S>, dependent: &[usize]) -> Result<Motion<S>, Unsolvable> {
        let n = self.n;
        let independent: Vec<usize> = (0..n).filter(|i| !dependent.contains(i)).collect();
        let (c, b) = self.row_parts(&p.q, &[], p.t);
        let aug: Matrix<S> = (c.iter().zip(&b))
            .map(|(r, &b)| r.iter().copied().chain([b]).collect())
            .collect();
        let kept = linalg::independent_rows(&aug, n, 1e-9).map_err(Unsolvable::Contradiction)?;
        if kept.len() != dependent.len() {
            return Err(Unsolvable::RowCount {
                rows: kept.len(),
                dependent: dependent.len(),
            });
        }
        let cs: Matrix<S> = kept
            .iter()
            .map(|&a| dependent.iter().map(|&s| c[a][s]).collect())
            .collect();
        let cr: Matrix<S> = kept
            .iter()
            .map(|&a| independent.iter().map(|&r| c[a][r]).collect())
            .collect();
        // ṡ = −c_s⁻¹ (c_r ṙ + b), A = c_s⁻¹ c_r
        let mut rhs: Matrix<S> = Vec::new();
        for (row, &a) in kept.iter().enumerate() {
            let known = (0..independent.len()).fold(b[a], |s, j| s + cr[row][j] * p.v[j]);
            rhs.push(
                std::iter::once(-known)
                    .chain(cr[row].iter().copied())
                    .collect(),
            );
        }
        let (sol, _) = linalg::solve(&cs, &rhs).ok_or(Unsolvable::Singular("c_s"))?;
        let hadamard = linalg::hadamard_ratio(&cs);
        let mut qd = vec![S::zero(); n];
        for (j, &r) in independent.iter().enumerate() {
            qd[r] = p.v[j];
        }
        for (a, &s) in dependent.iter().enumerate() {
            qd[s] = sol[a][0];
        }
        let a_matrix: Matrix<S> = sol.iter().map(|row| row[1..].to_vec()).collect();
        let (mass, bias) = self.euler_lagrange(&p.q, &qd, &[], p.t);
        let rates = self.row_rates(&p.q, &qd, &[], p.t);
        // [M  −cᵀ; c  0] [q̈; μ] = [−h; −d]
        let m = kept.len();
        let mut kkt = vec![vec![S::zero(); n + m]; n + m];
        let mut f = vec![vec![S::zero()]; n + m];
        for i in 0..n {
            kkt[i][..n].copy_from_slice(&mass[i]);
            for (row, &a) in kept.iter().enumerate() {
                kkt[i][n + row] = -c[a][i];
                kkt[n + row][i] = c[a][i];
            }
            f[i][0] = -bias[i];
        }
        for (row, &a) in kept.iter().enumerate() {
            f[n + row][0] = -rates[a];
        }
        let (x, condition) =
            linalg::solve(&kkt, &f).ok_or(Unsolvable::Singular("the equations of motion"))?;
        let qdd: Vec<S> = (0..n).map(|i| x[i][0]).collect();
        let reduced_condition = reduced_condition(&mass, &a_matrix, dependent);
        let e: Vec<S> = (0..n)
            .map(|j| (0..n).fold(bias[j], |s, i| s + mass[j][i] * qdd[i]))
            .collect();
        let chart = momenta::Chart {
            dependent,
            independent: &independent,
            kept: &kept,
            cs: &cs,
            a: &a_matrix,
        };
        let (momenta, momentum_rates) =
            (self.momenta(&p.q, &qd, p.t, &chart)).ok_or(Unsolvable::Singular("c_s"))?;
        let cyclic_slopes = self.cyclic_slopes(&p.q, &qd, p.t, &p.v, &chart);
        Ok(Motion {
            sdot: dependent.iter().map(|&s| qd[s]).collect(),
            accelerations: independent.iter().map(|&r| qdd[r]).collect(),
            multipliers: dependent.iter().map(|&s| e[s]).collect(),
            energy: self.energy(&p.q, &qd, &[], p.t),
            qdot: qd,
            mass,
            constraint_matrix: a_matrix,
            condition,
            chart: hadamard,
            reduced_condition,
            momenta,
            momentum_rates,
            cyclic_slopes,
            qdd,
        })
    }

    /// The motion of a system in speeds at `p` (`p.v` the speeds): q̇ = w,
    /// (Sᵀ M S) u̇ = −Sᵀ(h + M a), S = ∂w/∂u, a = Σ ∂w/∂q_j w_j + ∂w/∂t.
    pub fn speeds_motion(&self, p: &Point<S>) -> Result<Motion<S>, Unsolvable> {
        let n = self.n;
        let kin = &self
            .eval
            .sys
            .speeds
            .as_ref()
            .expect("a system in speeds")
            .kinematics;
        let k = p.v.len();
        let base = self.at(&p.q, &vec![S::zero(); n], &p.v, p.t);
        let w: Vec<S> = kin.iter().map(|x| self.eval.ex(x, &base).value()).collect();
        let mut s = vec![vec![S::zero(); k]; n];
        for a in 0..k {
            let mut at = base.clone();
            at.u[a] = at.u[a].plus_eps(Eps::One, &Jet::constant(S::one()));
            for i in 0..n {
                s[i][a] = self.eval.ex(&kin[i], &at).part(1);
            }
        }
        let mut at = base.clone();
        for i in 0..n {
            at.q[i] = at.q[i].plus_eps(Eps::One, &Jet::constant(w[i]));
        }
        at.t = at.t.plus_eps(Eps::One, &Jet::constant(S::one()));
        let acc: Vec<S> = kin.iter().map(|x| self.eval.ex(x, &at).part(1)).collect();
        let (mass, bias) = self.euler_lagrange(&p.q, &w, &p.v, p.t);
        let ma: Vec<S> = (0..n)
            .map(|i| (0..n).fold(bias[i], |s, j| s + mass[i][j] * acc[j]))
            .collect();
        let ms: Matrix<S> = (0..n)
            .map(|i| {
                (0..k)
                    .map(|a| (0..n).fold(S::zero(), |x, j| x + mass[i][j] * s[j][a]))
                    .collect()
            })
            .collect();
        let red: Matrix<S> = (0..k)
            .map(|a| {
                (0..k)
                    .map(|b| (0..n).fold(S::zero(), |x, i| x + s[i][a] * ms[i][b]))
                    .collect()
            })
            .collect();
        let f: Matrix<S> = (0..k)
            .map(|a| vec![-(0..n).fold(S::zero(), |x, i| x + s[i][a] * ma[i])])
            .collect();
        let (x, condition) = linalg::solve(&red, &f).ok_or(Unsolvable::Singular("Sᵀ M S"))?;
        Ok(Motion {
            sdot: Vec::new(),
            accelerations: x.iter().map(|r| r[0]).collect(),
            multipliers: Vec::new(),
            energy: self.energy(&p.q, &w, &p.v, p.t),
            qdot: w,
            mass: red.clone(),
            reduced_condition: linalg::spd_condition(&red),
            constraint_matrix: Vec::new(),
            condition,
            chart: 1.0,
            momenta: Vec::new(),
            momentum_rates: Vec::new(),
            cyclic_slopes: Vec::new(),
            qdd: Vec::new(),
        })
    }
}
