use nonholonomic::prelude::*;

nonholonomic_system! {
    /// Tokens swapped across the boundaries of items: `let` inside the braces
    /// of the block before it, a name after the braces of its list, a `;`
    /// after the `let` that follows it, the name of a `let` before `let`. One
    /// error at each; every item is still read.
    pub struct Disc {
        parameters { m, R, } g
        coordinates { theta, phi, psi, x, y let } X = x - R*sin(phi)*sin(psi);
        let Y = y + R*cos(phi)*sin(psi) let ;
        Z = R*cos(psi);
        V let = m*g*Z;
        lagrangian = m/2*(dot(X)^2 + dot(Y)^2 + dot(Z)^2)
                   + m*R^2/2*(dot(theta)^2/2 + dot(phi)^2/4 + dot(psi)^2/4)
                   - V;
        constraints {
            dot(x) = R*cos(phi)*dot(theta);
            dot(y) = R*sin(phi)*dot(theta);
        }
    }
}

fn main() {
    let disc = Disc::new(1.0, 0.5, 9.81);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::new(1.0, 2.0, 0.0);
    let _: SVector<f64, 3> = disc.accelerations(0.0, &q, &rdot);
    let x0 = SVector::<f64, 8>::zeros();
    let _ = Dopri5::new(1e-8, 1e-8).integrate(&disc, 0.0, x0, 1.0);
}
