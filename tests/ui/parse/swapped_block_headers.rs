use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Two blocks with a token swapped at their headers: the name of a block
    /// inside its braces, and a name between the block's name and its braces.
    /// One error at each token; the names stay declared, so their uses below
    /// raise nothing.
    pub struct Sled {
        { parameters m, J, a }
        coordinates x { , theta, y }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.5, 0.2);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = sled.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = sled.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 5>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&sled, 0.0, x0, 1.0);
}
