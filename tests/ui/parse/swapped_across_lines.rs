use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Tokens swapped across the `;` between two lines of a block (a force's
    /// coordinate before the `;`, the `dot` of the next constraint before it)
    /// or across a field's `,` in a body: one error each, at the token, and
    /// the next line or field is not reported again.
    pub struct Sled {
        parameters { m, J, a, c }
        coordinates { x, theta, y, z }
        inputs { push }
        body marker { mass: , m centre: [x, y, 0] }
        lagrangian = J*dot(theta)^2/2 + m/2*(dot(x)^2 + dot(y)^2 + dot(z)^2) + kinetic_energy(marker);
        constraints {
            dot(y) = tan(theta)*dot(x) dot;
            (z) = dot(x);
        }
        forces { x: push*cos(theta) - c*dot(x) y; : push*sin(theta) - c*dot(y); }
    }
}

fn main() {
    let sled = Sled::new(1.0, 0.5, 0.2, 0.1);
    let q = SVector::<f64, 4>::zeros();
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let u = SVector::<f64, 1>::from([0.3]);
    let _: SVector<f64, 2> = sled.accelerations(0.0, &q, &rdot, &u);
    let _: SVector<f64, 2> = sled.dependent_velocities(&q, &rdot);
}
