//! Lowering of expressions: numbers, names, sums and products, powers and
//! calls become the engine's expressions, each misuse reported at its
//! token.

use super::values::Value;
use super::{Binding, Lowerer, Place, short, show};
use crate::ctxt::SpanRange;
use crate::names;
use crate::parse::{BinOp, Expr};
use crate::sym::{ExprId, Fun, Rational, SymId, ZERO};
use crate::words::{Constant, Function};
use proc_macro2::{Ident, Span};

impl Lowerer<'_> {
    /// Lowers a surface expression of any kind; `None` after recording an error.
    pub(crate) fn lower_value(&mut self, x: &Expr, depth: usize) -> Option<Value> {
        let v = self.lower_inner(x, depth)?;
        let Value::Scalar(v) = v else {
            return Some(v);
        };
        if self.huge_constant.is_none()
            && let Some(c) = self.e.as_constant(v)
            && !c.to_f64().is_finite()
        {
            self.huge_constant = Some(x.range());
        }
        Some(Value::Scalar(v))
    }

    /// The sign of `e` if it is a rational constant times a power of π.
    pub(crate) fn constant_sign(&self, e: ExprId) -> Option<std::cmp::Ordering> {
        if let Some(c) = self.e.as_constant(e) {
            return Some(c.cmp(&Rational::ZERO));
        }
        match self.e.terms(e) {
            [(_, c)] if self.e.free_symbols(e) == [self.pi_sym] => Some(c.cmp(&Rational::ZERO)),
            _ => None,
        }
    }

    /// ": `src` is value" for a message about an argument, if the value
    /// says more than the source text.
    pub(crate) fn value_note(&self, arg: &Expr, v: ExprId) -> String {
        let src = short(arg.to_source());
        let val = match self.e.as_constant(v) {
            Some(c) => show(c),
            None => short(self.e.display_capped(v, 60)),
        };
        if src == val {
            String::new()
        } else {
            format!(": `{src}` is {val}")
        }
    }

    /// The rational `c` if `e` is `c·π`.
    pub(crate) fn pi_multiple(&self, e: ExprId) -> Option<Rational> {
        if self.e.free_symbols(e) != [self.pi_sym] {
            return None;
        }
        let [(m, c)] = self.e.terms(e) else {
            return None;
        };
        match self.e.factors(*m) {
            [(_, k)] if k.is_one() => Some(*c),
            _ => None,
        }
    }

    pub(crate) fn lower_inner(&mut self, x: &Expr, depth: usize) -> Option<Value> {
        if depth > crate::parse::MAX_DEPTH {
            self.cx.error(
                x.range(),
                "expression nested too deeply: split it into `let` items",
            );
            return None;
        }
        match x {
            Expr::Num(q, _) => Some(Value::Scalar(self.e.constant(*q))),
            Expr::Name(id) => self.lower_name(id),
            Expr::Neg(inner, _) => match self.lower_value(inner, depth + 1)? {
                Value::Scalar(v) => Some(Value::Scalar(self.e.neg(v))),
                v => {
                    let minus = Value::Scalar(self.e.int(-1));
                    self.combine(BinOp::Mul, minus, v, x.range(), inner)
                }
            },
            Expr::Chain { first, rest, .. } => self.lower_chain(first, rest, depth),
            Expr::Pow { base, exp, .. } => self.lower_pow(x, base, exp, depth).map(Value::Scalar),
            Expr::Call { func, args, range } => self.lower_call(func, args, *range, depth),
            Expr::Vector { items, range } => self.lower_brackets(items, *range, depth),
            Expr::Component { base, field } => self.lower_component(base, field, depth),
        }
    }

    /// A chain of binary operations of one precedence, left to right.
    pub(crate) fn lower_chain(
        &mut self,
        first: &Expr,
        rest: &[(BinOp, Span, Expr)],
        depth: usize,
    ) -> Option<Value> {
        // every operand is lowered, so that all their errors are reported
        let mut acc = self.lower_value(first, depth + 1);
        for (op, op_span, operand) in rest {
            let v = self.lower_value(operand, depth + 1);
            acc = match (acc, v) {
                (Some(a), Some(v)) => match op {
                    BinOp::Div if matches!(v, Value::Scalar(ZERO)) => {
                        let at = SpanRange {
                            first: *op_span,
                            last: operand.range().last,
                        };
                        let msg = if matches!(operand, Expr::Num(..)) {
                            "division by zero".to_string()
                        } else {
                            format!("division by zero: `{}` is 0", short(operand.to_source()))
                        };
                        self.cx.error(at, msg);
                        None
                    }
                    _ => {
                        let at = first.range().to(operand.range());
                        self.combine(*op, a, v, at, operand)
                    }
                },
                _ => None,
            };
        }
        acc
    }

    /// `base ^ exp`.
    pub(crate) fn lower_pow(
        &mut self,
        x: &Expr,
        base: &Expr,
        exp: &Expr,
        depth: usize,
    ) -> Option<ExprId> {
        let l = self.lower(base, depth + 1);
        let r = self.lower(exp, depth + 1);
        let (l, r) = (l?, r?);
        let base_const = self.e.as_constant(l);
        Some(match self.e.as_constant(r) {
            Some(q) => {
                if l == ZERO && q.is_zero() {
                    self.cx.error(x.range(), "`0^0` is undefined");
                    return None;
                }
                if l == ZERO && q.is_negative() {
                    self.cx.error(
                        x.range(),
                        format!("division by zero: 0 to the negative power {q}"),
                    );
                    return None;
                }
                if let Some(c) = base_const {
                    if c.is_negative() && !q.is_integer() {
                        self.cx.error(x.range(), format!("a negative constant to a fractional power is not a real number: ({})^({})", show(c), show(q)));
                        return None;
                    }
                    let digits = c.pow_digits(q.floor());
                    if digits > f64::from(Rational::MAX_DIGITS) {
                        self.cx.error(x.range(), format!("this power is too large to compute exactly: it has about {} digits, and the limit is {}", if digits < 1e12 { format!("{digits:.0}") } else { format!("{digits:.1e}") }, Rational::MAX_DIGITS));
                        return None;
                    }
                }
                if q.abs() > Rational::int(64) && base_const.is_none() {
                    self.cx.error(
                        exp.range(),
                        "exponent too large: powers up to 64 are supported",
                    );
                    return None;
                }
                self.e.pow(l, q)
            }
            // a^b = exp(b ln a) for a symbolic exponent
            None => {
                if let Some(c) = base_const
                    && c <= Rational::ZERO
                {
                    let what = if c.is_zero() {
                        "0 to a symbolic power is undefined here (it is exp(b·ln 0), and ln 0 = −∞)"
                            .to_string()
                    } else {
                        format!(
                            "a negative constant to a symbolic power is not a real number: ({})^(..)",
                            show(c)
                        )
                    };
                    self.cx.error(x.range(), what);
                    return None;
                }
                let ln = self.e.func(Fun::Ln, l);
                let p = self.e.mul(r, ln);
                self.e.func(Fun::Exp, p)
            }
        })
    }

    pub(crate) fn lower_name(&mut self, id: &Ident) -> Option<Value> {
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        if let Some(Binding::Let(i)) = self.scope.get(&s).copied() {
            let v = self.lets[i].value.clone()?;
            let inputs: Vec<SymId> = self.inputs.iter().map(|u| u.sym).collect();
            let uses_input = v
                .entries()
                .iter()
                .any(|&x| inputs.iter().any(|&u| self.e.depends_on(x, u)));
            if self.place == Place::Lagrangian && uses_input {
                self.cx.error_at(id.span(), format!("`{s}` depends on an input, and inputs cannot appear in the Lagrangian: put actuation in `forces`"));
                return None;
            }
            return Some(v);
        }
        if let Some(Binding::Body(_)) = self.scope.get(&s) {
            self.cx.error_at(
                id.span(),
                format!(
                    "`{s}` is a body, not a value: its kinetic energy is `kinetic_energy({s})`"
                ),
            );
            return None;
        }
        self.lower_scalar_name(id).map(Value::Scalar)
    }

    pub(crate) fn lower_scalar_name(&mut self, id: &Ident) -> Option<ExprId> {
        let s = id.to_string();
        match self.scope.get(&s).copied() {
            Some(Binding::Param(i)) => Some(self.e.sym(self.params[i].sym)),
            Some(Binding::Coord(i)) => Some(self.e.sym(self.coords[i].position)),
            Some(Binding::Input(i)) => {
                match self.place {
                    Place::Lagrangian => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in the Lagrangian: inputs act through `forces {{ q: ..; }}` (generalized forces), which is where actuation belongs"));
                        return None;
                    }
                    Place::Constraint => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in a constraint: constraints depend on the coordinates only"));
                        return None;
                    }
                    Place::Kinematics => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in `kinematics`: q̇ = S(q, t) u + σ(q, t) depends on the coordinates, the speeds and time only; inputs act through `forces`"));
                        return None;
                    }
                    Place::Body => {
                        self.cx.error_at(id.span(), format!("input `{s}` cannot appear in a body or a rolling contact: they enter the Lagrangian and the constraints; inputs act through `forces`"));
                        return None;
                    }
                    _ => {}
                }
                Some(self.e.sym(self.inputs[i].sym))
            }
            Some(Binding::Let(_) | Binding::Body(_)) => None,
            Some(Binding::Bound(b)) => Some(self.e.sym(b)),
            Some(Binding::Speed(i)) => {
                if self.place != Place::Kinematics {
                    self.cx.error_at(id.span(), format!("speed `{s}` can appear only on the right sides of `kinematics`: write the Lagrangian, forces and `let`s with the velocities `dot(q)` of the coordinates (they are substituted by q̇ = S u + σ)"));
                    return None;
                }
                Some(self.e.sym(self.speed_syms[i]))
            }
            None => match (Constant::of(id), Function::of(id)) {
                (Some(Constant::Time), _) => Some(self.e.sym(self.t_sym)),
                (Some(Constant::Pi), _) => Some(self.e.sym(self.pi_sym)),
                (_, Some(f)) if !f.of_vectors() => {
                    let (args, example) = match f {
                        Function::Atan2 => ("two arguments", "atan2(y, x)".to_string()),
                        _ => ("an argument", format!("{s}(x)")),
                    };
                    self.cx.error_at(
                        id.span(),
                        format!("`{s}` is a function: call it with {args}, as in `{example}`"),
                    );
                    None
                }
                _ if self.all_lets.contains(&s) => {
                    self.cx.error_at(
                        id.span(),
                        format!("`{s}` is used before its `let`: a `let` may use only the items above it; move `let {s} = ..;` up"),
                    );
                    None
                }
                _ => {
                    let known = self.known_names();
                    let refs: Vec<&str> = known.iter().map(|k| k.as_str()).collect();
                    let hint = names::suggest(&s, &refs);
                    self.cx.error_at(id.span(), format!("unknown name `{s}`{hint}: declare it in `parameters {{ .. }}`, `coordinates {{ .. }}`, `inputs {{ .. }}` or with an earlier `let`"));
                    None
                }
            },
        }
    }

    pub(crate) fn lower_call(
        &mut self,
        func: &Ident,
        args: &[Expr],
        range: SpanRange,
        depth: usize,
    ) -> Option<Value> {
        let word = Function::of(func);
        if word == Some(Function::Dot) && args.len() == 1 {
            return self.lower_dot(&args[0], range);
        }
        if let Some(f) = word
            && let Some(v) = self.lower_vector_call(f, args, range, depth)
        {
            return v;
        }
        self.lower_scalar_call(func, args, range, depth)
            .map(Value::Scalar)
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::{close, lowered, value};

    /// Numbers, names, sums, products, powers, π and calls lower to the
    /// engine's expressions with their values.
    #[test]
    fn expressions_lower_to_their_values() {
        let src = "pub struct S {
            parameters { a }
            coordinates { q }
            lagrangian = dot(q)^2/2 - (a*q^3 - 2.5*sin(pi/6 + q) + sqrt(a)/ (1 + q^2) + atan2(q, a));
        }";
        let (model, engine) = lowered(src);
        let (a, q): (f64, f64) = (1.7, 0.4);
        let at = [("a", a), ("q", q), ("dot(q)", 0.0)];
        let want = -(a * q.powi(3) - 2.5 * (std::f64::consts::PI / 6.0 + q).sin()
            + a.sqrt() / (1.0 + q * q)
            + q.atan2(a));
        assert!(close(
            value(&model, &engine, model.lagrangian_folded, &at),
            want
        ));
    }
}
