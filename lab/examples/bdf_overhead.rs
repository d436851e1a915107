//! One run for counting instructions with callgrind: the own work per step
//! of `Bdf` and `Rodas4` on the stiff disc (k = 1e6, t ∈ [0, 1],
//! atol = rtol/100, generated Jacobian), outside the right-hand side and
//! Jacobian.
//!
//! ```text
//! cargo build --release -p nh-lab --example bdf_overhead
//! valgrind --tool=callgrind target/release/examples/bdf_overhead none      # process baseline
//! valgrind --tool=callgrind target/release/examples/bdf_overhead rhs       # + 1000 right-hand sides
//! valgrind --tool=callgrind target/release/examples/bdf_overhead jac       # + 1000 Jacobians
//! valgrind --tool=callgrind target/release/examples/bdf_overhead bdf 1e-8  # or rodas; prints Stats
//! ```
//!
//! Own instructions per step attempt = (run − baseline − RHS·(rhs − baseline)/1000
//! − Jacobians·(jac − baseline)/1000) / attempts. The `-opaque` modes keep the
//! system's calls out of line, so that `callgrind_annotate --inclusive=yes`
//! splits the run by function. Measured: 312 instructions per right-hand
//! side, 477 per Jacobian; `Bdf` 1,990 / 1,830 / 1,740 per attempt at rtol
//! 1e-6 / 1e-8 / 1e-10 (1,660 between the last two), `Rodas4` 7,350.
use nh_lab::systems::StiffDisc;
use nonholonomic::prelude::*;
use std::hint::black_box;

/// The system behind calls that are never inlined, so that callgrind
/// attributes the right-hand side and Jacobian to functions of their own.
struct Opaque<'a>(&'a StiffDisc);

impl OdeSystem<f64, 8> for Opaque<'_> {
    #[inline(never)]
    fn rhs(&self, t: f64, x: &SVector<f64, 8>) -> SVector<f64, 8> {
        self.0.rhs(t, x)
    }
    fn is_autonomous(&self) -> bool {
        true
    }
}

impl OdeJacobian<f64, 8> for Opaque<'_> {
    #[inline(never)]
    fn jacobian(&self, t: f64, x: &SVector<f64, 8>) -> SMatrix<f64, 8, 8> {
        self.0.jacobian(t, x)
    }
}

fn main() {
    let (m, r, k) = (1.7, 0.35, 1e6);
    let inertia = 1.25 * m * r * r;
    let sys: StiffDisc = StiffDisc::new(m, r, 9.81, k, 2.0 * (k * inertia).sqrt(), 0.2);
    let x0 = SVector::<f64, 8>::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5]);
    let args: Vec<String> = std::env::args().collect();
    let mode = args[1].as_str();
    let rtol: f64 = args.get(2).map_or(1e-6, |v| v.parse().unwrap());
    match mode {
        "none" => {
            black_box(&sys);
        }
        "bdf" => {
            let out = Bdf::new(rtol, rtol * 1e-2)
                .integrate_with_jacobian(black_box(&sys), 0.0, black_box(x0), 1.0)
                .unwrap();
            eprintln!("{:?}", out.stats);
        }
        "bdf-opaque" => {
            let out = Bdf::new(rtol, rtol * 1e-2)
                .integrate_with_jacobian(black_box(&Opaque(&sys)), 0.0, black_box(x0), 1.0)
                .unwrap();
            eprintln!("{:?}", out.stats);
        }
        "rodas-opaque" => {
            let out = Rodas4::new(rtol, rtol * 1e-2)
                .integrate_with_jacobian(black_box(&Opaque(&sys)), 0.0, black_box(x0), 1.0)
                .unwrap();
            eprintln!("{:?}", out.stats);
        }
        "rodas" => {
            let out = Rodas4::new(rtol, rtol * 1e-2)
                .integrate_with_jacobian(black_box(&sys), 0.0, black_box(x0), 1.0)
                .unwrap();
            eprintln!("{:?}", out.stats);
        }
        "rhs" => {
            let mut acc = SVector::<f64, 8>::zeros();
            for i in 0..1000 {
                let x = x0 * (1.0 + 1e-3 * i as f64);
                acc += black_box(&sys).rhs(0.0, black_box(&x));
            }
            black_box(acc);
        }
        "jac" => {
            let mut acc = SMatrix::<f64, 8, 8>::zeros();
            for i in 0..1000 {
                let x = x0 * (1.0 + 1e-3 * i as f64);
                acc += black_box(&sys).jacobian(0.0, black_box(&x));
            }
            black_box(acc);
        }
        _ => panic!("mode"),
    }
}
