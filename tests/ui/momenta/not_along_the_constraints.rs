use nonholonomic::prelude::*;

nonholonomic_system! {
    /// A rolling ball whose `K_x` turns it about the x axis through its
    /// centre without moving the centre: the ball would slip.
    pub struct RollingBall {
        parameters { m, R }
        coordinates { x, y, yaw, pitch, roll }
        let Q = rot_z(yaw) * rot_y(pitch) * rot_x(roll);
        let w = omega(Q);
        lagrangian = m/2*(dot(x)^2 + dot(y)^2) + m*R^2/5*(w.x^2 + w.y^2 + w.z^2);
        constraints {
            dot(x) = R*w.y;
            dot(y) = -R*w.x;
        }
        momenta {
            K_x(Q: [1, 0, 0]);
            K_z(Q: [0, 0, 1]);
        }
    }
}

fn main() {
    let ball = RollingBall::new(1.0, 0.3);
    let q = SVector::<f64, 5>::zeros();
    let rdot = SVector::<f64, 3>::from([0.5, 1.0, 0.2]);
    let _ = ball.declared_momenta(0.0, &q, &rdot);
    let _ = RollingBall::MOMENTUM_CONSERVED;
}
