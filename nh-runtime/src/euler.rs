//! One rotation in two sequences of Euler angles (DESIGN §9.4). A free
//! rotation written as three angles, `R = R_a(α) R_b(β) R_c(γ)`, is
//! singular where its middle angle makes the first and last axes coincide
//! (gimbal lock): `cos β = 0` when `c ≠ a` (Tait–Bryan), `sin β = 0` when
//! `c = a` (proper Euler). A generated system whose orientation is such a
//! rotation has a second chart in which the same three coordinates are the
//! angles of another sequence, singular elsewhere; [`EulerSequence::change`]
//! maps angles and their rates between the two, through the rotation and
//! its angular velocity, which both sequences describe alike.

use nalgebra::{Matrix3, RealField, Vector3};

/// A sequence of elementary rotations `R = R_a(α) R_b(β) R_c(γ)` about the
/// axes `a`, `b`, `c` (0 for x, 1 for y, 2 for z; `a ≠ b ≠ c`), each
/// `R_k(θ)` the right-handed rotation by θ about axis k (`rot_x`, `rot_y`,
/// `rot_z` of the input language).
///
/// # Example
///
/// ```rust
/// use nh_runtime::EulerSequence;
///
/// // Yaw, pitch and roll near gimbal lock (pitch 1.5), in the sequence
/// // z-x-y, where they are far from its own singularity.
/// let (zyx, zxy) = (EulerSequence::ZYX, EulerSequence::ZXY);
/// let (angles, rates): ([f64; 3], [f64; 3]) = ([0.3, 1.5, -0.2], [0.1, 0.2, 0.3]);
/// let (other, other_rates) = EulerSequence::change(zyx, zxy, &angles, &rates, None);
/// assert!(zxy.regularity(&other).abs() > 0.99);
/// let gap = (zyx.matrix(&angles) - zxy.matrix(&other)).amax();
/// assert!(gap < 1e-15);
/// let spin = zyx.body_rates(&angles, &rates) - zxy.body_rates(&other, &other_rates);
/// assert!(spin.amax() < 1e-15);
/// // and back, to the angles nearest the ones we started from
/// let (back, back_rates) = EulerSequence::change(zxy, zyx, &other, &other_rates, Some(&angles));
/// assert!((0..3).all(|i| (back[i] - angles[i]).abs() < 1e-12));
/// assert!((0..3).all(|i| (back_rates[i] - rates[i]).abs() < 1e-12));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EulerSequence {
    axes: [usize; 3],
}

impl EulerSequence {
    /// `R_x R_y R_z`.
    pub const XYZ: Self = Self { axes: [0, 1, 2] };
    /// `R_x R_z R_y`.
    pub const XZY: Self = Self { axes: [0, 2, 1] };
    /// `R_y R_x R_z`.
    pub const YXZ: Self = Self { axes: [1, 0, 2] };
    /// `R_y R_z R_x`.
    pub const YZX: Self = Self { axes: [1, 2, 0] };
    /// `R_z R_x R_y`.
    pub const ZXY: Self = Self { axes: [2, 0, 1] };
    /// `R_z R_y R_x`.
    pub const ZYX: Self = Self { axes: [2, 1, 0] };
    /// `R_x R_y R_x`.
    pub const XYX: Self = Self { axes: [0, 1, 0] };
    /// `R_x R_z R_x`.
    pub const XZX: Self = Self { axes: [0, 2, 0] };
    /// `R_y R_x R_y`.
    pub const YXY: Self = Self { axes: [1, 0, 1] };
    /// `R_y R_z R_y`.
    pub const YZY: Self = Self { axes: [1, 2, 1] };
    /// `R_z R_x R_z`.
    pub const ZXZ: Self = Self { axes: [2, 0, 2] };
    /// `R_z R_y R_z`.
    pub const ZYZ: Self = Self { axes: [2, 1, 2] };

