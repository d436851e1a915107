use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Ball {
        parameters { m, r }
        coordinates { x, y, z, yaw, pitch, roll }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, axle: [0, 1, 0], inside: sphere(2*r)); }
    }
}

fn main() {}
