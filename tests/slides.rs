//! A body point kept on a surface without friction, `slides(BODY[, at: p][,
//! on: ..])` (DESIGN §10): a symmetric top whose tip slides on a smooth
//! table precesses steadily at the rate its centre-of-mass Euler equations
//! give, and a bead on a plane that tilts and oscillates vertically moves
//! as the closed form says.
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A symmetric top whose tip slides without friction on the table
    /// z = 0; Euler angles z-x-z.
    pub struct SlidingTop {
        parameters { m, I1, I3, l, g }
        coordinates { x, y, z, phi, theta, psi }
        let R = rot_z(phi)*rot_x(theta)*rot_z(psi);
        body top { mass: m, centre: [x, y, z], orientation: R, inertia: diag(I1, I1, I3) }
        lagrangian = kinetic_energy(top) - m*g*z;
        constraints { slides(top, at: [0, 0, -l]); }
        outputs { multipliers }
    }
}

nonholonomic_system! {
    /// A bead on the plane z = s x + A sin(ω t), which tilts by s and
    /// oscillates vertically.
    pub struct Bead {
        parameters { m, g, s, A, w }
        coordinates { x, y, z }
        body bead { mass: m, centre: [x, y, z] }
        lagrangian = kinetic_energy(bead) - m*g*z;
        constraints { slides(bead, on: z = s*x + A*sin(w*t)); }
    }
}

#[test]
fn a_top_sliding_on_a_smooth_table_precesses_steadily() {
    let (m, i1, i3, l, g): (f64, f64, f64, f64, f64) = (0.3, 2.0e-3, 1.2e-3, 0.05, 9.81);
    let sys = SlidingTop::new(m, i1, i3, l, g);
    assert_eq!(SlidingTop::<f64>::DEPENDENT, [2]);
    // steady precession at θ0, φ̇ = Ω: ∂L/∂θ = 0 with θ̇ = 0 gives
    // m g l = I3 ω3 Ω − I1 Ω² cos θ0 (I1 about the centre of mass: the
    // tip slides, the centre moves only vertically)
    let (theta0, omega) = (0.5f64, 3.0f64);
    let w3 = (m * g * l + i1 * omega * omega * theta0.cos()) / (i3 * omega);
    let psi_rate = w3 - omega * theta0.cos();
    // state: x, y, z, φ, θ, ψ, then ẋ, ẏ, φ̇, θ̇, ψ̇
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[2] = l * theta0.cos();
    x0[4] = theta0;
    x0[8] = omega;
    x0[10] = psi_rate;
    let t1 = 5.0;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, t1)
        .expect("runs");
    let (dtheta, dphi) = ((out.x[4] - theta0).abs(), (out.x[3] - omega * t1).abs());
    let drift = out.x[0].abs().max(out.x[1].abs());
    // the table pushes up with m g: the centre of mass does not accelerate
    let q = SVector::<f64, 6>::from_column_slice(&x0.as_slice()[..6]);
    let rdot = SVector::<f64, 5>::from_column_slice(&x0.as_slice()[6..]);
    let lambda = sys.multipliers(0.0, &q, &rdot)[0];
    println!(
        "sliding top after {t1} s: θ {dtheta:.1e} from θ0, φ {dphi:.1e} from Ω t, centre {drift:.1e} from the axis; normal force {lambda:.6} against m g = {:.6}",
        m * g
    );
    assert!(
        dtheta < 1e-10 && dphi < 1e-9 && drift < 1e-12,
        "{dtheta:e} {dphi:e} {drift:e}"
    );
    assert!((lambda.abs() - m * g).abs() < 1e-12 * m * g, "{lambda}");
}

#[test]
fn a_bead_on_a_tilting_oscillating_plane_follows_the_closed_form() {
    let (m, g, s, a, w): (f64, f64, f64, f64, f64) = (0.2, 9.81, 0.3, 0.05, 7.0);
    let sys = Bead::new(m, g, s, a, w);
    assert_eq!(Bead::<f64>::DEPENDENT, [2]);
    // ẍ = s (A ω² sin ωt − g)/(1 + s²), from rest at the origin
    let (v0, t1) = (0.4, 2.0);
    let mut x0 = SVector::<f64, 5>::zeros();
    x0[3] = v0;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, t1)
        .expect("runs");
    let k = s / (1.0 + s * s);
    let x = v0 * t1 + k * (a * w * t1 - a * (w * t1).sin() - 0.5 * g * t1 * t1);
    let z = s * x + a * (w * t1).sin();
    let err = (out.x[0] - x)
        .abs()
        .max((out.x[2] - z).abs())
        .max(out.x[1].abs());
    println!(
        "bead after {t1} s: x {:.12}, closed form {x:.12}: {err:.1e}",
        out.x[0]
    );
    assert!(err < 1e-10, "{err:e}");
}
