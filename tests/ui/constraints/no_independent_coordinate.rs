use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pair {
        parameters { m }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2;
        constraints {
            dot(x) = y*dot(y);
            dot(y) = x*dot(x);
        }
    }
}

fn main() {
    let pair = Pair::new(1.0);
    let q = SVector::<f64, 2>::from([0.1, 0.2]);
    let rdot = SVector::<f64, 0>::zeros();
    let _: SVector<f64, 0> = pair.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 2> = pair.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 2>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&pair, 0.0, x0, 1.0);
}
