//! Random well-formed systems in the language, reproducible from a seed.
//!
//! Four families, each built the way users write systems:
//! - `lagrangian`: a Lagrangian written out (sums of squares of velocity
//!   combinations with coefficients in q, gyroscopic and time-dependent
//!   terms, `dot(X)` of `let`s, potentials), with explicit, implicit,
//!   affine, time-dependent and holonomic constraints, inputs and forces;
//! - `bodies`: a tree of rigid bodies and point masses, each frame its
//!   parent's times elementary rotations (angles that are coordinates,
//!   sums of them, constant tilts, `w*t`, repeated axes; coordinates that
//!   constraints make dependent), centres fixed in a parent frame or moved
//!   by coordinates, constant, coordinate-dependent or time-dependent
//!   masses and general inertias, gravity, springs, the same constraints;
//! - `rolling`: discs, spheres, tori and axles of wheels in contact with
//!   the ground (`rolls(..)`), with consistent or free heights, offset
//!   centres of mass, riders, headings and chains;
//! - `speeds`: the same Lagrangians written in generalized speeds.
//!
//! Outputs are chosen among those the system admits.

use crate::model::{Body, Constraint, Ex, Fun, LetValue, Rx, Speeds, System, Vx};

/// SplitMix64: a small, well-mixed generator, the same on every platform.
#[derive(Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }

    /// Uniform in [a, b).
    pub fn uniform(&mut self, a: f64, b: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        a + (b - a) * u
    }

    /// One element of a slice.
    pub fn pick<T: Copy>(&mut self, v: &[T]) -> T {
        v[self.below(v.len())]
    }
}

fn num(p: i64, q: i64) -> Ex {
    Ex::Num(p, q)
}

fn add(v: Vec<Ex>) -> Ex {
    if v.len() == 1 {
        v.into_iter().next().unwrap_or(num(0, 1))
    } else {
        Ex::Add(v)
    }
}

fn mul(v: Vec<Ex>) -> Ex {
    if v.len() == 1 {
        v.into_iter().next().unwrap_or(num(1, 1))
    } else {
        Ex::Mul(v)
    }
}

fn call(f: Fun, a: Ex) -> Ex {
    Ex::Call(f, Box::new(a))
}

fn pow(a: Ex, p: i64) -> Ex {
    Ex::Pow(Box::new(a), p, 1)
}

fn lit(a: Ex, b: Ex, c: Ex) -> Vx {
    Vx::Lit(Box::new([a, b, c]))
}

fn rot(k: usize, a: Ex) -> Rx {
    Rx::Elem(k, Box::new(a))
}

fn rmul(a: Rx, b: Rx) -> Rx {
    Rx::Mul(Box::new(a), Box::new(b))
}

fn vrot(r: Rx, v: Vx) -> Vx {
    Vx::Rot(Box::new(r), Box::new(v))
}

fn vadd(a: Vx, b: Vx) -> Vx {
    Vx::Add(Box::new(a), Box::new(b))
}

/// The system under construction, with what the family decided.
struct Builder {
    rng: Rng,
    sys: System,
    /// Coordinates a constraint's `dot(s) = ..` already has on its left.
    explicit: Vec<usize>,
    /// Whether some constraint or kinematics depends on t.
    timed: bool,
    /// Whether some constraint is holonomic or affine.
    holonomic: bool,
    affine: bool,
    /// The world axis a family of bodies' weight acts along: z for half the
    /// seeds, y or x for a quarter each (the engine takes all three through
    /// the partial velocities), drawn from a sequence of its own so that the
    /// rest of every system is the one the seed gave before.
    weight_axis: usize,
    /// Whether a family of bodies is a chain of 3–5 rigid bodies, each hung
    /// from the last or now and then from an earlier one, its frames
    /// turning with the state alone (a quarter of the seeds, from a
    /// sequence of its own): the composite inertias of a tree's subtrees
    /// need several bodies on chains of frames, which the free trees
    /// rarely give.
    serial: bool,
    /// Whether a serial chain is one the articulated-body recursion
    /// solves (half the serial seeds, from a sequence of its own): its
    /// root joint fixed or sliding along one axis, each child's joint at
    /// its parent's end point, each body's centre and end point along its
    /// own axes, each angle a coordinate of its own (or a constant) with one
    /// at least per body, no two turns about one axis in a row, every other
    /// term free of velocities, no constraints: all of Cᵀ M C from the
    /// composite inertias of a tree.
    articulated: bool,
    /// The draw of `articulated`, taken by the bodies' family alone.
    tree_draw: bool,
}

/// The system of a seed.
pub fn system(seed: u64) -> System {
    let mut b = Builder::new(seed);
    match b.rng.below(20) {
        0..=5 => b.lagrangian_family(),
        6..=12 => b.bodies_family(),
        13..=16 => b.rolling_family(),
        _ => b.speeds_family(),
    }
    b.outputs();
    b.sys
}

