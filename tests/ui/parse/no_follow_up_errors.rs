use nonholonomic::prelude::*;

nonholonomic_system! {
    /// One mistake in the system (`cso`); the code that uses the system below
    /// must produce no further errors.
    pub struct Pendulum {
        parameters { m, l, g }
        coordinates { theta }
        lagrangian = m*l^2*dot(theta)^2/2 + m*g*l*cso(theta);
        outputs { energy }
    }
}

fn main() {
    let p: Pendulum = Pendulum::new(1.0, 2.0, 9.81);
    let q = SVector::<f64, 1>::from([0.3]);
    let v = SVector::<f64, 1>::from([0.0]);
    let _a = p.accelerations(0.0, &q, &v);
    let _e = p.energy(&q, &v);
    let x0 = SVector::<f64, 2>::from([0.3, 0.0]);
    let _ = Dopri5::new(1e-8, 1e-10).integrate(&p, 0.0, x0, 1.0);
    assert_eq!(Pendulum::<f64>::COORDINATES, ["theta"]);
}
