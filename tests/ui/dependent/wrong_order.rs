use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A blade (no sideways slip) and a wheel of radius R rolling along it:
    /// the 1st constraint is solved for y, the 2nd for phi.
    pub struct BladeAndWheel {
        parameters { m, J, R }
        coordinates { x, y, theta, phi }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*(dot(theta)^2 + dot(phi)^2)/2;
        constraints {
            cos(theta)*dot(y) - sin(theta)*dot(x) = 0;
            R*dot(phi) = cos(theta)*dot(x) + sin(theta)*dot(y);
        }
        dependent { phi, y }
    }
}

fn main() {
    let s = BladeAndWheel::new(1.0, 0.5, 0.2);
    let q = SVector::<f64, 4>::from([0.1, 0.2, 0.3, 0.4]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 2> = s.dependent_velocities(&q, &rdot);
}
