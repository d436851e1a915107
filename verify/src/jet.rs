//! Hyper-dual numbers of order three: a value with three nilpotent
//! perturbations ε₁, ε₂, ε₃ (εᵢ² = 0) and their products, eight components
//! indexed by the set of perturbations they carry (bit i for εᵢ₊₁). One
//! evaluation of a function at x + ε₁u + ε₂v + ε₃w gives every derivative
//! up to the third along u, v, w, exactly (no step size): the plain
//! derivation takes its mass matrix, Euler–Lagrange terms and constraint
//! rates this way.

use crate::Scalar;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The perturbation a derivative is taken along.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Eps {
    /// ε₁.
    One = 1,
    /// ε₂.
    Two = 2,
    /// ε₃ (kept for total time derivatives inside an evaluation).
    Three = 4,
}

/// A hyper-dual number over the scalar `S`.
#[derive(Clone, Copy, Debug)]
pub struct Jet<S> {
    /// Component k carries the perturbations of the bits of k.
    pub c: [S; 8],
}

impl<S: Scalar> Jet<S> {
    /// A constant.
    pub fn constant(x: S) -> Self {
        let mut c = [S::zero(); 8];
        c[0] = x;
        Jet { c }
    }

    /// x + ε d.
    pub fn seeded(x: S, eps: Eps, d: S) -> Self {
        let mut j = Self::constant(x);
        j.c[eps as usize] = d;
        j
    }

    /// The value without perturbations.
    pub fn value(&self) -> S {
        self.c[0]
    }

    /// The coefficient of the product of the perturbations in `mask`.
    pub fn part(&self, mask: usize) -> S {
        self.c[mask]
    }

    /// This number plus ε times `d` (d free of ε).
    pub fn plus_eps(&self, eps: Eps, d: &Jet<S>) -> Jet<S> {
        let bit = eps as usize;
        let mut out = *self;
        for k in 0..8 {
            if k & bit == 0 {
                out.c[k | bit] = out.c[k | bit] + d.c[k];
            }
        }
        out
    }

    /// The coefficient of ε as a number in the other perturbations.
    pub fn along(&self, eps: Eps) -> Jet<S> {
        let bit = eps as usize;
        let mut out = Self::constant(S::zero());
        for k in 0..8 {
            if k & bit == 0 {
                out.c[k] = self.c[k | bit];
            }
        }
        out
    }

    /// The number with ε set to zero.
    pub fn without(&self, eps: Eps) -> Jet<S> {
        let bit = eps as usize;
        let mut out = *self;
        for k in 0..8 {
            if k & bit != 0 {
                out.c[k] = S::zero();
            }
        }
        out
    }

    fn scale(&self, s: S) -> Jet<S> {
        Jet {
            c: self.c.map(|x| x * s),
        }
    }

    /// The perturbation part δ = x − x₀.
    fn delta(&self) -> Jet<S> {
        let mut d = *self;
        d.c[0] = S::zero();
        d
    }

    /// f(x₀ + δ) = f₀ + f₁δ + f₂δ²/2 + f₃δ³/6 from the derivatives at x₀
    /// (δ⁴ = 0).
    fn taylor(&self, f: [S; 4]) -> Jet<S> {
        let d = self.delta();
        let d2 = d * d;
        let d3 = d2 * d;
        let half = S::from_f64(0.5);
        let sixth = S::one() / S::from_f64(6.0);
        let mut out = d.scale(f[1]) + d2.scale(f[2] * half) + d3.scale(f[3] * sixth);
        out.c[0] = f[0];
        out
    }

    /// sin and cos.
    pub fn sin_cos(&self) -> (Jet<S>, Jet<S>) {
        let (s, c) = self.c[0].sin_cos();
        (self.taylor([s, c, -s, -c]), self.taylor([c, -s, -c, s]))
    }

    /// sin.
    pub fn sin(&self) -> Jet<S> {
        self.sin_cos().0
    }

