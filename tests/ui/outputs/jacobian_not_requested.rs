// Rodas4 with the analytic Jacobian, for systems whose definitions do
// not ask for it (one with inputs, held by `Driven`, one without): each
// error names the missing trait and the output to add.
use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pushed {
        parameters { m, c }
        coordinates { x }
        inputs { F }
        lagrangian = m*dot(x)^2/2;
        forces { x: F - c*dot(x); }
    }
}

nonholonomic_system! {
    pub struct Damped {
        parameters { m, c }
        coordinates { x }
        lagrangian = m*dot(x)^2/2;
        forces { x: -c*dot(x); }
    }
}

fn main() {
    let cart: Pushed = Pushed::new(1.0, 50.0);
    let driven = Driven::new(&cart, SVector::from([5.0]));
    let x0 = Pushed::state(PushedCoordinates { x: 0.0 }, PushedVelocities { x: 0.0 });
    let out = Rodas4::new(1e-8, 1e-10).integrate_with_jacobian(&driven, 0.0, x0, 1.0);
    println!("{:?}", out.map(|o| o.x));

    let damped: Damped = Damped::new(1.0, 50.0);
    let x0 = Damped::state(DampedCoordinates { x: 0.0 }, DampedVelocities { x: 1.0 });
    let out = Rodas4::new(1e-8, 1e-10).integrate_with_jacobian(&damped, 0.0, x0, 1.0);
    println!("{:?}", out.map(|o| o.x));
}
