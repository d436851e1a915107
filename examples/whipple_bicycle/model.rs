//! The Whipple bicycle of the benchmark (Meijaard, Papadopoulos, Ruina and
//! Schwab 2007, Proc. R. Soc. A 463:1955–1982), written with bodies and
//! rolling contacts. World axes: x forward, y to the left, z up (the paper's
//! z points down, so its zB, zH and products of inertia change sign here).
//! Roll is positive to the right and steer positive to the right, as in the
//! paper, so the linearisation compares with its matrices entry by entry.

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The benchmark bicycle: rear wheel, rear frame with rider, front frame
    /// (fork and handlebar) and front wheel, both wheels knife-edge discs
    /// rolling without slipping. Coordinates: roll, steer, rear wheel angle
    /// (independent), yaw, pitch, front wheel angle and the rear contact
    /// point (x, y) (dependent; the pitch through the holonomic contact of
    /// the front wheel).
    pub struct Whipple {
        parameters {
            w, c, lambda, g,
            rR, mR, IRxx, IRyy,
            xB, zB, mB, IBxx, IByy, IBzz, IBxz,
            xH, zH, mH, IHxx, IHyy, IHzz, IHxz,
            rF, mF, IFxx, IFyy
        }
        coordinates { roll, steer, rear, yaw, pitch, front, x, y }
        let Y = rot_z(yaw) * rot_x(roll);                             // heading and lean
        let B = Y * rot_y(pitch);                                     // rear frame
        let H = B * rot_y(-lambda) * rot_z(-steer) * rot_y(lambda);   // front frame, steered about the head tube
        let CR = [x, y, 0] + rR*(Y*[0, 0, 1]);                       // rear axle, above the rear contact
        let S = CR + B*[w + c, 0, -rR];                               // the head tube's axis meets the ground here when upright
        let GB = CR + B*[xB, 0, zB - rR];                             // rear frame's centre of mass
        let GH = S + H*[xH - w - c, 0, zH];                           // front frame's centre of mass
        let CF = S + H*[-c, 0, rF];                                   // front axle
        body rear_wheel { mass: mR, centre: CR, orientation: B*rot_y(rear), inertia: diag(IRxx, IRyy, IRxx) }
        body frame { mass: mB, centre: GB, orientation: B, inertia: [[IBxx, 0, IBxz], [0, IByy, 0], [IBxz, 0, IBzz]] }
        body fork { mass: mH, centre: GH, orientation: H, inertia: [[IHxx, 0, IHxz], [0, IHyy, 0], [IHxz, 0, IHzz]] }
        body front_wheel { mass: mF, centre: CF, orientation: H*rot_y(front), inertia: diag(IFxx, IFyy, IFxx) }
        lagrangian = kinetic_energy(rear_wheel) + kinetic_energy(frame) + kinetic_energy(fork)
                   + kinetic_energy(front_wheel) - g*(mR*CR.z + mB*GB.z + mH*GH.z + mF*CF.z);
        constraints {
            rolls(rear_wheel, radius: rR, axle: [0, 1, 0]);
            rolls(front_wheel, radius: rF, axle: [0, 1, 0]);   // adds the front contact's height = 0
        }
        dependent { x, y, pitch, yaw, front }
        outputs { energy, jacobian, mass_matrix, constraint_matrix, contact_points }
    }
}

/// The benchmark's parameters (the paper's Table 1), in this model's axes.
pub fn benchmark() -> Whipple {
    benchmark_in::<f64>()
}

