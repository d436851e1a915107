use nonholonomic::prelude::*;

// A `let` that is not linear in the velocities, used in a constraint: the
// error is at the name.
nonholonomic_system! {
    pub struct Slide {
        parameters { m }
        coordinates { x, y, theta }
        let V = abs(dot(x));
        lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(theta)^2)/2;
        constraints { dot(y) = V*cos(theta); }
    }
}

fn main() {
    let s = Slide::new(1.0);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
}
