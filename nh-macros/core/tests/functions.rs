//! The engine's functions beyond sin, cos, tan, exp and ln (`abs`, `cot`,
//! `sec`, `csc`, `sinh`, `cosh`, `tanh`, `asin`, `acos`, `atan`, `atan2`):
//! canonical forms, exact values, derivatives (against closed forms and
//! central differences) and evaluation in `f64` and double-double.
use nh_core::sym::dd::Dd;
use nh_core::sym::{Engine, ExprId, Fun, ONE, Rational, SymId, ZERO, exact_atan2, exact_value};

fn q(n: i128, d: i128) -> Rational {
    Rational::new(n, d).unwrap()
}

/// An engine with symbols x and y.
fn engine_xy() -> (Engine, SymId, SymId, ExprId, ExprId) {
    let mut e = Engine::new();
    let x = e.symbol("x");
    let y = e.symbol("y");
    let (xs, ys) = (e.sym(x), e.sym(y));
    (e, x, y, xs, ys)
}

const UNARY: [Fun; 11] = [
    Fun::Abs,
    Fun::Cot,
    Fun::Sec,
    Fun::Csc,
    Fun::Sinh,
    Fun::Cosh,
    Fun::Tanh,
    Fun::Asin,
    Fun::Acos,
    Fun::Atan,
    Fun::Sign,
];

/// The reference value of `f(v)` from the standard library.
fn reference(f: Fun, v: f64) -> f64 {
    match f {
        Fun::Abs => v.abs(),
        Fun::Cot => 1.0 / v.tan(),
        Fun::Sec => 1.0 / v.cos(),
        Fun::Csc => 1.0 / v.sin(),
        Fun::Sinh => v.sinh(),
        Fun::Cosh => v.cosh(),
        Fun::Tanh => v.tanh(),
        Fun::Asin => v.asin(),
        Fun::Acos => v.acos(),
        Fun::Atan => v.atan(),
        Fun::Sign => {
            if v == 0.0 {
                0.0
            } else {
                v.signum()
            }
        }
        _ => unreachable!(),
    }
}

#[test]
fn values_match_the_standard_library_in_f64_and_double_double() {
    let (mut e, x, _, xs, _) = engine_xy();
    // an argument that is a sum, so no rewriting makes it trivial
    let half = e.constant(q(1, 7));
    let arg = e.add(xs, half);
    for f in UNARY {
        let fx = e.func(f, arg);
        for v in [-0.6, -0.3, 0.2, 0.7] {
            let mut vals = vec![0.0; e.num_symbols()];
            vals[x.index()] = v;
            let want = reference(f, v + 1.0 / 7.0);
            let got = e.eval(fx, &vals);
            assert!(
                (got - want).abs() <= 1e-14 * want.abs().max(1.0),
                "{f:?} at {v}: {got} vs {want}"
            );
            let dvals: Vec<Dd> = vals.iter().map(|&a| Dd::from_f64(a)).collect();
            let got_dd = e.eval(fx, &dvals).to_f64();
            assert!(
                (got_dd - want).abs() <= 1e-14 * want.abs().max(1.0),
                "{f:?} (double-double) at {v}: {got_dd} vs {want}"
            );
        }
    }
    let at = e.atan2(arg, xs);
    for (v, w) in [
        (0.5, 0.5 + 1.0 / 7.0),
        (-0.5, -0.5 + 1.0 / 7.0),
        (-0.1, -0.1 + 1.0 / 7.0),
    ] {
        let mut vals = vec![0.0; e.num_symbols()];
        vals[x.index()] = v;
        let want = f64::atan2(w, v);
        assert!((e.eval(at, &vals) - want).abs() < 1e-15);
        let dvals: Vec<Dd> = vals.iter().map(|&a| Dd::from_f64(a)).collect();
        assert!((e.eval(at, &dvals).to_f64() - want).abs() < 1e-15);
    }
}

