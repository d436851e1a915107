//! Scenes with an independent reference, shared by the lab's tests and
//! reports.

/// The stiff disc of the reports and tests: the thesis disc with a
/// critically damped spring of stiffness 1e6 on the lean, over t ∈ [0, 1].
pub mod stiff_disc {
    use crate::systems::StiffDisc;
    use nonholonomic::prelude::SVector;

    /// The state `(θ, φ, ψ, x, y, θ̇, φ̇, ψ̇)`.
    pub type State = SVector<f64, 8>;

    /// The end of the run (it starts at 0).
    pub const END: f64 = 1.0;

    /// m = 1.7, R = 0.35, g = 9.81, k = 1e6, c critical for the lean's
    /// inertia 5mR²/4, rest lean 0.2.
    pub fn system() -> StiffDisc {
        let (m, r, k) = (1.7, 0.35, 1e6);
        let inertia = 1.25 * m * r * r;
        StiffDisc::new(m, r, 9.81, k, 2.0 * (k * inertia).sqrt(), 0.2)
    }

    /// The state at t = 0.
    pub fn initial_state() -> State {
        State::from([0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5])
    }

    /// The state at [`END`] by `tests/data/stiff_disc_reference.py`: the
    /// equations derived there with SymPy (Lagrange multipliers eliminated
    /// by the null space of the rolling constraints), integrated in mpmath
    /// at 24 digits by Gragg–Bulirsch–Stoer extrapolation of order 10
    /// (order 8 differs by < 3e-17). Dop853 at rtol 1e-14 differs by 5e-14.
    #[allow(clippy::excessive_precision)] // the reference's digits, kept as computed
    pub fn reference() -> State {
        State::from([
            3.5396566823792241,
            21.211305486216771,
            0.20000409189806110,
            0.042010152020332791,
            0.099871982988029790,
            3.5370733851093618,
            21.212485074748761,
            0.0,
        ])
    }
}
