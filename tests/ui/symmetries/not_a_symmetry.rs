use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A sleigh whose declared rotation has the wrong sign: (x, y) turns
    /// one way and the blade the other.
    pub struct Sleigh {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        symmetries {
            turn(x: y, y: -x, theta: 1);
            slide_x(x: 1);
        }
    }
}

fn main() {
    let sleigh = Sleigh::new(2.0, 0.3);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _ = sleigh.symmetry_momenta(0.0, &q, &rdot);
    let _ = Sleigh::SYMMETRIES;
}
