//! A raw identifier is the same name as its plain spelling, as in Rust:
//! `r#x` declared, `x` used (and the other way round); keywords work raw.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Raw {
        parameters { m, r#type }
        coordinates { r#x, y }
        lagrangian = m/2*(dot(x)^2 + dot(r#y)^2) - r#type/2*r#x^2 - m*y;
    }
}

fn main() {
    let s = Raw::new(2.0, 0.2);
    assert_eq!(s.r#type, 0.2);
    let a = s.accelerations(0.0, &SVector::from([1.0, 0.0]), &SVector::from([0.0, 0.0]));
    // m ẍ = −type·x, m ÿ = −m
    assert_eq!(a, SVector::<f64, 2>::from([-0.1, -1.0]));
    assert_eq!(Raw::<f64>::COORDINATES, ["x", "y"]);
}
