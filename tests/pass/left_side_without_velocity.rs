//! A left side without a velocity: an implicit, affine row.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            x = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {}
