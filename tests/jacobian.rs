//! `outputs { jacobian }`: the symbolic ∂f/∂x of the first-order system
//! agrees with central differences of the generated right side.
use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The thesis's disc with the Jacobian for stiff solvers.
    pub struct ThesisDisc {
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
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// refdata/random_03.json (six coordinates, two constraints; A depends on s).
    pub struct Random03 {
        parameters { k1, k2 }
        coordinates { xi, eta, q_1, q_2, r1, s1 }
        lagrangian = dot(eta)^2*(q_2^2/2 + 9/4) - dot(eta)*dot(q_1)/4 - dot(eta)*dot(q_2)*sin(r1)/3 - dot(eta)*dot(r1)/3 - dot(eta)*dot(s1)*cos(eta)*cos(s1)/3 - k2*cos(xi) + dot(q_1)^2*(sin(q_2)*cos(xi)/4 + 5/2) - 2*dot(q_1)*dot(q_2)/5 - 2*dot(q_1)*dot(s1)*cos(s1)*cos(xi)/5 - 2*q_2/5 + 7*dot(q_2)^2/4 - 2*dot(q_2)*dot(r1)*cos(eta)/5 + dot(q_2)*dot(xi)*sin(s1)*cos(eta)/4 + dot(r1)^2*(sin(q_1)^2/2 + 11/4) + 2*dot(r1)*dot(s1)/5 + 7*dot(s1)^2/4 + dot(s1)*dot(xi)*sin(eta)*cos(r1)/4 + dot(xi)^2*(q_2^2/2 + 7/4);
        constraints {
            dot(r1) = 3*s1^2/2*dot(xi) - 2*xi*cos(q_1)*dot(eta) - 1/3*dot(q_1);
            dot(s1) = -1/2*dot(xi) + 2*cos(r1)/3*dot(eta) + (q_2^2 + 1)*dot(q_2);
        }
        outputs { jacobian }
    }
}

nonholonomic_system! {
    /// A pushed sled with damping: forces depend on velocities and inputs.
    pub struct PushedSled {
        parameters { m, J, a, c }
        coordinates { x, theta, y }
        inputs { push, steer }
        lagrangian = J*dot(theta)^2/2 + m/2*((dot(x) - a*sin(theta)*dot(theta))^2 + (dot(y) + a*cos(theta)*dot(theta))^2);
        constraints { dot(y) = tan(theta)*dot(x); }
        forces { x: push*cos(theta) - c*dot(x); y: push*sin(theta) - c*dot(y); theta: steer - c*dot(theta); }
        outputs { jacobian, linearization }
    }
}

struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        lo + (hi - lo) * ((v >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// Max relative deviation of `jac` from central differences of `f` at `x`.
fn check<const D: usize>(
    f: impl Fn(&SVector<f64, D>) -> SVector<f64, D>,
    jac: &SMatrix<f64, D, D>,
    x: &SVector<f64, D>,
) -> f64 {
    let mut worst = 0.0f64;
    for c in 0..D {
        let h = 1e-6 * x[c].abs().max(1.0);
        let (mut xp, mut xm) = (*x, *x);
        xp[c] += h;
        xm[c] -= h;
        let col = (f(&xp) - f(&xm)) / (2.0 * h);
        for r in 0..D {
            worst = worst.max((jac[(r, c)] - col[r]).abs() / col[r].abs().max(1.0));
        }
    }
    worst
}

#[test]
fn thesis_disc_jacobian_matches_central_differences() {
    let d: ThesisDisc = ThesisDisc::new(1.7, 0.35, 9.81);
    let mut rng = Rng(17);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let x = SVector::<f64, 8>::from_fn(|i, _| {
            if i == 2 {
                rng.uniform(-1.2, 1.2)
            } else {
                rng.uniform(-3.0, 3.0)
            }
        });
        let j = OdeJacobian::jacobian(&d, 0.0, &x);
        worst = worst.max(check(|x| d.rhs(0.0, x), &j, &x));
    }
    println!("ThesisDisc: max relative deviation {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn coupled_system_jacobian_matches_central_differences() {
    let s: Random03 = Random03::new(1.495, 0.319);
    let mut rng = Rng(23);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let x = SVector::<f64, 10>::from_fn(|_, _| rng.uniform(-1.2, 1.2));
        let j = s.jacobian(0.0, &x);
        worst = worst.max(check(|x| s.rhs(0.0, x), &j, &x));
    }
    println!("Random03: max relative deviation {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn jacobian_with_inputs_and_velocity_dependent_forces() {
    let s: PushedSled = PushedSled::new(2.0, 0.3, 0.5, 0.4);
    let u = SVector::<f64, 2>::from([0.7, -0.2]);
    let mut rng = Rng(29);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let x = SVector::<f64, 5>::from_fn(|i, _| {
            if i == 1 {
                rng.uniform(-1.2, 1.2)
            } else {
                rng.uniform(-2.0, 2.0)
            }
        });
        let j = s.jacobian(0.0, &x, &u);
        worst = worst.max(check(|x| s.rhs_with_input(0.0, x, &u), &j, &x));
    }
    println!("PushedSled: max relative deviation {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn linearization_matches_central_differences_in_state_and_input() {
    let s: PushedSled = PushedSled::new(2.0, 0.3, 0.5, 0.4);
    let mut rng = Rng(31);
    let (mut worst_a, mut worst_b) = (0.0f64, 0.0f64);
    for _ in 0..50 {
        let x = SVector::<f64, 5>::from_fn(|i, _| {
            if i == 1 {
                rng.uniform(-1.2, 1.2)
            } else {
                rng.uniform(-2.0, 2.0)
            }
        });
        let u = SVector::<f64, 2>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let (a, b) = s.linearization(0.0, &x, &u);
        assert_eq!(a, s.jacobian(0.0, &x, &u));
        worst_a = worst_a.max(check(|x| s.rhs_with_input(0.0, x, &u), &a, &x));
        for c in 0..2 {
            let h = 1e-6;
            let (mut up, mut um) = (u, u);
            up[c] += h;
            um[c] -= h;
            let col = (s.rhs_with_input(0.0, &x, &up) - s.rhs_with_input(0.0, &x, &um)) / (2.0 * h);
            for r in 0..5 {
                worst_b = worst_b.max((b[(r, c)] - col[r]).abs() / col[r].abs().max(1.0));
            }
        }
    }
    println!("PushedSled linearization: A {worst_a:e}, B {worst_b:e}");
    assert!(worst_a < 1e-6 && worst_b < 1e-6, "{worst_a:e} {worst_b:e}");
}
