//! Two rows written for the same velocity: the second is implicit and is solved for another coordinate.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(x) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {}
