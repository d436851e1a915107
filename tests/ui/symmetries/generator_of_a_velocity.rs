use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Cart {
        parameters { m }
        coordinates { x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2);
        symmetries {
            drift(x: dot(y));
            lift(z: 1);
        }
    }
}

fn main() {
    let _ = Cart::new(1.0);
}
