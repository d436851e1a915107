//! The thesis's own result: the rolling disc of section 6 reproduces
//! (6.60)–(6.62) and the curvature (6.35)–(6.38).
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Rolling disc of the thesis, section 6, written with the centre of mass.
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
        outputs { multipliers, curvature, energy, routes }
    }
}

nonholonomic_system! {
    /// The same disc with the Lagrangian expanded as in (6.22)–(6.23).
    pub struct ThesisDiscExpanded {
        parameters { m, R, g }
        coordinates { theta, phi, psi, x, y }
        let F = 2*R*(dot(phi)*sin(psi)*(dot(x)*cos(phi) + dot(y)*sin(phi))
                   + dot(psi)*cos(psi)*(dot(x)*sin(phi) - dot(y)*cos(phi)));   // (6.23)
        lagrangian = m/2*(dot(x)^2 + dot(y)^2 + 5*R^2/4*dot(psi)^2
                          + R^2*(1/4 + sin(psi)^2)*dot(phi)^2 + R^2/2*dot(theta)^2
                          - 2*g*R*cos(psi) - F);                               // (6.22)
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
        outputs { multipliers, curvature, energy }
    }
}

/// xorshift64*: a small deterministic generator for random states.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

fn random_state(rng: &mut Rng) -> (SVector<f64, 5>, SVector<f64, 3>) {
    let q = SVector::<f64, 5>::from_fn(|i, _| match i {
        2 => rng.uniform(-1.4, 1.4), // lean ψ away from ±π/2
        _ => rng.uniform(-3.0, 3.0),
    });
    let rdot = SVector::<f64, 3>::from_fn(|_, _| rng.uniform(-5.0, 5.0));
    (q, rdot)
}

/// (6.60)–(6.62) solved for the accelerations (DESIGN §4).
fn closed_form(d: &ThesisDisc, q: &SVector<f64, 5>, rdot: &SVector<f64, 3>) -> [f64; 3] {
    let (psi, td, pd, sd) = (q[2], rdot[0], rdot[1], rdot[2]);
    let den = 4.0 * psi.sin().powi(2) + 3.0;
    [
        4.0 * psi.cos() * pd * sd / den,
        -4.0 * (2.0 * psi).sin() * pd * sd / den,
        4.0 * (d.R * (psi.sin() * pd - td) * psi.cos() * pd + d.g * psi.sin()) / (5.0 * d.R),
    ]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1.0)
}

#[test]
fn accelerations_reproduce_the_thesis_closed_form() {
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let (q, rdot) = random_state(&mut rng);
        let a = d.accelerations(0.0, &q, &rdot);
        let c = closed_form(&d, &q, &rdot);
        for i in 0..3 {
            worst = worst.max(rel(a[i], c[i]));
        }
    }
    println!("max relative deviation from (6.60)-(6.62) over 200 states: {worst:e}");
    assert!(worst <= 1e-12, "{worst:e}");
}

#[test]
fn expanded_lagrangian_gives_the_same_system() {
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let e = ThesisDiscExpanded::new(1.7, 0.35, 9.81);
    let mut rng = Rng(7);
    for _ in 0..100 {
        let (q, rdot) = random_state(&mut rng);
        let (a, b) = (
            d.accelerations(0.0, &q, &rdot),
            e.accelerations(0.0, &q, &rdot),
        );
        let (la, lb) = (d.multipliers(0.0, &q, &rdot), e.multipliers(0.0, &q, &rdot));
        for i in 0..3 {
            assert!(rel(a[i], b[i]) <= 1e-13, "{a} vs {b}");
        }
        for i in 0..2 {
            assert!(rel(la[i], lb[i]) <= 1e-13, "{la} vs {lb}");
        }
        assert!(rel(d.energy(&q, &rdot), e.energy(&q, &rdot)) <= 1e-13);
    }
}

#[test]
fn curvature_is_6_35_to_6_38() {
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(11);
    for _ in 0..100 {
        let (q, _) = random_state(&mut rng);
        let b = d.curvature(&q);
        let (r, phi) = (d.R, q[1]);
        let expect = |bb: usize, al: usize, be: usize| -> f64 {
            match (bb, al, be) {
                (0, 0, 1) => r * phi.sin(),  // (6.35)
                (1, 0, 1) => -r * phi.cos(), // (6.36)
                (0, 1, 0) => -r * phi.sin(), // (6.37)
                (1, 1, 0) => r * phi.cos(),  // (6.38)
                _ => 0.0,                    // all other B's zero
            }
        };
        for (bb, mat) in b.iter().enumerate() {
            for al in 0..3 {
                for be in 0..3 {
                    let e = expect(bb, al, be);
                    assert!((mat[(al, be)] - e).abs() <= 1e-15, "B[{bb}][({al},{be})]");
                }
            }
        }
    }
    const { assert!(!ThesisDisc::<f64>::INTEGRABLE) };
}

