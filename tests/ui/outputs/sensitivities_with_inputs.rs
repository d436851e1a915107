use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Cart {
        parameters { m, c }
        coordinates { x }
        inputs { u }
        lagrangian = m*dot(x)^2/2;
        forces { x: u - c*dot(x); }
        outputs { sensitivities }
    }
}

fn main() {
    let cart = Cart::new(1.0, 0.5);
    let x = SVector::<f64, 2>::zeros();
    let u = SVector::<f64, 1>::from([1.0]);
    let _: SMatrix<f64, 2, 2> = cart.parameter_jacobian(0.0, &x, &u);
    let _: SMatrix<f64, 2, 2> = cart.jacobian(0.0, &x, &u);
    let _ = Driven::new(&cart, u);
}
