//! The algebra on both carriers: in the engine against closed forms (equal
//! canonical forms, or a difference that vanishes at random points); on the
//! graph with constant entries, which its folds evaluate exactly to a
//! constant node, and with leaves, whose operations are counted.

use super::ldlt::{self, Updates};
use super::*;
use crate::emit::ONE_NODE;
use crate::mechanics::vanish_at_random_points;
use crate::sym::{ONE, Rational, SymId};
use quote::quote;

/// An engine with π and the symbols `names`, as expressions.
fn symbols(names: &[&str]) -> (Engine, SymId, Vec<ExprId>) {
    let mut e = Engine::new();
    let pi = e.symbol("pi");
    let xs = names
        .iter()
        .map(|n| {
            let s = e.symbol(n);
            e.sym(s)
        })
        .collect();
    (e, pi, xs)
}

/// The rational constant p/q on the graph.
fn q(d: &mut Dag, p: i128, q: i128) -> Node {
    d.constant(Rational::new(p, q).expect("a nonzero denominator"))
}

/// The integer constants `rows` on the graph.
fn constants(d: &mut Dag, rows: &[&[i128]]) -> Vec<Vec<Node>> {
    rows.iter()
        .map(|r| r.iter().map(|&x| d.constant(Rational::int(x))).collect())
        .collect()
}

