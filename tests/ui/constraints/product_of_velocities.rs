use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta)*dot(phi);
            dot(y) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {
    let disc = Disc::new(1.0, 0.5);
    let q = SVector::<f64, 4>::from([0.1, 0.2, 0.3, 0.4]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = disc.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 2> = disc.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 6>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&disc, 0.0, x0, 1.0);
}
