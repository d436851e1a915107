//! The methods compared: ours (the runtime's integrators) and the peers'
//! (ode_solvers, diffsol, russell_ode), each behind the same signature and
//! handed the same generated right-hand side and Jacobian.
//!
//! Adding one of ours is one entry in [`our_methods`].

use std::cell::RefCell;

use nonholonomic::prelude::*;

use crate::measure::{Counted, Sys};

/// The start of a run: initial state at t = 0, final time, step budget.
#[derive(Clone, Copy, Debug)]
pub struct Start<const D: usize> {
    /// The state at t = 0.
    pub x0: SVector<f64, D>,
    /// The final time.
    pub t1: f64,
    /// The most steps a method may take.
    pub max_steps: usize,
}

/// The end of a successful run.
#[derive(Clone, Copy, Debug)]
pub struct Finish<const D: usize> {
    /// The state at the final time.
    pub x: SVector<f64, D>,
    /// Accepted steps.
    pub steps: usize,
}

/// Who wrote a method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Suite {
    /// This project's runtime.
    Ours,
    /// The `ode_solvers` crate.
    OdeSolvers,
    /// The `diffsol` crate.
    Diffsol,
    /// The `russell_ode` crate.
    Russell,
}

impl Suite {
    /// The suite's name as printed.
    pub fn label(self) -> &'static str {
        match self {
            Suite::Ours => "ours",
            Suite::OdeSolvers => "ode_solvers",
            Suite::Diffsol => "diffsol",
            Suite::Russell => "russell_ode",
        }
    }
}

/// What a method's ladder varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// The relative tolerance (absolute tolerance = [`ATOL_PER_RTOL`] × rtol).
    Tolerance,
    /// The fixed step size.
    StepSize,
}

/// One run of a method at one setting on the counting wrapper of a system.
pub type RunFn<S, const D: usize> =
    for<'a> fn(&Counted<'a, S>, &Start<D>, f64) -> Result<Finish<D>, String>;

/// A method: its name, its author, what its ladder varies and how to run it.
pub struct Method<S, const D: usize> {
    /// The name as printed (unique across suites).
    pub name: &'static str,
    /// Who wrote it.
    pub suite: Suite,
    /// Tolerance or step size.
    pub setting: Setting,
    /// One run.
    pub run: RunFn<S, D>,
}

/// The absolute tolerance of every adaptive run is this × its relative tolerance.
pub const ATOL_PER_RTOL: f64 = 1e-2;

/// The absolute tolerance that goes with `rtol`.
pub fn atol(rtol: f64) -> f64 {
    rtol * ATOL_PER_RTOL
}

fn method<S, const D: usize>(
    suite: Suite,
    name: &'static str,
    setting: Setting,
    run: RunFn<S, D>,
) -> Method<S, D> {
    Method {
        name,
        suite,
        setting,
        run,
    }
}

/// One of ours: a name, the setting its ladder varies, and the run.
fn ours<S, const D: usize>(name: &'static str, setting: Setting, run: RunFn<S, D>) -> Method<S, D> {
    method(Suite::Ours, name, setting, run)
}

/// Our outcome as a [`Finish`].
fn done<const D: usize>(r: Result<Outcome<f64, D>, SimError<f64, D>>) -> Result<Finish<D>, String> {
    r.map(|o| Finish {
        x: o.x,
        steps: o.stats.steps,
    })
    .map_err(|e| e.to_string())
}

