//! Ready-made systems: the scenes of the examples, tests and benchmarks,
//! written with [`nonholonomic_system!`] exactly as a user would write them.

use nonholonomic::nonholonomic_system;

nonholonomic_system! {
    /// The rolling disc of the thesis (Flygare 2012, section 6), as written
    /// there: centre of mass (6.12)–(6.14) (with the sign of (6.13) as (6.16)
    /// uses it) and the simplified rotational energy of (6.5)–(6.8), which
    /// omits the cross terms of a real tilted disc (see [`RollingDisc`]).
    /// θ spin, φ heading, ψ lean from vertical, (x, y) contact point.
    pub struct ThesisDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);      // (6.12)
        let Y = y + R*cos(phi)*sin(psi);      // (6.13), sign as (6.16) uses it
        let Z = R*cos(psi);                   // (6.14)
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);   // (6.27)
            dot(y) = R*sin(phi)*dot(theta);   // (6.28)
        }
        outputs { energy, multipliers, curvature, constraint_matrix, jacobian, routes, sensitivities }
    }
}

nonholonomic_system! {
    /// The physically correct thin rolling disc: radius R, mass m, moments
    /// mR²/2 about the axle and mR²/4 about a diameter, rolling without
    /// slipping; same coordinates and constraints as [`ThesisDisc`].
    ///
    /// Derivation. The frame (t, u, n) follows the disc without spinning with
    /// it: t = (cos φ, sin φ, 0) the rolling direction, u = sin ψ l + cos ψ z
    /// from the contact point to the centre (l = (−sin φ, cos φ, 0)), n = t × u
    /// the axle. The frame turns with φ̇ z − ψ̇ t; the disc turns relative to
    /// it about n with −θ̇, θ chosen so that the contact point moves with
    /// R θ̇ t (the rolling constraints (6.27)–(6.28)). The body angular
    /// velocity is therefore ω = −ψ̇ t + φ̇ cos ψ u + (φ̇ sin ψ − θ̇) n, and
    /// T = m/2 |Ċ|² + mR²/8 (ω_t² + ω_u²) + mR²/4 ω_n² with C = (x, y, 0) + R u.
    pub struct RollingDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        let w_t = -dot(psi);
        let w_u = dot(phi)*cos(psi);
        let w_n = dot(phi)*sin(psi) - dot(theta);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/8*(w_t^2 + w_u^2) + m*R^2/4*w_n^2
                   - m*g*Z;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { energy, multipliers, curvature, constraint_matrix, jacobian, sensitivities }
    }
}

nonholonomic_system! {
    /// [`RollingDisc`] written as a rigid body with a rolling contact: the
    /// frame F of the disc's plane (heading φ, then lean ψ), the centre above
    /// the contact point (x, y), the disc turned by θ about its axle in F,
    /// and `rolls(..)` for the no-slip constraints. The macro derives the
    /// angular velocity, the kinetic energy and the constraints that are
    /// written out by hand in [`RollingDisc`].
    pub struct BodyDisc {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let F = rot_z(phi) * rot_x(-psi);          // heading, then lean
        let C = [x, y, 0] + R*(F*[0, 0, 1]);       // centre, above the contact point
        body disc {
            mass: m, centre: C, orientation: F*rot_y(theta),
            inertia: diag(m*R^2/4, m*R^2/2, m*R^2/4),
        }
        lagrangian = kinetic_energy(disc) - m*g*C.z;
        constraints { rolls(disc, radius: R, axle: [0, 1, 0]); }
        outputs { energy, multipliers, curvature, constraint_matrix, jacobian, contact_points }
    }
}

nonholonomic_system! {
    /// [`ThesisDisc`] with a stiff spring-damper on the lean: the generalized
    /// force Q_ψ = −k (ψ − ψ0) − c ψ̇ (the stiff scene of the reports).
    pub struct StiffDisc {
        parameters { m, R, g, k, c, psi0 }
        coordinates { theta, phi, psi, x, y }
        let X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi);
        let Z = R*cos(psi);
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - m*g*Z;
        forces { psi: -k*(psi - psi0) - c*dot(psi); }
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { energy, jacobian }
    }
}

nonholonomic_system! {
    /// The Chaplygin sled: a knife edge at (x, y) with heading θ, centre of
    /// mass a distance a ahead of it, moment of inertia J about the centre of
    /// mass; no sideways slip.
    pub struct ChaplyginSled {
        parameters { m, J, a }
        coordinates { x, theta, y }
        lagrangian = J*dot(theta)^2/2
                   + m*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2)/2;
        constraints { dot(y) = tan(theta)*dot(x); }
        outputs { energy, multipliers, jacobian, routes }
    }
}

nonholonomic_system! {
    /// A knife edge on a plane inclined at `alpha`: x down the slope, y
    /// across, φ the blade's heading; J the moment of inertia about the
    /// plane's normal.
    pub struct KnifeEdge {
        parameters { m, J, g, alpha }
        coordinates { x, phi, y }
        lagrangian = J*dot(phi)^2/2 + g*m*x*sin(alpha) + m*(dot(x)^2 + dot(y)^2)/2;
        constraints { dot(y) = tan(phi)*dot(x); }
        outputs { energy, multipliers, jacobian }
    }
}

nonholonomic_system! {
    /// The largest reference system, refdata/random_03.json: six coupled
    /// coordinates, two constraints (both derivation routes emitted).
    pub struct Random03 {
        parameters { k1, k2 }
        coordinates { xi, eta, q_1, q_2, r1, s1 }
        lagrangian = dot(eta)^2*(q_2^2/2 + 9/4) - dot(eta)*dot(q_1)/4 - dot(eta)*dot(q_2)*sin(r1)/3 - dot(eta)*dot(r1)/3 - dot(eta)*dot(s1)*cos(eta)*cos(s1)/3 - k2*cos(xi) + dot(q_1)^2*(sin(q_2)*cos(xi)/4 + 5/2) - 2*dot(q_1)*dot(q_2)/5 - 2*dot(q_1)*dot(s1)*cos(s1)*cos(xi)/5 - 2*q_2/5 + 7*dot(q_2)^2/4 - 2*dot(q_2)*dot(r1)*cos(eta)/5 + dot(q_2)*dot(xi)*sin(s1)*cos(eta)/4 + dot(r1)^2*(sin(q_1)^2/2 + 11/4) + 2*dot(r1)*dot(s1)/5 + 7*dot(s1)^2/4 + dot(s1)*dot(xi)*sin(eta)*cos(r1)/4 + dot(xi)^2*(q_2^2/2 + 7/4);
        constraints {
            dot(r1) = 3*s1^2/2*dot(xi) - 2*xi*cos(q_1)*dot(eta) - 1/3*dot(q_1);
            dot(s1) = -1/2*dot(xi) + 2*cos(r1)/3*dot(eta) + (q_2^2 + 1)*dot(q_2);
        }
        outputs { routes }
    }
}
