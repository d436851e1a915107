//! The algebra on both carriers: in the engine against closed forms (equal
//! canonical forms, or a difference that vanishes at random points); on the
//! graph with constant entries, which its folds evaluate exactly to a
//! constant node, and with leaves, whose operations are counted.

use super::ldlt::{self, Updates};
use super::lu::{self, Order};
use super::*;
use crate::sym::SymId;
use crate::sym::random_points::vanish_at_random_points;
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

/// A 3 × 3 with a zero where a pivot in order would be: m₀₀ = 0.
fn needs_pivoting(e: &mut Engine, s: &[ExprId]) -> Vec<Vec<ExprId>> {
    let two = e.int(2);
    vec![
        vec![ZERO, s[0], s[1]],
        vec![s[2], two, s[3]],
        vec![s[4], s[5], ONE],
    ]
}

#[test]
fn lu_with_given_pivots_in_the_engine() {
    let (mut e, pi, s) = symbols(&["a", "b", "c", "d", "f", "g", "u", "v", "w"]);
    let m = needs_pivoting(&mut e, &s);
    let rhs = vec![s[6], s[7], s[8]];
    // row 0 takes column 1, row 1 column 0, row 2 column 2 (an odd permutation)
    let steps = [(0, 1), (1, 0), (2, 2)];
    let lu = lu::factor_at(&mut e, m.clone(), &steps);
    assert!(lu.complete());
    for order in [Order::Columns, Order::Pivots] {
        let x = lu::solve(&mut e, &lu, rhs.clone(), order);
        let residuals: Vec<ExprId> = (0..3)
            .map(|i| {
                let mx = dot(&mut e, m[i].iter().copied().zip(x.iter().copied()));
                e.sub(mx, rhs[i])
            })
            .collect();
        assert!(vanish_at_random_points(&e, pi, &residuals));
    }
    // the pivots' product with the permutation's sign is the determinant
    let det = lu::det(&mut e, &lu);
    let want = lu::laplace(&mut e, &m);
    let diff = e.sub(det, want);
    assert!(vanish_at_random_points(&e, pi, &[diff]));
    assert!(!vanish_at_random_points(&e, pi, &[det]));
}