impl Builder {
    fn new(seed: u64) -> Builder {
        let mut rng = Rng::new(seed);
        let np = 1 + rng.below(4);
        let sys = System {
            name: format!("Random{seed}"),
            params: (0..np).map(|i| format!("k{i}")).collect(),
            coords: Vec::new(),
            inputs: Vec::new(),
            lets: Vec::new(),
            bodies: Vec::new(),
            lagrangian: num(0, 1),
            forces: Vec::new(),
            constraints: Vec::new(),
            dependent: None,
            speeds: None,
            outputs: Vec::new(),
        };
        Builder {
            rng,
            sys,
            explicit: Vec::new(),
            timed: false,
            holonomic: false,
            affine: false,
            weight_axis: [2, 2, 1, 0][Rng::new(seed ^ 0x0A71_5EED_6A1A_0034).below(4)],
            serial: Rng::new(seed ^ 0x5E41_A1C4_A125_0035).below(4) == 0,
            articulated: false,
            tree_draw: Rng::new(seed ^ 0x7AEE_ABA0_0035_0001).below(2) == 0,
        }
    }

    fn coords(&mut self, n: usize) {
        let names = ["q", "a", "th", "z"];
        let stem = self.rng.pick(&names);
        self.sys.coords = (0..n).map(|i| format!("{stem}{i}")).collect();
    }

    fn param(&mut self) -> Ex {
        Ex::Param(self.rng.below(self.sys.params.len()))
    }

    fn coord(&mut self) -> usize {
        self.rng.below(self.sys.coords.len())
    }

    /// A positive constant: a parameter, a small rational or their product.
    fn positive(&mut self) -> Ex {
        match self.rng.below(4) {
            0 => num(1 + self.rng.below(3) as i64, 1 + self.rng.below(3) as i64),
            1 => mul(vec![num(1, 2), self.param()]),
            _ => self.param(),
        }
    }

    /// A small function of the coordinates (and sometimes t), regular on
    /// the states the checks use (|q| ≤ 1.2).
    fn coefficient(&mut self) -> Ex {
        let i = self.coord();
        let q = Ex::Coord(i);
        match self.rng.below(16) {
            0 => num(self.rng.below(5) as i64 - 2, 1 + self.rng.below(3) as i64),
            1 => self.param(),
            2 | 3 => call(Fun::Sin, q),
            4 | 5 => call(Fun::Cos, q),
            6 => q,
            7 => {
                let j = self.coord();
                mul(vec![
                    self.param(),
                    call(Fun::Cos, add(vec![q, Ex::Coord(j)])),
                ])
            }
            8 => add(vec![num(1, 1), mul(vec![num(1, 2), pow(q, 2)])]),
            9 => call(Fun::Exp, mul(vec![num(1, 3), q])),
            10 => call(Fun::Ln, add(vec![num(2, 1), pow(q, 2)])),
            11 => call(Fun::Sqrt, add(vec![num(1, 1), pow(q, 2)])),
            12 => call(Fun::Atan, q),
            13 => {
                let j = self.coord();
                mul(vec![q, Ex::Coord(j)])
            }
            14 => call(Fun::Cosh, mul(vec![num(1, 2), q])),
            _ => {
                self.timed = true;
                mul(vec![
                    self.param(),
                    call(Fun::Cos, mul(vec![self.param(), Ex::Time])),
                ])
            }
        }
    }

    /// A potential: springs, pendulum terms and couplings.
    fn potential(&mut self) -> Ex {
        let terms = 1 + self.rng.below(3);
        let mut v = Vec::new();
        for _ in 0..terms {
            let i = self.coord();
            let q = Ex::Coord(i);
            v.push(match self.rng.below(4) {
                0 => mul(vec![num(1, 2), self.param(), pow(q, 2)]),
                1 => mul(vec![self.param(), call(Fun::Cos, q)]),
                2 => {
                    let j = self.coord();
                    mul(vec![num(1, 5), q, Ex::Coord(j)])
                }
                _ => mul(vec![
                    self.param(),
                    call(Fun::Sin, q),
                    Ex::Coord(self.coord()),
                ]),
            });
        }
        add(v)
    }

    /// ½ c q̇ᵢ² for every coordinate in `which`.
    fn own_kinetic(&mut self, which: &[usize]) -> Vec<Ex> {
        which
            .iter()
            .map(|&i| mul(vec![num(1, 2), self.positive(), pow(Ex::Vel(i), 2)]))
            .collect()
    }

    fn lagrangian_family(&mut self) {
        let n = 1 + self.rng.below(6);
        self.coords(n);
        let mut t = self.own_kinetic(&(0..n).collect::<Vec<_>>());
        // squares of velocity combinations with coefficients in q
        for _ in 0..self.rng.below(3) {
            let mut combo = Vec::new();
            for i in 0..n {
                if self.rng.chance(0.5) {
                    combo.push(mul(vec![self.coefficient(), Ex::Vel(i)]));
                }
            }
            if !combo.is_empty() {
                t.push(mul(vec![num(1, 2), self.positive(), pow(add(combo), 2)]));
            }
        }
        // dot(X) of a position `let`, sometimes moving with t
        if self.rng.chance(0.4) {
            let mut x = vec![self.coefficient(), Ex::Coord(self.coord())];
            if self.rng.chance(0.3) {
                self.timed = true;
                x.push(mul(vec![self.param(), call(Fun::Sin, Ex::Time)]));
            }
            let l = self.sys.lets.len();
            self.sys
                .lets
                .push((format!("X{l}"), LetValue::Scalar(add(x))));
            t.push(mul(vec![num(1, 2), self.positive(), pow(Ex::DotLet(l), 2)]));
        }
        // a gyroscopic term, linear in a velocity
        if self.rng.chance(0.3) {
            let i = self.coord();
            t.push(mul(vec![self.coefficient(), Ex::Vel(i)]));
        }
        let v = self.potential();
        self.sys.lagrangian = Ex::Sub(Box::new(add(t)), Box::new(v));
        self.forces_and_inputs();
        let p = self.rng.below(n.min(5));
        self.constraints(p);
    }

