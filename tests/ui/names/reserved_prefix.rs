use nonholonomic::prelude::*;

// Names starting with `__nh_` are the generated code's: one error at each
// such name, none from inside the generated code, none at the uses.
nonholonomic_system! {
    pub struct Slope {
        parameters { m, __nh_cache }
        coordinates { x, y }
        let __nh_drop = sin(__nh_cache);
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2 - m*__nh_drop*x;
    }
}

fn main() {
    let s = Slope::new(1.0, 0.2);
    let q = SVector::<f64, 2>::from([0.1, 0.2]);
    let rdot = SVector::<f64, 2>::from([0.5, 1.0]);
    let _: SVector<f64, 2> = s.accelerations(0.0, &q, &rdot);
    let _ = Slope::from_parameters(SlopeParameters { m: 1.0, __nh_cache: 0.2 });
    let x0 = SVector::<f64, 4>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&s, 0.0, x0, 1.0);
}
