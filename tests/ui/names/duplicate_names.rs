use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Slide {
        parameters { m, x }
        coordinates { x, y, y }
        lagrangian = m*dot(x)^2/2 + m*dot(y)^2/2;
    }
}

fn main() {
    let slide = Slide::new(1.0, 0.5);
    let q = SVector::<f64, 3>::from([0.1, 0.2, 0.3]);
    let rdot = SVector::<f64, 3>::from([0.5, 1.0, 1.5]);
    let _: SVector<f64, 3> = slide.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 6>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&slide, 0.0, x0, 1.0);
}
