#![deny(deprecated)]
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// x = R θ: rolling on a line is integrable.
    pub struct LineWheel {
        parameters { m, R }
        coordinates { theta, x }
        lagrangian = m/2*dot(x)^2 + m*R^2/4*dot(theta)^2;
        constraints { dot(x) = R*dot(theta); }
    }
}

fn main() {
    let linewheel = LineWheel::new(1.0, 0.5);
    let q = SVector::<f64, 2>::from([0.1, 0.2]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = linewheel.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = linewheel.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 3>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&linewheel, 0.0, x0, 1.0);
}
