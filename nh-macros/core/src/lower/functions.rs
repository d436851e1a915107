//! The scalar functions of the language (`sin`, ..., `atan2`, `sqrt`):
//! calls resolved by name (a name is a function only where it is called,
//! so `abs` or `atan` can still name a coordinate), constant arguments
//! outside a function's domain reported at the argument, and exact values
//! at constant arguments folded (`acos(0)` is `pi/2`).

use super::Lowerer;
use crate::ctxt::SpanRange;
use crate::names;
use crate::parse::Expr;
use crate::sym::{ExprId, Fun, Rational, ZERO, exact_atan2, exact_value};
use crate::words::Function;
use proc_macro2::Ident;

/// The engine's function for a scalar function of one argument; `None`
/// for `sqrt`, a power (and for the other words, which are not lowered
/// here).
fn symbolic(f: Function) -> Option<Fun> {
    Some(match f {
        Function::Sin => Fun::Sin,
        Function::Cos => Fun::Cos,
        Function::Tan => Fun::Tan,
        Function::Cot => Fun::Cot,
        Function::Sec => Fun::Sec,
        Function::Csc => Fun::Csc,
        Function::Asin => Fun::Asin,
        Function::Acos => Fun::Acos,
        Function::Atan => Fun::Atan,
        Function::Sinh => Fun::Sinh,
        Function::Cosh => Fun::Cosh,
        Function::Tanh => Fun::Tanh,
        Function::Exp => Fun::Exp,
        Function::Ln => Fun::Ln,
        Function::Abs => Fun::Abs,
        _ => return None,
    })
}

