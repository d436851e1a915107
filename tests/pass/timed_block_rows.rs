//! Four implicit rows, one whose coefficients move with t (homogeneous, not
//! affine) by a factor that cancels from the solved velocities: the block
//! is solved symbolically, not by the numeric LU of time-independent
//! blocks. Before, that LU evaluated the row at `t` in
//! `dependent_velocities`, which (its velocities free of t) does not take
//! `t`: a compile error in the generated code, found by the differential
//! verification.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct TimedBlock {
        parameters { w }
        coordinates { a, b, c, d, e, f }
        lagrangian = (dot(a)^2 + dot(b)^2 + dot(c)^2 + dot(d)^2 + dot(e)^2 + dot(f)^2)/2;
        constraints {
            dot(a) + dot(b) + sin(e)*dot(f) = 0;
            dot(b) - dot(c) + cos(e)*dot(f) = 0;
            dot(c) + 2*dot(d) - dot(e) = 0;
            cos(w*t)*(dot(d) + dot(a)/2 + dot(e)/3) = 0;
        }
    }
}

fn main() {
    let sys = TimedBlock::new(1.3);
    let q = SVector::<f64, 6>::new(0.1, 0.2, 0.3, 0.4, 0.5, 0.6);
    let rdot = SVector::<f64, 2>::new(0.7, -0.4);
    let sdot = sys.dependent_velocities(&q, &rdot);
    // the fourth row holds: ḋ + ȧ/2 + ė/3 = 0 (a, e independent or not)
    let mut v = [0.0; 6];
    for (j, &i) in TimedBlock::INDEPENDENT.iter().enumerate() {
        v[i] = rdot[j];
    }
    for (a, &s) in TimedBlock::DEPENDENT.iter().enumerate() {
        v[s] = sdot[a];
    }
    assert!((v[3] + v[0] / 2.0 + v[4] / 3.0).abs() < 1e-14);
    let _ = sys.accelerations(0.3, &q, &rdot);
}
