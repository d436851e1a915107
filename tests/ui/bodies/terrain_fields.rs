use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct RadiusEquation {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r = 2, on: z = a*x^2, contact: [u, v]); }
    }
}

nonholonomic_system! {
    pub struct WithOrigin {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*x^2, origin: [0, 0, 1], contact: [u, v]); }
    }
}

nonholonomic_system! {
    pub struct WithRail {
        parameters { m, r, a }
        coordinates { x, y, z, yaw, pitch, roll, u, v }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: z = a*x^2, contact: [u, v], rail: [1, 0, 0]); }
    }
}

fn main() {}
