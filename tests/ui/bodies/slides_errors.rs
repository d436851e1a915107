use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct PointMassAt {
        parameters { m, l, a }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(top) + kinetic_energy(bead);
        constraints { slides(bead, at: [0, 0, -l]); }
    }
}

nonholonomic_system! {
    pub struct NotAGraph {
        parameters { m, l, a }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(top) + kinetic_energy(bead);
        constraints { slides(top, at: [0, 0, -l], on: y = a*x); }
    }
}

nonholonomic_system! {
    pub struct MovesWithTheSystem {
        parameters { m, l, a }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(top) + kinetic_energy(bead);
        constraints { slides(top, at: [0, 0, -l], on: z = theta*x); }
    }
}

nonholonomic_system! {
    pub struct SurfaceWithOrigin {
        parameters { m, l, a }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(top) + kinetic_energy(bead);
        constraints { slides(top, on: z = a*x, origin: [0, 0, 1]); }
    }
}

nonholonomic_system! {
    pub struct UnknownField {
        parameters { m, l, a }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(top) + kinetic_energy(bead);
        constraints { slides(top, across: [0, 1, 0]); }
    }
}

fn main() {}