#[test]
fn derivatives_match_central_differences() {
    let (mut e, x, y, xs, ys) = engine_xy();
    let third = e.constant(q(1, 3));
    let xy = e.mul(xs, ys);
    let arg = e.add(xy, third); // x·y + 1/3
    let mut exprs: Vec<(String, ExprId)> = UNARY
        .iter()
        .filter(|&&f| f != Fun::Sign)
        .map(|&f| (format!("{f:?}"), e.func(f, arg)))
        .collect();
    let at = e.atan2(arg, xs);
    exprs.push(("atan2".into(), at));
    for (name, fx) in exprs {
        for s in [x, y] {
            let d = e.diff(fx, s);
            for (vx, vy) in [(0.4, 0.5), (-0.7, 0.3), (0.9, -0.2)] {
                let mut vals = vec![0.0; e.num_symbols()];
                vals[x.index()] = vx;
                vals[y.index()] = vy;
                let h = 1e-6;
                let mut plus = vals.clone();
                plus[s.index()] += h;
                let mut minus = vals.clone();
                minus[s.index()] -= h;
                let fd = (e.eval(fx, &plus) - e.eval(fx, &minus)) / (2.0 * h);
                let got = e.eval(d, &vals);
                assert!(
                    (got - fd).abs() <= 1e-7 * fd.abs().max(1.0),
                    "d{name}/d{} at ({vx}, {vy}): {got} vs {fd}",
                    e.sym_name(s)
                );
            }
        }
    }
}

#[test]
fn derivatives_have_their_closed_forms() {
    let (mut e, x, y, xs, ys) = engine_xy();
    // d atan2(y, x) = (x dy − y dx)/(x² + y²)
    let at = e.atan2(ys, xs);
    let x2 = e.mul(xs, xs);
    let y2 = e.mul(ys, ys);
    let r2 = e.add(x2, y2);
    let inv = e.pow(r2, Rational::MINUS_ONE);
    let dy = e.diff(at, y);
    assert_eq!(dy, e.mul(xs, inv));
    let dx = e.diff(at, x);
    let my = e.neg(ys);
    assert_eq!(dx, e.mul(my, inv));
    // d|x| = sign(x), whose derivative is 0
    let ax = e.func(Fun::Abs, xs);
    let sx = e.func(Fun::Sign, xs);
    assert_eq!(e.diff(ax, x), sx);
    assert_eq!(e.diff(sx, x), ZERO);
    // d asin = (1 − x²)^(−1/2), d acos = −(1 − x²)^(−1/2), d atan = 1/(1 + x²)
    let one_minus = e.sub(ONE, x2);
    let root = e.pow(one_minus, q(-1, 2));
    let asin = e.func(Fun::Asin, xs);
    assert_eq!(e.diff(asin, x), root);
    let acos = e.func(Fun::Acos, xs);
    assert_eq!(e.diff(acos, x), e.neg(root));
    let atan = e.func(Fun::Atan, xs);
    let one_plus = e.add(ONE, x2);
    assert_eq!(e.diff(atan, x), e.pow(one_plus, Rational::MINUS_ONE));
    // sinh' = cosh, cosh' = sinh, tanh' = 1 − tanh²
    let sh = e.func(Fun::Sinh, xs);
    let ch = e.func(Fun::Cosh, xs);
    assert_eq!(e.diff(sh, x), ch);
    assert_eq!(e.diff(ch, x), sh);
    let th = e.func(Fun::Tanh, xs);
    let th2 = e.mul(th, th);
    assert_eq!(e.diff(th, x), e.sub(ONE, th2));
}

#[test]
fn canonical_forms_fold_signs_roots_and_quotients() {
    let (mut e, _, _, xs, ys) = engine_xy();
    let mx = e.neg(xs);
    // odd functions pull the sign out, even ones drop it
    for f in [Fun::Sinh, Fun::Tanh, Fun::Asin, Fun::Atan, Fun::Sign] {
        let a = e.func(f, mx);
        let b = e.func(f, xs);
        assert_eq!(a, e.neg(b), "{f:?} is odd");
    }
    for f in [Fun::Cosh, Fun::Abs] {
        assert_eq!(e.func(f, mx), e.func(f, xs), "{f:?} is even");
    }
    // |x|² = x², sqrt(x²) = |x|, sqrt(x⁴) = x², |x²y| = x²|y|, |exp x| = exp x
    let ax = e.func(Fun::Abs, xs);
    let x2 = e.mul(xs, xs);
    assert_eq!(e.mul(ax, ax), x2);
    assert_eq!(e.pow(x2, q(1, 2)), ax);
    let x4 = e.mul(x2, x2);
    assert_eq!(e.pow(x4, q(1, 2)), x2);
    let three = e.int(3);
    let root3 = e.pow(three, q(1, 2));
    let three_x2 = e.scale(x2, Rational::int(3));
    assert_eq!(e.pow(three_x2, q(1, 2)), e.mul(root3, ax));
    let x2y = e.mul(x2, ys);
    let ay = e.func(Fun::Abs, ys);
    let mx2y = e.neg(x2y);
    assert_eq!(e.func(Fun::Abs, mx2y), e.mul(x2, ay));
    let ex = e.func(Fun::Exp, xs);
    assert_eq!(e.func(Fun::Abs, ex), ex);
    assert_eq!(e.func(Fun::Abs, ax), ax);
    // cot, sec and csc are powers of sin and cos
    let s = e.func(Fun::Sin, xs);
    let c = e.func(Fun::Cos, xs);
    let cot = e.func(Fun::Cot, xs);
    assert_eq!(e.mul(cot, s), c);
    let sec = e.func(Fun::Sec, xs);
    assert_eq!(e.mul(sec, c), ONE);
    let csc = e.func(Fun::Csc, xs);
    assert_eq!(e.mul(csc, s), ONE);
    let tan = e.func(Fun::Tan, xs);
    assert_eq!(e.mul(cot, tan), ONE);
}

