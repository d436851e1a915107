//! The number types the interpreter and the plain derivation compute in:
//! `f64` (what a user's code runs) and double-double (about 32 digits, for
//! the reference).

use nh_core::sym::dd::Dd;
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number type: the operations the generated code and the language use.
pub trait Scalar:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The value of an `f64`.
    fn from_f64(x: f64) -> Self;
    /// The nearest `f64`.
    fn to_f64(self) -> f64;
    /// π.
    fn pi() -> Self;
    /// sin and cos.
    fn sin_cos(self) -> (Self, Self);
    /// √x.
    fn sqrt(self) -> Self;
    /// eˣ.
    fn exp(self) -> Self;
    /// ln x.
    fn ln(self) -> Self;
    /// atan2(self, x).
    fn atan2(self, x: Self) -> Self;
    /// sinh.
    fn sinh(self) -> Self;
    /// cosh.
    fn cosh(self) -> Self;
    /// tanh.
    fn tanh(self) -> Self;
    /// |x|.
    fn abs(self) -> Self;

    /// 0.
    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    /// 1.
    fn one() -> Self {
        Self::from_f64(1.0)
    }
    /// sin x.
    fn sin(self) -> Self {
        self.sin_cos().0
    }
    /// cos x.
    fn cos(self) -> Self {
        self.sin_cos().1
    }
    /// tan x.
    fn tan(self) -> Self {
        let (s, c) = self.sin_cos();
        s / c
    }
    /// asin x (NaN beyond |x| = 1).
    fn asin(self) -> Self {
        let root = ((Self::one() - self) * (Self::one() + self)).sqrt();
        self.atan2(root)
    }
    /// acos x (NaN beyond |x| = 1).
    fn acos(self) -> Self {
        let root = ((Self::one() - self) * (Self::one() + self)).sqrt();
        root.atan2(self)
    }
    /// atan x.
    fn atan(self) -> Self {
        self.atan2(Self::one())
    }
    /// xᵏ by repeated multiplication (k < 0: 1/x^|k|).
    fn powi(self, k: i32) -> Self {
        let mut acc = Self::one();
        for _ in 0..k.unsigned_abs() {
            acc = acc * self;
        }
        if k < 0 { Self::one() / acc } else { acc }
    }
    /// xʸ = e^(y ln x).
    fn powf(self, y: Self) -> Self {
        (y * self.ln()).exp()
    }
    /// Whether the value is finite.
    fn is_finite(self) -> bool {
        self.to_f64().is_finite()
    }
}

impl Scalar for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn pi() -> Self {
        std::f64::consts::PI
    }
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn exp(self) -> Self {
        f64::exp(self)
    }
    fn ln(self) -> Self {
        f64::ln(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    fn sinh(self) -> Self {
        f64::sinh(self)
    }
    fn cosh(self) -> Self {
        f64::cosh(self)
    }
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
    fn abs(self) -> Self {
        f64::abs(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn tan(self) -> Self {
        f64::tan(self)
    }
    fn asin(self) -> Self {
        f64::asin(self)
    }
    fn acos(self) -> Self {
        f64::acos(self)
    }
    fn atan(self) -> Self {
        f64::atan(self)
    }
    fn powi(self, k: i32) -> Self {
        f64::powi(self, k)
    }
    fn powf(self, y: Self) -> Self {
        f64::powf(self, y)
    }
}

impl Scalar for Dd {
    fn from_f64(x: f64) -> Self {
        Dd::from_f64(x)
    }
    fn to_f64(self) -> f64 {
        Dd::to_f64(self)
    }
    fn pi() -> Self {
        Dd::PI
    }
    fn sin_cos(self) -> (Self, Self) {
        Dd::sin_cos(self)
    }
    fn sqrt(self) -> Self {
        Dd::sqrt(self)
    }
    fn exp(self) -> Self {
        Dd::exp(self)
    }
    fn ln(self) -> Self {
        Dd::ln(self)
    }
    fn atan2(self, x: Self) -> Self {
        Dd::atan2(self, x)
    }
    fn sinh(self) -> Self {
        Dd::sinh(self)
    }
    fn cosh(self) -> Self {
        Dd::cosh(self)
    }
    fn tanh(self) -> Self {
        Dd::tanh(self)
    }
    fn abs(self) -> Self {
        Dd::abs(self)
    }
}
