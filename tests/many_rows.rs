//! Blocks of dependent velocities larger than Cramer's rule solves (DESIGN §9,
//! more than 3 implicit or holonomic rows, solved by sparse elimination):
//!
//! * two upright rolling discs joined by a spring, their rolling written
//!   implicitly as rotated combinations of the rolling rows with non-constant
//!   factors, plus a holonomic row `z = x1 - x2`: 5 rows, against the same
//!   system written explicitly (accelerations, dependent velocities,
//!   multipliers) and the closed form of its chart regularity;
//! * a hanging chain of four links in Cartesian coordinates: 4 holonomic rows,
//!   whose projection solves a 4×4 Jacobian.

use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Two upright discs (radius R, mass m, moments A about the vertical and
    /// C about the axle) joined by a spring k, and a slider z = x1 − x2 of
    /// mass M; the rolling rows combined by the rotation [[a, b], [−b, a]],
    /// a = 2 + cos θ, b = sin φ.
    pub struct ImplicitPair {
        parameters { m, A, C, R, k, M }
        coordinates { theta1, phi1, x1, y1, theta2, phi2, x2, y2, z }
        lagrangian = m/2*(dot(x1)^2 + dot(y1)^2 + dot(x2)^2 + dot(y2)^2)
            + A/2*(dot(phi1)^2 + dot(phi2)^2) + C/2*(dot(theta1)^2 + dot(theta2)^2)
            + M/2*dot(z)^2 - k/2*((x1 - x2)^2 + (y1 - y2)^2);
        constraints {
            (2 + cos(theta1))*(dot(x1) - R*cos(phi1)*dot(theta1))
                + sin(phi1)*(dot(y1) - R*sin(phi1)*dot(theta1)) = 0;
            -sin(phi1)*(dot(x1) - R*cos(phi1)*dot(theta1))
                + (2 + cos(theta1))*(dot(y1) - R*sin(phi1)*dot(theta1)) = 0;
            (2 + cos(theta2))*(dot(x2) - R*cos(phi2)*dot(theta2))
                + sin(phi2)*(dot(y2) - R*sin(phi2)*dot(theta2)) = 0;
            -sin(phi2)*(dot(x2) - R*cos(phi2)*dot(theta2))
                + (2 + cos(theta2))*(dot(y2) - R*sin(phi2)*dot(theta2)) = 0;
            z = x1 - x2;
        }
        outputs { multipliers }
    }
}

nonholonomic_system! {
    /// The same pair with every constraint explicit.
    pub struct ExplicitPair {
        parameters { m, A, C, R, k, M }
        coordinates { theta1, phi1, x1, y1, theta2, phi2, x2, y2, z }
        lagrangian = m/2*(dot(x1)^2 + dot(y1)^2 + dot(x2)^2 + dot(y2)^2)
            + A/2*(dot(phi1)^2 + dot(phi2)^2) + C/2*(dot(theta1)^2 + dot(theta2)^2)
            + M/2*dot(z)^2 - k/2*((x1 - x2)^2 + (y1 - y2)^2);
        constraints {
            dot(x1) = R*cos(phi1)*dot(theta1);
            dot(y1) = R*sin(phi1)*dot(theta1);
            dot(x2) = R*cos(phi2)*dot(theta2);
            dot(y2) = R*sin(phi2)*dot(theta2);
            dot(z) = R*cos(phi1)*dot(theta1) - R*cos(phi2)*dot(theta2);
        }
        outputs { multipliers }
    }
}

nonholonomic_system! {
    /// A chain of four links of length l hanging from the origin, its joints
    /// (x_i, y_i) of mass m each (y up).
    pub struct Chain {
        parameters { m, l, g }
        coordinates { x1, y1, x2, y2, x3, y3, x4, y4 }
        lagrangian = m/2*(dot(x1)^2 + dot(y1)^2 + dot(x2)^2 + dot(y2)^2
                        + dot(x3)^2 + dot(y3)^2 + dot(x4)^2 + dot(y4)^2)
            - m*g*(y1 + y2 + y3 + y4);
        constraints {
            x1^2 + y1^2 = l^2;
            (x2 - x1)^2 + (y2 - y1)^2 = l^2;
            (x3 - x2)^2 + (y3 - y2)^2 = l^2;
            (x4 - x3)^2 + (y4 - y3)^2 = l^2;
        }
    }
}

/// A deterministic uniform sample in [lo, hi).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// max_i |a_i − b_i| / max(1, |b_i|).
fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1.0))
        .fold(0.0, f64::max)
}

const PAIR: (f64, f64, f64, f64, f64, f64) = (1.3, 0.4, 0.7, 0.35, 2.1, 0.6);

