use nonholonomic::prelude::*;

// Three mistakes with bodies, each one error: an orientation that is not a
// rotation, `kinetic_energy` of an expression, `kinetic_energy` in a
// constraint. The code below uses the system as a user does, with its types
// inferred: the stand-in next to the errors raises no error there.
nonholonomic_system! {
    pub struct Cart {
        parameters { m, R }
        coordinates { theta, phi, psi, x, y }
        let F = rot_z(phi) * rot_x(-psi);
        let C = [x, y, 0] + R*(F*[0, 0, 1]);
        body disc {
            mass: m, centre: C, orientation: F*rot_y(theta),
            inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4),
        }
        body plate { mass: m, centre: C, orientation: 2*F, inertia: diag(1, 1, 1) }
        lagrangian = kinetic_energy(disc) + kinetic_energy(2*disc) - m*C.z;
        constraints {
            rolls(disc, radius: R, axle: [0, 1, 0]);
            kinetic_energy(disc) = 1;
        }
    }
}

fn main() {
    let s = Cart::new(1.0, 2.0);
    let q = SVector::zeros();
    let v = SVector::zeros();
    let _ = s.accelerations(0.0, &q, &v);
    let _ = s.dependent_velocities(&q, &v);
    let x0 = SVector::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&s, 0.0, x0, 1.0);
}
