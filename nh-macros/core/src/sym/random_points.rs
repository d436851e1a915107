//! Random-point checks: whether expressions vanish at random points in
//! double-double arithmetic, for identities the canonical form does not
//! know.

use super::{Engine, ExprId, SymId};

/// Whether every expression of `entries` vanishes at 16 random points in
/// double-double arithmetic (about 32 digits): any point where one exceeds
/// 1e-24 of the sum of its terms' sizes proves it nonzero; entries below that
/// at every point are taken as zero (an identity the canonical form does not
/// know, such as an angle-addition formula). Every symbol but π takes values
/// in [0.3, 1.4], the same points every build.
pub fn vanish_at_random_points(engine: &Engine, pi: SymId, entries: &[ExprId]) -> bool {
    let mut rng = crate::sym::Rng::new(0x243F_6A88_85A3_08D3);
    let mut points = 0;
    for _ in 0..64 {
        if points == 16 {
            break;
        }
        let vals = rng.point(engine.num_symbols(), pi);
        let mut usable = true;
        for &b in entries {
            let (v, scale) = engine.eval_with_scale(b, &vals);
            if !v.is_finite() || !scale.is_finite() {
                usable = false;
                break;
            }
            if v.abs().to_f64() > 1e-24 * scale.to_f64() {
                return false;
            }
        }
        if usable {
            points += 1;
        }
    }
    points == 16
}

#[cfg(test)]
mod tests {
    use super::vanish_at_random_points;
    use crate::sym::{Engine, Fun};

    /// sin 2x − 2 sin x cos x vanishes at every point (an identity the
    /// canonical form does not apply); sin x does not.
    #[test]
    fn an_identity_vanishes_and_a_function_does_not() {
        let mut e = Engine::new();
        let (x, pi) = (e.symbol("x"), e.symbol("pi"));
        let xs = e.sym(x);
        let two = e.int(2);
        let two_x = e.mul(two, xs);
        let sin_2x = e.func(Fun::Sin, two_x);
        let (s, c) = (e.func(Fun::Sin, xs), e.func(Fun::Cos, xs));
        let sc = e.mul(s, c);
        let double = e.mul(two, sc);
        let identity = e.sub(sin_2x, double);
        assert!(vanish_at_random_points(&e, pi, &[identity]));
        assert!(!vanish_at_random_points(&e, pi, &[s]));
        assert!(!vanish_at_random_points(&e, pi, &[identity, s]));
    }
}
