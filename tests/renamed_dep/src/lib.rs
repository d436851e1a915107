//! The facade under another name: `nh = { package = "nonholonomic", .. }`.
//! No crate named `nonholonomic` is in scope here, so this crate compiles
//! only if the generated code reaches the facade through the `$crate` its
//! `nonholonomic_system!` wrapper passes. Every output is requested, so
//! every generated method and trait implementation is checked;
//! `cargo test --workspace` builds and runs it.
#![forbid(unsafe_code)]

use nh::prelude::*;

nonholonomic_system! {
    /// The thesis's rolling disc, with every output but `linearization`.
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

nh::nonholonomic_system! {
    /// A sled with inputs (the macro by its path), with `linearization`.
    pub struct Sled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer - c*dot(theta); }
        outputs { linearization, jacobian }
    }
}

nh::nonholonomic_system! {
    /// No parameters: no hoisted values, `Default` derived.
    pub struct Unit {
        coordinates { x }
        lagrangian = dot(x)^2/2 - x^2/2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_disc_matches_the_closed_form() {
        let d = Disc::new(1.0, 0.5, 9.81);
        let q = SVector::<f64, 5>::from([0.1, 0.2, 0.3, 0.4, 0.5]);
        let r = SVector::<f64, 3>::from([6.0, 20.0, 0.5]);
        let a = d.accelerations(0.0, &q, &r);
        let (psi, thd, phd, psd, rr, g) = (0.3_f64, 6.0, 20.0, 0.5, 0.5, 9.81);
        let den = 4.0 * psi.sin().powi(2) + 3.0;
        let expect = [
            4.0 * psi.cos() * phd * psd / den,
            -4.0 * (2.0 * psi).sin() * phd * psd / den,
            4.0 * (rr * (psi.sin() * phd - thd) * psi.cos() * phd + g * psi.sin()) / (5.0 * rr),
        ];
        for i in 0..3 {
            assert!((a[i] - expect[i]).abs() < 1e-12 * expect[i].abs().max(1.0));
        }
        assert!(d.energy(&q, &r).is_finite());
        assert!(d.multipliers(0.0, &q, &r).iter().all(|v| v.is_finite()));
    }

    #[test]
    fn the_systems_integrate() {
        let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5]);
        let out = Dopri5::new(1e-8, 1e-10)
            .integrate(&Disc::new(1.7, 0.35, 9.81), 0.0, x0, 1.0)
            .expect("the disc integrates");
        assert!(out.x.iter().all(|v| v.is_finite()));
        let s: Sled = Sled::new(2.0, 0.3, 0.5, 0.1);
        let (a, b) = s.linearization(
            0.0,
            &SVector::from([0.0, 0.1, 0.0, 1.0, 0.0]),
            &SVector::from([0.0, 0.0]),
        );
        assert!(a.iter().chain(b.iter()).all(|v| v.is_finite()));
        assert_eq!(Unit::<f64>::default(), Unit::new());
        let u = Unit::<f64>::new().accelerations(0.0, &SVector::from([0.5]), &SVector::from([0.0]));
        assert_eq!(u[0], -0.5);
    }
}
