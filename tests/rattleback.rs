//! The rattleback through `rolls(shell, semi_axes: ..)` against an
//! independent derivation (`tests/data/rattleback_sympy.py`: the contact
//! point from the support function, the Lagrange–d'Alembert equations with
//! multipliers in SymPy, 30-digit mpmath values, and the spin reversal
//! integrated by Bulirsch–Stoer at tolerances 1e-11 and 1e-13 and by a
//! Dormand–Prince 8 at 1e-12): the accelerations at 12 random states, and
//! the spin reversal — when the vertical spin first changes sign and how
//! fast it turns the other way — for the ellipsoid with its inertia turned
//! by δ = 0.1 and for Kane and Levinson's (1982) parameters.
use nalgebra::{SVector, Vector2};
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The rattleback: semi-axes a1, a2, a3 along the body axes, the centre
    /// of mass h below the ellipsoid's centre, the inertia about it in body
    /// axes with a product Ixy in the horizontal plane.
    pub struct Rattleback {
        parameters { a1, a2, a3, h, m, g, Ixx, Iyy, Izz, Ixy }
        coordinates { psi, theta, phi, x, y, z }
        let R = rot_z(psi)*rot_y(theta)*rot_x(phi);
        let Cg = [x, y, z];
        let G = Cg + R*[0, 0, -h];
        body shell {
            mass: m, centre: G, orientation: R,
            inertia: [[Ixx, Ixy, 0], [Ixy, Iyy, 0], [0, 0, Izz]],
        }
        lagrangian = kinetic_energy(shell) - m*g*G.z;
        constraints { rolls(shell, semi_axes: [a1, a2, a3], centre: Cg); }
    }
}

type Json = serde_json::Value;

fn reference() -> Json {
    serde_json::from_str(include_str!("data/rattleback.json")).expect("json")
}

fn num(v: &Json) -> f64 {
    match v {
        Json::String(s) => s.parse().expect("a number"),
        other => other.as_f64().expect("a number"),
    }
}

fn system(set: &Json) -> Rattleback<f64> {
    let p = &set["derived"];
    let k = |n: &str| num(&p[n]);
    Rattleback::new(
        k("a1"),
        k("a2"),
        k("a3"),
        k("h"),
        k("m"),
        k("g"),
        k("Ixx"),
        k("Iyy"),
        k("Izz"),
        k("Ixy"),
    )
}

