use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A sleigh tied to the origin by a spring, turning against a torsion
    /// spring: neither x nor theta is cyclic.
    pub struct TiedSleigh {
        parameters { m, J, k, c }
        coordinates { x, y, theta }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2 - k/2*(x^2 + y^2) - c/2*theta^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { momenta }
    }
}

fn main() {
    let sleigh = TiedSleigh::new(1.0, 0.5, 2.0, 0.3);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _ = sleigh.momenta(0.0, &q, &rdot);
    let _ = sleigh.momentum_rates(0.0, &q, &rdot);
    let _ = TiedSleigh::CONSERVED;
}