impl Lowerer<'_> {
    /// A call of a scalar function (`func` is neither `dot` nor a function
    /// of vectors).
    pub(super) fn lower_scalar_call(
        &mut self,
        func: &Ident,
        args: &[Expr],
        range: SpanRange,
        depth: usize,
    ) -> Option<ExprId> {
        let f = func.to_string();
        let Some(word) = Function::parse(&f).filter(|w| w.is_scalar()) else {
            self.unknown_function(func, args, depth);
            return None;
        };
        let arity = if word == Function::Atan2 { 2 } else { 1 };
        if args.len() != arity {
            let msg = match word {
                Function::Atan2 => {
                    "`atan2` takes two arguments: `atan2(y, x)` is the angle of the point (x, y)"
                        .to_string()
                }
                _ => format!("`{f}` takes one argument"),
            };
            self.cx.error(range, msg);
            return None;
        }
        if word == Function::Atan2 {
            return self.lower_atan2(&args[0], &args[1], range, depth);
        }
        let arg = &args[0];
        let a = self.lower(arg, depth + 1)?;
        let fun = symbolic(word);
        if let Some(msg) = self.domain_error(fun, arg, a) {
            // the functions before `abs` and the others kept their message
            // on the whole call; the others point at the argument
            let at = match fun {
                None | Some(Fun::Ln | Fun::Tan) => range,
                Some(_) => arg.range(),
            };
            self.cx.error(at, msg);
            return None;
        }
        Some(match fun {
            Some(fun) => self.apply_function(fun, a),
            None => self.e.pow(a, Rational::new(1, 2).unwrap_or(Rational::ONE)),
        })
    }

    /// Reports an unknown function, with the function it probably means
    /// (by meaning, then by spelling), and lowers its arguments for the
    /// errors inside them.
    fn unknown_function(&mut self, func: &Ident, args: &[Expr], depth: usize) {
        let f = func.to_string();
        let hint = match names::function_meaning(&f) {
            Some(meaning) => format!(" ({meaning})"),
            None => Function::suggest(&f),
        };
        self.cx.error_at(
            func.span(),
            format!(
                "unknown function `{f}`{hint}; the functions are {}",
                Function::listed()
            ),
        );
        for a in args {
            let _ = self.lower_value(a, depth + 1);
        }
    }

    /// `f(a)`, with an exact value at a constant argument that is a
    /// multiple of π (`acos(0) = π/2`) folded.
    fn apply_function(&mut self, fun: Fun, a: ExprId) -> ExprId {
        if let Some(c) = self.e.as_constant(a)
            && let Some((r, k)) = exact_value(fun, c)
        {
            return self.rational_plus_pi(r, k);
        }
        self.e.func(fun, a)
    }

    /// `r + k·π`.
    fn rational_plus_pi(&mut self, r: Rational, k: Rational) -> ExprId {
        let r = self.e.constant(r);
        let pi = self.e.sym(self.pi_sym);
        let kpi = self.e.scale(pi, k);
        self.e.add(r, kpi)
    }

    /// `atan2(y, x)`: the origin, where the angle is undefined, rejected
    /// when both are constants; exact angles at constant points folded.
    fn lower_atan2(
        &mut self,
        y_arg: &Expr,
        x_arg: &Expr,
        range: SpanRange,
        depth: usize,
    ) -> Option<ExprId> {
        let y = self.lower(y_arg, depth + 1);
        let x = self.lower(x_arg, depth + 1);
        let (y, x) = (y?, x?);
        if y == ZERO && x == ZERO {
            self.cx.error(range, "`atan2(0, 0)` is undefined: the origin has no angle; `atan2(y, x)` is the angle of the point (x, y), which must not be (0, 0)");
            return None;
        }
        if let (Some(cy), Some(cx)) = (self.e.as_constant(y), self.e.as_constant(x))
            && let Some((r, k)) = exact_atan2(cy, cx)
        {
            return Some(self.rational_plus_pi(r, k));
        }
        Some(self.e.atan2(y, x))
    }

    /// The message for a constant argument outside the domain of `fun`
    /// (`None`: `sqrt`), if it is.
    fn domain_error(&mut self, fun: Option<Fun>, arg: &Expr, a: ExprId) -> Option<String> {
        use std::cmp::Ordering::{Equal, Less};
        let note = |lw: &Self| lw.value_note(arg, a);
        match (fun, self.constant_sign(a)) {
            (None, Some(Less)) => Some(format!(
                "`sqrt` of a negative constant is not a real number{}",
                note(self)
            )),
            (Some(Fun::Ln), Some(Equal)) => {
                Some("`ln(0)` is undefined (the logarithm tends to −∞ at 0)".to_string())
            }
            (Some(Fun::Ln), Some(Less)) => Some(format!(
                "`ln` of a negative constant is not a real number{}",
                note(self)
            )),
            (Some(f @ (Fun::Asin | Fun::Acos)), _) if self.constant_beyond_one(a) => Some(format!(
                "`{}` of a constant outside [−1, 1] is not a real number{}: its argument is a {}, between −1 and 1 (for a ratio such as `{}(d/l)`, keep |d| ≤ l)",
                f.name(),
                note(self),
                if f == Fun::Asin { "sine" } else { "cosine" },
                f.name()
            )),
            (Some(f @ (Fun::Tan | Fun::Sec)), _) if self.odd_multiple_of_half_pi(a) => {
                Some(format!(
                    "`{}` is undefined at odd multiples of π/2 (its cosine is 0){}",
                    f.name(),
                    note(self)
                ))
            }
            (Some(f @ (Fun::Cot | Fun::Csc)), _) if a == ZERO || self.multiple_of_pi(a) => {
                Some(format!(
                    "`{}` is undefined at multiples of π (its sine is 0){}",
                    f.name(),
                    note(self)
                ))
            }
            _ => None,
        }
    }

    /// Is `a` a constant (a rational, or a rational multiple of π) of
    /// magnitude above 1?
    fn constant_beyond_one(&self, a: ExprId) -> bool {
        if let Some(c) = self.e.as_constant(a) {
            return c.abs() > Rational::ONE;
        }
        self.pi_multiple(a)
            .is_some_and(|c| c.abs().to_f64() * std::f64::consts::PI > 1.0)
    }

    /// Is `a` an odd multiple of π/2?
    fn odd_multiple_of_half_pi(&self, a: ExprId) -> bool {
        self.pi_multiple(a)
            .and_then(|c| c.checked_sub(Rational::new(1, 2)?))
            .is_some_and(|d| d.is_integer())
    }

    /// Is `a` a nonzero integer multiple of π?
    fn multiple_of_pi(&self, a: ExprId) -> bool {
        self.pi_multiple(a).is_some_and(|c| c.is_integer())
    }
}
