use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Three implicit constraints: solved for x, y, z in this order, the
    /// first two are singular together (ẋ + ẏ twice); x, z, y works.
    pub struct Three {
        parameters { m, a }
        coordinates { x, y, z, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2 + dot(z)^2 + dot(theta)^2)/2;
        constraints {
            dot(x) + dot(y) = a*dot(theta);
            dot(x) + dot(y) + dot(z) = 0;
            dot(x) - dot(y) = 0;
        }
        dependent { x, y, z }
    }
}

fn main() {
    let s = Three::new(1.0, 0.5);
    let q = SVector::<f64, 4>::from([0.1, 0.2, 0.3, 0.4]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = s.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 3> = s.dependent_velocities(&q, &rdot);
}
