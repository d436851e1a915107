use nonholonomic::prelude::*;

nonholonomic_system! {
    pub fn Slide {
        coordinates { x }
        lagrangian = dot(x)^2;
    }
}

fn main() {
    let slide = Slide::new();
    let q = SVector::<f64, 1>::from([0.1]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = slide.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 2>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&slide, 0.0, x0, 1.0);
}
