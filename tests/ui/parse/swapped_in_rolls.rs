use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A swap inside `rolls(..)`: the line is rejected with one error, and
    /// the system still has its contact (no error at `contact_points`, and the
    /// stand-in keeps the dimensions).
    pub struct Ball {
        parameters { m, r }
        coordinates { x, y, a, b, c }
        body ball {
            mass: m, centre: [x, y, r], orientation: rot_z(a)*rot_y(b)*rot_x(c),
            inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5),
        }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius r :); }
        outputs { contact_points }
    }
}

fn main() {
    let ball = Ball::new(1.0, 0.5);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::new(1.0, 2.0, 0.0);
    let _: SVector<f64, 3> = ball.accelerations(0.0, &q, &rdot);
    let _: SMatrix<f64, 3, 1> = ball.contact_points(&q);
}
