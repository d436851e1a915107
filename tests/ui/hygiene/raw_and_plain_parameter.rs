use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A parameter declared twice, once raw: one error, and the code using the system raises none.
    pub struct Spring {
        parameters { m, k, r#k }
        coordinates { x }
        lagrangian = m/2*dot(x)^2 - k/2*x^2;
    }
}

fn main() {
    let s: Spring = Spring::new(1.0, 2.0, 3.0);
    let _ = (s.m, s.k);
    let _ = s.accelerations(0.0, &SVector::from([0.1]), &SVector::from([0.0]));
}
