use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { mass, k }
        coordinates { x }
        lagrangian = mas*dot(x)^2/2 - k*x^2/2;
    }
}

fn main() {
    let slide = Slide::new(1.0, 0.5);
    let q = SVector::<f64, 1>::from([0.1]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = slide.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 2>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&slide, 0.0, x0, 1.0);
}
