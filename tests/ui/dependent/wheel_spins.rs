use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A differential-drive robot whose wheels' rates are listed as
    /// dependent: the left wheel's two rows cannot both be solved for its
    /// spin and the heading, whatever the order.
    pub struct Robot {
        parameters { m, Ic, d, mw, Iw, Id, r, b }
        coordinates { x, y, theta, phi_l, phi_r }
        let heading = [cos(theta), sin(theta), 0];
        let axle = [-sin(theta), cos(theta), 0];
        let O = [x, y, r];
        body chassis { mass: m, centre: O + d*heading, orientation: rot_z(theta), inertia: diag(0, 0, Ic) }
        body wheel_l { mass: mw, centre: O + b*axle, orientation: rot_z(theta)*rot_y(phi_l), inertia: diag(Id, Iw, Id) }
        body wheel_r { mass: mw, centre: O - b*axle, orientation: rot_z(theta)*rot_y(phi_r), inertia: diag(Id, Iw, Id) }
        lagrangian = kinetic_energy(chassis) + kinetic_energy(wheel_l) + kinetic_energy(wheel_r);
        constraints {
            rolls(wheel_l, radius: r, axle: [0, 1, 0]);
            rolls(wheel_r, radius: r, axle: [0, 1, 0]);
        }
        dependent { phi_l, phi_r, theta }
    }
}

fn main() {
    let robot = Robot::new(10.0, 0.5, 0.1, 1.0, 0.02, 0.01, 0.1, 0.25);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 2>::from([1.0, 1.0]);
    let _: SVector<f64, 2> = robot.accelerations(0.0, &q, &rdot);
}
