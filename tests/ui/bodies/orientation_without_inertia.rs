use nonholonomic::prelude::*;

// An orientation without an inertia (both, or neither for a point mass).
nonholonomic_system! {
    pub struct Disc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let F = rot_z(phi) * rot_x(-psi);
        let C = [x, y, 0] + R*(F*[0, 0, 1]);
        body disc {
            mass: m, centre: C, orientation: F*rot_y(theta),
        }
        lagrangian = kinetic_energy(disc) - m*g*C.z;
        constraints { rolls(disc, radius: R, axle: [0, 1, 0]); }
    }
}

fn main() {
    let disc = Disc::new(1.0, 0.5, 9.81);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::new(1.0, 2.0, 0.0);
    let _: SVector<f64, 3> = disc.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 8>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&disc, 0.0, x0, 1.0);
}