    /// Forces on some coordinates: damping, inputs, time forcing.
    fn forces_and_inputs(&mut self) {
        if self.rng.chance(0.3) {
            let m = 1 + self.rng.below(2);
            self.sys.inputs = (0..m).map(|i| format!("u{i}")).collect();
        }
        for _ in 0..self.rng.below(3) {
            let i = self.coord();
            let f = match self.rng.below(4) {
                0 => mul(vec![num(-1, 1), self.param(), Ex::Vel(i)]),
                1 if !self.sys.inputs.is_empty() => {
                    let u = self.rng.below(self.sys.inputs.len());
                    mul(vec![Ex::Input(u), self.coefficient()])
                }
                2 => mul(vec![self.param(), call(Fun::Sin, Ex::Time)]),
                _ => mul(vec![num(-1, 4), Ex::Coord(i), Ex::Vel(self.coord())]),
            };
            match self.sys.forces.iter_mut().find(|(j, _)| *j == i) {
                Some((_, g)) => *g = add(vec![std::mem::take(g), f]),
                None => self.sys.forces.push((i, f)),
            }
        }
    }

    /// `p` constraints of random forms on the coordinates.
    fn constraints(&mut self, p: usize) {
        for _ in 0..p {
            match self.rng.below(10) {
                0..=4 => self.explicit_constraint(),
                5..=7 => self.implicit_constraint(),
                _ => self.holonomic_constraint(),
            }
        }
    }

    fn explicit_constraint(&mut self) {
        let n = self.sys.coords.len();
        let free: Vec<usize> = (0..n).filter(|i| !self.explicit.contains(i)).collect();
        if free.len() < 2 {
            return;
        }
        let s = free[self.rng.below(free.len())];
        let mut rhs = Vec::new();
        for i in 0..n {
            if i != s && self.rng.chance(0.5) {
                rhs.push(mul(vec![self.coefficient(), Ex::Vel(i)]));
            }
        }
        if rhs.is_empty() {
            let r = free.iter().copied().find(|&i| i != s).unwrap_or(0);
            rhs.push(mul(vec![self.coefficient(), Ex::Vel(r)]));
        }
        if self.rng.chance(0.2) {
            self.affine = true;
            rhs.push(self.coefficient());
        }
        self.explicit.push(s);
        self.sys
            .constraints
            .push(Constraint::Explicit { s, rhs: add(rhs) });
    }

    fn implicit_constraint(&mut self) {
        let n = self.sys.coords.len();
        let mut terms = Vec::new();
        for i in 0..n {
            if self.rng.chance(0.6) {
                terms.push(mul(vec![self.coefficient(), Ex::Vel(i)]));
            }
        }
        if terms.len() < 2 {
            let (i, j) = (self.coord(), self.coord());
            terms = vec![Ex::Vel(i), mul(vec![self.coefficient(), Ex::Vel(j)])];
        }
        if self.rng.chance(0.2) {
            self.affine = true;
            terms.push(self.coefficient());
        }
        // written as lhs = rhs with some terms moved across
        let split = self.rng.below(terms.len());
        let rhs: Vec<Ex> = terms
            .split_off(split)
            .into_iter()
            .map(|x| Ex::Neg(Box::new(x)))
            .collect();
        let lhs = if terms.is_empty() {
            num(0, 1)
        } else {
            add(terms)
        };
        let rhs = if rhs.is_empty() { num(0, 1) } else { add(rhs) };
        self.sys.constraints.push(Constraint::Implicit { lhs, rhs });
    }

    fn holonomic_constraint(&mut self) {
        self.holonomic = true;
        let (i, j) = (self.coord(), self.coord());
        let (qi, qj) = (Ex::Coord(i), Ex::Coord(j));
        let (lhs, rhs) = match self.rng.below(4) {
            0 => (qi, mul(vec![self.param(), call(Fun::Sin, qj)])),
            1 => (
                add(vec![call(Fun::Sin, qi), mul(vec![num(1, 3), qj])]),
                self.param(),
            ),
            2 => {
                self.timed = true;
                (qi, mul(vec![self.param(), call(Fun::Cos, Ex::Time)]))
            }
            _ => (add(vec![qi, pow(qj, 2)]), num(1, 2)),
        };
        self.sys
            .constraints
            .push(Constraint::Holonomic { lhs, rhs });
    }

