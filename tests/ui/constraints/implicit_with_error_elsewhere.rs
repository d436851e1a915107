use nonholonomic::prelude::*;

// An implicit constraint, no `dependent` block, and an error elsewhere: the
// stand-in still has the dimensions the user meant (one dependent
// coordinate), so the code below raises no follow-up error.
nonholonomic_system! {
    pub struct Sled {
        parameters { m, J }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2 + m*(dot(x)^2 + dot(y)^2)/2 + cso(theta);
        constraints {
            cos(theta)*dot(y) - sin(theta)*dot(x) = 0;
        }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.5);
    let q = SVector::<f64, 3>::zeros();
    let rdot = SVector::<f64, 2>::zeros();
    let _: SVector<f64, 2> = sled.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = sled.dependent_velocities(&q, &rdot);
    let _: [usize; 2] = Sled::<f64>::INDEPENDENT;
}
