use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A blade and a wheel whose rate also follows the heading: neither
    /// phi nor theta is in the 1st constraint, in any order.
    pub struct BladeAndWheel {
        parameters { m, J, R, a }
        coordinates { x, y, theta, phi }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*(dot(theta)^2 + dot(phi)^2)/2;
        constraints {
            cos(theta)*dot(y) - sin(theta)*dot(x) = 0;
            R*dot(phi) = cos(theta)*dot(x) + sin(theta)*dot(y) + a*dot(theta);
        }
        dependent { phi, theta }
    }
}

fn main() {
    let s = BladeAndWheel::new(1.0, 0.5, 0.2, 0.1);
    let q = SVector::<f64, 4>::from([0.1, 0.2, 0.3, 0.4]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 2> = s.dependent_velocities(&q, &rdot);
}