    /// The sequence of the axes `axes` (0 for x, 1 for y, 2 for z), if
    /// they are axes and no two neighbours are equal.
    pub const fn new(axes: [usize; 3]) -> Option<Self> {
        let [a, b, c] = axes;
        if a < 3 && b < 3 && c < 3 && a != b && b != c {
            Some(Self { axes })
        } else {
            None
        }
    }

    /// The axes `[a, b, c]`.
    pub const fn axes(&self) -> [usize; 3] {
        self.axes
    }

    /// Whether the last axis is the first (proper Euler angles, singular
    /// where `sin β = 0`) rather than the third (Tait–Bryan, `cos β = 0`).
    pub const fn is_proper(&self) -> bool {
        self.axes[0] == self.axes[2]
    }

    /// The rotation `R_a(α) R_b(β) R_c(γ)`.
    pub fn matrix<T: RealField + Copy>(&self, angles: &[T; 3]) -> Matrix3<T> {
        let [a, b, c] = self.axes;
        elementary(a, angles[0]) * elementary(b, angles[1]) * elementary(c, angles[2])
    }

    /// The body's angular velocity `ω_b` (in the axes of the rotated body,
    /// `Rᵀ Ṙ = [ω_b]×`) at the angles `angles` moving at `rates`.
    pub fn body_rates<T: RealField + Copy>(&self, angles: &[T; 3], rates: &[T; 3]) -> Vector3<T> {
        self.rate_matrix(angles) * Vector3::from(*rates)
    }

    /// The rates of the angles at `angles` that give the body's angular
    /// velocity `omega` ([`Self::body_rates`] inverted): not finite where
    /// the sequence is singular.
    pub fn rates<T: RealField + Copy>(&self, angles: &[T; 3], omega: &Vector3<T>) -> [T; 3] {
        match self.rate_matrix(angles).try_inverse() {
            Some(inv) => (inv * omega).into(),
            None => [T::zero() / T::zero(); 3],
        }
    }

