use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, a, R }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*(dot(x)^2 + dot(y)^2)/2;
        constraints { R = 1; }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.5, 9.81, 0.2);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = sled.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = sled.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 5>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&sled, 0.0, x0, 1.0);
}
