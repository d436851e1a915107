//! Property tests of the symbolic engine on random expressions: the
//! canonical form evaluates like the expression it came from, derivatives
//! match central differences, and canonicalisation is idempotent.
use nh_core::sym::{Atom, Engine, ExprId, Fun, Rational, SymId};

struct Rng(u64);
impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// A random expression tree, kept alongside its canonical form.
#[derive(Debug)]
enum Tree {
    Var(usize),
    Num(i64, i64),
    Add(Box<Tree>, Box<Tree>),
    Sub(Box<Tree>, Box<Tree>),
    Mul(Box<Tree>, Box<Tree>),
    /// a / (1 + b²): never divides by zero
    DivSafe(Box<Tree>, Box<Tree>),
    Pow(Box<Tree>, u32),
    Sin(Box<Tree>),
    Cos(Box<Tree>),
    Tan(Box<Tree>),
    /// exp(a / 4)
    Exp(Box<Tree>),
    /// sqrt(1 + a²)
    Hypot(Box<Tree>),
    /// ln(2 + a²)
    Ln(Box<Tree>),
}

fn random_tree(rng: &mut Rng, depth: u32) -> Tree {
    if depth == 0 || rng.below(4) == 0 {
        return if rng.below(3) == 0 {
            Tree::Num(rng.below(7) as i64 - 3, 1 + rng.below(4) as i64)
        } else {
            Tree::Var(rng.below(3) as usize)
        };
    }
    let which = rng.below(12);
    let mut sub = || Box::new(random_tree(rng, depth - 1));
    match which {
        0 => Tree::Add(sub(), sub()),
        1 => Tree::Sub(sub(), sub()),
        2 | 3 => Tree::Mul(sub(), sub()),
        4 => Tree::DivSafe(sub(), sub()),
        5 => Tree::Pow(sub(), 1 + (rng.below(3) as u32)),
        6 => Tree::Sin(sub()),
        7 => Tree::Cos(sub()),
        8 => Tree::Tan(Box::new(Tree::Mul(
            Box::new(Tree::Num(1, 4)),
            Box::new(Tree::Sin(sub())),
        ))),
        9 => Tree::Exp(sub()),
        10 => Tree::Hypot(sub()),
        _ => Tree::Ln(sub()),
    }
}

fn eval_tree(t: &Tree, v: &[f64]) -> f64 {
    match t {
        Tree::Var(i) => v[*i],
        Tree::Num(n, d) => *n as f64 / *d as f64,
        Tree::Add(a, b) => eval_tree(a, v) + eval_tree(b, v),
        Tree::Sub(a, b) => eval_tree(a, v) - eval_tree(b, v),
        Tree::Mul(a, b) => eval_tree(a, v) * eval_tree(b, v),
        Tree::DivSafe(a, b) => eval_tree(a, v) / (1.0 + eval_tree(b, v).powi(2)),
        Tree::Pow(a, k) => eval_tree(a, v).powi(*k as i32),
        Tree::Sin(a) => eval_tree(a, v).sin(),
        Tree::Cos(a) => eval_tree(a, v).cos(),
        Tree::Tan(a) => eval_tree(a, v).tan(),
        Tree::Exp(a) => (eval_tree(a, v) / 4.0).exp(),
        Tree::Hypot(a) => (1.0 + eval_tree(a, v).powi(2)).sqrt(),
        Tree::Ln(a) => (2.0 + eval_tree(a, v).powi(2)).ln(),
    }
}

fn build(e: &mut Engine, t: &Tree, vars: &[SymId]) -> ExprId {
    let one = e.int(1);
    match t {
        Tree::Var(i) => e.sym(vars[*i]),
        Tree::Num(n, d) => e.constant(Rational::new(*n as i128, *d as i128).unwrap()),
        Tree::Add(a, b) => {
            let (a, b) = (build(e, a, vars), build(e, b, vars));
            e.add(a, b)
        }
        Tree::Sub(a, b) => {
            let (a, b) = (build(e, a, vars), build(e, b, vars));
            e.sub(a, b)
        }
        Tree::Mul(a, b) => {
            let (a, b) = (build(e, a, vars), build(e, b, vars));
            e.mul(a, b)
        }
        Tree::DivSafe(a, b) => {
            let (a, b) = (build(e, a, vars), build(e, b, vars));
            let b2 = e.mul(b, b);
            let den = e.add(one, b2);
            e.div(a, den)
        }
        Tree::Pow(a, k) => {
            let a = build(e, a, vars);
            e.pow(a, Rational::int(*k as i128))
        }
        Tree::Sin(a) => {
            let a = build(e, a, vars);
            e.func(Fun::Sin, a)
        }
        Tree::Cos(a) => {
            let a = build(e, a, vars);
            e.func(Fun::Cos, a)
        }
        Tree::Tan(a) => {
            let a = build(e, a, vars);
            e.func(Fun::Tan, a)
        }
        Tree::Exp(a) => {
            let a = build(e, a, vars);
            let a = e.scale(a, Rational::new(1, 4).unwrap());
            e.func(Fun::Exp, a)
        }
        Tree::Hypot(a) => {
            let a = build(e, a, vars);
            let a2 = e.mul(a, a);
            let s = e.add(one, a2);
            e.pow(s, Rational::new(1, 2).unwrap())
        }
        Tree::Ln(a) => {
            let a = build(e, a, vars);
            let a2 = e.mul(a, a);
            let two = e.int(2);
            let s = e.add(two, a2);
            e.func(Fun::Ln, s)
        }
    }
}

