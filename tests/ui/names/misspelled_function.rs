use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { theta }
        lagrangian = m*l^2*dot(theta)^2/2 + m*g*l*cso(theta);
    }
}

fn main() {
    let pendulum = Pendulum::new(1.0, 0.5, 9.81);
    let q = SVector::<f64, 1>::from([0.1]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = pendulum.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 2>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&pendulum, 0.0, x0, 1.0);
}