    /// The body's angular acceleration `ω̇_b` at the angles `angles` moving
    /// at `rates` with the second derivatives `accelerations`: the
    /// derivative of [`Self::body_rates`], `W q̈ + Σ_{i<j} q̇_i q̇_j (u_i × u_j)`
    /// with `u_i` the columns of `W` in `ω_b = W q̇` (each column turns with
    /// the angles after its own).
    pub fn body_accelerations<T: RealField + Copy>(
        &self,
        angles: &[T; 3],
        rates: &[T; 3],
        accelerations: &[T; 3],
    ) -> Vector3<T> {
        let w = self.rate_matrix(angles);
        let u = [w.column(0), w.column(1), w.column(2)];
        let mut out = w * Vector3::from(*accelerations);
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            out += u[i].cross(&u[j]) * (rates[i] * rates[j]);
        }
        out
    }

    /// `W` in `ω_b = W (α̇, β̇, γ̇)`: the columns `R_cᵀ R_bᵀ e_a`, `R_cᵀ e_b`,
    /// `e_c`; its determinant is the [`Self::regularity`] up to sign.
    fn rate_matrix<T: RealField + Copy>(&self, angles: &[T; 3]) -> Matrix3<T> {
        let [a, b, c] = self.axes;
        let rc = elementary(c, angles[2]).transpose();
        let rb = elementary(b, angles[1]).transpose();
        let (ea, eb, ec) = (unit::<T>(a), unit::<T>(b), unit::<T>(c));
        Matrix3::from_columns(&[rc * (rb * ea), rc * eb, ec])
    }

    /// How far the angles are from the sequence's singularity: `cos β`
    /// (Tait–Bryan) or `sin β` (proper Euler), in [−1, 1], zero where the
    /// first and last axes coincide.
    pub fn regularity<T: RealField + Copy>(&self, angles: &[T; 3]) -> T {
        if self.is_proper() {
            angles[1].sin()
        } else {
            angles[1].cos()
        }
    }

    /// [`Self::regularity`] of this sequence's angles of the rotation `r`,
    /// in magnitude, read off `r` without the angles: `√(1 − R_ac²)`
    /// (Tait–Bryan, `|sin β| = |R_ac|`) or `√(R_ab² + R_ac′²)` with c′ the
    /// third axis (proper Euler, `|cos β| = |R_aa|`).
    pub fn regularity_at<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
        let [a, b, c] = self.axes;
        if self.is_proper() {
            let c = 3 - a - b;
            (r[(a, b)] * r[(a, b)] + r[(a, c)] * r[(a, c)]).sqrt()
        } else {
            (T::one() - r[(a, c)] * r[(a, c)]).max(T::zero()).sqrt()
        }
    }

    /// The angles of the rotation `r` in this sequence: α and γ in
    /// (−π, π], β in [−π/2, π/2] (Tait–Bryan) or [0, π] (proper Euler).
    /// Where the sequence is singular, γ = 0 and α carries the rotation
    /// about the common axis.
    pub fn angles<T: RealField + Copy>(&self, r: &Matrix3<T>) -> [T; 3] {
        let [a, b, c] = self.axes;
        if self.is_proper() {
            let c = 3 - a - b;
            let s: T = parity(a, b, c);
            let beta = (r[(a, b)] * r[(a, b)] + r[(a, c)] * r[(a, c)])
                .sqrt()
                .atan2(r[(a, a)]);
            let alpha = r[(b, a)].atan2(-s * r[(c, a)]);
            let gamma = r[(a, b)].atan2(s * r[(a, c)]);
            [alpha, beta, gamma]
        } else {
            let s: T = parity(a, b, c);
            let sin_beta = (s * r[(a, c)]).clamp(-T::one(), T::one());
            let alpha = (-s * r[(b, c)]).atan2(r[(c, c)]);
            let gamma = (-s * r[(a, b)]).atan2(r[(a, a)]);
            [alpha, sin_beta.asin(), gamma]
        }
    }

    /// The angles of `r` in this sequence nearest `near`: of the two sets
    /// of angles of one rotation (β and its mirror, `π − β` or `−β`, with α
    /// and γ turned by π), each angle shifted by whole turns to the nearest
    /// of `near`'s, the set nearest `near` in the sum of squares.
    pub fn angles_near<T: RealField + Copy>(&self, r: &Matrix3<T>, near: &[T; 3]) -> [T; 3] {
        let [alpha, beta, gamma] = self.angles(r);
        let pi = T::pi();
        let mirror = if self.is_proper() { -beta } else { pi - beta };
        let sets = [[alpha, beta, gamma], [alpha + pi, mirror, gamma + pi]];
        let mut best = sets[0];
        let mut best_gap = None;
        for set in sets {
            let shifted = [0, 1, 2].map(|i| nearest_turn(set[i], near[i]));
            let gap = (0..3).fold(T::zero(), |g, i| {
                let d = shifted[i] - near[i];
                g + d * d
            });
            if best_gap.is_none_or(|b| gap < b) {
                (best, best_gap) = (shifted, Some(gap));
            }
        }
        best
    }

    /// The angles and rates of sequence `from` written in sequence `to`:
    /// the same rotation and the same angular velocity. The angles are
    /// [`Self::angles`] of the rotation, or [`Self::angles_near`] `near`;
    /// the rates are not finite where `to` is singular.
    pub fn change<T: RealField + Copy>(
        from: Self,
        to: Self,
        angles: &[T; 3],
        rates: &[T; 3],
        near: Option<&[T; 3]>,
    ) -> ([T; 3], [T; 3]) {
        let r = from.matrix(angles);
        let new = match near {
            Some(near) => to.angles_near(&r, near),
            None => to.angles(&r),
        };
        let omega = from.body_rates(angles, rates);
        (new, to.rates(&new, &omega))
    }
}