/// Our methods. To add one, add one entry: name, setting, and the call
/// that integrates `s` from `p.x0` at t = 0 to `p.t1` at setting `v`.
pub fn our_methods<S: Sys<D>, const D: usize>() -> Vec<Method<S, D>> {
    use Setting::{StepSize, Tolerance};
    vec![
        ours("Dopri5", Tolerance, |s, p, v| {
            done(
                Dopri5::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Dop853", Tolerance, |s, p, v| {
            done(
                Dop853::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Rodas4", Tolerance, |s, p, v| {
            done(
                Rodas4::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate_with_jacobian(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Rodas5P", Tolerance, |s, p, v| {
            done(
                Rodas5P::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate_with_jacobian(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Bdf (NDF 1-5)", Tolerance, |s, p, v| {
            done(
                Bdf::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate_with_jacobian(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("AutoSwitch (DP5/Rodas4)", Tolerance, |s, p, v| {
            done(
                AutoSwitch::new(v, atol(v))
                    .with_max_steps(p.max_steps)
                    .integrate_with_jacobian(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Rk4", StepSize, |s, p, v| {
            done(
                Rk4::new(v)
                    .with_max_steps(p.max_steps)
                    .integrate(s, 0.0, p.x0, p.t1),
            )
        }),
        ours("Gauss-Legendre 4", StepSize, |s, p, v| {
            done(
                GaussLegendre4::new(v)
                    .with_max_steps(p.max_steps)
                    .integrate_with_jacobian(s, 0.0, p.x0, p.t1),
            )
        }),
    ]
}

/// Every peer's methods.
pub fn peer_methods<S: Sys<D>, const D: usize>() -> Vec<Method<S, D>> {
    use Setting::{StepSize, Tolerance};
    use Suite::{Diffsol, OdeSolvers, Russell};
    vec![
        method(OdeSolvers, "ode_solvers Dopri5", Tolerance, |s, p, v| {
            ode_solvers_peer::dopri5(s, p, v)
        }),
        method(OdeSolvers, "ode_solvers Dop853", Tolerance, |s, p, v| {
            ode_solvers_peer::dop853(s, p, v)
        }),
        method(OdeSolvers, "ode_solvers Rk4", StepSize, |s, p, v| {
            ode_solvers_peer::rk4(s, p, v)
        }),
        method(Diffsol, "diffsol bdf", Tolerance, |s, p, v| {
            diffsol_peer::run(s, p, v, diffsol_peer::Kind::Bdf)
        }),
        method(Diffsol, "diffsol esdirk34", Tolerance, |s, p, v| {
            diffsol_peer::run(s, p, v, diffsol_peer::Kind::Esdirk34)
        }),
        method(Diffsol, "diffsol tr_bdf2", Tolerance, |s, p, v| {
            diffsol_peer::run(s, p, v, diffsol_peer::Kind::TrBdf2)
        }),
        method(Diffsol, "diffsol tsit45", Tolerance, |s, p, v| {
            diffsol_peer::run(s, p, v, diffsol_peer::Kind::Tsit45)
        }),
        method(Russell, "russell Radau5", Tolerance, |s, p, v| {
            russell_peer::run(s, p, v, russell_ode::prelude::Method::Radau5)
        }),
        method(Russell, "russell DoPri5", Tolerance, |s, p, v| {
            russell_peer::run(s, p, v, russell_ode::prelude::Method::DoPri5)
        }),
        method(Russell, "russell DoPri8", Tolerance, |s, p, v| {
            russell_peer::run(s, p, v, russell_ode::prelude::Method::DoPri8)
        }),
    ]
}

/// `ode_solvers` (nalgebra 0.34): the state is copied between its vectors
/// and ours at every call. Output is `Sparse` (the accepted steps, no
/// interpolation; `Dense` would cost Dop853 three more right-hand sides a step).
pub mod ode_solvers_peer {
    use super::*;
    use ode_solvers::{Dop853 as ODop853, Dopri5 as ODopri5, OutputType, Rk4 as ORk4, System};

    type OVec<const D: usize> = ode_solvers::SVector<f64, D>;

    struct Adapter<'s, 'a, S>(&'s Counted<'a, S>);

    impl<S: Sys<D>, const D: usize> System<f64, OVec<D>> for Adapter<'_, '_, S> {
        #[inline]
        fn system(&self, t: f64, y: &OVec<D>, dy: &mut OVec<D>) {
            let f = self.0.rhs(t, &SVector::from_column_slice(y.as_slice()));
            dy.as_mut_slice().copy_from_slice(f.as_slice());
        }
    }

    fn ours<const D: usize>(y: &OVec<D>) -> SVector<f64, D> {
        SVector::from_column_slice(y.as_slice())
    }

    fn last<const D: usize>(ys: &[OVec<D>], steps: u32) -> Result<Finish<D>, String> {
        ys.last()
            .map(|y| Finish {
                x: ours(y),
                steps: steps as usize,
            })
            .ok_or_else(|| "no output".to_string())
    }

    /// Dopri5 at `rtol`.
    pub fn dopri5<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        rtol: f64,
    ) -> Result<Finish<D>, String> {
        let y0 = OVec::<D>::from_column_slice(p.x0.as_slice());
        let mut solver = ODopri5::new(Adapter(s), 0.0, p.t1, p.t1, y0, rtol, atol(rtol));
        solver.set_output(OutputType::Sparse);
        let stats = solver.integrate().map_err(|e| e.to_string())?;
        last(solver.y_out(), stats.accepted_steps)
    }

    /// Dop853 at `rtol`.
    pub fn dop853<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        rtol: f64,
    ) -> Result<Finish<D>, String> {
        let y0 = OVec::<D>::from_column_slice(p.x0.as_slice());
        let mut solver = ODop853::new(Adapter(s), 0.0, p.t1, p.t1, y0, rtol, atol(rtol));
        solver.set_output(OutputType::Sparse);
        let stats = solver.integrate().map_err(|e| e.to_string())?;
        last(solver.y_out(), stats.accepted_steps)
    }

    /// Dop853 at `rtol` with ode_solvers' default controller but a step
    /// budget of `p.max_steps` and no stiffness test: the reference's
    /// cross-check.
    pub fn dop853_unlimited<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        rtol: f64,
    ) -> Result<Finish<D>, String> {
        let y0 = OVec::<D>::from_column_slice(p.x0.as_slice());
        let n_max = u32::try_from(p.max_steps).unwrap_or(u32::MAX);
        let mut solver = ODop853::from_param(
            Adapter(s),
            0.0,
            p.t1,
            p.t1,
            y0,
            rtol,
            atol(rtol),
            0.9,
            0.0,
            0.333,
            6.0,
            p.t1,
            0.0,
            n_max,
            u32::MAX,
            OutputType::Sparse,
        );
        let stats = solver.integrate().map_err(|e| e.to_string())?;
        last(solver.y_out(), stats.accepted_steps)
    }

    /// Rk4 with step `h`.
    pub fn rk4<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        h: f64,
    ) -> Result<Finish<D>, String> {
        if p.t1 / h > p.max_steps as f64 {
            return Err(format!("more than {} steps", p.max_steps));
        }
        let y0 = OVec::<D>::from_column_slice(p.x0.as_slice());
        let mut solver = ORk4::new(Adapter(s), 0.0, y0, p.t1, h);
        let stats = solver.integrate().map_err(|e| e.to_string())?;
        last(solver.y_out(), stats.accepted_steps)
    }
}

/// `diffsol` with its nalgebra backend: the builder's closure right-hand
/// side and Jacobian–vector product. diffsol assembles the Jacobian matrix
/// column by column from products J·eᵢ; the product closure keeps the last
/// generated Jacobian and its (t, x), so one assembly costs one Jacobian.
pub mod diffsol_peer {
    use super::*;
    use diffsol::{
        NalgebraLU, NalgebraMat, OdeBuilder, OdeEquations, OdeSolverMethod, OdeSolverStopReason,
        Vector,
    };

    type M = NalgebraMat<f64>;
    type LS = NalgebraLU<f64>;

    /// The diffsol solver.
    #[derive(Clone, Copy, Debug)]
    pub enum Kind {
        /// Variable-order BDF (NDF).
        Bdf,
        /// ESDIRK34.
        Esdirk34,
        /// TR-BDF2.
        TrBdf2,
        /// Tsitouras 5(4), explicit.
        Tsit45,
    }

    /// A Jacobian with the time and state it was evaluated at.
    type Evaluated<const D: usize> = (f64, SVector<f64, D>, SMatrix<f64, D, D>);

    /// The Jacobian–vector product J(t, x)·v from the generated Jacobian,
    /// which is evaluated once per (t, x): the products J·eᵢ of one
    /// assembly cost one Jacobian.
    pub struct JacobianCache<'s, S, const D: usize> {
        sys: &'s S,
        last: RefCell<Option<Evaluated<D>>>,
    }

    impl<'s, S: Sys<D>, const D: usize> JacobianCache<'s, S, D> {
        /// An empty cache for `sys`.
        pub fn new(sys: &'s S) -> Self {
            Self {
                sys,
                last: RefCell::new(None),
            }
        }

        /// `y = J(t, x) v`.
        pub fn product(&self, t: f64, x: &[f64], v: &[f64], y: &mut [f64]) {
            let x = SVector::<f64, D>::from_column_slice(x);
            let mut last = self.last.borrow_mut();
            let j = match &*last {
                Some((tl, xl, j)) if *tl == t && *xl == x => *j,
                _ => {
                    let j = self.sys.jacobian(t, &x);
                    *last = Some((t, x, j));
                    j
                }
            };
            let r = j * SVector::<f64, D>::from_column_slice(v);
            y.copy_from_slice(r.as_slice());
        }
    }

    /// One diffsol run at `rtol`.
    pub fn run<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        rtol: f64,
        kind: Kind,
    ) -> Result<Finish<D>, String> {
        let cache = JacobianCache::new(s);
        let x0 = p.x0;
        let problem = OdeBuilder::<M>::new()
            .rtol(rtol)
            .atol([atol(rtol)])
            .rhs_implicit(
                |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| {
                    let f = s.rhs(t, &SVector::from_column_slice(x));
                    y.copy_from_slice(f.as_slice());
                },
                |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| cache.product(t, x, v, y),
            )
            .init(
                move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(x0.as_slice()),
                D,
            )
            .build()
            .map_err(|e| e.to_string())?;
        let e = |e: diffsol::DiffsolError| e.to_string();
        match kind {
            Kind::Bdf => step_to(problem.bdf::<LS>().map_err(e)?, p),
            Kind::Esdirk34 => step_to(problem.esdirk34::<LS>().map_err(e)?, p),
            Kind::TrBdf2 => step_to(problem.tr_bdf2::<LS>().map_err(e)?, p),
            Kind::Tsit45 => step_to(problem.tsit45().map_err(e)?, p),
        }
    }

    /// Steps `solver` to `p.t1` exactly (its stop time) within the step budget.
    fn step_to<'a, Eqn, Solver, const D: usize>(
        mut solver: Solver,
        p: &Start<D>,
    ) -> Result<Finish<D>, String>
    where
        Eqn: OdeEquations<T = f64> + 'a,
        Solver: OdeSolverMethod<'a, Eqn>,
    {
        solver.set_stop_time(p.t1).map_err(|e| e.to_string())?;
        let mut steps = 0;
        loop {
            match solver.step().map_err(|e| e.to_string())? {
                OdeSolverStopReason::TstopReached => break,
                _ if steps >= p.max_steps => {
                    return Err(format!("more than {} steps", p.max_steps));
                }
                _ => steps += 1,
            }
        }
        let y = solver.state().y.clone_as_vec();
        Ok(Finish {
            x: SVector::from_column_slice(&y),
            steps: solver.get_statistics().number_of_steps,
        })
    }
}

/// `russell_ode` (its default pure-Rust linear algebra): the closure
/// right-hand side and the analytic Jacobian as a dense coordinate matrix.
/// Radau5 runs with `concurrent = false`: its default factorises the real
/// and complex systems on two threads, which costs more than it saves on
/// an 8 × 8 system.
pub mod russell_peer {
    use super::*;
    use russell_lab::{NoArgs, Vector as RVector};
    use russell_ode::prelude::{Method as RMethod, OdeSolver, Params, System};
    use russell_sparse::{CooMatrix, Sym};

    /// One russell_ode run at `rtol`.
    pub fn run<S: Sys<D>, const D: usize>(
        s: &Counted<'_, S>,
        p: &Start<D>,
        rtol: f64,
        method: RMethod,
    ) -> Result<Finish<D>, String> {
        let mut system = System::new(D, |f: &mut RVector, t: f64, y: &RVector, _: &mut NoArgs| {
            let r = s.rhs(t, &SVector::from_column_slice(y.as_data()));
            f.as_mut_data().copy_from_slice(r.as_slice());
            Ok(())
        });
        system
            .set_jacobian(
                None,
                Sym::No,
                |jj: &mut CooMatrix, alpha: f64, t: f64, y: &RVector, _: &mut NoArgs| {
                    let j = s.jacobian(t, &SVector::from_column_slice(y.as_data()));
                    jj.reset();
                    for c in 0..D {
                        for r in 0..D {
                            jj.put(r, c, alpha * j[(r, c)])?;
                        }
                    }
                    Ok(())
                },
            )
            .map_err(str::to_string)?;
        let mut params = Params::new(method);
        params
            .set_tolerances(atol(rtol), rtol, None)
            .map_err(str::to_string)?;
        params.step.n_step_max = p.max_steps;
        params.radau5.concurrent = false;
        let mut solver = OdeSolver::new(params, system).map_err(str::to_string)?;
        let mut y = RVector::from(&p.x0.as_slice());
        solver
            .solve(&mut y, 0.0, p.t1, None, &mut 0, None)
            .map_err(str::to_string)?;
        Ok(Finish {
            x: SVector::from_column_slice(y.as_data()),
            steps: solver.stats().n_accepted,
        })
    }
}
