//! Zero crossings of event functions: which way one counts
//! ([`Direction`]) and one that happened ([`EventHit`]), what the event
//! tracker reports and an [`Outcome`](crate::Outcome) carries.

use nalgebra::{RealField, SVector};

/// Which sign changes of an event function count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Direction {
    /// From negative to zero or positive.
    Rising,
    /// From positive to zero or negative.
    Falling,
    /// Either way (the default).
    #[default]
    Either,
}

impl Direction {
    /// Whether a step from `g_prev` to `g_new` crosses zero this way.
    ///
    /// A value exactly zero at the start of a step (at `t0`, or at an event
    /// found exactly at the end of the previous step) starts no crossing;
    /// NaN has no sign and crosses nothing (the tracker compares the values
    /// on either side of it); `±∞` have their sign.
    pub(crate) fn crossed<T: RealField + Copy>(self, g_prev: T, g_new: T) -> bool {
        let zero = T::zero();
        let rising = g_prev < zero && g_new >= zero;
        let falling = g_prev > zero && g_new <= zero;
        match self {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Either => rising || falling,
        }
    }
}

/// An event that happened: which one, when, in which state.
///
/// # Example
///
/// ```rust
/// use nalgebra::{Vector1, Vector2};
/// use nh_runtime::{Direction, Events, Integrator, Rk4};
///
/// // The oscillator q = cos t passes through 0 at π/2, 3π/2, 5π/2.
/// let oscillator = |_t: f64, x: &Vector2<f64>| Vector2::new(x[1], -x[0]);
/// let zero = Events::new(|_t: f64, x: &Vector2<f64>| Vector1::new(x[0]));
/// let mut hits = Vec::new();
/// Rk4::new(0.01)
///     .integrate_with_events(&oscillator, 0.0, Vector2::new(1.0, 0.0), 9.0, &zero, |h| hits.push(*h))
///     .unwrap();
/// assert_eq!(hits.len(), 3);
/// assert_eq!(hits[0].direction, Direction::Falling);
/// assert_eq!(hits[1].direction, Direction::Rising);
/// assert!((hits[2].t - 2.5 * std::f64::consts::PI).abs() < 1e-8);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventHit<T, const D: usize> {
    /// Which event function, `0..N`.
    pub index: usize,
    /// The located time.
    pub t: T,
    /// The state there, from the step's dense output.
    pub x: SVector<T, D>,
    /// Which way `g` crossed zero: [`Direction::Rising`] or
    /// [`Direction::Falling`].
    pub direction: Direction,
    /// Whether the event ended the run.
    pub terminal: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_count_their_sign_changes() {
        use Direction::{Either, Falling, Rising};
        let crosses = |d: Direction| {
            [(-1.0, 1.0), (-1.0, 0.0), (1.0, -1.0), (1.0, 0.0)].map(|(a, b)| d.crossed(a, b))
        };
        assert_eq!(crosses(Rising), [true, true, false, false]);
        assert_eq!(crosses(Falling), [false, false, true, true]);
        assert_eq!(crosses(Either), [true, true, true, true]);
        assert_eq!(Direction::default(), Either);
    }

    #[test]
    fn zero_at_the_start_and_nan_cross_nothing_infinities_do() {
        for d in [Direction::Rising, Direction::Falling, Direction::Either] {
            assert!(!d.crossed(0.0, 1.0) && !d.crossed(0.0, -1.0));
            assert!(!d.crossed(f64::NAN, 1.0) && !d.crossed(-1.0, f64::NAN));
            assert!(!d.crossed(1.0, 2.0) && !d.crossed(-1.0, -2.0));
        }
        assert!(Direction::Rising.crossed(f64::NEG_INFINITY, f64::INFINITY));
        assert!(Direction::Falling.crossed(f64::INFINITY, -1.0));
    }
}
