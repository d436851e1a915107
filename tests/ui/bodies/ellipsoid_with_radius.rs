use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Rattleback {
        parameters { a1, a2, a3, m, A, B, C }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        body shell { mass: m, centre: [x, y, z], orientation: R, inertia: diag(A, B, C) }
        lagrangian = kinetic_energy(shell);
        constraints { rolls(shell, semi_axes: [a1, a2, a3], radius: a3); }
    }
}

fn main() {}
