use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Many {
        parameters { m }
        coordinates { q0, q1, q2, q3, q4, q5, q6, q7, q8, q9 }
        lagrangian = m*(dot(q0)^2 + dot(q1)^2 + dot(q2)^2 + dot(q3)^2 + dot(q4)^2 + dot(q5)^2 + dot(q6)^2 + dot(q7)^2 + dot(q8)^2 + dot(q9)^2)/2;
        constraints {
            dot(q1) + q0*dot(q0) = 0;
            dot(q2) + q0*dot(q0) = 0;
            dot(q3) + q0*dot(q0) = 0;
            dot(q4) + q0*dot(q0) = 0;
            dot(q5) + q0*dot(q0) = 0;
            dot(q6) + q0*dot(q0) = 0;
            dot(q7) + q0*dot(q0) = 0;
            dot(q8) + q0*dot(q0) = 0;
            dot(q9) + q0*dot(q0) = 0;
        }
    }
}

fn main() {
    let many = Many::new(1.0);
    let q = SVector::<f64, 10>::from([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = many.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 9> = many.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 11>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&many, 0.0, x0, 1.0);
}
