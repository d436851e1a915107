use nonholonomic::prelude::*;

// A ball rolling on a plate that shakes with time: its rows depend on `t`, so
// `dependent_velocities` takes `t`. A mistake in another body must not change
// that in the stand-in next to the error.
nonholonomic_system! {
    pub struct Ball {
        parameters { m, r, w }
        coordinates { x, y, a, b, c }
        let C = [x + sin(w*t), y, r];
        body ball {
            mass: m, centre: C, orientation: rot_z(a)*rot_y(b)*rot_x(c),
            inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5),
        }
        body marker { mass: m, centre: C, orientation: 2*rot_z(a), inertia: diag(1, 1, 1) }
        lagrangian = kinetic_energy(ball) + kinetic_energy(marker);
        constraints { rolls(ball, radius: r); }
    }
}

fn main() {
    let ball = Ball::new(1.0, 0.5, 3.0);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::new(1.0, 2.0, 0.0);
    let _: SVector<f64, 3> = ball.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 2> = ball.dependent_velocities(0.0, &q, &rdot);
}