    /// An angle of a frame's elementary rotation.
    fn angle(&mut self, own: &mut Vec<usize>) -> Ex {
        let n = self.sys.coords.len();
        let fresh = (0..n).find(|i| !own.contains(i));
        // a serial chain's frames turn with the state alone (a time in an
        // angle takes the bodies off Kane's form)
        let draw = match self.rng.below(10) {
            1 | 2 if self.serial => 9,
            x => x,
        };
        if self.articulated {
            return match (draw, fresh) {
                (_, None) | (0, _) => self.param(),
                (d, Some(i)) => {
                    own.push(i);
                    if d == 4 {
                        Ex::Neg(Box::new(Ex::Coord(i)))
                    } else {
                        Ex::Coord(i)
                    }
                }
            };
        }
        match (draw, fresh) {
            (0, _) => self.param(),
            (1, _) => {
                self.timed = true;
                mul(vec![self.param(), Ex::Time])
            }
            (2, Some(i)) => {
                own.push(i);
                add(vec![Ex::Coord(i), mul(vec![self.param(), Ex::Time])])
            }
            (3, _) => {
                let (i, j) = (self.coord(), self.coord());
                add(vec![Ex::Coord(i), Ex::Coord(j)])
            }
            (4, _) => Ex::Neg(Box::new(Ex::Coord(self.coord()))),
            (_, Some(i)) => {
                own.push(i);
                Ex::Coord(i)
            }
            (_, None) => Ex::Coord(self.coord()),
        }
    }

    /// A chain of 1–3 elementary rotations.
    fn chain(&mut self, own: &mut Vec<usize>) -> Rx {
        let before = own.len();
        let len = 1 + self.rng.below(3);
        let mut axis = self.rng.below(3);
        let mut r = rot(axis, self.angle(own));
        for _ in 1..len {
            let mut k = self.rng.below(3);
            // (turns about one axis in a row would move as one: singular)
            if self.articulated && k == axis {
                k = (k + 1 + self.rng.below(2)) % 3;
            }
            axis = k;
            let a = self.angle(own);
            r = rmul(r, rot(k, a));
        }
        // a tree's body turns with a coordinate of its own (else it would
        // be fixed to its parent, one body with it)
        let fresh = (0..self.sys.coords.len()).find(|i| !own.contains(i));
        if self.articulated
            && own.len() == before
            && let Some(i) = fresh
        {
            own.push(i);
            r = rmul(r, rot((axis + 1) % 3, Ex::Coord(i)));
        }
        r
    }

    fn small_vector(&mut self) -> Vx {
        let c = [0, 1, 2].map(|_| match self.rng.below(4) {
            0 => num(0, 1),
            1 => self.param(),
            2 => num(self.rng.below(5) as i64 - 2, 2),
            _ => mul(vec![num(1, 2), self.param()]),
        });
        let [a, b, c] = c;
        lit(a, b, c)
    }

    fn inertia(&mut self, spin_axis: Option<usize>) -> ([[Ex; 3]; 3], bool) {
        let mut i: [[Ex; 3]; 3] = Default::default();
        for (k, row) in i.iter_mut().enumerate() {
            row[k] = add(vec![num(1, 2), self.positive()]);
        }
        for a in 0..3 {
            for b in 0..3 {
                if a != b {
                    i[a][b] = num(0, 1);
                }
            }
        }
        if let Some(k) = spin_axis {
            // symmetric about the spin axis: the two others equal
            let (p, q) = ((k + 1) % 3, (k + 2) % 3);
            i[q][q] = i[p][p].clone();
            return (i, true);
        }
        if self.rng.chance(0.4) {
            let (a, b) = (self.rng.below(3), self.rng.below(3));
            if a != b {
                let off = mul(vec![num(1, 10), self.param()]);
                i[a][b] = off.clone();
                i[b][a] = off;
                return (i, false);
            }
        }
        (i, true)
    }

    /// Adds a body.
    fn body(
        &mut self,
        name: impl Into<String>,
        mass: Ex,
        centre: Vx,
        rotation: Option<(Rx, [[Ex; 3]; 3])>,
        diagonal: bool,
    ) {
        let body = Body {
            mass,
            centre,
            rotation,
            diagonal,
        };
        self.sys.bodies.push((name.into(), body));
    }

    fn let_of(&mut self, stem: &str, v: LetValue) -> usize {
        let l = self.sys.lets.len();
        self.sys.lets.push((format!("{stem}{l}"), v));
        l
    }

