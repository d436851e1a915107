use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Sled {
        parameters { m, J, b }
        coordinates { x, y, theta }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + J*dot(theta)^2/2;
        speeds { v, omega }
        kinematics {
            dot(x) = v*cos(theta) + b*t;
            dot(y) = v*sin(theta);
            dot(theta) = omega;
        }
        outputs { energy }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.5, 9.81);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let u = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = sled.accelerations(0.0, &q, &u);
    let _: SVector<f64, 3> = sled.velocities(0.0, &q, &u);
    let _: f64 = sled.energy(&q, &u);
    let x0 = SVector::<f64, 5>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&sled, 0.0, x0, 1.0);
}