    /// cos.
    pub fn cos(&self) -> Jet<S> {
        self.sin_cos().1
    }

    /// exp.
    pub fn exp(&self) -> Jet<S> {
        let e = self.c[0].exp();
        self.taylor([e; 4])
    }

    /// ln.
    pub fn ln(&self) -> Jet<S> {
        let x = self.c[0];
        let r = S::one() / x;
        self.taylor([x.ln(), r, -r * r, S::from_f64(2.0) * r * r * r])
    }

    /// xᵃ for a constant exponent a.
    pub fn powc(&self, a: S) -> Jet<S> {
        let x = self.c[0];
        let one = S::one();
        let p0 = x.powf(a);
        let r = one / x;
        let p1 = a * p0 * r;
        let p2 = (a - one) * p1 * r;
        let p3 = (a - S::from_f64(2.0)) * p2 * r;
        self.taylor([p0, p1, p2, p3])
    }

    /// xᵏ for an integer k, by multiplication (k < 0: its reciprocal).
    pub fn powi(&self, k: i32) -> Jet<S> {
        let mut acc = Self::constant(S::one());
        for _ in 0..k.unsigned_abs() {
            acc = acc * *self;
        }
        if k < 0 {
            Self::constant(S::one()) / acc
        } else {
            acc
        }
    }

    /// √x.
    pub fn sqrt(&self) -> Jet<S> {
        self.powc(S::from_f64(0.5))
    }

    /// atan2(self, x): θ₀ + atan(z), z = (x₀y − y₀x)/(x₀x + y₀y), whose value is 0.
    pub fn atan2(&self, x: &Jet<S>) -> Jet<S> {
        let (y0, x0) = (self.c[0], x.c[0]);
        let num = self.scale(x0) - x.scale(y0);
        let den = x.scale(x0) + self.scale(y0);
        let z = num / den;
        let z3 = z * z * z;
        let mut out = z - z3.scale(S::one() / S::from_f64(3.0));
        out.c[0] = y0.atan2(x0);
        out
    }

    /// asin.
    pub fn asin(&self) -> Jet<S> {
        let one = Self::constant(S::one());
        let root = ((one - *self) * (one + *self)).sqrt();
        self.atan2(&root)
    }

    /// acos.
    pub fn acos(&self) -> Jet<S> {
        let one = Self::constant(S::one());
        let root = ((one - *self) * (one + *self)).sqrt();
        root.atan2(self)
    }

    /// atan.
    pub fn atan(&self) -> Jet<S> {
        self.atan2(&Self::constant(S::one()))
    }

    /// sinh.
    pub fn sinh(&self) -> Jet<S> {
        let (e, f) = (self.exp(), (-*self).exp());
        (e - f).scale(S::from_f64(0.5))
    }

    /// cosh.
    pub fn cosh(&self) -> Jet<S> {
        let (e, f) = (self.exp(), (-*self).exp());
        (e + f).scale(S::from_f64(0.5))
    }

    /// tanh.
    pub fn tanh(&self) -> Jet<S> {
        self.sinh() / self.cosh()
    }

    /// |x| (x₀ ≠ 0; at 0 the derivative's sign is taken as 0, as the engine's).
    pub fn abs(&self) -> Jet<S> {
        self.scale(self.sign())
    }

    /// The sign of the value: 1, −1 or 0.
    pub fn sign(&self) -> S {
        let v = self.c[0].to_f64();
        S::from_f64(if v > 0.0 {
            1.0
        } else if v < 0.0 {
            -1.0
        } else {
            0.0
        })
    }
}

impl<S: Scalar> Add for Jet<S> {
    type Output = Jet<S>;
    fn add(self, o: Jet<S>) -> Jet<S> {
        let mut c = self.c;
        for k in 0..8 {
            c[k] = c[k] + o.c[k];
        }
        Jet { c }
    }
}