    fn bodies_family(&mut self) {
        let n = 2 + self.rng.below(5);
        self.coords(n);
        let count = match self.serial {
            true => 3 + self.rng.below(3),
            false => 1 + self.rng.below(4),
        };
        self.articulated = self.serial && self.tree_draw;
        let heading = match self.articulated {
            true => None,
            false => self.rng.chance(0.3).then(|| self.coord()),
        };
        let mut own: Vec<usize> = heading.into_iter().collect();
        // (rotation let, centre let) of each body
        let mut frames: Vec<(Option<usize>, usize)> = Vec::new();
        // (each body's end point, where a tree's children hang)
        let mut ends: Vec<usize> = Vec::new();
        let mut energy = Vec::new();
        let mut weight = Vec::new();
        for b in 0..count {
            if self.articulated && b > 0 && (0..n).all(|i| own.contains(&i)) {
                break;
            }
            let parent = match self.serial {
                // a branch off an earlier body now and then: a tree
                true if b >= 2 && self.rng.chance(0.3) => Some(self.rng.below(b - 1)),
                true => (b > 0).then(|| b - 1),
                false => (b > 0 && self.rng.chance(0.6)).then(|| self.rng.below(b)),
            };
            let rigid = self.rng.chance(0.8) || self.serial;
            let rotation = rigid.then(|| {
                let mut r = self.chain(&mut own);
                if let Some(h) = heading.filter(|_| parent.is_none()) {
                    r = rmul(rot(2, Ex::Coord(h)), r);
                }
                if let Some((Some(pr), _)) = parent.map(|p| frames[p]) {
                    r = rmul(Rx::Let(pr), r);
                }
                self.let_of("R", LetValue::Rotation(r))
            });
            let centre = match (parent, rotation) {
                (_, Some(r)) if self.articulated => {
                    // a joint at the root or at the parent's end point, the
                    // centre and the end point along the body's own axes
                    let joint = match parent {
                        Some(p) => Vx::Let(ends[p]),
                        None => {
                            let root = self.fixed_or_sliding_root(&mut own);
                            Vx::Let(self.let_of("P", LetValue::Vector(root)))
                        }
                    };
                    let (arm, reach) = (self.small_vector(), self.small_vector());
                    let end = vadd(joint.clone(), vrot(Rx::Let(r), reach));
                    ends.push(self.let_of("E", LetValue::Vector(end)));
                    vadd(joint, vrot(Rx::Let(r), arm))
                }
                (Some(p), _) => {
                    let (pr, pc) = frames[p];
                    let off = self.small_vector();
                    let arm = match (pr, rotation) {
                        (_, Some(r)) if self.rng.chance(0.4) => vrot(Rx::Let(r), off),
                        (Some(r), _) => vrot(Rx::Let(r), off),
                        _ => off,
                    };
                    vadd(Vx::Let(pc), arm)
                }
                (None, _) => {
                    let xs: Vec<Ex> = (0..3)
                        .map(|_| match self.rng.below(3) {
                            0 => Ex::Coord(self.coord()),
                            1 => self.coefficient(),
                            _ => num(0, 1),
                        })
                        .collect();
                    let mut xs = xs.into_iter();
                    let mut next = || xs.next().unwrap_or_default();
                    lit(next(), next(), next())
                }
            };
            let c = self.let_of("C", LetValue::Vector(centre));
            frames.push((rotation, c));
            let mass = match self.rng.below(12) {
                _ if self.articulated => self.positive(),
                0 => add(vec![
                    num(1, 1),
                    mul(vec![num(1, 2), pow(Ex::Coord(self.coord()), 2)]),
                ]),
                1 => {
                    self.timed = true;
                    add(vec![num(2, 1), call(Fun::Sin, Ex::Time)])
                }
                _ => self.positive(),
            };
            let rotation = rotation.map(|r| {
                let (i, diagonal) = self.inertia(None);
                (Rx::Let(r), i, diagonal)
            });
            let diagonal = rotation.as_ref().is_some_and(|r| r.2);
            self.body(
                format!("b{b}"),
                mass.clone(),
                Vx::Let(c),
                rotation.map(|(r, i, _)| (r, i)),
                diagonal,
            );
            energy.push(Ex::Kinetic(b));
            let axis = self.weight_axis;
            weight.push(mul(vec![mass, Ex::Comp(Box::new(Vx::Let(c)), axis)]));
        }
        // coordinates no body moves carry kinetic energy of their own, the
        // others sometimes
        let text = self.sys.text();
        // (a coordinate named in a `let` or a body's line moves a body)
        let lines: Vec<&str> = (text.lines())
            .filter(|l| l.contains("let ") || l.contains("body "))
            .collect();
        let moved = |name: &str| {
            lines.iter().any(|l| {
                l.split(|c: char| !c.is_alphanumeric() && c != '_')
                    .any(|w| w == name)
            })
        };
        let names = self.sys.coords.clone();
        let which: Vec<usize> = (0..n)
            .filter(|&i| !moved(&names[i]) || (!self.articulated && self.rng.chance(0.3)))
            .collect();
        energy.extend(self.own_kinetic(&which));
        let mut v = vec![];
        if self.rng.chance(0.7) {
            v.push(mul(vec![self.param(), add(weight)]));
        }
        if self.rng.chance(0.5) {
            v.push(self.potential());
        }
        let v = if v.is_empty() { num(0, 1) } else { add(v) };
        self.sys.lagrangian = Ex::Sub(Box::new(add(energy)), Box::new(v));
        self.forces_and_inputs();
        let p = self.rng.below(n.min(4));
        self.constraints(if self.articulated { 0 } else { p });
    }

    /// A root centre of constants, or sliding along one axis with a
    /// coordinate of its own.
    fn fixed_or_sliding_root(&mut self, own: &mut Vec<usize>) -> Vx {
        let fresh = (0..self.sys.coords.len()).find(|i| !own.contains(i));
        let Vx::Lit(mut xs) = self.small_vector() else {
            unreachable!("a literal")
        };
        if let Some(i) = fresh.filter(|_| self.rng.chance(0.3)) {
            own.push(i);
            xs[self.rng.below(3)] = Ex::Coord(i);
        }
        Vx::Lit(xs)
    }

    fn rolling_family(&mut self) {
        match self.rng.below(7) {
            0 | 1 => self.disc(),
            2 => self.sphere(),
            3 => self.axle(),
            4 => self.cart(),
            5 => self.two_rollers(),
            _ => self.disc_with_rider(),
        }
        self.forces_and_inputs();
        if self.rng.chance(0.3) {
            self.constraints(1);
        }
    }

