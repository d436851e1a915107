//! An explicit constraint with an affine term (a moving support): accepted (DESIGN §9).
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R, v }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta) + v;
            dot(y) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {}