#[test]
fn lu_with_pivots_chosen_as_it_goes_and_right_sides_carried() {
    let (mut e, pi, s) = symbols(&["a", "b", "c", "d", "f", "g"]);
    let m = needs_pivoting(&mut e, &s);
    // the first nonzero entry of the rows and columns left
    let first = |_: &Engine, a: &[Vec<ExprId>], left: lu::Left| {
        let n = a.len();
        (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .find(|&(i, j)| !left.row_done[i] && !left.col_done[j] && a[i][j] != ZERO)
    };
    let mut carried = vec![vec![ONE, ZERO, ZERO], vec![ZERO, ONE, ZERO]];
    let lu = lu::factor(&mut e, m.clone(), first, &mut carried);
    assert_eq!(lu.pivots[0], (0, 1));
    let x = lu::back(&mut e, &lu, &carried, Order::Columns);
    // the first two columns of m⁻¹: m x_k = e_k
    let mut residuals = Vec::new();
    for (k, xk) in x.iter().enumerate() {
        for (i, row) in m.iter().enumerate() {
            let mx = dot(&mut e, row.iter().copied().zip(xk.iter().copied()));
            let ek = if i == k { ONE } else { ZERO };
            residuals.push(e.sub(mx, ek));
        }
    }
    assert!(vanish_at_random_points(&e, pi, &residuals));
    // a structurally singular matrix: no pivot left, det 0
    let mut singular = m.clone();
    for row in &mut singular {
        row[2] = ZERO;
    }
    let lu = lu::factor(&mut e, singular, first, &mut []);
    assert!(!lu.complete());
    assert_eq!(lu::det(&mut e, &lu), ZERO);
}

#[test]
fn lu_on_the_graph_evaluates_exactly_and_skips_zeros() {
    let mut d = Dag::new();
    // [[0, 1, 2], [3, 2, 1], [1, 1, 3]] x = (8, 10, 12): x = (1, 2, 3),
    // with m₀₀ = 0 passed over by the pivots
    let steps = [(1, 0), (0, 1), (2, 2)];
    let m = constants(&mut d, &[&[0, 1, 2], &[3, 2, 1], &[1, 1, 3]]);
    let b = constants(&mut d, &[&[8, 10, 12]]);
    let want = [1, 2, 3].map(|x| q(&mut d, x, 1));
    let lu = lu::factor_at(&mut d, m.clone(), &steps);
    for order in [Order::Pivots, Order::Columns] {
        assert_eq!(lu::solve(&mut d, &lu, b[0].clone(), order), want);
    }
    // det = 0·5 − 1·8 + 2·1, an odd permutation of pivots 3, 1, 2
    let det = lu::det(&mut d, &lu);
    assert_eq!(det, q(&mut d, -6, 1));
    assert_eq!(lu::laplace(&mut d, &m), det);
    // a singular one: its last pivot is exactly zero
    let m = constants(&mut d, &[&[0, 1, 2], &[3, 2, 1], &[1, 1, 1]]);
    let lu = lu::factor_at(&mut d, m.clone(), &steps);
    assert_eq!(lu::det(&mut d, &lu), ZERO_NODE);
    assert_eq!(lu::laplace(&mut d, &m), ZERO_NODE);
    // structural zeros: a zero below a pivot is no multiplier, a zero in
    // the pivot row no update
    let count = |zeros: &[(usize, usize)]| {
        let mut d = Dag::new();
        let l = leaves(&mut d, 9);
        let mut m: Vec<Vec<Node>> = (0..3).map(|i| l[3 * i..3 * i + 3].to_vec()).collect();
        for &(i, j) in zeros {
            m[i][j] = ZERO_NODE;
        }
        let lu = lu::factor_at(&mut d, m, &[(0, 0), (1, 1), (2, 2)]);
        let x = lu::solve(&mut d, &lu, l[..3].to_vec(), Order::Pivots);
        d.op_count(&x)
    };
    let (dense, sparse) = (count(&[]), count(&[(1, 0), (0, 2), (2, 1)]));
    assert!(sparse < dense, "{sparse} !< {dense}");
}

/// det of a 3 × 3 by Laplace against the cofactor expansion written out,
/// a(ei − fh) − b(di − fg) + c(dh − eg): the same polynomial.
#[test]
fn laplace_determinant_against_the_cofactor_expansion() {
    let (mut e, pi, s) = symbols(&["a", "b", "c", "d", "e", "f", "g", "h", "i"]);
    let m: Vec<Vec<ExprId>> = s.chunks(3).map(<[ExprId]>::to_vec).collect();
    let minor = |e: &mut Engine, p: usize, q: usize, r: usize, t: usize| {
        let x = e.mul(s[p], s[q]);
        let y = e.mul(s[r], s[t]);
        e.sub(x, y)
    };
    let m0 = minor(&mut e, 4, 8, 5, 7);
    let m1 = minor(&mut e, 3, 8, 5, 6);
    let m2 = minor(&mut e, 3, 7, 4, 6);
    let t0 = e.mul(s[0], m0);
    let t1 = e.mul(s[1], m1);
    let t2 = e.mul(s[2], m2);
    let t01 = e.sub(t0, t1);
    let want = e.add(t01, t2);
    assert_eq!(lu::laplace(&mut e, &m), want);
    // Cramer's rule: m (m⁻¹ w) = w
    let w = [s[0], ONE, s[8]];
    let inv = e.recip(want);
    let x = lu::cramer(&mut e, &m, &w, inv);
    let residuals: Vec<ExprId> = (0..3)
        .map(|i| {
            let mx = dot(&mut e, m[i].iter().copied().zip(x.iter().copied()));
            e.sub(mx, w[i])
        })
        .collect();
    assert!(vanish_at_random_points(&e, pi, &residuals));
}