/// Where a free rotation sits in a system's state (DESIGN §9.4): its
/// angles, of the sequence `sequence`, in the slots `angles`, and their
/// rates in the slots `rates`. A generated system whose orientation is a
/// free rotation gives it for each chart ([`crate::OdeSystem::free_rotation`]);
/// the one-step integrators then advance the rotation itself, not its
/// angles, and hand back the angles of chart 0.
///
/// # Example
///
/// ```rust
/// use nh_runtime::{EulerSequence, FreeRotation};
///
/// // x, y, yaw, pitch, roll and their rates: the angles in slots 2..5
/// let r = FreeRotation {
///     sequence: EulerSequence::ZYX,
///     angles: [2, 3, 4],
///     rates: [5, 6, 7],
///     world: true,
/// };
/// assert_eq!(r.sequence.axes(), [2, 1, 0]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FreeRotation {
    /// The sequence of the angles.
    pub sequence: EulerSequence,
    /// The state's slots of the three angles, in the sequence's order.
    pub angles: [usize; 3],
    /// The state's slots of their rates, in the same order.
    pub rates: [usize; 3],
    /// Whether the system writes the angular velocity in world
    /// components (`omega(Q)`) rather than body ones (`omega_body(Q)`, a
    /// `body`'s inertia): the canonical coordinates then turn the rotation
    /// on the left, `R = exp([θ]×) B`, and carry `ω` in world components,
    /// which are the smooth ones for such a system (a ball whose inertia
    /// is isotropic, driven from the world); otherwise on the right, with
    /// the body's components, which Euler's equations keep smooth.
    pub world: bool,
}

/// `x + 2πk` nearest `near`.
fn nearest_turn<T: RealField + Copy>(x: T, near: T) -> T {
    let turn = T::two_pi();
    x + ((near - x) / turn).round() * turn
}

/// +1 for an even permutation `(a, b, c)` of the axes (x-y-z, y-z-x,
/// z-x-y), −1 for an odd one.
fn parity<T: RealField + Copy>(a: usize, b: usize, _c: usize) -> T {
    if (a + 1) % 3 == b {
        T::one()
    } else {
        -T::one()
    }
}

/// The unit vector of axis `k`.
fn unit<T: RealField + Copy>(k: usize) -> Vector3<T> {
    Vector3::from_fn(|i, _| if i == k { T::one() } else { T::zero() })
}

