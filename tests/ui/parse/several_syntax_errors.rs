use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Three independent mistakes, reported in one compilation.
    pub struct Slide {
        parameters { m k }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - k*x^^2;
        constraints { dot(y) = ; }
    }
}

fn main() {
    let slide = Slide::new(1.0, 0.5);
    let q = SVector::<f64, 2>::from([0.1, 0.2]);
    let rdot = SVector::<f64, 1>::from([0.5]);
    let _: SVector<f64, 1> = slide.accelerations(0.0, &q, &rdot);
    let _: SVector<f64, 1> = slide.dependent_velocities(&q, &rdot);
    let x0 = SVector::<f64, 3>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&slide, 0.0, x0, 1.0);
}
