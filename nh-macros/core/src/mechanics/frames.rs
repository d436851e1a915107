//! Body frames as products of elementary rotations (DESIGN §10): a frame
//! from a body's factors, its trailing constant factors, and ω_b step by
//! step.

use super::chains::{Frame, FrameStep, Tail};
use super::scene::Scene;
use crate::sym::ExprId;

impl Scene<'_> {
    /// The frame of a body's elementary rotations; `heading_out` when the
    /// bodies' vectors are in the heading's frame, which needs the first
    /// factor to be the heading R_z(ψ).
    pub(crate) fn frame_of(
        &mut self,
        factors: &[(usize, ExprId)],
        heading_out: bool,
    ) -> Option<Frame> {
        if factors.is_empty() || (heading_out && factors.first() != Some(&(2, self.heading()?))) {
            return None;
        }
        let steps = factors
            .iter()
            .map(|&(axis, angle)| {
                let rate = self.along_motion(angle);
                FrameStep {
                    axis,
                    turn: crate::lower::values::elementary(self.engine, axis, angle),
                    rate,
                    rate_jacobian: self.velocity_jacobian(rate),
                }
            })
            .collect();
        Some(Frame { steps, heading_out })
    }

    /// The factors without their trailing constant ones, and the product T
    /// of those (R = R' T, so a body vector v is T v in the axes of R').
    pub(crate) fn trimmed(
        &mut self,
        factors: &[(usize, ExprId)],
    ) -> (Vec<(usize, ExprId)>, Option<Tail>) {
        let mut kept = factors.to_vec();
        let mut tail: Option<[[ExprId; 3]; 3]> = None;
        while let Some(&(k, angle)) = kept.last() {
            if !self.fixed(angle) {
                break;
            }
            kept.pop();
            let f = crate::lower::values::elementary(self.engine, k, angle);
            tail = Some(match tail {
                Some(t) => crate::lower::values::mat_mat(self.engine, &f, &t),
                None => f,
            });
        }
        (kept, tail)
    }

    /// ω_b of the product of `factors` (body components): ω' = Fᵀ ω + θ̇ e_k
    /// step by step.
    pub(crate) fn body_omega(&mut self, factors: &[(usize, ExprId)]) -> [ExprId; 3] {
        use crate::lower::values::{chain_omega, scale3, unit};
        let own: Vec<[ExprId; 3]> = factors
            .iter()
            .map(|&(k, angle)| {
                let rate = self.along_motion(angle);
                scale3(self.engine, rate, unit(k))
            })
            .collect();
        chain_omega(self.engine, factors, &own, false)
    }
}

#[cfg(test)]
mod tests {
    use super::Scene;
    use crate::testing::{DISC, close, lowered, value};

    /// The disc's orientation rot_z(φ) rot_x(−ψ) rot_y(θ) as a frame: three
    /// steps about z, x, y at the rates φ̇, −ψ̇, θ̇; and its body angular
    /// velocity against the closed form ω_b = R_y(θ)ᵀ (R_x(−ψ)ᵀ φ̇ e_z −
    /// ψ̇ e_x) + θ̇ e_y.
    #[test]
    fn the_discs_frame_and_body_angular_velocity() {
        let (model, mut engine) = lowered(DISC);
        let mut scene = Scene::new(&model, &mut engine);
        let factors = model.kinetic.as_ref().expect("bodies").bodies[0]
            .factors
            .clone();
        let frame = scene.frame_of(&factors, false).expect("a frame");
        let axes: Vec<usize> = frame.steps.iter().map(|s| s.axis).collect();
        assert_eq!(axes, [2, 0, 1]);
        let (th, ph, ps, thd, phd, psd) = (0.4f64, -0.7f64, 0.25f64, 1.3, -0.6, 0.45);
        let at = [
            ("theta", th),
            ("phi", ph),
            ("psi", ps),
            ("dot(theta)", thd),
            ("dot(phi)", phd),
            ("dot(psi)", psd),
        ];
        let rates: Vec<f64> = frame
            .steps
            .iter()
            .map(|s| value(&model, scene.engine, s.rate, &at))
            .collect();
        assert_eq!(rates, [phd, -psd, thd]);
        let omega = scene.body_omega(&factors);
        // R_x(a)ᵀ v and R_y(b)ᵀ v for a = −ψ, b = θ
        let (a, b) = (-ps, th);
        let v = [0.0, phd * a.sin(), phd * a.cos()]; // R_x(a)ᵀ φ̇ e_z
        let v = [v[0] - psd, v[1], v[2]];
        let w = [
            b.cos() * v[0] - b.sin() * v[2],
            v[1] + thd,
            b.sin() * v[0] + b.cos() * v[2],
        ];
        for (x, want) in omega.iter().zip(w) {
            assert!(close(value(&model, scene.engine, *x, &at), want));
        }
    }
}