#[test]
fn exact_values_at_constants() {
    let (mut e, _, _, xs, _) = engine_xy();
    for f in [
        Fun::Sinh,
        Fun::Tanh,
        Fun::Asin,
        Fun::Atan,
        Fun::Abs,
        Fun::Sign,
    ] {
        assert_eq!(e.func(f, ZERO), ZERO, "{f:?}(0)");
    }
    assert_eq!(e.func(Fun::Cosh, ZERO), ONE);
    let m3 = e.constant(q(-3, 2));
    assert_eq!(e.func(Fun::Abs, m3), e.constant(q(3, 2)));
    assert_eq!(e.func(Fun::Sign, m3), e.int(-1));
    // multiples of π, which the engine leaves to the caller (π is a symbol)
    let pi = |n, d| Some((Rational::ZERO, q(n, d)));
    assert_eq!(exact_value(Fun::Acos, Rational::ZERO), pi(1, 2));
    assert_eq!(exact_value(Fun::Acos, Rational::MINUS_ONE), pi(1, 1));
    assert_eq!(exact_value(Fun::Acos, q(1, 2)), pi(1, 3));
    assert_eq!(exact_value(Fun::Asin, Rational::MINUS_ONE), pi(-1, 2));
    assert_eq!(exact_value(Fun::Asin, q(1, 2)), pi(1, 6));
    assert_eq!(exact_value(Fun::Atan, Rational::ONE), pi(1, 4));
    assert_eq!(exact_value(Fun::Asin, Rational::int(2)), None);
    assert_eq!(exact_value(Fun::Acos, q(1, 3)), None);
    assert_eq!(exact_atan2(Rational::ZERO, Rational::int(-2)), pi(1, 1));
    assert_eq!(exact_atan2(Rational::int(-5), Rational::ZERO), pi(-1, 2));
    assert_eq!(exact_atan2(Rational::int(-2), Rational::int(-2)), pi(-3, 4));
    assert_eq!(exact_atan2(Rational::ZERO, Rational::ZERO), None);
    assert_eq!(exact_atan2(Rational::ONE, Rational::int(2)), None);
    // atan2(0, c > 0) = 0 folds in the engine; a symbolic point stays
    let two = e.int(2);
    assert_eq!(e.atan2(ZERO, two), ZERO);
    let at = e.atan2(xs, two);
    assert_eq!(e.display(at), "atan2(x, 2)");
}

#[test]
fn the_sign_is_zero_at_zero() {
    let (mut e, x, _, xs, _) = engine_xy();
    let sx = e.func(Fun::Sign, xs);
    let d_abs = {
        let ax = e.func(Fun::Abs, xs);
        e.diff(ax, x)
    };
    assert_eq!(d_abs, sx);
    let vals = vec![0.0; e.num_symbols()];
    assert_eq!(e.eval(sx, &vals), 0.0);
    let dvals = vec![Dd::ZERO; e.num_symbols()];
    assert_eq!(e.eval(sx, &dvals).to_f64(), 0.0);
}

#[test]
fn substitution_rebuilds_the_new_atoms() {
    let (mut e, x, y, xs, ys) = engine_xy();
    let at = e.atan2(ys, xs);
    let ax = e.func(Fun::Abs, xs);
    let sum = e.add(at, ax);
    let mut map = rustc_hash::FxHashMap::default();
    let mx = e.neg(xs);
    map.insert(x, mx);
    map.insert(y, ZERO);
    let r = e.subst(sum, &map, &mut Default::default());
    // atan2(0, −x) stays symbolic (its value depends on the sign of x); |−x| = |x|
    let at2 = e.atan2(ZERO, mx);
    assert_eq!(r, e.add(at2, ax));
}
