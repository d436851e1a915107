use nonholonomic::prelude::*;

nonholonomic_system! {
    pub struct Pair {
        parameters { m }
        coordinates { x, y }
        lagrangian = m*(dot(x)^2 + dot(y)^2)/2;
        constraints {
            dot(x) = y*dot(y);
            dot(y) = x*dot(x);
        }
    }
}

fn main() {}
