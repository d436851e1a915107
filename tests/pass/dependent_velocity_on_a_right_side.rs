//! A right side using another constraint's dependent velocity: the row becomes implicit and is solved with the other.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = tan(phi)*dot(x);
        }
    }
}

fn main() {}
