use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Oscillator {
        parameters { m, c, k }
        coordinates { x }
        lagrangian = m*dot(x)^2/2 - k*x^2/2;
        forces { x: -c*dot(x); }
        outputs { sensitivities(mass, k, k) }
    }
}

fn main() {
    // the stand-in keeps the three columns listed: no follow-up errors
    let osc = Oscillator::new(1.0, 0.1, 4.0);
    let x = SVector::<f64, 2>::from([1.0, 0.0]);
    let _: SMatrix<f64, 2, 3> = osc.parameter_jacobian(0.0, &x);
    let _: [&str; 3] = Oscillator::SENSITIVITY_PARAMETERS;
    let sens = osc.sensitivities();
    let x0 = sens.initial_state(&x);
    let out = Dopri5::new(1e-8, 1e-10).integrate(&sens, 0.0, x0, 1.0).unwrap();
    let (_x, _dx_dp, _dx_dx0) = sens.split(&out.x);
    let _: SVector<f64, 2> = osc.time_derivative(0.0, &x);
}
