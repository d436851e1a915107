use nonholonomic::prelude::*;

nonholonomic_system! {
    /// The macro derives `Clone`, `Copy`, `Debug` and `PartialEq` itself; other derives pass through.
    #[derive(Clone, Eq, core::fmt::Debug)]
    pub struct Slide {
        parameters { m }
        coordinates { x }
        lagrangian = m/2*dot(x)^2;
    }
}

fn main() {
    let s: Slide = Slide::new(1.0);
    let t = s.clone();
    let _ = s.accelerations(0.0, &SVector::from([0.1]), &SVector::from([0.0]));
    println!("{t:?}");
}