/// The right-handed rotation by `angle` about axis `k`.
fn elementary<T: RealField + Copy>(k: usize, angle: T) -> Matrix3<T> {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let (s, c) = angle.sin_cos();
    let mut m = Matrix3::identity();
    m[(i, i)] = c;
    m[(j, j)] = c;
    m[(i, j)] = -s;
    m[(j, i)] = s;
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [EulerSequence; 12] = [
        EulerSequence::XYZ,
        EulerSequence::XZY,
        EulerSequence::YXZ,
        EulerSequence::YZX,
        EulerSequence::ZXY,
        EulerSequence::ZYX,
        EulerSequence::XYX,
        EulerSequence::XZX,
        EulerSequence::YXY,
        EulerSequence::YZY,
        EulerSequence::ZXZ,
        EulerSequence::ZYZ,
    ];

    /// A few rotations: products of elementary ones with assorted angles.
    fn rotations() -> Vec<Matrix3<f64>> {
        let mut out = Vec::new();
        for k in 0..40 {
            let t = k as f64;
            let a = [
                (0.7 * t).sin() * 3.0,
                (1.3 * t).cos() * 1.4,
                (0.4 * t + 1.0).sin() * 3.1,
            ];
            out.push(EulerSequence::ZYX.matrix(&a) * EulerSequence::XZX.matrix(&[t, 0.2 * t, -t]));
        }
        out
    }

    #[test]
    fn every_sequence_reproduces_the_rotation_of_its_angles() {
        for seq in ALL {
            for r in rotations() {
                let a = seq.angles(&r);
                let gap = (seq.matrix(&a) - r).amax();
                assert!(gap < 1e-13, "{seq:?}: {gap:e}");
                // the mirrored set is the same rotation
                let near = [a[0] + 3.0, a[1] + 0.1, a[2] - 9.0];
                let b = seq.angles_near(&r, &near);
                assert!((seq.matrix(&b) - r).amax() < 1e-13, "{seq:?}");
                assert!((0..3).all(|i| (b[i] - near[i]).abs() <= std::f64::consts::PI + 0.2));
            }
        }
    }

    #[test]
    fn rates_invert_the_body_rates_and_the_determinant_is_the_regularity() {
        for seq in ALL {
            let angles: [f64; 3] = [0.4, 1.1, -2.0];
            let rates: [f64; 3] = [0.3, -0.7, 1.9];
            let w = seq.body_rates(&angles, &rates);
            let back = seq.rates(&angles, &w);
            assert!(
                (0..3).all(|i| (back[i] - rates[i]).abs() < 1e-14),
                "{seq:?}"
            );
            let det = seq.rate_matrix(&angles).determinant().abs();
            assert!(
                (det - seq.regularity(&angles).abs()).abs() < 1e-15,
                "{seq:?}"
            );
            // ω_b against a difference quotient of R: Rᵀ Ṙ = [ω_b]×
            let h = 1e-6;
            let step = |s: f64| [0, 1, 2].map(|i| angles[i] + s * rates[i]);
            let rdot = (seq.matrix(&step(h)) - seq.matrix(&step(-h))) / (2.0 * h);
            let skew = seq.matrix(&angles).transpose() * rdot;
            let from_skew = Vector3::new(skew[(2, 1)], skew[(0, 2)], skew[(1, 0)]);
            assert!((from_skew - w).amax() < 1e-9, "{seq:?}");
        }
    }

    #[test]
    fn the_regularity_read_off_the_rotation_is_the_angles() {
        for seq in ALL {
            for r in rotations() {
                let direct = seq.regularity_at(&r);
                let angles = seq.regularity(&seq.angles(&r)).abs();
                assert!((direct - angles).abs() < 1e-14, "{seq:?}");
            }
        }
    }

    #[test]
    fn body_accelerations_are_the_derivative_of_the_body_rates() {
        // along q(t) = q0 + q̇0 t + q̈0 t²/2, against a central difference
        let (q0, v0, a0): ([f64; 3], [f64; 3], [f64; 3]) =
            ([0.4, 1.1, -2.0], [0.3, -0.7, 1.9], [-1.2, 0.5, 0.8]);
        for seq in ALL {
            let at = |t: f64| {
                let q = [0, 1, 2].map(|i| q0[i] + v0[i] * t + a0[i] * t * t / 2.0);
                let v = [0, 1, 2].map(|i| v0[i] + a0[i] * t);
                seq.body_rates(&q, &v)
            };
            let h = 1e-5;
            let diff = (at(h) - at(-h)) / (2.0 * h);
            let gap = (seq.body_accelerations(&q0, &v0, &a0) - diff).amax();
            assert!(gap < 1e-9, "{seq:?}: {gap:e}");
        }
    }

    #[test]
    fn singular_angles_give_rates_that_are_not_finite() {
        let r = EulerSequence::ZYX.rates(
            &[0.1, std::f64::consts::FRAC_PI_2, 0.2],
            &Vector3::new(0.0, 0.0, 1.0),
        );
        // cos(π/2) is not exactly zero in floating point: huge, or not finite
        assert!(r.iter().any(|v| !v.is_finite() || v.abs() > 1e10));
        assert_eq!(EulerSequence::new([0, 0, 1]), None);
        assert_eq!(EulerSequence::new([2, 1, 2]), Some(EulerSequence::ZYZ));
    }
}
