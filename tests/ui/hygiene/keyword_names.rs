use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Keywords cannot name anything the generated code declares.
    pub struct Slide {
        parameters { m, self, Self }
        coordinates { x, super }
        inputs { crate }
        let _ = m*x;
        lagrangian = m/2*dot(x)^2 + self*dot(super)^2 - Self*x^2;
        forces { x: crate; }
    }
}

fn main() {
    let s: Slide = Slide::new(1.0, 2.0, 3.0);
    let _ = s.m;
    let u = SVector::<f64, 1>::from([0.0]);
    let _ = s.accelerations(0.0, &SVector::from([0.1, 0.2]), &SVector::from([0.0, 0.0]), &u);
}
