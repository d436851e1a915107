//! A `#![no_std]` crate that invokes `nonholonomic_system!` and steps the
//! generated system with `Rk4`: CI builds it with `cargo build -p
//! nh-no-std-check`, where `nonholonomic` (and so nh-runtime and nalgebra)
//! come without their `std` features and the math goes through libm. If the
//! generated code or the runtime named `std`, this crate would not compile.
#![no_std]
#![forbid(unsafe_code)]

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The thesis's rolling disc, with every output.
    pub struct Disc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { energy, multipliers, curvature, constraint_matrix, mass_matrix, jacobian, routes }
    }
}

nonholonomic_system! {
    /// A sled with inputs, for a controller.
    pub struct Sled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer - c*dot(theta); }
        outputs { linearization }
    }
}

/// Advances the disc by 10 ms with fixed 1 ms steps, in single precision.
pub fn step_disc(d: &Disc<f32>, x: SVector<f32, 8>) -> Result<SVector<f32, 8>, SimError<f32, 8>> {
    Rk4::new(1e-3).integrate(d, 0.0, x, 1e-2).map(|o| o.x)
}

/// One 1 ms control step of the sled with a held input.
pub fn step_sled(
    s: &Sled,
    x: SVector<f64, 5>,
    u: SVector<f64, 2>,
) -> Result<SVector<f64, 5>, SimError<f64, 5>> {
    Rk4::new(1e-3)
        .integrate(&Driven::new(s, u), 0.0, x, 1e-3)
        .map(|o| o.x)
}

/// Advances four discs by 10 ms at once, one per lane of a `WideF64x4`.
pub fn step_discs_in_lanes(
    d: &Disc<WideF64x4>,
    x: SVector<WideF64x4, 8>,
) -> Result<SVector<WideF64x4, 8>, SimError<f64, 8>> {
    Rk4::new(1e-3).integrate_lanes(d, 0.0, x, 1e-2).map(|o| o.x)
}
