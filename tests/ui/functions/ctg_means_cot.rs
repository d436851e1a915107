use nonholonomic::prelude::*;

// `ctg` is written `cot`.
nonholonomic_system! {
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { theta, x }
        lagrangian = m*l^2*dot(theta)^2/2 + m*dot(x)^2/2 + m*g*l*cos(theta)*ctg(1 + x^2);
    }
}

fn main() {
    let p = Pendulum::new(1.0, 2.0, 9.81);
    let q = SVector::<f64, 2>::new(0.3, 0.1);
    let _: SVector<f64, 2> = p.accelerations(0.0, &q, &SVector::zeros());
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&p, 0.0, SVector::<f64, 4>::zeros(), 1.0);
}
