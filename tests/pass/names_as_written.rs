//! Names are used as written: capitals, underscores, raw identifiers, Greek-free ASCII.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub(crate) struct Names {
        parameters { M_total, I1, r#ref }
        coordinates { q_1, Q2 }
        inputs { u_a }
        lagrangian = M_total/2*dot(q_1)^2 + I1/2*dot(Q2)^2 - r#ref*q_1;
        forces { Q2: u_a; }
    }
}

fn main() {
    let n: Names = Names::new(2.0, 0.5, 1.0);
    let u = SVector::<f64, 1>::from([0.25]);
    let a = n.accelerations(0.0, &SVector::from([0.0, 0.0]), &SVector::from([0.0, 0.0]), &u);
    assert_eq!(a, SVector::<f64, 2>::from([-0.5, 0.5]));
    assert_eq!(Names::<f64>::COORDINATES, ["q_1", "Q2"]);
}