/// The centre's height √(γᵀ D² γ), γ = Rᵀ e_z.
fn height(set: &Json, theta: f64, phi: f64) -> f64 {
    let p = &set["derived"];
    let gam = [
        -theta.sin(),
        theta.cos() * phi.sin(),
        theta.cos() * phi.cos(),
    ];
    let axes = [num(&p["a1"]), num(&p["a2"]), num(&p["a3"])];
    (0..3)
        .map(|i| (axes[i] * gam[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn the_accelerations_agree_with_the_independent_derivation() {
    let data = reference();
    assert_eq!(Rattleback::<f64>::DEPENDENT, [3, 4, 5]);
    let mut worst = 0.0f64;
    for (set, states) in [("main", "main"), ("check", "check")] {
        let sys = system(&data["parameters"]["sets"][set]);
        for s in data["states"][states].as_array().expect("states") {
            let q5: Vec<f64> = s["q"].as_array().expect("q").iter().map(num).collect();
            let z = num(&s["centre_height"]);
            let q = SVector::<f64, 6>::from([q5[0], q5[1], q5[2], q5[3], q5[4], z]);
            let u: Vec<f64> = s["u"].as_array().expect("u").iter().map(num).collect();
            let u = SVector::<f64, 3>::from_column_slice(&u);
            let want: Vec<f64> = s["u_dot"]
                .as_array()
                .expect("u_dot")
                .iter()
                .map(num)
                .collect();
            let got = sys.accelerations(0.0, &q, &u);
            let scale = want.iter().fold(1.0f64, |m, w| m.max(w.abs()));
            for i in 0..3 {
                worst = worst.max((got[i] - want[i]).abs() / scale);
            }
            let sdot = sys.dependent_velocities(&q, &u);
            for (i, w) in s["qdot_dep"]
                .as_array()
                .expect("qdot_dep")
                .iter()
                .enumerate()
            {
                worst = worst.max((sdot[i] - num(w)).abs() / scale);
            }
        }
    }
    println!("rattleback: accelerations and contact velocities against SymPy: {worst:.1e}");
    assert!(worst < 1e-13, "{worst:e}");
}

/// The vertical spin ω_z = ψ̇ − φ̇ sin θ and its local extremes (where
/// ω̇_z changes sign) over [0, t1], with the first time ω_z changes sign.
fn spin_reversal(set: &str, t1: f64) -> (f64, Vec<(f64, f64)>) {
    let data = reference();
    let sr = &data["spin_reversal"][set]["initial_state"];
    let params = &data["parameters"]["sets"][set];
    let sys = system(params);
    let k = |n: &str| num(&sr[n]);
    let (theta, phi) = (k("theta"), k("phi"));
    let x0 = SVector::<f64, 9>::from([
        k("psi"),
        theta,
        phi,
        k("x"),
        k("y"),
        height(params, theta, phi),
        k("psi_d"),
        k("theta_d"),
        k("phi_d"),
    ]);
    let spin = |x: &SVector<f64, 9>| x[6] - x[8] * x[1].sin();
    let spin_rate = |t: f64, x: &SVector<f64, 9>| {
        let q = SVector::<f64, 6>::from_column_slice(&x.as_slice()[..6]);
        let u = SVector::<f64, 3>::from_column_slice(&x.as_slice()[6..]);
        let a = sys.accelerations(t, &q, &u);
        a[0] - a[2] * x[1].sin() - x[8] * x[7] * x[1].cos()
    };
    let events = Events::new(|t: f64, x: &SVector<f64, 9>| Vector2::new(spin(x), spin_rate(t, x)));
    let (mut first, mut extremes) = (f64::NAN, Vec::new());
    Dop853::new(1e-12, 1e-14)
        .integrate_with_events(&sys, 0.0, x0, t1, &events, |hit| {
            if hit.index == 0 && first.is_nan() {
                first = hit.t;
            }
            if hit.index == 1 {
                extremes.push((hit.t, spin(&hit.x)));
            }
        })
        .expect("runs");
    (first, extremes)
}

#[test]
fn the_spin_reverses_when_and_as_fast_as_the_independent_integration() {
    let data = reference();
    let main = &data["spin_reversal"]["main"];
    let (first, extremes) = spin_reversal("main", 3.0);
    // the largest spin of the other sign before the next reversal (3.08 s)
    let (t_max, w_max) = extremes
        .iter()
        .filter(|e| e.0 > first && e.0 < 3.0)
        .fold((0.0, f64::MIN), |m, e| if e.1 > m.1 { *e } else { m });
    let (want_first, want_w, want_t) = (
        num(&main["t_first_sign_change"]),
        num(&main["reversed_extreme_omega_z"]),
        num(&main["reversed_extreme_time"]),
    );
    println!(
        "rattleback (δ = 0.1), spun at −5 rad/s: the spin first changes sign at {first:.12} s ({:.1e} from the reference), reverses to {w_max:.10} rad/s ({:.1e}) at {t_max:.9} s ({:.1e})",
        first - want_first,
        w_max - want_w,
        t_max - want_t
    );
    assert!((first - want_first).abs() < 1e-9, "{first}");
    assert!((w_max - want_w).abs() < 1e-8 && (t_max - want_t).abs() < 1e-7);
    // Kane and Levinson's rattleback, spun at +5 rad/s: its spin first
    // changes sign in a dip of 0.31 ms to −4.2e-4 rad/s at 2.68 s, and
    // turns to −5.357 rad/s at 5.72 s
    let kl = &data["spin_reversal"]["kane_levinson_1982"];
    let (first, extremes) = spin_reversal("kane_levinson_1982", 8.0);
    let want_first = num(&kl["t_first_sign_change"]);
    println!(
        "Kane and Levinson's rattleback: the spin first changes sign at {first:.12} s ({:.1e} from the reference)",
        first - want_first
    );
    assert!((first - want_first).abs() < 1e-8, "{first}");
    let (t_min, w_min) = extremes
        .iter()
        .fold((0.0, f64::MAX), |m, e| if e.1 < m.1 { *e } else { m });
    let (want_w, want_t) = (
        num(&kl["reversed_extreme_omega_z"]),
        num(&kl["reversed_extreme_time"]),
    );
    println!(
        "Kane and Levinson's rattleback, spun at +5 rad/s: reverses to {w_min:.10} rad/s ({:.1e} from the reference) at {t_min:.9} s ({:.1e})",
        w_min - want_w,
        t_min - want_t
    );
    assert!((w_min - want_w).abs() < 1e-7 && (t_min - want_t).abs() < 1e-6);
}
