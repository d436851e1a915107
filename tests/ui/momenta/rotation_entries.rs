use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A knife edge turning in the plane: its heading's rotation turns
    /// about z only, and its rate cannot be given twice; `W`'s three angles
    /// turn it about two axes only.
    pub struct Knife {
        parameters { m, J }
        coordinates { x, y, theta }
        let H = rot_z(theta);
        let W = rot_z(x)*rot_x(y)*rot_x(theta);
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
        constraints { dot(y) = tan(theta)*dot(x); }
        momenta {
            tilt(H: [1, 0, 0]);
            spin(H: [0, 0, 1], theta: 1);
            along(H: 2);
            wobble(W: [0, 0, 1]);
        }
    }
}

fn main() {
    let _ = Knife::MOMENTA;
}