    /// A disc or torus rolling on its rim: heading, lean, spin, contact x, y
    /// (and a free height or an offset centre of mass).
    fn disc(&mut self) {
        let free_height = self.rng.chance(0.25);
        self.holonomic |= free_height;
        let n = if free_height { 6 } else { 5 };
        self.coords(n);
        let (phi, psi, theta, x, y) = (0, 1, 2, 3, 4);
        let r = self.param();
        // the axle along body y (lean about x) or body x (lean about y)
        let (lean_axis, axle) = if self.rng.chance(0.5) { (0, 1) } else { (1, 0) };
        let lean = match lean_axis {
            0 => rot(0, Ex::Coord(psi)),
            _ => rot(1, Ex::Coord(psi)),
        };
        let f = self.let_of("F", LetValue::Rotation(rmul(rot(2, Ex::Coord(phi)), lean)));
        let tube = self
            .rng
            .chance(0.2)
            .then(|| mul(vec![num(1, 4), self.param()]));
        let up = vrot(Rx::Let(f), lit(num(0, 1), num(0, 1), num(1, 1)));
        let ground = match free_height {
            true => lit(Ex::Coord(x), Ex::Coord(y), Ex::Coord(5)),
            false => lit(Ex::Coord(x), Ex::Coord(y), num(0, 1)),
        };
        let mut centre = vadd(ground, Vx::Scale(Box::new(r.clone()), Box::new(up)));
        if let Some(t) = &tube {
            centre = vadd(centre, lit(num(0, 1), num(0, 1), t.clone()));
        }
        let g = self.let_of("G", LetValue::Vector(centre));
        let offset = self.rng.chance(0.25);
        let com = match offset {
            true => {
                let d = lit(num(0, 1), num(0, 1), mul(vec![num(1, 5), self.param()]));
                let c = vadd(Vx::Let(g), vrot(Rx::Let(f), d));
                self.let_of("C", LetValue::Vector(c))
            }
            false => g,
        };
        let (inertia, _) = self.inertia(Some(axle));
        let mass = self.positive();
        self.body(
            "disc",
            mass.clone(),
            Vx::Let(com),
            Some((rmul(Rx::Let(f), rot(axle, Ex::Coord(theta))), inertia)),
            true,
        );
        let mut a = [0, 0, 0];
        a[axle] = 1 + self.rng.below(2) as i64;
        self.sys.constraints.push(Constraint::Rolls {
            body: 0,
            radius: r,
            axle: Some(a),
            tube,
            centre: offset.then_some(Vx::Let(g)),
        });
        let mut t = vec![Ex::Kinetic(0)];
        if free_height {
            t.extend(self.own_kinetic(&[5]));
        }
        let weight = mul(vec![
            self.param(),
            mass,
            Ex::Comp(Box::new(Vx::Let(com)), 2),
        ]);
        self.sys.lagrangian = Ex::Sub(Box::new(add(t)), Box::new(weight));
    }

    /// A sphere with a general inertia, maybe an offset centre of mass.
    fn sphere(&mut self) {
        let n = 5;
        self.coords(n);
        let mut own = vec![3, 4];
        let order: [usize; 3] = match self.rng.below(3) {
            0 => [2, 1, 0],
            1 => [2, 0, 2],
            _ => [0, 1, 2],
        };
        let mut r = rot(order[0], Ex::Coord(0));
        own.push(0);
        for (k, &ax) in order.iter().enumerate().skip(1) {
            r = rmul(r, rot(ax, Ex::Coord(k)));
            own.push(k);
        }
        let rl = self.let_of("R", LetValue::Rotation(r));
        let radius = self.param();
        let g = lit(Ex::Coord(3), Ex::Coord(4), radius.clone());
        let g = self.let_of("G", LetValue::Vector(g));
        let offset = self.rng.chance(0.5);
        let com = match offset {
            true => {
                let d = self.small_vector();
                let c = vadd(Vx::Let(g), vrot(Rx::Let(rl), d));
                self.let_of("C", LetValue::Vector(c))
            }
            false => g,
        };
        let (inertia, diagonal) = self.inertia(None);
        let mass = self.positive();
        self.body(
            "ball",
            mass.clone(),
            Vx::Let(com),
            Some((Rx::Let(rl), inertia)),
            diagonal,
        );
        self.sys.constraints.push(Constraint::Rolls {
            body: 0,
            radius,
            axle: None,
            tube: None,
            centre: offset.then_some(Vx::Let(g)),
        });
        let weight = mul(vec![
            self.param(),
            mass,
            Ex::Comp(Box::new(Vx::Let(com)), 2),
        ]);
        self.sys.lagrangian = Ex::Sub(Box::new(Ex::Kinetic(0)), Box::new(weight));
    }

    /// Two wheels on one axle under a chassis (their sideways rows coincide).
    fn axle(&mut self) {
        self.coords(5);
        let (phi, t1, t2, x, y) = (0, 1, 2, 3, 4);
        let r = self.param();
        let h = self.let_of("H", LetValue::Rotation(rot(2, Ex::Coord(phi))));
        let hub = lit(Ex::Coord(x), Ex::Coord(y), r.clone());
        let hub = self.let_of("O", LetValue::Vector(hub));
        let mut energy = Vec::new();
        for (w, (theta, side)) in [(t1, 1), (t2, -1)].into_iter().enumerate() {
            let off = lit(num(0, 1), mul(vec![num(side, 1), self.param()]), num(0, 1));
            let c = vadd(Vx::Let(hub), vrot(Rx::Let(h), off));
            let c = self.let_of("W", LetValue::Vector(c));
            energy.push(self.wheel(w, c, Rx::Let(h), theta, &r));
        }
        let d = lit(mul(vec![num(1, 2), self.param()]), num(0, 1), num(0, 1));
        energy.push(self.chassis(hub, h, d));
        self.sys.lagrangian = add(energy);
    }

