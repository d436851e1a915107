//! The Lie-group step of a free rotation (DESIGN §9.4). A one-step method
//! integrates a system whose orientation is a free rotation not in its
//! Euler angles but in the rotation's canonical coordinates about the
//! orientation at the start of each step: `R = exp([θ]×) B` with the
//! angular velocity `ω` in world components in the rates' slots and
//! `θ̇ = J_l(θ)⁻¹ ω`, or `R = B exp([θ]×)` with body components and
//! `θ̇ = J_r(θ)⁻¹ ω` ([`FreeRotation::world`]), `θ = 0` at the start. After
//! each accepted step the base moves to the step's end and `θ` to 0, so
//! that every step starts at the centre of its chart: the
//! Runge–Kutta–Munthe-Kaas method (Munthe-Kaas 1998; Iserles et al., Acta
//! Numerica 2000), of the Runge–Kutta method's order. For a constant `ω`,
//! `θ` is linear in time and the step is exact in the rotation: the steps
//! follow the change of the angular velocity, not the turning of the
//! angles, which a fast spin makes oscillate whatever their sequence.
//!
//! The equations are still the generated ones: at each evaluation the
//! rotation is written in the Euler sequence of the system's charts that
//! is regular there ([`OdeSystem::free_rotation`]), its right side evaluated
//! in that chart, and the angles' accelerations turned into `ω̇`
//! ([`crate::EulerSequence::body_accelerations`]).

use core::cell::Cell;

use nalgebra::{Matrix3, RealField, SVector, Vector3};

use crate::euler::FreeRotation;
use crate::numeric::c;
use crate::{OdeSystem, ProjectionFailure};

/// `[v]×`, the cross-product matrix.
fn hat<T: RealField + Copy>(v: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -v.z, v.y, v.z, z, -v.x, -v.y, v.x, z)
}

/// `exp([θ]×)`, the rotation by `|θ|` about `θ` (Rodrigues).
pub(crate) fn exp<T: RealField + Copy>(theta: &Vector3<T>) -> Matrix3<T> {
    let a2 = theta.norm_squared();
    let a = a2.sqrt();
    let k = hat(theta);
    // sin a / a and (1 − cos a)/a², by their series below 1e-4
    let (s, v) = if a < c(1e-4) {
        (T::one() - a2 / c(6.0), c::<T>(0.5) - a2 / c(24.0))
    } else {
        (a.sin() / a, (T::one() - a.cos()) / a2)
    };
    Matrix3::identity() + k * s + k * k * v
}

/// `θ` with `exp([θ]×) = r` and `|θ| ≤ π`, for a rotation `r`.
pub(crate) fn log<T: RealField + Copy>(r: &Matrix3<T>) -> Vector3<T> {
    let axis = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    );
    let sin2 = axis.norm(); // 2 sin a
    let cos2 = r.trace() - T::one(); // 2 cos a
    let a = sin2.atan2(cos2);
    if a < c(1e-4) {
        return axis * (c::<T>(0.5) + a * a / c(12.0));
    }
    if a < c(3.0) {
        return axis * (a / sin2);
    }
    // near a half turn: the axis from the symmetric part r + rᵀ = 2 cos a I
    // + 2 (1 − cos a) n nᵀ, its sign from the skew part
    let s = (r + r.transpose()) * c::<T>(0.5) - Matrix3::identity() * (cos2 * c(0.5));
    let i = (0..3).fold(0, |b, i| if s[(i, i)] > s[(b, b)] { i } else { b });
    let mut n: Vector3<T> = s.column(i).into_owned();
    n /= n.norm();
    if n.dot(&axis) < T::zero() {
        n = -n;
    }
    n * a
}

/// `J_r(θ)⁻¹`, the inverse of the right Jacobian of `exp`: `θ̇ = J_r(θ)⁻¹
/// ω_b` when `R = B exp([θ]×)` turns at the body rates `ω_b`.
pub(crate) fn right_jacobian_inverse<T: RealField + Copy>(theta: &Vector3<T>) -> Matrix3<T> {
    let a2 = theta.norm_squared();
    let a = a2.sqrt();
    let k = hat(theta);
    // 1/a² − (1 + cos a)/(2 a sin a), by its series below 1e-3
    let g = if a < c(1e-3) {
        T::one() / c(12.0) + a2 / c(720.0)
    } else {
        T::one() / a2 - (T::one() + a.cos()) / (c::<T>(2.0) * a * a.sin())
    };
    Matrix3::<T>::identity() + k * c::<T>(0.5) + k * k * g
}

/// The regularity of the canonical coordinates: `1 − |θ|/2π`, which falls
/// to 0 where `J_r(θ)⁻¹` has its pole.
fn canonical_regularity<T: RealField + Copy>(theta: &Vector3<T>) -> T {
    T::one() - theta.norm() / T::two_pi()
}

