use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Oscillator {
        parameters { m, k }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        outputs { energy(m), sensitivities() }
    }
}

fn main() {
    let osc = Oscillator::new(1.0, 4.0);
    let q = SVector::<f64, 1>::from([1.0]);
    let _: f64 = osc.energy(&q, &q);
    let _ = osc.sensitivities();
}
