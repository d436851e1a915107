use nonholonomic::prelude::*;

// A disc that only turns about the vertical, with the vertical axle: it lies
// flat, with no single contact point. One error at the axle (it used to add a
// silent height row `z = 0`, and the code below then failed on the
// dimensions).
nonholonomic_system! {
    pub struct Puck {
        parameters { m, R, g }
        coordinates { phi, x, y, z }
        let C = [x, y, z];
        body puck {
            mass: m, centre: C, orientation: rot_z(phi),
            inertia: diag(m*R^2/4, m*R^2/4, m*R^2/2),
        }
        lagrangian = kinetic_energy(puck) - m*g*C.z;
        constraints { rolls(puck, radius: R, axle: [0, 0, 1]); }
    }
}

fn main() {
    let puck = Puck::new(1.0, 0.5, 9.81);
    let q = SVector::<f64, 4>::zeros();
    let rdot = SVector::<f64, 2>::new(1.0, 2.0);
    let _: SVector<f64, 2> = puck.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 6>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&puck, 0.0, x0, 1.0);
}
