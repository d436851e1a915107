use nonholonomic::prelude::*;

// A sphere of radius `r` rolling on z = 0 has its centre at height `r`, not
// `2*r`: its contact's height row would be the constant `r = 0` (which used to
// be "constant: remove it"). One error at the centre, with both heights.
nonholonomic_system! {
    pub struct Ball {
        parameters { m, r }
        coordinates { x, y, a, b, c }
        body ball {
            mass: m, centre: [x, y, r], orientation: rot_z(a)*rot_y(b)*rot_x(c),
            inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5),
        }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, centre: [x, y, 2*r]); }
    }
}

fn main() {
    let ball = Ball::new(1.0, 0.5);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::new(1.0, 2.0, 0.0);
    let _: SVector<f64, 3> = ball.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 8>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&ball, 0.0, x0, 1.0);
}
