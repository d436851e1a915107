use nonholonomic::prelude::*;

// A mistake outside the constraints (`dot(phi_ll)`) in a robot whose two
// wheels roll on one axle: their sideways rows coincide and one is dropped, so
// the system has three constraint rows, not the four its two `rolls(..)`
// lines suggest. The stand-in next to the error takes the rows lowering
// counted: the code below, written for two independent velocities, raises no
// error.
nonholonomic_system! {
    pub struct Robot {
        parameters { m, Ic, d, mw, Iw, Id, r, b, c }
        coordinates { x, y, theta, phi_l, phi_r }
        inputs { tau_l, tau_r }
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
        forces {
            phi_l: tau_l - c*dot(phi_ll);
            phi_r: tau_r - c*dot(phi_r);
        }
    }
}

fn main() {
    let robot = Robot::new(10.0, 0.5, 0.1, 0.5, 0.01, 0.005, 0.1, 0.2, 0.01);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 2>::new(1.0, 2.0);
    let u = SVector::<f64, 2>::new(0.1, 0.0);
    let _: SVector<f64, 2> = robot.accelerations(0.0, &q, &rdot, &u);
    let _: SVector<f64, 3> = robot.dependent_velocities(&q, &rdot);
    assert_eq!(Robot::K, 2);
}