impl<S: Scalar> Sub for Jet<S> {
    type Output = Jet<S>;
    fn sub(self, o: Jet<S>) -> Jet<S> {
        let mut c = self.c;
        for k in 0..8 {
            c[k] = c[k] - o.c[k];
        }
        Jet { c }
    }
}

impl<S: Scalar> Neg for Jet<S> {
    type Output = Jet<S>;
    fn neg(self) -> Jet<S> {
        Jet {
            c: self.c.map(|x| -x),
        }
    }
}

impl<S: Scalar> Mul for Jet<S> {
    type Output = Jet<S>;
    fn mul(self, o: Jet<S>) -> Jet<S> {
        let mut c = [S::zero(); 8];
        for i in 0..8 {
            for j in 0..8 {
                if i & j == 0 {
                    c[i | j] = c[i | j] + self.c[i] * o.c[j];
                }
            }
        }
        Jet { c }
    }
}

impl<S: Scalar> Div for Jet<S> {
    type Output = Jet<S>;
    fn div(self, o: Jet<S>) -> Jet<S> {
        let x = o.c[0];
        let r = S::one() / x;
        let inv = o.taylor([
            r,
            -r * r,
            S::from_f64(2.0) * r * r * r,
            -S::from_f64(6.0) * r * r * r * r,
        ]);
        self * inv
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + b.abs())
    }

    #[test]
    fn third_derivatives_of_a_product_of_functions() {
        // f(x) = sin(x) e^x / (1 + x²) at x = 0.7; f', f'', f''' by a
        // five-point finite difference of the closed-form f'
        let f = |x: Jet<f64>| x.sin() * x.exp() / (Jet::constant(1.0) + x * x);
        let x = 0.7;
        let mut j = Jet::constant(x);
        j.c[1] = 1.0;
        j.c[2] = 1.0;
        j.c[4] = 1.0;
        let y = f(j);
        let g = |x: f64| x.sin() * x.exp() / (1.0 + x * x);
        let h = 1e-3;
        let d1 = (g(x - 2.0 * h) - 8.0 * g(x - h) + 8.0 * g(x + h) - g(x + 2.0 * h)) / (12.0 * h);
        let d2 = (-g(x - 2.0 * h) + 16.0 * g(x - h) - 30.0 * g(x) + 16.0 * g(x + h)
            - g(x + 2.0 * h))
            / (12.0 * h * h);
        assert!(close(y.c[0], g(x)));
        assert!((y.c[1] - d1).abs() < 1e-9, "{} {d1}", y.c[1]);
        assert!((y.c[3] - d2).abs() < 1e-6, "{} {d2}", y.c[3]);
        assert!(close(y.c[1], y.c[2]) && close(y.c[1], y.c[4]));
        assert!(close(y.c[3], y.c[5]) && close(y.c[3], y.c[6]));
    }

    #[test]
    fn atan2_and_inverse_functions_differentiate_as_their_closed_forms() {
        let (y, x) = (0.3, -1.2);
        let yj = Jet::seeded(y, Eps::One, 1.0);
        let xj = Jet::seeded(x, Eps::Two, 1.0);
        let a = yj.atan2(&xj);
        let r2 = x * x + y * y;
        assert!(close(a.c[0], y.atan2(x)));
        assert!(close(a.c[1], x / r2));
        assert!(close(a.c[2], -y / r2));
        // ∂²/∂y∂x of atan2(y, x) = (y² − x²)/r⁴
        assert!(close(a.c[3], (y * y - x * x) / (r2 * r2)));
        let s = Jet::seeded(0.4, Eps::One, 1.0).asin();
        assert!(close(s.c[1], 1.0 / (1.0 - 0.16f64).sqrt()));
        let p = Jet::seeded(2.0, Eps::One, 1.0).powc(1.5);
        assert!(close(p.c[1], 1.5 * 2f64.sqrt()));
    }
}
