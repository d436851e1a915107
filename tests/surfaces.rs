//! A ball rolling inside a fixed sphere (a bowl) and inside a horizontal
//! cylinder (a half-pipe), `rolls(BALL, radius: r, inside: sphere(..))` and
//! `inside: cylinder(..)` (DESIGN §10). In a vertical plane through the
//! centre (the axis) the ball's angle θ from the bottom obeys exactly the
//! pendulum (7/5)(R0 − r) θ̈ = −g sin θ (kinetic energy ½ m v² + ½ (2/5) m
//! r² ω² with v = (R0 − r) θ̇ = r ω), whose period from the amplitude θ₀ is
//! 4 √(L/g) K(sin(θ₀/2)), L = 7(R0 − r)/5.
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A homogeneous ball in a spherical bowl whose bottom is at the origin.
    pub struct BowlBall {
        parameters { m, r, Rb, g }
        coordinates { x, y, z, yaw, pitch, roll }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, inside: sphere(Rb, [0, 0, Rb])); }
        outputs { energy }
    }
}

nonholonomic_system! {
    /// A homogeneous ball in a horizontal pipe along x whose bottom line is
    /// the x axis.
    pub struct PipeBall {
        parameters { m, r, Rc, g }
        coordinates { x, y, z, yaw, pitch, roll }
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, inside: cylinder(Rc, [1, 0, 0], [0, 0, Rc])); }
        outputs { energy }
    }
}

/// K(k), the complete elliptic integral of the first kind, by the
/// arithmetic–geometric mean.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-16 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The state at rest at angle θ₀ from the bottom: x = 0 or y the
/// transverse coordinate, by `transverse` (0 for x, 1 for y).
fn at_rest<const D: usize>(big: f64, r: f64, theta0: f64, transverse: usize) -> SVector<f64, D> {
    let mut x0 = SVector::<f64, D>::zeros();
    x0[transverse] = (big - r) * theta0.sin();
    x0[2] = big - (big - r) * theta0.cos();
    x0
}

#[test]
fn a_ball_in_a_bowl_swings_as_a_pendulum_of_seven_fifths_its_track() {
    let (m, r, big, g, theta0) = (0.3, 0.05, 0.8, 9.81, 0.5f64);
    let sys = BowlBall::new(m, r, big, g);
    let x0 = at_rest::<9>(big, r, theta0, 0);
    let l = 7.0 * (big - r) / 5.0;
    let period = 4.0 * (l / g).sqrt() * elliptic_k((theta0 / 2.0).sin());
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, period)
        .expect("runs");
    let (x_end, z_end) = (out.x[0], out.x[2]);
    let err = (x_end - x0[0]).abs().max((z_end - x0[2]).abs());
    let half = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, period / 2.0)
        .expect("runs");
    let err_half = (half.x[0] + x0[0]).abs();
    println!(
        "bowl: DEPENDENT {:?}; after one period {period:.6} s the centre is {err:.1e} from its start, after half {err_half:.1e} from its mirror image",
        BowlBall::<f64>::DEPENDENT
    );
    assert!(err < 1e-10 && err_half < 1e-10, "{err:e} {err_half:e}");
    let q = SVector::<f64, 6>::from([x0[0], x0[1], x0[2], 0.0, 0.0, 0.0]);
    let e0 = sys.energy(&q, &SVector::<f64, 3>::zeros());
    let qn = SVector::<f64, 6>::from_column_slice(&out.x.as_slice()[..6]);
    let vn = SVector::<f64, 3>::from_column_slice(&out.x.as_slice()[6..]);
    assert!((sys.energy(&qn, &vn) - e0).abs() < 1e-11 * e0.abs().max(1.0));
}

#[test]
fn a_ball_in_a_pipe_swings_across_it_as_the_same_pendulum() {
    let (m, r, big, g, theta0) = (0.3, 0.05, 0.8, 9.81, 0.5f64);
    let sys = PipeBall::new(m, r, big, g);
    let x0 = at_rest::<9>(big, r, theta0, 1);
    let l = 7.0 * (big - r) / 5.0;
    let period = 4.0 * (l / g).sqrt() * elliptic_k((theta0 / 2.0).sin());
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, period)
        .expect("runs");
    let err = (0..3).map(|i| (out.x[i] - x0[i]).abs()).fold(0.0, f64::max);
    println!(
        "pipe: DEPENDENT {:?}; after one period the centre is {err:.1e} from its start",
        PipeBall::<f64>::DEPENDENT
    );
    assert!(err < 1e-10, "{err:e}");
}
