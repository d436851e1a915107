use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
                   + m*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { energy, contact_points }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.2, 0.3);
    let q = SVector::<f64, 3>::from([0.0, 0.1, 0.0]);
    let rdot = SVector::<f64, 2>::from([1.0, 0.5]);
    let _ = (sled.accelerations(0.0, &q, &rdot), sled.energy(&q, &rdot));
}
