#![deny(deprecated)]
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// x = R θ: rolling on a line is integrable.
    pub struct LineWheel {
        parameters { m, R }
        coordinates { theta, x }
        lagrangian = m/2*dot(x)^2 + m*R^2/4*dot(theta)^2;
        constraints { dot(x) = R*dot(theta); }
    }
}

fn main() {}