/// Rebuilds an expression from its canonical parts with the engine's own
/// operations; canonicalisation is idempotent if this returns the same id.
fn rebuild(e: &mut Engine, x: ExprId) -> ExprId {
    let terms = e.terms(x).to_vec();
    let mut parts = Vec::new();
    for (m, c) in terms {
        let mut t = e.constant(c);
        for (a, ex) in e.factors(m).to_vec() {
            let base = match e.atom(a).clone() {
                Atom::Sym(s) => e.sym(s),
                Atom::Func(f, u) => {
                    let u = rebuild(e, u);
                    e.func(f, u)
                }
                Atom::Base(b) => rebuild(e, b),
                Atom::Atan2(y, x) => {
                    let (y, x) = (rebuild(e, y), rebuild(e, x));
                    e.atan2(y, x)
                }
            };
            let p = e.pow(base, ex);
            t = e.mul(t, p);
        }
        parts.push(t);
    }
    e.sum(&parts)
}

fn scale(x: f64) -> f64 {
    x.abs().max(1.0)
}

#[test]
fn canonical_form_evaluates_like_the_tree() {
    let mut rng = Rng(0xDEAD_BEEF_CAFE_F00D);
    let mut checked = 0;
    for _ in 0..400 {
        let mut e = Engine::new();
        let vars = [e.symbol("x"), e.symbol("y"), e.symbol("z")];
        let tree = random_tree(&mut rng, 4);
        let x = build(&mut e, &tree, &vars);
        assert!(!e.overflowed());
        for _ in 0..5 {
            let v = [
                rng.uniform(-1.5, 1.5),
                rng.uniform(-1.5, 1.5),
                rng.uniform(-1.5, 1.5),
            ];
            let direct = eval_tree(&tree, &v);
            if !direct.is_finite() || direct.abs() > 1e8 {
                continue;
            }
            let canon = e.eval(x, &v);
            assert!(
                (canon - direct).abs() <= 1e-9 * scale(direct),
                "{tree:?}\ncanonical {} = {canon}, direct {direct}",
                e.display(x)
            );
            checked += 1;
        }
    }
    assert!(checked > 1500, "only {checked} points checked");
}

#[test]
fn derivatives_match_central_differences() {
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    let mut checked = 0;
    for _ in 0..300 {
        let mut e = Engine::new();
        let vars = [e.symbol("x"), e.symbol("y"), e.symbol("z")];
        let tree = random_tree(&mut rng, 3);
        let x = build(&mut e, &tree, &vars);
        let which = rng.below(3) as usize;
        let dx = e.diff(x, vars[which]);
        for _ in 0..3 {
            let v = [
                rng.uniform(-1.2, 1.2),
                rng.uniform(-1.2, 1.2),
                rng.uniform(-1.2, 1.2),
            ];
            let h = 1e-6;
            let (mut vp, mut vm) = (v, v);
            vp[which] += h;
            vm[which] -= h;
            let fd = (eval_tree(&tree, &vp) - eval_tree(&tree, &vm)) / (2.0 * h);
            if !fd.is_finite() || fd.abs() > 1e5 {
                continue;
            }
            let exact = e.eval(dx, &v);
            assert!(
                (exact - fd).abs() <= 1e-5 * scale(fd),
                "d/d{which} of {}: exact {exact}, central difference {fd}",
                e.display(x)
            );
            checked += 1;
        }
    }
    assert!(checked > 600, "only {checked} derivatives checked");
}

#[test]
fn canonicalisation_is_idempotent_and_hash_consed() {
    let mut rng = Rng(42);
    for _ in 0..300 {
        let mut e = Engine::new();
        let vars = [e.symbol("x"), e.symbol("y"), e.symbol("z")];
        let tree = random_tree(&mut rng, 4);
        let x = build(&mut e, &tree, &vars);
        let size = e.num_exprs();
        let again = build(&mut e, &tree, &vars);
        assert_eq!(x, again, "the same expression built twice is one node");
        assert_eq!(e.num_exprs(), size, "building it again stores nothing new");
        let r = rebuild(&mut e, x);
        assert_eq!(r, x, "not idempotent: {} vs {}", e.display(x), e.display(r));
    }
}

#[test]
fn memoised_derivatives_are_not_recomputed() {
    let mut e = Engine::new();
    let x = e.symbol("x");
    let xs = e.sym(x);
    let s = e.func(Fun::Sin, xs);
    let p = e.pow(s, Rational::int(5));
    let d1 = e.diff(p, x);
    let count = e.counters.derivatives;
    let d2 = e.diff(p, x);
    assert_eq!(d1, d2);
    assert_eq!(e.counters.derivatives, count);
}
