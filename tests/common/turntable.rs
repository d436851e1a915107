//! The ball on a turntable with the rates of three fictitious angles as
//! velocities, and its closed form, shared by the tests of its forms.

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A homogeneous ball (I = 2/5 m R²) rolling on a table that turns at
    /// rate Omega about the vertical through the origin; its angular velocity
    /// written as the rates of three fictitious angles (its inertia is
    /// isotropic). The contact point moves with the table.
    pub struct TurntableBall {
        parameters { m, R, Omega }
        coordinates { x, y, phix, phiy, phiz }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 + m*R^2/5*(dot(phix)^2 + dot(phiy)^2 + dot(phiz)^2);
        constraints {
            dot(x) = R*dot(phiy) - Omega*y;
            dot(y) = -R*dot(phix) + Omega*x;
        }
    }
}

/// The centre of a homogeneous ball rolling without slipping on a table
/// turning at Ω: its velocity turns at ν = 2Ω/7, so
/// r(t) = r0 + v0 (e^{iνt} − 1)/(iν) in complex notation.
pub fn ball_centre(r0: (f64, f64), v0: (f64, f64), nu: f64, t: f64) -> (f64, f64) {
    let (s, c) = (nu * t).sin_cos();
    // (e^{iνt} − 1)/(iν) = (sin νt + i(1 − cos νt))/ν
    let (re, im) = (s / nu, (1.0 - c) / nu);
    (r0.0 + v0.0 * re - v0.1 * im, r0.1 + v0.0 * im + v0.1 * re)
}