    /// Wheel `w` (the body of that index) at the centre `let` `c`, turning
    /// by `theta` about the y axis of `frame`, rolling on radius `r`: its
    /// kinetic energy.
    fn wheel(&mut self, w: usize, c: usize, frame: Rx, theta: usize, r: &Ex) -> Ex {
        let (inertia, _) = self.inertia(Some(1));
        let mass = self.positive();
        let orientation = rmul(frame, rot(1, Ex::Coord(theta)));
        self.body(
            format!("wheel{w}"),
            mass,
            Vx::Let(c),
            Some((orientation, inertia)),
            true,
        );
        self.sys.constraints.push(Constraint::Rolls {
            body: w,
            radius: r.clone(),
            axle: Some([0, 1, 0]),
            tube: None,
            centre: None,
        });
        Ex::Kinetic(w)
    }

    /// The chassis over the hub `let` `hub`, turned by the rotation `let`
    /// `h`, its centre at `d` in its frame: its kinetic energy.
    fn chassis(&mut self, hub: usize, h: usize, d: Vx) -> Ex {
        let centre = vadd(Vx::Let(hub), vrot(Rx::Let(h), d));
        let centre = self.let_of("K", LetValue::Vector(centre));
        let (inertia, diagonal) = self.inertia(None);
        let mass = self.positive();
        let index = self.sys.bodies.len();
        self.body(
            "chassis",
            mass,
            Vx::Let(centre),
            Some((Rx::Let(h), inertia)),
            diagonal,
        );
        Ex::Kinetic(index)
    }

    /// A cart: a chassis turning with φ on two wheels on a rear axle and a
    /// front wheel steered by δ (a second `rot_z` after the heading), with
    /// the contact point (x, y) of the axle's middle: five rows, one implied,
    /// solved as a block whose planar pair is (x, y).
    fn cart(&mut self) {
        self.coords(7);
        let (phi, t1, t2, tf, delta, x, y) = (0, 1, 2, 3, 4, 5, 6);
        let r = self.param();
        let h = self.let_of("H", LetValue::Rotation(rot(2, Ex::Coord(phi))));
        let hub = self.let_of(
            "O",
            LetValue::Vector(lit(Ex::Coord(x), Ex::Coord(y), r.clone())),
        );
        let mut energy = Vec::new();
        let wheels = [(t1, Some(1)), (t2, Some(-1)), (tf, None)];
        for (w, (theta, side)) in wheels.into_iter().enumerate() {
            let (frame, off) = match side {
                Some(side) => (
                    Rx::Let(h),
                    lit(num(0, 1), mul(vec![num(side, 1), self.param()]), num(0, 1)),
                ),
                None => {
                    let f = rmul(Rx::Let(h), rot(2, Ex::Coord(delta)));
                    (f, lit(self.param(), num(0, 1), num(0, 1)))
                }
            };
            let c = self.let_of(
                "W",
                LetValue::Vector(vadd(Vx::Let(hub), vrot(Rx::Let(h), off))),
            );
            energy.push(self.wheel(w, c, frame, theta, &r));
        }
        let d = lit(mul(vec![num(1, 2), self.param()]), num(0, 1), num(1, 5));
        energy.push(self.chassis(hub, h, d));
        energy.extend(self.own_kinetic(&[delta]));
        self.sys.lagrangian = add(energy);
    }

    /// A disc and a ball rolling apart, tied by a spring between their
    /// centres: four rows solved as a block.
    fn two_rollers(&mut self) {
        self.coords(10);
        let (phi, psi, theta, x1, y1) = (0, 1, 2, 3, 4);
        let (a, b, c, x2, y2) = (5, 6, 7, 8, 9);
        let r = self.param();
        let f = self.let_of(
            "F",
            LetValue::Rotation(rmul(rot(2, Ex::Coord(phi)), rot(0, Ex::Coord(psi)))),
        );
        let up = vrot(Rx::Let(f), lit(num(0, 1), num(0, 1), num(1, 1)));
        let g1 = vadd(
            lit(Ex::Coord(x1), Ex::Coord(y1), num(0, 1)),
            Vx::Scale(Box::new(r.clone()), Box::new(up)),
        );
        let g1 = self.let_of("G", LetValue::Vector(g1));
        let (inertia, _) = self.inertia(Some(1));
        let m1 = self.positive();
        self.body(
            "disc",
            m1,
            Vx::Let(g1),
            Some((rmul(Rx::Let(f), rot(1, Ex::Coord(theta))), inertia)),
            true,
        );
        let rb = self.param();
        let q = rmul(
            rmul(rot(2, Ex::Coord(a)), rot(1, Ex::Coord(b))),
            rot(0, Ex::Coord(c)),
        );
        let q = self.let_of("Q", LetValue::Rotation(q));
        let g2 = self.let_of(
            "B",
            LetValue::Vector(lit(Ex::Coord(x2), Ex::Coord(y2), rb.clone())),
        );
        let (inertia, diagonal) = self.inertia(None);
        let m2 = self.positive();
        self.body(
            "ball",
            m2,
            Vx::Let(g2),
            Some((Rx::Let(q), inertia)),
            diagonal,
        );
        self.sys.constraints.push(Constraint::Rolls {
            body: 0,
            radius: r,
            axle: Some([0, 1, 0]),
            tube: None,
            centre: None,
        });
        self.sys.constraints.push(Constraint::Rolls {
            body: 1,
            radius: rb,
            axle: None,
            tube: None,
            centre: None,
        });
        let dx = Ex::Sub(Box::new(Ex::Coord(x1)), Box::new(Ex::Coord(x2)));
        let dy = Ex::Sub(Box::new(Ex::Coord(y1)), Box::new(Ex::Coord(y2)));
        let spring = mul(vec![
            num(1, 2),
            self.param(),
            add(vec![pow(dx, 2), pow(dy, 2)]),
        ]);
        let g = self.param();
        let weight = mul(vec![g, Ex::Comp(Box::new(Vx::Let(g1)), 2)]);
        self.sys.lagrangian = Ex::Sub(
            Box::new(add(vec![Ex::Kinetic(0), Ex::Kinetic(1)])),
            Box::new(add(vec![spring, weight])),
        );
    }

