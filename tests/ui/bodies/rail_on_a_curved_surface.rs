use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Ball {
        parameters { m, r }
        coordinates { x, y, z, yaw, pitch, roll }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, inside: sphere(4*r), rail: [1, 0, 0]); }
    }
}

fn main() {}
