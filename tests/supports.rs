//! Rolling on a support that tilts or moves, `rolls(BODY, .., on: F[,
//! origin: O])` (DESIGN §10): a ball on an incline (its centre accelerates
//! at 5/7 g sin α down the slope) and on a turntable (its centre's velocity
//! turns at 2Ω/7, so the centre circles), against the closed forms.
use nalgebra::SVector;
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A homogeneous ball on a plane tilted by α about x.
    pub struct InclineBall {
        parameters { m, r, g, alpha }
        coordinates { x, y, z, yaw, pitch, roll }
        let slope = rot_x(alpha);
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: slope); }
    }
}

nonholonomic_system! {
    /// A homogeneous ball on a table turning at Ω about the vertical.
    pub struct TurntableBall {
        parameters { m, r, Omega }
        coordinates { x, y, yaw, pitch, roll }
        let table = rot_z(Omega*t);
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, r], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball);
        constraints { rolls(ball, radius: r, on: table); }
    }
}

#[test]
fn a_ball_rolls_down_an_incline_at_five_sevenths_of_g_sin_alpha() {
    let (m, r, g, alpha): (f64, f64, f64, f64) = (0.7, 0.1, 9.81, 0.3);
    let sys = InclineBall::new(m, r, g, alpha);
    println!("DEPENDENT {:?}", InclineBall::<f64>::DEPENDENT);
    // at rest on the plane through the origin: (G·N) = r, N = (0, −sin α, cos α)
    let mut x0 = SVector::<f64, 9>::zeros();
    x0[2] = r / alpha.cos();
    let t1 = 1.0;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, t1)
        .expect("runs");
    // down the slope: along −(0, cos α, sin α)
    let s = 0.5 * 5.0 / 7.0 * g * alpha.sin() * t1 * t1;
    let want = [0.0, -s * alpha.cos(), r / alpha.cos() - s * alpha.sin()];
    let err = (0..3)
        .map(|i| (out.x[i] - want[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "incline: centre after 1 s {:?}, closed form {want:?}: {err:.1e}",
        &out.x.as_slice()[..3]
    );
    assert!(err < 1e-10, "{err:e}");
}

#[test]
fn a_ball_on_a_turntable_circles_at_two_sevenths_of_its_rate() {
    let (m, r, omega) = (0.2, 0.05, 2.0);
    let sys = TurntableBall::new(m, r, omega);
    println!("DEPENDENT {:?}", TurntableBall::<f64>::DEPENDENT);
    // the centre at (x0, y0) with velocity v0: ω horizontal with
    // v0 = Ω e_z × P + r ω × e_z, world ω = (roll', pitch', yaw') at zero angles
    let (p0, v0) = ([0.3, -0.1], [0.05, 0.08]);
    let table = [-omega * p0[1], omega * p0[0]];
    let (wy, wx) = ((v0[0] - table[0]) / r, -(v0[1] - table[1]) / r);
    let mut x0 = SVector::<f64, 8>::zeros();
    x0[0] = p0[0];
    x0[1] = p0[1];
    let ind = TurntableBall::<f64>::INDEPENDENT;
    let rates = [v0[0], v0[1], 0.3, wy, wx];
    for (k, &i) in ind.iter().enumerate() {
        x0[5 + k] = rates[i];
    }
    let turns = 100.0;
    let t1 = turns * std::f64::consts::TAU / omega;
    let out = Dop853::new(1e-13, 1e-15)
        .with_max_steps(10_000_000)
        .integrate(&sys, 0.0, x0, t1)
        .expect("runs");
    // v(t) = Rot(wt) v0 with w = 2Ω/7
    let w = 2.0 * omega / 7.0;
    let (s, c) = (w * t1).sin_cos();
    let want = [
        p0[0] + (s * v0[0] - (1.0 - c) * v0[1]) / w,
        p0[1] + ((1.0 - c) * v0[0] + s * v0[1]) / w,
    ];
    let err = (0..2)
        .map(|i| (out.x[i] - want[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "turntable: centre after {turns} table turns {:?}, closed form {want:?}: {err:.1e} ({} steps)",
        &out.x.as_slice()[..2],
        out.stats.steps
    );
    assert!(err < 1e-9, "{err:e}");
}

nonholonomic_system! {
    /// A ball on a plate that a joint tilts about x: the plate is a body of
    /// the system, driven by the torque u.
    pub struct TiltingPlate {
        parameters { m, r, Jx, g }
        coordinates { beta, x, y, z, a, b, c }
        inputs { u }
        let R = rot_z(a)*rot_y(b)*rot_x(c);
        body plate { mass: 1, centre: [0, 0, 0], orientation: rot_x(beta), inertia: diag(Jx, 1, 1) }
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = Jx/2*dot(beta)^2 + kinetic_energy(ball) - m*g*z;
        forces { beta: u; }
        constraints { rolls(ball, radius: r, on: plate); }
        outputs { energy }
    }
}

/// The tilting plate's state at rest at tilt β with the ball at rest at
/// the plate's centre (G = r N), in the order of `INDEPENDENT`.
fn plate_at_rest(beta: f64, r: f64) -> SVector<f64, 11> {
    let mut x0 = SVector::<f64, 11>::zeros();
    x0[0] = beta;
    x0[2] = -r * beta.sin();
    x0[3] = r * beta.cos();
    x0
}

#[test]
fn a_ball_on_a_heavy_plate_rolls_as_on_an_incline_and_a_light_one_keeps_the_energy() {
    let (m, r, g, beta) = (0.5, 0.1, 9.81, 0.3f64);
    println!("plate: DEPENDENT {:?}", TiltingPlate::<f64>::DEPENDENT);
    // a plate too heavy to turn in half a second: the incline's 5/7 g sin β
    let heavy = TiltingPlate::new(m, r, 1e9, g);
    let free = SVector::<f64, 1>::zeros();
    let t1 = 0.5;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&Driven::new(&heavy, free), 0.0, plate_at_rest(beta, r), t1)
        .unwrap_or_else(|e| panic!("{e:?}"));
    let s = 0.5 * 5.0 / 7.0 * g * beta.sin() * t1 * t1;
    let want = [
        0.0,
        -r * beta.sin() - s * beta.cos(),
        r * beta.cos() - s * beta.sin(),
    ];
    let err = (0..3)
        .map(|i| (out.x[1 + i] - want[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "heavy plate: the ball's centre after {t1} s is {err:.1e} from the incline's closed form, the plate turned {:.1e}",
        out.x[0] - beta
    );
    assert!(err < 1e-8, "{err:e}");
    // a light plate, free (u = 0): the energy is a constant of the motion
    let light = TiltingPlate::new(m, r, 0.3, g);
    let x0 = plate_at_rest(beta, r);
    let split = |x: &SVector<f64, 11>| {
        let q = SVector::<f64, 7>::from_column_slice(&x.as_slice()[..7]);
        let v = SVector::<f64, 4>::from_column_slice(&x.as_slice()[7..]);
        light.energy(&q, &v)
    };
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&Driven::new(&light, free), 0.0, x0, 2.0)
        .unwrap_or_else(|e| panic!("{e:?}"));
    let drift = (split(&out.x) - split(&x0)).abs();
    println!(
        "light plate: energy drift over 2 s {drift:.1e}; the plate turned to {:.4}",
        out.x[0]
    );
    assert!(drift < 1e-10, "{drift:e}");
}

nonholonomic_system! {
    /// A homogeneous ball on a rail that runs down a plane tilted by α
    /// about y: the contact keeps to the rail and does not slip along it;
    /// sideways the rail holds it.
    pub struct RailBall {
        parameters { m, r, g, alpha }
        coordinates { x, y, z, yaw, pitch, roll }
        let slope = rot_y(alpha);
        let R = rot_z(yaw)*rot_y(pitch)*rot_x(roll);
        body ball { mass: m, centre: [x, y, z], orientation: R, inertia: diag(2*m*r^2/5, 2*m*r^2/5, 2*m*r^2/5) }
        lagrangian = kinetic_energy(ball) - m*g*z;
        constraints { rolls(ball, radius: r, on: slope, rail: [1, 0, 0]); }
        dependent { z, y, x }
    }
}

#[test]
fn a_ball_spinning_about_a_rail_rolls_down_it_at_five_sevenths_of_g_sin_alpha() {
    let (m, r, g, alpha): (f64, f64, f64, f64) = (0.7, 0.1, 9.81, 0.4);
    let sys = RailBall::new(m, r, g, alpha);
    println!("rail: DEPENDENT {:?}", RailBall::<f64>::DEPENDENT);
    // at rest at the top of the rail, spinning at s about the rail's
    // direction d = (cos α, 0, −sin α): world ω = (roll', pitch', yaw')
    let (s, (sa, ca)) = (3.0, alpha.sin_cos());
    let rates = [0.0, 0.0, 0.0, -s * sa, 0.0, s * ca];
    let mut x0 = SVector::<f64, 9>::zeros();
    x0[0] = r * sa;
    x0[2] = r * ca;
    for (k, &i) in RailBall::<f64>::INDEPENDENT.iter().enumerate() {
        x0[6 + k] = rates[i];
    }
    let t1 = 1.0;
    let out = Dop853::new(1e-12, 1e-14)
        .integrate(&sys, 0.0, x0, t1)
        .unwrap_or_else(|e| panic!("{e:?}"));
    let along = 0.5 * 5.0 / 7.0 * g * sa * t1 * t1;
    let want = [r * sa + along * ca, 0.0, r * ca - along * sa];
    let err = (0..3)
        .map(|i| (out.x[i] - want[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "rail: centre after 1 s {:?}, closed form {want:?}: {err:.1e}",
        &out.x.as_slice()[..3]
    );
    assert!(err < 1e-10, "{err:e}");
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_str().expect("a string").parse().expect("a number")
}

#[test]
fn the_tilting_plate_agrees_with_an_independent_derivation() {
    // tests/data/tilting_plate_sympy.py: the same model derived in SymPy
    // (Lagrange–d'Alembert with multipliers, cross-checked by KanesMethod),
    // evaluated at 50 digits at 12 random consistent states and 6 special ones
    let data: serde_json::Value =
        serde_json::from_str(include_str!("data/tilting_plate.json")).expect("json");
    let p = &data["parameters"];
    let sys = TiltingPlate::new(num(&p["m"]), num(&p["r"]), num(&p["Jx"]), num(&p["g"]));
    let (ind, dep) = (
        TiltingPlate::<f64>::INDEPENDENT,
        TiltingPlate::<f64>::DEPENDENT,
    );
    let states = data["cases"].as_array().expect("cases").iter();
    let special = data["special"].as_array().expect("special").iter();
    let mut worst = 0.0f64;
    let mut count = 0;
    for s in states.chain(special) {
        let vec = |k: &str| -> Vec<f64> { s[k].as_array().expect(k).iter().map(num).collect() };
        let (q, qdot, qddot) = (vec("q"), vec("qdot"), vec("qddot"));
        let q = SVector::<f64, 7>::from_column_slice(&q);
        let rdot = SVector::<f64, 4>::from_iterator(ind.iter().map(|&i| qdot[i]));
        let u = SVector::<f64, 1>::new(num(&s["u"]));
        let acc = sys.accelerations(0.0, &q, &rdot, &u);
        let sdot = sys.dependent_velocities(&q, &rdot);
        let scale = qddot.iter().fold(1.0f64, |m, a| m.max(a.abs()));
        for (k, &i) in ind.iter().enumerate() {
            worst = worst.max((acc[k] - qddot[i]).abs() / scale);
        }
        for (k, &i) in dep.iter().enumerate() {
            worst = worst.max((sdot[k] - qdot[i]).abs() / scale);
        }
        count += 1;
    }
    println!("tilting plate against SymPy at {count} states: {worst:.1e}");
    assert!(count == 18 && worst < 1e-13, "{count} {worst:e}");
}