    /// A disc with a pendulum rider hinged at its centre.
    fn disc_with_rider(&mut self) {
        self.disc();
        let n = self.sys.coords.len();
        let stem: String = self.sys.coords[0]
            .chars()
            .filter(|c| c.is_alphabetic())
            .collect();
        self.sys.coords.push(format!("{stem}{n}"));
        let f = (self.sys.lets.iter())
            .position(|(name, _)| name.starts_with('F'))
            .unwrap_or(0);
        let g = (self.sys.lets.iter())
            .position(|(name, _)| name.starts_with('G'))
            .unwrap_or(0);
        let arm = rmul(Rx::Let(f), rot(self.rng.below(3), Ex::Coord(n)));
        let arm = self.let_of("P", LetValue::Rotation(arm));
        let tip = lit(num(0, 1), num(0, 1), self.param());
        let c = self.let_of(
            "E",
            LetValue::Vector(vadd(Vx::Let(g), vrot(Rx::Let(arm), tip))),
        );
        let (inertia, diagonal) = self.inertia(None);
        let mass = self.positive();
        self.body(
            "rider",
            mass.clone(),
            Vx::Let(c),
            Some((Rx::Let(arm), inertia)),
            diagonal,
        );
        let weight = mul(vec![self.param(), mass, Ex::Comp(Box::new(Vx::Let(c)), 2)]);
        let l = std::mem::replace(&mut self.sys.lagrangian, num(0, 1));
        self.sys.lagrangian = Ex::Sub(Box::new(add(vec![l, Ex::Kinetic(1)])), Box::new(weight));
    }

    fn speeds_family(&mut self) {
        let n = 2 + self.rng.below(4);
        self.coords(n);
        let k = 1 + self.rng.below(n - 1);
        let names = (0..k).map(|a| format!("w{a}")).collect();
        // the first k coordinates move with their own speed (full rank)
        let mut kin = Vec::new();
        for i in 0..n {
            let mut w = Vec::new();
            if i < k {
                w.push(mul(vec![self.positive(), Ex::Speed(i)]));
            }
            for a in 0..k {
                if a != i && self.rng.chance(0.4) {
                    w.push(mul(vec![self.coefficient(), Ex::Speed(a)]));
                }
            }
            if self.rng.chance(0.15) {
                w.push(self.coefficient());
            }
            if w.is_empty() {
                w.push(mul(vec![self.coefficient(), Ex::Speed(self.rng.below(k))]));
            }
            kin.push(add(w));
        }
        let mut t = self.own_kinetic(&(0..n).collect::<Vec<_>>());
        if self.rng.chance(0.5) {
            let (i, j) = (self.coord(), self.coord());
            let c = self.coefficient();
            t.push(mul(vec![num(1, 4), c, Ex::Vel(i), Ex::Vel(j)]));
        }
        let v = self.potential();
        self.sys.lagrangian = Ex::Sub(Box::new(add(t)), Box::new(v));
        self.sys.speeds = Some(Speeds {
            names,
            kinematics: kin,
        });
        self.forces_and_inputs();
    }

    /// Outputs the system admits, chosen at random.
    fn outputs(&mut self) {
        let mut out = Vec::new();
        let speeds = self.sys.speeds.is_some();
        let time_free_rows = !self.sys.timed_rows();
        let time_free = !self.sys.timed(&self.sys.lagrangian) && time_free_rows;
        if !speeds && !self.sys.constraints.is_empty() && self.rng.chance(0.4) {
            out.push("multipliers");
        }
        if time_free && self.rng.chance(0.2) {
            out.push("energy");
        }
        if time_free && self.rng.chance(0.15) {
            out.push("mass_matrix");
        }
        if !speeds && time_free_rows && !self.sys.constraints.is_empty() && self.rng.chance(0.1) {
            out.push("constraint_matrix");
        }
        let homogeneous = !self.affine && !self.holonomic && time_free_rows;
        if !speeds && homogeneous && !self.sys.constraints.is_empty() && self.rng.chance(0.1) {
            out.push("routes");
        }
        self.sys.outputs = out;
    }
}
