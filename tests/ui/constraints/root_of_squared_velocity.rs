use nonholonomic::prelude::*;

// `sqrt(dot(x)^2)` is `abs(dot(x))`: an explicit constraint's right side must
// be linear in the other velocities.
nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(theta)^2)/2;
        constraints { dot(y) = sqrt(dot(x)^2)*cos(theta); }
    }
}

fn main() {
    let s = Slide::new(1.0);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = s.dependent_velocities(&q, &rdot);
}