/// The largest turn (rad) between two points at which
/// [`Frame::follow`] reads the angles.
const FOLLOW: f64 = core::f64::consts::FRAC_PI_8;

/// What the angles' slots hold besides the canonical coordinates, `θ +
/// OFFSET` each: at the centre they read 1 rad, so that the error control
/// and the difference quotients of the implicit methods see them at the
/// scale of an angle, as they see Euler angles, rather than at zero, where
/// a relative tolerance and a relative increment shrink to nothing.
const OFFSET: f64 = 1.0;

/// The most points [`Frame::follow`] reads (a turn of 8π).
const MAX_PARTS: usize = 64;

/// The base orientation of a run in canonical coordinates, and the chart
/// of the system's atlas its last evaluation used.
pub(crate) struct Frame<T> {
    /// The rotation of chart 0 (every chart's is in the same slots).
    own: FreeRotation,
    base: Cell<Matrix3<T>>,
    chart: Cell<usize>,
}

/// The rotation's slots in the state.
fn slots<T: RealField + Copy, const D: usize>(x: &SVector<T, D>, s: [usize; 3]) -> [T; 3] {
    s.map(|i| x[i])
}

/// The slots `s` of `x` set to `v`.
fn set<T: RealField + Copy, const D: usize>(x: &mut SVector<T, D>, s: [usize; 3], v: [T; 3]) {
    for (i, v) in s.into_iter().zip(v) {
        x[i] = v;
    }
}

