use nonholonomic::prelude::*;

// A speed, `sqrt(dot(x)^2 + dot(y)^2)`, has no linear form.
nonholonomic_system! {
    pub struct Cart {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2;
        constraints { sqrt(dot(x)^2 + dot(y)^2) = dot(theta); }
    }
}

fn main() {
    let s = Cart::new(1.0, 0.5);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
}
