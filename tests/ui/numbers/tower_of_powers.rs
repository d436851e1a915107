use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Each `let` takes the one before to the 64th power: the coefficient
    /// 3^262144 of `a3` has 125,000 digits, and computing it exceeds the
    /// engine's limit of work at `a3`.
    pub struct Tower {
        parameters { m, k }
        coordinates { x }
        let a1 = (3*x)^64;
        let a2 = a1^64;
        let a3 = a2^64;
        lagrangian = m*dot(x)^2/2 - k*a3;
    }
}

fn main() {
    let tower = Tower::new(1.0, 0.5);
    let q = SVector::<f64, 1>::from([0.1]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = tower.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 2>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&tower, 0.0, x0, 1.0);
}
