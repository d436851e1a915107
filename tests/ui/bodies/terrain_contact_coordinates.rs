use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct NoContact {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*x^2); }
    }
}

nonholonomic_system! {
    pub struct NotCoordinates {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*x^2, contact: [u, a]); }
    }
}

nonholonomic_system! {
    pub struct Twice {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*x^2, contact: [u, u]); }
    }
}

nonholonomic_system! {
    pub struct OnAPlane {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, contact: [u, v]); }
    }
}

fn main() {}
