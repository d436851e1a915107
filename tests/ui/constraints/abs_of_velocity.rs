use nonholonomic::prelude::*;

// `abs(dot(x)) = dot(y)` is not linear in the velocities: its coefficient of
// `dot(x)` is the sign of `dot(x)` (its second derivative in the velocities
// vanishes, which is not the test).
nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(theta)^2)/2;
        constraints { abs(dot(x)) = dot(y); }
    }
}

fn main() {
    let s = Slide::new(1.0);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = s.dependent_velocities(&q, &rdot);
    assert!(!Slide::INTEGRABLE);
}
