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
