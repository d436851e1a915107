//! `let` items that build on each other, and `dot` of a `let` of a `let`.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Cart {
        parameters { m, M, l, g }
        coordinates { s, th }
        let px = s + l*sin(th);
        let py = -l*cos(th);
        let vx = dot(px);
        let vy = dot(py);
        let T = M/2*dot(s)^2 + m/2*(vx^2 + vy^2);
        let V = m*g*py;
        lagrangian = T - V;
    }
}

fn main() {
    // the cart-pendulum at rest hanging down stays at rest
    let c: Cart = Cart::new(0.5, 2.0, 0.8, 9.81);
    let a = c.accelerations(0.0, &SVector::from([0.0, 0.0]), &SVector::from([0.0, 0.0]));
    assert!(a.amax() < 1e-15);
}
