use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct NotZ {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: y = a*x^2, contact: [u, v]); }
    }
}

nonholonomic_system! {
    pub struct UsesZ {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = sqrt(1 - x^2 - z^2), contact: [u, v]); }
    }
}

nonholonomic_system! {
    pub struct Moving {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*sin(t)*x, contact: [u, v]); }
    }
}

fn main() {}
