use super::*;

fn q(n: i128, d: i128) -> Rational {
    Rational::new(n, d).unwrap()
}

/// An engine with one symbol `x`: the symbol and its expression.
fn engine_with_x() -> (Engine, SymId, ExprId) {
    let mut e = Engine::new();
    let x = e.symbol("x");
    let xs = e.sym(x);
    (e, x, xs)
}

#[test]
fn pythagorean_identity_is_zero() {
    let (mut e, _, xs) = engine_with_x();
    let s = e.func(Fun::Sin, xs);
    let c = e.func(Fun::Cos, xs);
    let s2 = e.mul(s, s);
    let c2 = e.mul(c, c);
    let sum = e.add(s2, c2);
    assert_eq!(sum, ONE);
}

#[test]
fn hash_consing_shares() {
    let (mut e, _, xs) = engine_with_x();
    let y = e.symbol("y");
    let ys = e.sym(y);
    let a = e.add(xs, ys);
    let b = e.add(ys, xs);
    assert_eq!(a, b);
    let a2 = e.mul(a, a);
    let expanded = {
        let xx = e.mul(xs, xs);
        let yy = e.mul(ys, ys);
        let xy = e.mul(xs, ys);
        let two_xy = e.scale(xy, Rational::int(2));
        e.sum(&[xx, yy, two_xy])
    };
    assert_eq!(a2, expanded);
}

#[test]
fn derivative_rules() {
    let (mut e, x, xs) = engine_with_x();
    let t = e.func(Fun::Tan, xs);
    let dt = e.diff(t, x);
    let t2 = e.mul(t, t);
    let expect = e.add(ONE, t2);
    assert_eq!(dt, expect);
    let sq = e.pow(xs, q(1, 2));
    let dsq = e.diff(sq, x);
    let expect = e.pow(xs, q(-1, 2));
    let expect = e.scale(expect, q(1, 2));
    assert_eq!(dsq, expect);
}

#[test]
fn powers_follow_real_semantics() {
    let (mut e, _, xs) = engine_with_x();
    let x2 = e.mul(xs, xs);
    let r = e.pow(x2, q(1, 2));
    assert_ne!(r, xs, "(x^2)^(1/2) is |x|, not x");
    let s = e.pow(xs, q(1, 2));
    let back = e.mul(s, s);
    assert_eq!(back, xs);
    let one_plus = e.add(ONE, xs);
    let inv = e.pow(one_plus, Rational::MINUS_ONE);
    let prod = e.mul(inv, one_plus);
    // (1+x)^-1 * (1+x) is not simplified (distributed), but evaluates to 1
    assert!((e.eval(prod, &[0.7]) - 1.0).abs() < 1e-15);
}

#[test]
fn exponentials_are_canonical() {
    let (mut e, x, xs) = engine_with_x();
    let y = e.symbol("y");
    let ys = e.sym(y);
    let s = e.add(xs, ys);
    let exy = e.func(Fun::Exp, s);
    let ex = e.func(Fun::Exp, xs);
    let ey = e.func(Fun::Exp, ys);
    let prod = e.mul(ex, ey);
    assert_eq!(exy, prod, "exp(x + y) = exp(x) exp(y)");
    let third = e.scale(xs, q(1, 3));
    let e3 = e.func(Fun::Exp, third);
    let cube = e.pow_int(e3, 3);
    assert_eq!(cube, ex, "exp(x/3)^3 = exp(x)");
    let ln = e.func(Fun::Ln, ex);
    assert_eq!(ln, xs, "ln(exp(x)) = x");
    let lnx = e.func(Fun::Ln, xs);
    let two_ln = e.scale(lnx, Rational::int(2));
    let back = e.func(Fun::Exp, two_ln);
    let x2 = e.mul(xs, xs);
    assert_eq!(back, x2, "exp(2 ln x) = x^2");
    let d = e.diff(e3, x);
    let expect = e.scale(e3, q(1, 3));
    assert_eq!(d, expect);
}

#[test]
fn one_minus_sin_squared_to_a_power_is_a_power_of_cos() {
    let (mut e, _, xs) = engine_with_x();
    let s = e.func(Fun::Sin, xs);
    let c = e.func(Fun::Cos, xs);
    let s2 = e.mul(s, s);
    let quarter = e.constant(q(1, 4));
    let one_minus = e.sub(ONE, s2);
    let d = e.mul(quarter, one_minus); // (1 − sin²x)/4, as a pivot comes out
    let inv = e.pow(d, Rational::MINUS_ONE);
    let expect = {
        let c2 = e.mul(c, c);
        let c2 = e.scale(c2, q(1, 4));
        e.pow(c2, Rational::MINUS_ONE)
    };
    assert_eq!(inv, expect);
    // and cos·(1 − sin²)⁻¹ = 1/cos
    let r = e.mul(c, inv);
    let cinv = e.pow(c, Rational::MINUS_ONE);
    let four_over_c = e.scale(cinv, Rational::int(4));
    assert_eq!(r, four_over_c);
}

/// A sum of more than `SCALED_MIN` terms times a single term stays one
/// atom times that term (it is not distributed), and still differentiates
/// and evaluates as the distributed product: (Σ_i sin(x)^i/i)·cos(x)·y.
#[test]
fn a_long_sum_times_a_term_is_kept() {
    let mut e = Engine::new();
    let (x, y) = (e.symbol("x"), e.symbol("y"));
    let (xe, ye) = (e.sym(x), e.sym(y));
    let s = e.func(Fun::Sin, xe);
    let terms: Vec<ExprId> = (1..=SCALED_MIN as u32 + 1)
        .map(|i| {
            let p = e.pow_int(s, i);
            let c = e.constant(q(1, i128::from(i)));
            e.mul(c, p)
        })
        .collect();
    let long = e.sum(&terms);
    assert_eq!(e.num_terms(long), SCALED_MIN + 1);
    let c = e.func(Fun::Cos, xe);
    let term = e.mul(c, ye);
    let kept = e.mul(long, term);
    assert_eq!(e.num_terms(kept), 1, "kept as one atom times the term");
    let short = e.sum(&terms[..3]);
    let distributed = e.mul(short, term);
    assert_eq!(e.num_terms(distributed), 3, "a short sum is distributed");
    // d/dx at a point, against the distributed product's derivative
    let d = e.diff(kept, x);
    let at = |v: f64, w: f64| {
        let mut vals = vec![0.0; e.num_symbols()];
        vals[x.index()] = v;
        vals[y.index()] = w;
        vals
    };
    for (v, w) in [(0.3, 1.7), (1.1, -0.4)] {
        let (sv, cv) = (f64::sin(v), f64::cos(v));
        let (mut sum, mut dsum) = (0.0, 0.0);
        for i in 1..=SCALED_MIN as i32 + 1 {
            sum += sv.powi(i) / f64::from(i);
            dsum += sv.powi(i - 1) * cv;
        }
        let value = e.eval(kept, &at(v, w));
        let slope = e.eval(d, &at(v, w));
        assert!((value - sum * cv * w).abs() <= 1e-12 * sum.abs().max(1.0));
        let want = (dsum * cv - sum * sv) * w;
        assert!(
            (slope - want).abs() <= 1e-12 * want.abs().max(1.0),
            "{slope} {want}"
        );
    }
}