#[test]
fn routes_agree_and_multipliers_sign_convention() {
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(3);
    for _ in 0..100 {
        let (q, rdot) = random_state(&mut rng);
        let a = d.accelerations_multiplier_route(0.0, &q, &rdot);
        let b = d.accelerations_curvature_route(0.0, &q, &rdot);
        for i in 0..3 {
            assert!(rel(a[i], b[i]) <= 1e-12, "{a} vs {b}");
        }
        // (5.10) for this Lagrangian by hand: λ_x = d/dt ∂L/∂ẋ with
        // ∂L/∂ẋ = m ẋ − m R (φ̇ sinψ cosφ + ψ̇ cosψ sinφ) (6.52), ∂L/∂x = 0.
        let (m, r) = (d.m, d.R);
        let (phi, psi) = (q[1], q[2]);
        let (td, pd, sd) = (rdot[0], rdot[1], rdot[2]);
        let (tdd, pdd, sdd) = (b[0], b[1], b[2]);
        // ẍ = d/dt (R cosφ θ̇)
        let xdd = r * (-phi.sin() * pd * td + phi.cos() * tdd);
        let ddt_term = pdd * psi.sin() * phi.cos()
            + pd * (psi.cos() * sd * phi.cos() - psi.sin() * phi.sin() * pd)
            + sdd * psi.cos() * phi.sin()
            + sd * (-psi.sin() * sd * phi.sin() + psi.cos() * phi.cos() * pd);
        let lambda_x = m * xdd - m * r * ddt_term;
        let lam = d.multipliers(0.0, &q, &rdot);
        assert!(rel(lam[0], lambda_x) <= 1e-11, "{} vs {lambda_x}", lam[0]);
    }
}

#[test]
fn single_precision_agrees() {
    let d64 = ThesisDisc::new(1.7, 0.35, 9.81);
    let d32 = ThesisDisc::<f32>::new(1.7, 0.35, 9.81);
    let mut rng = Rng(5);
    for _ in 0..100 {
        let (q, rdot) = random_state(&mut rng);
        let a = d64.accelerations(0.0, &q, &rdot);
        let b = d32.accelerations(0.0, &q.cast::<f32>(), &rdot.cast::<f32>());
        for i in 0..3 {
            assert!(rel(a[i], b[i] as f64) <= 1e-4, "{a} vs {b}");
        }
    }
}

#[test]
fn state_layout_and_runtime_rhs() {
    assert_eq!(
        ThesisDisc::<f64>::COORDINATES,
        ["theta", "phi", "psi", "x", "y"]
    );
    assert_eq!(ThesisDisc::<f64>::INDEPENDENT, [0, 1, 2]);
    assert_eq!(ThesisDisc::<f64>::DEPENDENT, [3, 4]);
    let d = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(9);
    let (q, rdot) = random_state(&mut rng);
    let x = SVector::<f64, 8>::from_fn(|i, _| if i < 5 { q[i] } else { rdot[i - 5] });
    let dx = d.rhs(0.0, &x);
    let sdot = d.dependent_velocities(&q, &rdot);
    let rdd = d.accelerations(0.0, &q, &rdot);
    let expect = [
        rdot[0], rdot[1], rdot[2], sdot[0], sdot[1], rdd[0], rdd[1], rdd[2],
    ];
    for i in 0..8 {
        assert!(rel(dx[i], expect[i]) <= 1e-15, "component {i}");
    }
    // ṡ = −A ṙ with A of (6.33)-(6.34)
    assert!(rel(sdot[0], d.R * q[1].cos() * rdot[0]) <= 1e-15);
    assert!(rel(sdot[1], d.R * q[1].sin() * rdot[0]) <= 1e-15);
}

/// Constants of the user's scope named like parameters must not break the expansion.
mod scope_hygiene {
    #![allow(dead_code, non_upper_case_globals)]
    use nonholonomic::prelude::*;
    const R: f64 = 0.35;
    const m: f64 = 1.0;
    nonholonomic_system! {
        pub struct Hoop {
            parameters { m, R }
            coordinates { x }
            lagrangian = m*R^2*dot(x)^2/2;
        }
    }
    #[test]
    fn parameters_named_like_constants() {
        let h = Hoop::new(m, R);
        let a = h.accelerations(
            0.0,
            &SVector::<f64, 1>::from([0.1]),
            &SVector::<f64, 1>::from([1.0]),
        );
        assert_eq!(a[0], 0.0);
    }
}

#[test]
fn changing_a_parameter_field_never_reads_a_stale_cache() {
    // values that depend on parameters alone are cached when the system is
    // built; the fields are public, so a changed field must be honoured
    let mut d: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let q = SVector::<f64, 5>::from([0.1, 0.2, 0.3, 0.4, 0.5]);
    let rdot = SVector::<f64, 3>::from([4.0, 2.0, 1.0]);
    d.g = 1.62; // to the moon
    d.R = 0.5;
    let fresh: ThesisDisc = ThesisDisc::new(1.7, 0.5, 1.62);
    assert_eq!(
        d.accelerations(0.0, &q, &rdot),
        fresh.accelerations(0.0, &q, &rdot)
    );
    assert_eq!(
        d.multipliers(0.0, &q, &rdot),
        fresh.multipliers(0.0, &q, &rdot)
    );
    let c = closed_form(&fresh, &q, &rdot);
    let a = d.accelerations(0.0, &q, &rdot);
    assert!((0..3).all(|i| rel(a[i], c[i]) <= 1e-12));
}
