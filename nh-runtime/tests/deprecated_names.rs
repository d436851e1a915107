//! The former names of the integrators (`DormandPrince` for [`Dopri5`],
//! `Rosenbrock` for [`Rodas4`]) still compile, in every way code written
//! for 0.1 used them, and give the same results bit for bit.
#![allow(deprecated)]

use nalgebra::{Matrix2, Vector2};
use nh_runtime::{
    Dopri5, DormandPrince, Integrator, OdeJacobian, OdeSystem, Outcome, PerComponentTolerance,
    Rodas4, Rosenbrock, SimError,
};

/// A damped oscillator with a fast mode: `x' = y`, `y' = −x − 50 y`.
struct Damped;

impl OdeSystem<f64, 2> for Damped {
    fn rhs(&self, _t: f64, x: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(x[1], -x[0] - 50.0 * x[1])
    }
}

impl OdeJacobian<f64, 2> for Damped {
    fn jacobian(&self, _t: f64, _x: &Vector2<f64>) -> Matrix2<f64> {
        Matrix2::new(0.0, 1.0, -1.0, -50.0)
    }
}

const X0: Vector2<f64> = Vector2::new(1.0, 0.0);

/// A run through a generic bound, as the documentation writes them.
fn run<I: Integrator<f64>>(mut i: I) -> Result<Outcome<f64, 2>, SimError<f64, 2>> {
    i.integrate(&Damped, 0.0, X0, 2.0)
}

/// The same final state, to the bit, and the same work.
fn same(old: Outcome<f64, 2>, new: Outcome<f64, 2>) {
    assert_eq!(old.t.to_bits(), new.t.to_bits());
    assert_eq!(old.x.map(f64::to_bits), new.x.map(f64::to_bits));
    assert_eq!(old.stats, new.stats);
    assert!(new.stats.steps > 1);
}

#[test]
fn dormand_prince_is_dopri5() {
    let new = Dopri5::new(1e-8, 1e-10)
        .integrate(&Damped, 0.0, X0, 2.0)
        .unwrap();
    let old = DormandPrince::new(1e-8, 1e-10).integrate(&Damped, 0.0, X0, 2.0);
    same(old.unwrap(), new);
    // With the scalar type spelled out, through a generic bound, and as the
    // type of a binding that holds the new name.
    let turbofish = DormandPrince::<f64>::new(1e-8, 1e-10);
    same(run(turbofish).unwrap(), new);
    let annotated: DormandPrince<f64> = Dopri5::new(1e-8, 1e-10);
    same(run(annotated).unwrap(), new);
    // The builders, per-component tolerances included.
    let (rtol, atol) = (Vector2::new(1e-8, 1e-6), Vector2::new(1e-10, 1e-12));
    let built = |i: Dopri5<f64, PerComponentTolerance<f64, 2>>| i.with_max_steps(500);
    let old: DormandPrince<f64, PerComponentTolerance<f64, 2>> =
        DormandPrince::new(1.0, 1.0).with_tolerances(rtol, atol);
    let new = Dopri5::new(1.0, 1.0).with_tolerances(rtol, atol);
    same(run(built(old)).unwrap(), run(built(new)).unwrap());
    let mut old = DormandPrince::new(1e-6, 1e-9).with_max_step(0.1);
    let mut new = Dopri5::new(1e-6, 1e-9).with_max_step(0.1);
    let old_out = old.integrate(&Damped, 0.0, X0, 2.0).unwrap();
    same(old_out, new.integrate(&Damped, 0.0, X0, 2.0).unwrap());
    assert_eq!(old.last_step(), new.last_step());
    assert_eq!(old.last_stats(), new.last_stats());
}

#[test]
fn rosenbrock_is_rodas4() {
    let new = Rodas4::new(1e-8, 1e-10)
        .integrate(&Damped, 0.0, X0, 2.0)
        .unwrap();
    let old = Rosenbrock::new(1e-8, 1e-10).integrate(&Damped, 0.0, X0, 2.0);
    same(old.unwrap(), new);
    same(run(Rosenbrock::<f64>::new(1e-8, 1e-10)).unwrap(), new);
    // The analytic Jacobian and the fixed-step mode.
    let new = Rodas4::new(1e-8, 1e-10).integrate_with_jacobian(&Damped, 0.0, X0, 2.0);
    let old = Rosenbrock::new(1e-8, 1e-10).integrate_with_jacobian(&Damped, 0.0, X0, 2.0);
    same(old.unwrap(), new.unwrap());
    let old: Rosenbrock<f64> = Rosenbrock::new(1.0, 1.0).with_fixed_step(0.05);
    same(
        run(old).unwrap(),
        run(Rodas4::new(1.0, 1.0).with_fixed_step(0.05)).unwrap(),
    );
}
