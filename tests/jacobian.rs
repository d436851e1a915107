//! `outputs { jacobian }`: the symbolic ∂f/∂x of the first-order system
//! agrees with central differences of the generated right side.
use nonholonomic::prelude::*;

#[path = "common/differences.rs"]
mod central;

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

nonholonomic_system! {
    /// The dense synthetic system of the scaling benchmark at n = 12 (four
    /// constraints): its Jacobian goes through the multiplier route and is
    /// long enough (over 2,000 statements) to be emitted in blocks.
    pub struct Dense12 { parameters { g } coordinates { q1, q2, q3, q4, q5, q6, q7, q8, q9, q10, q11, q12 } lagrangian = (20/10)*dot(q1)^2/2 + cos(q1 - q2)*dot(q1)*dot(q2)/6 + cos(q1 - q3)*dot(q1)*dot(q3)/8 + cos(q1 - q4)*dot(q1)*dot(q4)/10 + cos(q1 - q5)*dot(q1)*dot(q5)/12 + cos(q1 - q6)*dot(q1)*dot(q6)/14 + cos(q1 - q7)*dot(q1)*dot(q7)/16 + cos(q1 - q8)*dot(q1)*dot(q8)/18 + cos(q1 - q9)*dot(q1)*dot(q9)/20 + cos(q1 - q10)*dot(q1)*dot(q10)/22 + cos(q1 - q11)*dot(q1)*dot(q11)/24 + cos(q1 - q12)*dot(q1)*dot(q12)/26 + g*cos(q1)/1 + (21/10)*dot(q2)^2/2 + cos(q2 - q3)*dot(q2)*dot(q3)/10 + cos(q2 - q4)*dot(q2)*dot(q4)/12 + cos(q2 - q5)*dot(q2)*dot(q5)/14 + cos(q2 - q6)*dot(q2)*dot(q6)/16 + cos(q2 - q7)*dot(q2)*dot(q7)/18 + cos(q2 - q8)*dot(q2)*dot(q8)/20 + cos(q2 - q9)*dot(q2)*dot(q9)/22 + cos(q2 - q10)*dot(q2)*dot(q10)/24 + cos(q2 - q11)*dot(q2)*dot(q11)/26 + cos(q2 - q12)*dot(q2)*dot(q12)/28 + g*cos(q2)/2 + (22/10)*dot(q3)^2/2 + cos(q3 - q4)*dot(q3)*dot(q4)/14 + cos(q3 - q5)*dot(q3)*dot(q5)/16 + cos(q3 - q6)*dot(q3)*dot(q6)/18 + cos(q3 - q7)*dot(q3)*dot(q7)/20 + cos(q3 - q8)*dot(q3)*dot(q8)/22 + cos(q3 - q9)*dot(q3)*dot(q9)/24 + cos(q3 - q10)*dot(q3)*dot(q10)/26 + cos(q3 - q11)*dot(q3)*dot(q11)/28 + cos(q3 - q12)*dot(q3)*dot(q12)/30 + g*cos(q3)/3 + (23/10)*dot(q4)^2/2 + cos(q4 - q5)*dot(q4)*dot(q5)/18 + cos(q4 - q6)*dot(q4)*dot(q6)/20 + cos(q4 - q7)*dot(q4)*dot(q7)/22 + cos(q4 - q8)*dot(q4)*dot(q8)/24 + cos(q4 - q9)*dot(q4)*dot(q9)/26 + cos(q4 - q10)*dot(q4)*dot(q10)/28 + cos(q4 - q11)*dot(q4)*dot(q11)/30 + cos(q4 - q12)*dot(q4)*dot(q12)/32 + g*cos(q4)/4 + (24/10)*dot(q5)^2/2 + cos(q5 - q6)*dot(q5)*dot(q6)/22 + cos(q5 - q7)*dot(q5)*dot(q7)/24 + cos(q5 - q8)*dot(q5)*dot(q8)/26 + cos(q5 - q9)*dot(q5)*dot(q9)/28 + cos(q5 - q10)*dot(q5)*dot(q10)/30 + cos(q5 - q11)*dot(q5)*dot(q11)/32 + cos(q5 - q12)*dot(q5)*dot(q12)/34 + g*cos(q5)/5 + (25/10)*dot(q6)^2/2 + cos(q6 - q7)*dot(q6)*dot(q7)/26 + cos(q6 - q8)*dot(q6)*dot(q8)/28 + cos(q6 - q9)*dot(q6)*dot(q9)/30 + cos(q6 - q10)*dot(q6)*dot(q10)/32 + cos(q6 - q11)*dot(q6)*dot(q11)/34 + cos(q6 - q12)*dot(q6)*dot(q12)/36 + g*cos(q6)/6 + (26/10)*dot(q7)^2/2 + cos(q7 - q8)*dot(q7)*dot(q8)/30 + cos(q7 - q9)*dot(q7)*dot(q9)/32 + cos(q7 - q10)*dot(q7)*dot(q10)/34 + cos(q7 - q11)*dot(q7)*dot(q11)/36 + cos(q7 - q12)*dot(q7)*dot(q12)/38 + g*cos(q7)/7 + (27/10)*dot(q8)^2/2 + cos(q8 - q9)*dot(q8)*dot(q9)/34 + cos(q8 - q10)*dot(q8)*dot(q10)/36 + cos(q8 - q11)*dot(q8)*dot(q11)/38 + cos(q8 - q12)*dot(q8)*dot(q12)/40 + g*cos(q8)/8 + (28/10)*dot(q9)^2/2 + cos(q9 - q10)*dot(q9)*dot(q10)/38 + cos(q9 - q11)*dot(q9)*dot(q11)/40 + cos(q9 - q12)*dot(q9)*dot(q12)/42 + g*cos(q9)/9 + (29/10)*dot(q10)^2/2 + cos(q10 - q11)*dot(q10)*dot(q11)/42 + cos(q10 - q12)*dot(q10)*dot(q12)/44 + g*cos(q10)/10 + (30/10)*dot(q11)^2/2 + cos(q11 - q12)*dot(q11)*dot(q12)/46 + g*cos(q11)/11 + (31/10)*dot(q12)^2/2 + g*cos(q12)/12; constraints { dot(q9) = sin(q1 + q9)/2*dot(q1) + sin(q2 + q9)/3*dot(q2) + sin(q3 + q9)/4*dot(q3) + sin(q4 + q9)/5*dot(q4) + sin(q5 + q9)/6*dot(q5) + sin(q6 + q9)/7*dot(q6) + sin(q7 + q9)/8*dot(q7) + sin(q8 + q9)/9*dot(q8); dot(q10) = sin(q1 + q10)/3*dot(q1) + sin(q2 + q10)/4*dot(q2) + sin(q3 + q10)/5*dot(q3) + sin(q4 + q10)/6*dot(q4) + sin(q5 + q10)/7*dot(q5) + sin(q6 + q10)/8*dot(q6) + sin(q7 + q10)/9*dot(q7) + sin(q8 + q10)/10*dot(q8); dot(q11) = sin(q1 + q11)/4*dot(q1) + sin(q2 + q11)/5*dot(q2) + sin(q3 + q11)/6*dot(q3) + sin(q4 + q11)/7*dot(q4) + sin(q5 + q11)/8*dot(q5) + sin(q6 + q11)/9*dot(q6) + sin(q7 + q11)/10*dot(q7) + sin(q8 + q11)/11*dot(q8); dot(q12) = sin(q1 + q12)/5*dot(q1) + sin(q2 + q12)/6*dot(q2) + sin(q3 + q12)/7*dot(q3) + sin(q4 + q12)/8*dot(q4) + sin(q5 + q12)/9*dot(q5) + sin(q6 + q12)/10*dot(q6) + sin(q7 + q12)/11*dot(q7) + sin(q8 + q12)/12*dot(q8); } outputs { jacobian } }
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
        worst = worst.max(central::jacobian_deviation(|x| d.rhs(0.0, x), &j, &x));
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
        worst = worst.max(central::jacobian_deviation(|x| s.rhs(0.0, x), &j, &x));
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
        worst = worst.max(central::jacobian_deviation(
            |x| s.rhs_with_input(0.0, x, &u),
            &j,
            &x,
        ));
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
        worst_a = worst_a.max(central::jacobian_deviation(
            |x| s.rhs_with_input(0.0, x, &u),
            &a,
            &x,
        ));
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

#[test]
fn large_jacobian_in_blocks_matches_central_differences() {
    let sys = Dense12::new(9.81);
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    for _ in 0..5 {
        let x = SVector::<f64, 20>::from_fn(|_, _| rng.uniform(-1.0, 1.0));
        let jac = sys.jacobian(0.0, &x);
        let err = central::jacobian_deviation(|x| sys.rhs(0.0, x), &jac, &x);
        assert!(err < 1e-6, "deviation {err:e}");
    }
}
