//! A skate or knife edge as one line, `skates(BODY, across: d, at: p)`
//! (DESIGN §10): the Chaplygin sleigh, its blade at the body point p
//! behind the centre of mass, against the same constraint written out and
//! against the sleigh's closed-form equations v̇ = a ω², ω̇ = −m a v ω/(J +
//! m a²) (v the blade's forward speed, ω the turning rate, a the distance
//! of the centre of mass ahead of the blade, J its moment of inertia).
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The sleigh by `skates`.
    pub struct Skating {
        parameters { m, J, a }
        coordinates { x, y, theta }
        let R = rot_z(theta);
        body sled { mass: m, centre: [x, y, 0] + R*[a, 0, 0], orientation: R, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(sled);
        constraints { skates(sled, across: [0, 1, 0], at: [-a, 0, 0]); }
    }
}

nonholonomic_system! {
    /// The sleigh with its blade's constraint written out.
    pub struct Written {
        parameters { m, J, a }
        coordinates { x, y, theta }
        let R = rot_z(theta);
        body sled { mass: m, centre: [x, y, 0] + R*[a, 0, 0], orientation: R, inertia: diag(J, J, J) }
        lagrangian = kinetic_energy(sled);
        constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; }
    }
}

#[test]
fn the_sleigh_by_skates_is_the_sleigh_written_out_and_the_closed_form() {
    let (m, j, a) = (1.3, 0.4, 0.25);
    let (skating, written) = (Skating::new(m, j, a), Written::new(m, j, a));
    assert_eq!(Skating::<f64>::DEPENDENT, Written::<f64>::DEPENDENT);
    println!("DEPENDENT {:?}", Skating::<f64>::DEPENDENT);
    let (mut worst, mut worst_closed) = (0.0f64, 0.0f64);
    for k in 0..20 {
        let s = k as f64;
        let q = SVector::<f64, 3>::from([0.3 * s.sin(), -0.2 * s.cos(), 0.9 * (1.7 * s).sin()]);
        let v = SVector::<f64, 2>::from([1.1 * (0.7 * s).cos(), 0.8 * (1.3 * s).sin()]);
        let (got, want) = (
            skating.accelerations(0.0, &q, &v),
            written.accelerations(0.0, &q, &v),
        );
        worst = worst.max((got - want).amax());
        // the closed form: x independent, y dependent, ẏ = tan θ ẋ
        let (xd, om) = (v[0], v[1]);
        let th = q[2];
        let yd = th.tan() * xd;
        let speed = xd * th.cos() + yd * th.sin();
        let (xdd, omd) = (got[0], got[1]);
        let ydd = (xdd * th.sin() + om * speed) / th.cos();
        let vdot = xdd * th.cos() + ydd * th.sin();
        let want_vdot = a * om * om;
        let want_omd = -m * a * speed * om / (j + m * a * a);
        worst_closed = worst_closed
            .max((vdot - want_vdot).abs())
            .max((omd - want_omd).abs());
    }
    println!(
        "sleigh by skates: {worst:.1e} from the written constraint, {worst_closed:.1e} from the closed form"
    );
    assert!(
        worst < 1e-14 && worst_closed < 1e-13,
        "{worst:e} {worst_closed:e}"
    );
}