/// The pair's chart regularity in closed form: c_s in the order (y1, x1,
/// y2, x2, z) is block diagonal with blocks [[b, a], [a, −b]] and the unit
/// row of z, so det c_s = (a1² + b1²)(a2² + b2²), over the rows' norms.
fn pair_regularity(q: &[f64]) -> f64 {
    let r = PAIR.3;
    let mut ratio = 1.0 / 3f64.sqrt(); // the row ż − ẋ1 + ẋ2
    for disc in [&q[0..4], &q[4..8]] {
        let (theta, phi) = (disc[0], disc[1]);
        let (a, b) = (2.0 + theta.cos(), phi.sin());
        let (c, s) = (phi.cos(), phi.sin());
        let n1 = (a * a + b * b + (r * (a * c + b * s)).powi(2)).sqrt();
        let n2 = (a * a + b * b + (r * (a * s - b * c)).powi(2)).sqrt();
        ratio *= (a * a + b * b) / (n1 * n2);
    }
    ratio
}

#[test]
fn five_implicit_and_holonomic_rows_agree_with_the_explicit_pair() {
    assert_eq!(ImplicitPair::<f64>::DEPENDENT, [2, 3, 6, 7, 8]);
    assert_eq!(ExplicitPair::<f64>::DEPENDENT, [2, 3, 6, 7, 8]);
    let (m, a, c, r, k, big_m) = PAIR;
    let imp = ImplicitPair::new(m, a, c, r, k, big_m);
    let exp = ExplicitPair::new(m, a, c, r, k, big_m);
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    let (mut worst, mut worst_chart) = (0.0f64, 0.0f64);
    for _ in 0..40 {
        let q = SVector::<f64, 9>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let v = SVector::<f64, 4>::from_fn(|_, _| rng.uniform(-2.0, 2.0));
        let t = rng.uniform(0.0, 1.0);
        worst = worst
            .max(rel_err(
                imp.accelerations(t, &q, &v).as_slice(),
                exp.accelerations(t, &q, &v).as_slice(),
            ))
            .max(rel_err(
                imp.dependent_velocities(&q, &v).as_slice(),
                exp.dependent_velocities(&q, &v).as_slice(),
            ));
        // λ_a = E_{s_a}: the same per dependent coordinate, in either order
        let (li, le) = (imp.multipliers(t, &q, &v), exp.multipliers(t, &q, &v));
        let by_coordinate = |l: &SVector<f64, 5>, dep: [usize; 5]| {
            let mut out = [0.0; 9];
            for (a, &s) in dep.iter().enumerate() {
                out[s] = l[a];
            }
            out
        };
        worst = worst.max(rel_err(
            &by_coordinate(&li, ImplicitPair::<f64>::DEPENDENT),
            &by_coordinate(&le, ExplicitPair::<f64>::DEPENDENT),
        ));
        let mut x = SVector::<f64, 13>::zeros();
        x.fixed_rows_mut::<9>(0).copy_from(&q);
        x.fixed_rows_mut::<4>(9).copy_from(&v);
        let rho = imp.chart_regularity(t, &x).unwrap();
        let reference = pair_regularity(q.as_slice());
        worst_chart = worst_chart.max((rho - reference).abs() / reference.abs());
    }
    println!(
        "implicit vs explicit pair at 40 random states: max relative difference {worst:.2e}; chart regularity vs closed form {worst_chart:.2e}"
    );
    assert!(worst <= 1e-12, "{worst:e}");
    assert!(worst_chart <= 1e-12, "{worst_chart:e}");
}

#[test]
fn four_holonomic_rows_are_projected_together() {
    let l = 0.8;
    let chain = Chain::new(1.0, l, 9.81);
    // the joints of a chain at angles 0.3, 0.5, 0.7, 0.9 from the downward
    // vertical, each joint's height then perturbed
    let mut x = SVector::<f64, 12>::zeros();
    let (mut px, mut py) = (0.0, 0.0);
    for (i, angle) in [0.3f64, 0.5, 0.7, 0.9].into_iter().enumerate() {
        px += l * angle.sin();
        py -= l * angle.cos();
        x[2 * i] = px;
        x[2 * i + 1] = py * (1.0 + 1e-4 * (i as f64 + 1.0));
    }
    let exact = {
        let mut e = x;
        let mut py = 0.0;
        for (i, angle) in [0.3f64, 0.5, 0.7, 0.9].into_iter().enumerate() {
            py -= l * angle.cos();
            e[2 * i + 1] = py;
        }
        e
    };
    assert!(chain.constraint_residual(0.0, &x).unwrap() > 1e-5);
    assert!(chain.project(0.0, &mut x).unwrap());
    let residual = chain.constraint_residual(0.0, &x).unwrap();
    let moved = (x - exact).amax();
    println!(
        "chain of four links: residual {residual:.2e} after projection, {moved:.2e} from the exact joints"
    );
    assert!(residual <= 1e-14, "{residual:e}");
    assert!(moved <= 1e-14, "{moved:e}");
    // a short run keeps the chain on its constraints
    let out = Dopri5::new(1e-10, 1e-12)
        .integrate(&chain, 0.0, x, 2.0)
        .unwrap();
    let max_residual = out.max_residual.unwrap();
    println!("chain over 2 s: max residual {max_residual:.2e}");
    assert!(max_residual <= 1e-12, "{max_residual:e}");
}
