//! The ball on a turntable's closed form, shared by the tests of its forms.

/// The centre of a homogeneous ball rolling without slipping on a table
/// turning at Ω: its velocity turns at ν = 2Ω/7, so
/// r(t) = r0 + v0 (e^{iνt} − 1)/(iν) in complex notation.
pub fn ball_centre(r0: (f64, f64), v0: (f64, f64), nu: f64, t: f64) -> (f64, f64) {
    let (s, c) = (nu * t).sin_cos();
    // (e^{iνt} − 1)/(iν) = (sin νt + i(1 − cos νt))/ν
    let (re, im) = (s / nu, (1.0 - c) / nu);
    (r0.0 + v0.0 * re - v0.1 * im, r0.1 + v0.0 * im + v0.1 * re)
}
