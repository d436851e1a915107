use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2;
        speeds { v, omega }
        kinematics {
            dot(x) = (v + 2*omega)*cos(theta);
            dot(y) = (v + 2*omega)*sin(theta);
            dot(theta) = 0;
        }
    }
}

fn main() {
    // the stand-in keeps the API of a system in speeds: no follow-up errors
    let sled = Sled::new(1.0, 0.1);
    let q = SVector::<f64, 3>::zeros();
    let u = SVector::<f64, { Sled::<f64>::K }>::zeros();
    let _ = (Sled::<f64>::SPEEDS, sled.velocities(0.0, &q, &u), sled.accelerations(0.0, &q, &u));
}
