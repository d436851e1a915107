//! The thesis's own result: the rolling disc of section 6.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Rolling disc of the thesis, section 6.
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }

        let X = x - R*sin(phi)*sin(psi);      // (6.12)
        let Y = y + R*cos(phi)*sin(psi);      // (6.13), sign as (6.16) uses it
        let Z = R*cos(psi);                   // (6.14)

        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;

        constraints {
            dot(x) = R*cos(phi)*dot(theta);   // (6.27)
            dot(y) = R*sin(phi)*dot(theta);   // (6.28)
        }
        outputs { multipliers, curvature, energy, constraint_matrix, mass_matrix, routes }
    }
}

#[test]
fn smoke() {
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let q = SVector::<f64, 5>::from([-1.878588, -1.565448, 1.193213, -1.805170, 0.608797]);
    let rdot = SVector::<f64, 3>::from([-4.246389, 2.045292, 1.354608]);
    let a = d.accelerations(0.0, &q, &rdot);
    println!("{a:?}");
    println!("{:?}", d.accelerations_multiplier_route(0.0, &q, &rdot));
    println!("{:?}", d.multipliers(0.0, &q, &rdot));
    println!("{:?}", d.energy(&q, &rdot));
    println!("{:?}", d.dependent_velocities(&q, &rdot));
}
