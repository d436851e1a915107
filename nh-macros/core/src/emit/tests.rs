use super::*;
use crate::sym::Engine;
use quote::quote;

#[test]
fn structural_zeros_cost_nothing() {
    let mut d = Dag::new();
    let a = d.leaf(quote!(a));
    let b = d.leaf(quote!(b));
    let m = vec![vec![a, ZERO_NODE], vec![ZERO_NODE, b]];
    let f = vec![a, b];
    let (x, _) =
        crate::algebra::ldlt::solve_symmetric(&mut d, &m, &f, crate::algebra::ldlt::Updates::Kept);
    // a diagonal system: two reciprocals and two products
    assert_eq!(d.op_count(&x), 4);
}

#[test]
fn horner_factoring_shares_atoms() {
    let mut e = Engine::new();
    let xs = e.symbol("x");
    let ys = e.symbol("y");
    let x = e.sym(xs);
    let y = e.sym(ys);
    // x*y + x*y^2 + x: factored as x*(1 + y*(1 + y)) -> 4 ops
    let xy = e.mul(x, y);
    let y2 = e.mul(y, y);
    let xy2 = e.mul(x, y2);
    let p = e.sum(&[xy, xy2, x]);
    let mut d = Dag::new();
    let lx = d.leaf(quote!(x));
    let ly = d.leaf(quote!(y));
    d.bind(xs, lx);
    d.bind(ys, ly);
    let n = d.expr(&e, p);
    assert_eq!(d.op_count(&[n]), 4);
}