impl<T: RealField + Copy> Frame<T> {
    /// The free rotation of chart `chart` of `sys`.
    fn rotation<S, const D: usize>(&self, sys: &S, chart: usize) -> FreeRotation
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        sys.free_rotation(chart).unwrap_or(self.own)
    }

    /// A frame for `sys`, if one-step methods may advance its rotation in
    /// canonical coordinates: every chart of its atlas is one of a free
    /// rotation, in the same slots.
    pub(crate) fn of<S, const D: usize>(sys: &S) -> Option<Self>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let own = sys.free_rotation(0)?;
        let same = (1..sys.charts()).all(|c| {
            sys.free_rotation(c)
                .is_some_and(|r| r.angles == own.angles && r.rates == own.rates)
        });
        same.then(|| Frame {
            own,
            base: Cell::new(Matrix3::identity()),
            chart: Cell::new(0),
        })
    }

    /// The state `x` of chart `chart` in canonical coordinates about its
    /// own orientation, which becomes the base.
    pub(crate) fn enter<S, const D: usize>(
        &self,
        sys: &S,
        chart: usize,
        x: &SVector<T, D>,
    ) -> SVector<T, D>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let r = self.rotation(sys, chart);
        let (angles, rates) = (slots(x, r.angles), slots(x, r.rates));
        let rot = r.sequence.matrix(&angles);
        self.base.set(rot);
        self.chart.set(chart);
        let mut y = *x;
        self.set_canonical(&mut y, &Vector3::zeros());
        let omega = self.carried(&rot, r.sequence.body_rates(&angles, &rates));
        set(&mut y, r.rates, omega.into());
        y
    }

    /// The rotation at the canonical coordinates `theta`: `exp([θ]×) B`
    /// with world rates, `B exp([θ]×)` with body rates.
    fn orientation(&self, theta: &Vector3<T>) -> Matrix3<T> {
        if self.own.world {
            exp(theta) * self.base.get()
        } else {
            self.base.get() * exp(theta)
        }
    }

    /// The components carried in the rates' slots of a body vector `v` of
    /// the rotation `rot`: its world components with world rates.
    fn carried(&self, rot: &Matrix3<T>, v: Vector3<T>) -> Vector3<T> {
        if self.own.world { rot * v } else { v }
    }

    /// The body components of the carried vector `v` at the rotation `rot`.
    fn body(&self, rot: &Matrix3<T>, v: Vector3<T>) -> Vector3<T> {
        if self.own.world {
            rot.transpose() * v
        } else {
            v
        }
    }

    /// `θ̇` at the canonical coordinates `theta` turning at the carried
    /// rates `omega`: `J_l(θ)⁻¹ ω = J_r(−θ)⁻¹ ω` on the left, `J_r(θ)⁻¹ ω`
    /// on the right.
    fn coordinate_rates(&self, theta: &Vector3<T>, omega: &Vector3<T>) -> Vector3<T> {
        if self.own.world {
            right_jacobian_inverse(&-theta) * omega
        } else {
            right_jacobian_inverse(theta) * omega
        }
    }

    /// `y` written in chart `chart`: its angles of the rotation (nearest
    /// `near`'s angles when given) and their rates.
    pub(crate) fn to_chart<S, const D: usize>(
        &self,
        sys: &S,
        chart: usize,
        y: &SVector<T, D>,
        near: Option<&SVector<T, D>>,
    ) -> SVector<T, D>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let rot = self.orientation(&self.canonical(y));
        self.written(sys, chart, y, &rot, near)
    }

    /// [`Self::to_chart`] where `y`'s rotation is `rot`.
    fn written<S, const D: usize>(
        &self,
        sys: &S,
        chart: usize,
        y: &SVector<T, D>,
        rot: &Matrix3<T>,
        near: Option<&SVector<T, D>>,
    ) -> SVector<T, D>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let r = self.rotation(sys, chart);
        let angles = match near {
            Some(near) => r.sequence.angles_near(rot, &slots(near, r.angles)),
            None => r.sequence.angles(rot),
        };
        let rates = r
            .sequence
            .rates(&angles, &self.body(rot, Vector3::from(slots(y, r.rates))));
        let mut x = *y;
        set(&mut x, r.angles, angles);
        set(&mut x, r.rates, rates);
        x
    }

    /// The chart in which `y` is evaluated, `y` written there, and its
    /// rotation: the last chart used while its sequence's regularity there
    /// is at least 1/2, else the best of them.
    fn best_chart<S, const D: usize>(
        &self,
        sys: &S,
        y: &SVector<T, D>,
    ) -> (usize, SVector<T, D>, Matrix3<T>)
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let rot = self.orientation(&self.canonical(y));
        let regularity = |chart: usize| self.rotation(sys, chart).sequence.regularity_at(&rot);
        let mut chart = self.chart.get();
        if regularity(chart) < c(0.5) {
            let mut best = regularity(chart);
            for other in 0..sys.charts() {
                let rho = regularity(other);
                if rho > best {
                    (chart, best) = (other, rho);
                }
            }
            self.chart.set(chart);
        }
        (chart, self.written(sys, chart, y, &rot, None), rot)
    }

    /// The right side at `y`: chart `c`'s at `y` written there, with the
    /// rotation's slots `θ̇ = J_r(θ)⁻¹ ω_b` and `ω̇_b`.
    pub(crate) fn rhs<S, const D: usize>(&self, sys: &S, t: T, y: &SVector<T, D>) -> SVector<T, D>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let (chart, x, rot) = self.best_chart(sys, y);
        let r = self.rotation(sys, chart);
        let mut f = sys.rhs_in_chart(chart, t, &x);
        let (theta, omega) = (self.canonical(y), Vector3::from(slots(y, r.rates)));
        let (angles, rates) = (slots(&x, r.angles), slots(&x, r.rates));
        let spin = r
            .sequence
            .body_accelerations(&angles, &rates, &slots(&f, r.rates));
        // ω̇_w = R ω̇_b: the body's own turning adds ω_b × ω_b = 0
        let spin = self.carried(&rot, spin);
        set(
            &mut f,
            r.angles,
            self.coordinate_rates(&theta, &omega).into(),
        );
        set(&mut f, r.rates, spin.into());
        f
    }

    /// The regularity at `y`: the canonical coordinates' times the
    /// constraints' (the chart's regularity over its sequence's), in
    /// magnitude.
    pub(crate) fn regularity<S, const D: usize>(
        &self,
        sys: &S,
        t: T,
        y: &SVector<T, D>,
    ) -> Option<T>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let (chart, x, _) = self.best_chart(sys, y);
        let r = self.rotation(sys, chart);
        let own = canonical_regularity(&self.canonical(y));
        let rho = sys.chart_regularity_in(chart, t, &x)?;
        Some(own * (rho / r.sequence.regularity(&slots(&x, r.angles))).abs())
    }

    /// The chart's hook `hook` at `y`, written in the chart where `y` is
    /// evaluated.
    pub(crate) fn in_chart<S, R, const D: usize>(
        &self,
        sys: &S,
        y: &SVector<T, D>,
        hook: impl FnOnce(usize, &SVector<T, D>) -> R,
    ) -> R
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let (chart, x, _) = self.best_chart(sys, y);
        hook(chart, &x)
    }

    /// `y` projected in the chart where it is evaluated
    /// ([`OdeSystem::project_in`]), its rotation read back in canonical
    /// coordinates about the same base.
    pub(crate) fn project<S, const D: usize>(
        &self,
        sys: &S,
        t: T,
        y: &mut SVector<T, D>,
    ) -> Result<bool, ProjectionFailure<T>>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let (chart, mut x, _) = self.best_chart(sys, y);
        if !sys.project_in(chart, t, &mut x)? {
            return Ok(false);
        }
        let r = self.rotation(sys, chart);
        let rot = r.sequence.matrix(&slots(&x, r.angles));
        let base = self.base.get().transpose();
        let theta = log(&if self.own.world {
            rot * base
        } else {
            base * rot
        });
        let omega = r
            .sequence
            .body_rates(&slots(&x, r.angles), &slots(&x, r.rates));
        let omega = self.carried(&rot, omega);
        *y = x;
        self.set_canonical(y, &theta);
        set(y, r.rates, omega.into());
        Ok(true)
    }

    /// The canonical coordinates of `y`.
    pub(crate) fn canonical<const D: usize>(&self, y: &SVector<T, D>) -> Vector3<T> {
        Vector3::from(slots(y, self.own.angles)).add_scalar(-c::<T>(OFFSET))
    }

    /// `y` with the canonical coordinates `theta`.
    fn set_canonical<const D: usize>(&self, y: &mut SVector<T, D>, theta: &Vector3<T>) {
        set(y, self.own.angles, theta.add_scalar(c(OFFSET)).into());
    }

    /// `y` in chart 0's layout, its angles followed continuously from
    /// `near` (a state of chart 0 at the canonical coordinates `from`)
    /// along the straight path between the two in canonical coordinates,
    /// in parts that turn the body by at most [`FOLLOW`] rad each, so that
    /// the angles take no whole turn or mirror set that the motion does
    /// not (where chart 0 is regular along the path).
    pub(crate) fn follow<S, const D: usize>(
        &self,
        sys: &S,
        y: &SVector<T, D>,
        (near, from): (&SVector<T, D>, &Vector3<T>),
    ) -> SVector<T, D>
    where
        S: OdeSystem<T, D> + ?Sized,
    {
        let r = self.rotation(sys, 0);
        let to = self.canonical(y);
        let turn = (to - from).norm();
        let mut parts = 1usize;
        while parts < MAX_PARTS && turn > c::<T>(FOLLOW) * c(parts as f64) {
            parts += 1;
        }
        let mut guide = *near;
        for k in 1..parts {
            let theta = from + (to - from) * c::<T>(k as f64 / parts as f64);
            let angles = r
                .sequence
                .angles_near(&self.orientation(&theta), &slots(&guide, r.angles));
            set(&mut guide, r.angles, angles);
        }
        self.to_chart(sys, 0, y, Some(&guide))
    }

    /// The largest step for the state `y`: one that turns the body by
    /// half a turn at its angular velocity there (`None` at rest), well
    /// inside the canonical coordinates, whose step error may be nil (a
    /// constant spin is advanced exactly).
    pub(crate) fn step_cap<const D: usize>(&self, y: &SVector<T, D>) -> Option<T> {
        let spin = Vector3::from(slots(y, self.own.rates)).norm();
        (spin > T::zero()).then(|| T::pi() / spin)
    }

    /// Moves the base to the rotation at `y` and `y`'s canonical
    /// coordinates to 0 (the body rates stay): `true` if they were not 0.
    pub(crate) fn recentre<const D: usize>(&self, y: &mut SVector<T, D>) -> bool {
        let theta = self.canonical(y);
        if theta == Vector3::zeros() {
            return false;
        }
        self.base.set(self.orientation(&theta));
        self.set_canonical(y, &Vector3::zeros());
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vectors() -> Vec<Vector3<f64>> {
        let mut out = vec![
            Vector3::new(1e-9, -2e-9, 3e-10),
            Vector3::new(0.0, 0.0, 3.1),
        ];
        for k in 0..30 {
            let t = k as f64;
            let v = Vector3::new((0.7 * t).sin(), (1.3 * t).cos(), (0.4 * t + 1.0).sin());
            out.push(v.normalize() * (0.1 * t).min(3.1));
        }
        out
    }

    #[test]
    fn exp_is_a_rotation_and_log_inverts_it() {
        for v in vectors() {
            let r = exp(&v);
            assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-15);
            assert!((r.determinant() - 1.0).abs() < 1e-14);
            let back = log(&r);
            assert!((back - v).amax() < 1e-12 * (1.0 + v.norm()), "{v} {back}");
        }
    }

    #[test]
    fn the_jacobian_inverse_gives_the_rate_of_the_canonical_coordinates() {
        // exp(θ + h θ̇) ≈ exp(θ) exp(h [ω]×) with θ̇ = J_r⁻¹ ω
        let omega = Vector3::new(0.3, -1.1, 0.7);
        for v in vectors().into_iter().filter(|v| v.norm() < 3.0) {
            let rate = right_jacobian_inverse(&v) * omega;
            let h = 1e-6;
            let diff = (exp(&(v + rate * h)) - exp(&(v - rate * h))) / (2.0 * h);
            let expected = exp(&v) * hat(&omega);
            assert!((diff - expected).amax() < 1e-8, "{v}");
        }
    }
}
