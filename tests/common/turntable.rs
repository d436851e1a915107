//! The ball on a turntable with the rates of three fictitious angles as
//! velocities, the same ball written by hand with a unit quaternion, and
//! the closed form of its centre, shared by the tests of its forms and the
//! lab's report on it.

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

/// The ball of radius `radius` on a table turning at `table` with its
/// orientation a unit quaternion q and its world angular velocity ω,
/// written by hand (no singularity, no engine): state x, y, ω, q. Rolling
/// on the table, `v = Ω e_z × r + R ω × e_z`; then `v̇ = (2/7) Ω e_z × v`,
/// `ω̇_xy = 5Ω/(7R) v`, `ω̇_z = 0`, and `q̇ = ½ (0, ω) q`.
pub fn quaternion_ball(
    radius: f64,
    table: f64,
) -> impl Fn(f64, &SVector<f64, 9>) -> SVector<f64, 9> {
    move |_t, s| {
        let vx = radius * s[3] - table * s[1];
        let vy = -radius * s[2] + table * s[0];
        let k = 5.0 * table / (7.0 * radius);
        let (wx, wy, wz) = (s[2], s[3], s[4]);
        let (a, b, c, d) = (s[5], s[6], s[7], s[8]);
        SVector::<f64, 9>::from([
            vx,
            vy,
            k * vx,
            k * vy,
            0.0,
            0.5 * (-wx * b - wy * c - wz * d),
            0.5 * (wx * a + wy * d - wz * c),
            0.5 * (wy * a + wz * b - wx * d),
            0.5 * (wz * a + wx * c - wy * b),
        ])
    }
}
