//! An explicit constraint with explicitly time-dependent coefficients: accepted; `dependent_velocities` takes `t`.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Disc {
        parameters { m, R, w }
        coordinates { theta, phi, x, y }
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/4*dot(theta)^2 + m*R^2/8*dot(phi)^2;
        constraints {
            dot(x) = R*cos(w*t)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {}
