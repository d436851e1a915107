use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { t, m }
        coordinates { x, sin }
        inputs { pi }
        lagrangian = m*dot(x)^2/2;
    }
}

fn main() {
    let slide = Slide::new(1.0, 0.5);
    let q = SVector::<f64, 2>::from([0.1, 0.2]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let inputs = SVector::<f64, 1>::from([1.0]);
    let _: SVector<f64, 2> = slide.accelerations(0.0, &q, &rdot, &inputs);
    let x0 = SVector::<f64, 4>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&Driven::new(&slide, inputs), 0.0, x0, 1.0);
}
