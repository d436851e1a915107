use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct NotHomogeneous {
        parameters { m, a, b, c }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        body shell { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(shell);
        constraints { rolls(shell, support_function: a*x^2 + b*y^2 + c*z^2); }
    }
}

nonholonomic_system! {
    pub struct NotConvex {
        parameters { m, a, b, c }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        body shell { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(shell);
        constraints { rolls(shell, support_function: sqrt(x^2 + y^2 + z^2) - 2*sqrt(x^2 + y^2)); }
    }
}

nonholonomic_system! {
    pub struct Moving {
        parameters { m, a, b, c }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        body shell { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(shell);
        constraints { rolls(shell, support_function: theta*sqrt(x^2 + y^2 + z^2)); }
    }
}

nonholonomic_system! {
    pub struct WithRadius {
        parameters { m, a, b, c }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        body shell { mass: m, centre: [x, y, z], orientation: R, inertia: diag(m, m, m) }
        lagrangian = kinetic_energy(shell);
        constraints { rolls(shell, radius: a, support_function: sqrt(x^2 + y^2 + z^2)); }
    }
}

fn main() {}