/// Leaves named `a0`, `a1`, .. on the graph.
fn leaves(d: &mut Dag, n: usize) -> Vec<Node> {
    (0..n)
        .map(|i| {
            let name = quote::format_ident!("a{i}");
            d.leaf(quote!(#name))
        })
        .collect()
}

#[test]
fn cross_of_the_unit_vectors_in_the_engine() {
    let mut e = Engine::new();
    let [ex, ey, ez] = [0, 1, 2].map(|k| [0, 1, 2].map(|i| if i == k { ONE } else { ZERO }));
    assert_eq!(cross(&mut e, ex, ey), ez);
    assert_eq!(cross(&mut e, ey, ez), ex);
    let minus_ey = cross(&mut e, ez, ex).map(|x| e.neg(x));
    assert_eq!(cross(&mut e, ex, ez), minus_ey);
    assert_eq!(dot3(&mut e, ex, ey), ZERO);
    assert_eq!(dot3(&mut e, ez, ez), ONE);
}

#[test]
fn cross_and_products_against_their_closed_forms() {
    let (mut e, _, s) = symbols(&["a", "b", "c", "x", "y", "z"]);
    let (u, v) = ([s[0], s[1], s[2]], [s[3], s[4], s[5]]);
    let w = cross(&mut e, u, v);
    // b z − c y, as a polynomial (a canonical form)
    let bz = e.mul(s[1], s[5]);
    let cy = e.mul(s[2], s[4]);
    assert_eq!(w[0], e.sub(bz, cy));
    assert_eq!(cross_component(&mut e, u, v, 2), w[2]);
    // u × v is orthogonal to u and v
    assert_eq!(dot3(&mut e, u, w), ZERO);
    assert_eq!(dot3(&mut e, v, w), ZERO);
    // (A B) v = A (B v), (A B)ᵀ = Bᵀ Aᵀ, Mᵀ v by rows of the transpose
    let a = [u, v, w];
    let b = [v, u, [s[0], ONE, s[5]]];
    let ab = mat_mat(&mut e, &a, &b);
    let bv = mat_vec(&mut e, &b, v);
    assert_eq!(mat_vec(&mut e, &ab, v), mat_vec(&mut e, &a, bv));
    let (at, bt) = (transpose(&a), transpose(&b));
    assert_eq!(transpose(&ab), mat_mat(&mut e, &bt, &at));
    assert_eq!(mat_t_vec(&mut e, &a, v), mat_vec(&mut e, &at, v));
    let sum = add3(&mut e, u, v);
    assert_eq!(sub3(&mut e, sum, v), u);
    let two = e.int(2);
    let twice = scale3(&mut e, two, u);
    assert_eq!(twice, add3(&mut e, u, u));
}

#[test]
fn cross_and_products_on_the_graph() {
    let mut d = Dag::new();
    let [ex, ey, ez] =
        [0, 1, 2].map(|k| [0, 1, 2].map(|i| if i == k { ONE_NODE } else { ZERO_NODE }));
    assert_eq!(cross(&mut d, ex, ey), ez);
    assert_eq!(cross(&mut d, ey, ez), ex);
    // (1, 2, 3) × (4, 5, 6) = (−3, 6, −3)
    let uv = constants(&mut d, &[&[1, 2, 3], &[4, 5, 6], &[-3, 6, -3]]);
    assert_eq!(cross(&mut d, &uv[0], &uv[1]).as_slice(), uv[2].as_slice());
    assert_eq!(cross_component(&mut d, &uv[0], &uv[1], 1), uv[2][1]);
    let l = leaves(&mut d, 6);
    let (u, v) = ([l[0], l[1], l[2]], [l[3], l[4], l[5]]);
    // six products, three differences
    let w = cross(&mut d, u, v);
    assert_eq!(d.op_count(&w), 9);
    // with e_z, two products and no differences: (u_y, −u_x, 0)
    let w = cross(&mut d, u, ez);
    assert_eq!(w[2], ZERO_NODE);
    assert_eq!(d.op_count(&w), 1);
    // a dot product: three products, two sums; from an initial value, three
    let x = dot3(&mut d, u, v);
    assert_eq!(d.op_count(&[x]), 5);
    let y = dot_from(&mut d, l[0], u.into_iter().zip(v));
    assert_eq!(d.op_count(&[y]), 6);
    // numbers: [[1, 2, 0], [0, 1, 3], [1, 0, 1]] (2, −1, 1)
    let m = constants(&mut d, &[&[1, 2, 0], &[0, 1, 3], &[1, 0, 1]]);
    let c = constants(&mut d, &[&[2, -1, 1]]);
    let mv = mat_vec(&mut d, &m, &c[0]);
    assert_eq!(mv, [q(&mut d, 0, 1), q(&mut d, 2, 1), q(&mut d, 3, 1)]);
    let mtv = mat_t_vec(&mut d, &m, &c[0]);
    assert_eq!(mtv, [q(&mut d, 3, 1), q(&mut d, 3, 1), q(&mut d, -2, 1)]);
    let mm = mat_mat(&mut d, &m, &m);
    let want = constants(&mut d, &[&[1, 4, 6], &[3, 1, 6], &[2, 2, 1]]);
    assert!((0..3).all(|i| mm[i].as_slice() == want[i].as_slice()));
}

/// [[a, b], [b, c]] x = (f, g) against Cramer's closed form.
#[test]
fn ldlt_of_a_symmetric_two_by_two_in_the_engine() {
    let (mut e, pi, s) = symbols(&["a", "b", "c", "f", "g"]);
    let (a, b, c, f, g) = (s[0], s[1], s[2], s[3], s[4]);
    let m = vec![vec![a, b], vec![b, c]];
    let ac = e.mul(a, c);
    let bb = e.mul(b, b);
    let det = e.sub(ac, bb);
    let inv = e.recip(det);
    let cf = e.mul(c, f);
    let bg = e.mul(b, g);
    let ag = e.mul(a, g);
    let bf = e.mul(b, f);
    let num = [e.sub(cf, bg), e.sub(ag, bf)];
    let want = num.map(|n| e.mul(n, inv));
    for updates in [Updates::Formed, Updates::Kept] {
        let (x, pivots) = ldlt::solve_symmetric(&mut e, &m, &[f, g], updates);
        assert_eq!(pivots[0], a);
        let diff: Vec<ExprId> = (0..2).map(|i| e.sub(x[i], want[i])).collect();
        assert!(vanish_at_random_points(&e, pi, &diff));
        assert!(!vanish_at_random_points(&e, pi, &x));
        let same = ldlt::solve_nonsingular(&mut e, &m, &[f, g], updates);
        assert_eq!(same, Some(x));
    }
    // at a = 2, b = 1, c = 3, f = 1, g = 4: x = (−1/5, 7/5)
    let fac = ldlt::factor(&mut e, &m, Updates::Formed);
    let x = ldlt::solve(&mut e, &fac, &[f, g]);
    let mut vals = vec![0.0; e.num_symbols()];
    for (k, v) in [2.0, 1.0, 3.0, 1.0, 4.0].into_iter().enumerate() {
        vals[k + 1] = v;
    }
    assert!((e.eval(x[0], &vals) + 0.2).abs() < 1e-14);
    assert!((e.eval(x[1], &vals) - 1.4).abs() < 1e-14);
}

#[test]
fn a_zero_pivot_stops_the_symbolic_factorisation() {
    let (mut e, _, s) = symbols(&["a", "b", "f"]);
    let (a, b, f) = (s[0], s[1], s[2]);
    // a zero on the diagonal
    let m = vec![vec![ZERO, b], vec![b, a]];
    assert_eq!(
        ldlt::solve_nonsingular(&mut e, &m, &[f, f], Updates::Formed),
        None
    );
    // a second pivot c − b²/a that cancels exactly: c = b²/a
    let bb = e.mul(b, b);
    let c = e.div(bb, a);
    let m = vec![vec![a, b], vec![b, c]];
    assert_eq!(
        ldlt::solve_nonsingular(&mut e, &m, &[f, f], Updates::Formed),
        None
    );
    let fac = ldlt::factor(&mut e, &m, Updates::Formed);
    assert_eq!(fac.d[1], ZERO);
}

#[test]
fn ldlt_on_the_graph_evaluates_exactly() {
    let mut d = Dag::new();
    // [[4, 2, 0], [2, 5, 1], [0, 1, 3]] x = (2, 7, 7): x = (0, 1, 2)
    let m = constants(&mut d, &[&[4, 2, 0], &[2, 5, 1], &[0, 1, 3]]);
    let f = constants(&mut d, &[&[2, 7, 7]]);
    let want = [q(&mut d, 0, 1), q(&mut d, 1, 1), q(&mut d, 2, 1)];
    for updates in [Updates::Kept, Updates::Formed] {
        let (x, pivots) = ldlt::solve_symmetric(&mut d, &m, &f[0], updates);
        assert_eq!(x, want);
        // D = (4, 4, 11/4)
        assert_eq!(pivots, [q(&mut d, 4, 1), q(&mut d, 4, 1), q(&mut d, 11, 4)]);
    }
}

#[test]
fn ldlt_on_the_graph_skips_structural_zeros() {
    let ops = |pattern: &[&[bool]], updates: Updates| {
        let mut d = Dag::new();
        let l = leaves(&mut d, 9);
        let k = pattern.len();
        let m: Vec<Vec<Node>> = (0..k)
            .map(|i| {
                (0..k)
                    .map(|j| match pattern[i][j] {
                        true => l[3 * i.min(j) + i.max(j)],
                        false => ZERO_NODE,
                    })
                    .collect()
            })
            .collect();
        let (x, _) = ldlt::solve_symmetric(&mut d, &m, &l[..k], updates);
        d.op_count(&x)
    };
    let (t, f) = (true, false);
    let dense: &[&[bool]] = &[&[t, t, t], &[t, t, t], &[t, t, t]];
    let banded: &[&[bool]] = &[&[t, t, f], &[t, t, t], &[f, t, t]];
    let diagonal: &[&[bool]] = &[&[t, f, f], &[f, t, f], &[f, f, t]];
    let counts = [dense, banded, diagonal].map(|p| ops(p, Updates::Kept));
    assert!(counts[0] > counts[1] && counts[1] > counts[2], "{counts:?}");
    // a diagonal system: three reciprocals and three products
    assert_eq!(counts[2], 6);
    // keeping L·D saves a product per update
    assert!(ops(dense, Updates::Kept) < ops(dense, Updates::Formed));
}