#[allow(dead_code)] // used by tests/lanes.rs and the lanes benchmark
/// [`benchmark`] in the scalar `T`: `f64`, or a lane type such as
/// `WideF64x4` with the same parameters in every lane.
pub fn benchmark_in<T: nonholonomic::runtime::Lanes>() -> Whipple<T> {
    let v = |x: f64| nonholonomic::nalgebra::convert::<f64, T>(x);
    Whipple::new(
        v(1.02),                        // w: wheelbase
        v(0.08),                        // c: trail
        v(std::f64::consts::PI / 10.0), // λ: steer axis tilt
        v(9.81),                        // g
        v(0.3),
        v(2.0),
        v(0.0603),
        v(0.12), // rear wheel: rR, mR, IRxx, IRyy
        v(0.3),
        v(0.9),
        v(85.0),
        v(9.2),
        v(11.0),
        v(2.8),
        v(-2.4), // rear frame: xB, zB (up), mB, IBxx, IByy, IBzz, IBxz
        v(0.9),
        v(0.7),
        v(4.0),
        v(0.05892),
        v(0.06),
        v(0.00708),
        v(0.00756), // front frame: xH, zH (up), mH, IHxx, IHyy, IHzz, IHxz
        v(0.35),
        v(3.0),
        v(0.1405),
        v(0.28), // front wheel: rF, mF, IFxx, IFyy
    )
}

#[allow(dead_code)] // used by tests/whipple.rs, which includes this file
/// The linearised equations about upright straight-ahead running at speed
/// `v`, read off the generated nonlinear system: M from its mass matrix
/// reduced by its constraint matrix, and M⁻¹(g K0 + v² K2), M⁻¹ v C1 from
/// its Jacobian. Returns (M, v C1, g K0 + v² K2) in (roll, steer).
pub fn linearised(
    b: &Whipple,
    v: f64,
) -> (SMatrix<f64, 2, 2>, SMatrix<f64, 2, 2>, SMatrix<f64, 2, 2>) {
    let q = SVector::<f64, 8>::zeros();
    let (m, a) = (b.mass_matrix(&q), b.constraint_matrix(&q));
    // q̇ = T ṙ: the independent velocities pass through, ṡ = −A ṙ
    let mut t = SMatrix::<f64, 8, 3>::zeros();
    for (j, &i) in Whipple::<f64>::INDEPENDENT.iter().enumerate() {
        t[(i, j)] = 1.0;
    }
    for (r, &s) in Whipple::<f64>::DEPENDENT.iter().enumerate() {
        for j in 0..3 {
            t[(s, j)] = -a[(r, j)];
        }
    }
    let reduced = t.transpose() * m * t;
    let m2 = reduced.fixed_view::<2, 2>(0, 0).into_owned();
    let mut x = SVector::<f64, 11>::zeros();
    x[10] = v / b.rR; // the rear wheel's rate for forward speed v
    let jac = b.jacobian(0.0, &x);
    let stiffness = -(m2 * jac.fixed_view::<2, 2>(8, 0));
    let damping = -(m2 * jac.fixed_view::<2, 2>(8, 8));
    (m2, damping, stiffness)
}

/// The four eigenvalues (re, im) of the linearised roll and steer motion at
/// speed `v`, from the generated Jacobian, sorted by real part (then
/// imaginary part).
pub fn eigenvalues(b: &Whipple, v: f64) -> Vec<(f64, f64)> {
    let mut x = SVector::<f64, 11>::zeros();
    x[10] = v / b.rR;
    let jac = b.jacobian(0.0, &x);
    let idx = [0, 1, 8, 9]; // roll, steer, their rates
    let a = SMatrix::<f64, 4, 4>::from_fn(|r, c| jac[(idx[r], idx[c])]);
    let mut ev: Vec<(f64, f64)> = a
        .complex_eigenvalues()
        .iter()
        .map(|e| (e.re, e.im))
        .collect();
    ev.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
    ev
}

/// The largest real part of the eigenvalues at speed `v`.
pub fn spectral_abscissa(b: &Whipple, v: f64) -> f64 {
    eigenvalues(b, v)
        .iter()
        .map(|e| e.0)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The speed in (lo, hi) where the spectral abscissa crosses zero, by bisection.
pub fn stability_boundary(b: &Whipple, mut lo: f64, mut hi: f64) -> f64 {
    let s_lo = spectral_abscissa(b, lo).signum();
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if spectral_abscissa(b, mid).signum() == s_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
