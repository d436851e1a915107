//! The Chaplygin sleigh's closed form, shared by the tests of its forms.

/// The sleigh's closed form (Bloch, sec. 1.7) for mass `m`, inertia `j`
/// about the centre of mass and arm `a`: θ, the speed v of the blade along
/// the body axis and ω = θ̇ at `t`, from θ₀, v₀, ω₀:
/// v = v∞ tanh(kt + c), ω = ω₀ cosh c / cosh(kt + c),
/// θ = θ₀ + ω₀ cosh c / k (gd(kt + c) − gd(c)), v∞ = sqrt(v₀² + (J + m a²) ω₀² / m),
/// k = m a v∞ / (J + m a²), c = atanh(v₀/v∞).
pub fn sleigh_closed_form(
    (m, j, a): (f64, f64, f64),
    (theta0, v0, omega0): (f64, f64, f64),
    t: f64,
) -> (f64, f64, f64) {
    let inertia = j + m * a * a;
    let v_inf = (v0 * v0 + inertia * omega0 * omega0 / m).sqrt();
    let k = m * a * v_inf / inertia;
    let c = (v0 / v_inf).atanh();
    let gd = |s: f64| s.sinh().atan();
    let s = k * t + c;
    (
        theta0 + omega0 * c.cosh() / k * (gd(s) - gd(c)),
        v_inf * s.tanh(),
        omega0 * c.cosh() / s.cosh(),
    )
}
