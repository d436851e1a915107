//! Velocities in the input: `dot(q)` lowered to the velocity's symbol, and
//! where velocities may and may not appear (a constraint's velocity side,
//! terms nonlinear in velocities).

use super::values::Value;
use super::{Binding, Lowerer, short};
use crate::ctxt::SpanRange;
use crate::names;
use crate::parse::{BinOp, Expr};
use crate::sym::SymId;
use crate::words::{Constant, Function};

impl Lowerer<'_> {
    pub(crate) fn lower_dot(&mut self, arg: &Expr, range: SpanRange) -> Option<Value> {
        let id = match arg {
            Expr::Name(id) => id,
            Expr::Call { func, .. } if *func == Function::Dot => {
                self.cx.error(range, "`dot(dot(..))`: second derivatives cannot be written; the equations of motion are derived from the Lagrangian, which needs only velocities `dot(q)`");
                return None;
            }
            _ => {
                self.cx.error(arg.range(), "`dot` takes a coordinate or the name of a `let`; to differentiate an expression, name it first: `let X = ..;` then `dot(X)`");
                return None;
            }
        };
        let s = id.to_string();
        if self.poisoned.contains(&s) {
            return None;
        }
        match self.scope.get(&s).copied() {
            Some(Binding::Coord(i)) => Some(Value::Scalar(self.e.sym(self.coords[i].velocity))),
            Some(Binding::Let(i)) => {
                let v = self.lets[i].value.clone()?;
                let name = self.lets[i].name.clone();
                let entries = v.entries();
                let mut fs: Vec<SymId> = Vec::new();
                for &x in &entries {
                    fs.extend_from_slice(self.e.free_symbols(x));
                }
                if self.coords.iter().any(|c| fs.contains(&c.velocity)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` contains velocities, and its time derivative would need accelerations; `dot` applies to velocity-free `let`s only"));
                    return None;
                }
                if self.inputs.iter().any(|u| fs.contains(&u.sym)) {
                    self.cx.error(range, format!("`dot({name})`: `{name}` depends on an input, whose time derivative is unknown"));
                    return None;
                }
                // total derivative by the chain rule: Σ ∂/∂q_i q̇_i + ∂/∂t
                Some(match v {
                    Value::Scalar(x) => Value::Scalar(self.time_derivative(x)),
                    Value::Vector(x) => Value::Vector(x.map(|c| self.time_derivative(c))),
                    Value::Rotation(r) => {
                        Value::Matrix(r.matrix.map(|row| row.map(|c| self.time_derivative(c))))
                    }
                    Value::Matrix(m) => {
                        Value::Matrix(m.map(|row| row.map(|c| self.time_derivative(c))))
                    }
                })
            }
            Some(Binding::Body(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a body; the velocity of its centre is `dot(C)` of a `let C` for the centre, its angular velocity `omega(R)` of its orientation"));
                None
            }
            Some(Binding::Bound(_)) => {
                self.cx.error(range, format!("`dot({s})`: here `{s}` is a component of the direction the support function takes, not a coordinate; it has no rate"));
                None
            }
            Some(Binding::Speed(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a speed; its derivative is what the equations of motion compute, it cannot be written"));
                None
            }
            Some(Binding::Param(_)) => {
                self.cx.error(range, format!("`dot({s})`: `{s}` is a parameter, constant in time, so its derivative is 0; remove the term"));
                None
            }
            Some(Binding::Input(_)) => {
                self.cx.error(
                    range,
                    format!("`dot({s})`: the time derivative of input `{s}` is unknown"),
                );
                None
            }
            None => {
                if *id == Constant::Time {
                    self.cx.error(range, "`dot(t)` is 1: write `1`");
                    return None;
                }
                let known = self.known_names();
                let refs: Vec<&str> = known.iter().map(|k| k.as_str()).collect();
                let hint = names::suggest(&s, &refs);
                self.cx.error_at(id.span(), format!("unknown name `{s}`{hint} in `dot(..)`: `dot` takes a coordinate or a `let` name"));
                None
            }
        }
    }

    /// Where the velocity of coordinate `d` is used in `x` (depth first, left to right).
    pub(crate) fn find_velocity_use(&mut self, x: &Expr, d: usize) -> Option<SpanRange> {
        let mut stack = vec![x];
        while let Some(x) = stack.pop() {
            match x {
                Expr::Call { func, args, range } if *func == Function::Dot && args.len() == 1 => {
                    if let Expr::Name(id) = &args[0]
                        && self
                            .scope
                            .get(&id.to_string())
                            .is_some_and(|b| matches!(b, Binding::Coord(i) if *i == d))
                    {
                        return Some(*range);
                    }
                }
                Expr::Call { args: items, .. } | Expr::Vector { items, .. } => {
                    stack.extend(items.iter().rev())
                }
                Expr::Component { base, .. } => stack.push(base),
                Expr::Neg(inner, _) => stack.push(inner),
                Expr::Chain { first, rest, .. } => {
                    for (_, _, e) in rest.iter().rev() {
                        stack.push(e);
                    }
                    stack.push(first);
                }
                Expr::Pow { base, exp, .. } => {
                    stack.push(exp);
                    stack.push(base);
                }
                Expr::Name(_) | Expr::Num(..) => {}
            }
        }
        None
    }

    /// The coordinate of a left side `dot(q)`; `msg` says what is expected.
    pub(crate) fn velocity_lhs(&mut self, lhs: &Expr, msg: &str) -> Option<usize> {
        match lhs.call1(Function::Dot) {
            Some(Expr::Name(id)) if self.poisoned.contains(&id.to_string()) => None,
            Some(Expr::Name(id)) => match self.scope.get(&id.to_string()) {
                Some(Binding::Coord(i)) => Some(*i),
                _ => {
                    let hint = self.coordinate_hint(id);
                    self.cx.error_at(
                        id.span(),
                        format!("`{id}` is not a coordinate{hint}: {msg}"),
                    );
                    None
                }
            },
            _ => {
                self.cx.error(lhs.range(), msg);
                None
            }
        }
    }

    pub(crate) fn has_velocity(&mut self, x: &Expr, independent: &[usize]) -> bool {
        match self.lower(x, 0) {
            Some(v) => independent
                .iter()
                .any(|&i| self.e.depends_on(v, self.coords[i].velocity)),
            None => false,
        }
    }

    /// The smallest subexpression that makes a term nonlinear in the
    /// velocities, and what is wrong with it.
    pub(crate) fn find_nonlinear<'e>(
        &mut self,
        x: &'e Expr,
        independent: &[usize],
    ) -> Option<(&'e Expr, String)> {
        match x {
            Expr::Neg(inner, _) => self.find_nonlinear(inner, independent),
            Expr::Chain { first, rest, .. } if x.is_sum() => {
                // a parenthesised sum inside a product or a function
                std::iter::once(&**first)
                    .chain(rest.iter().map(|r| &r.2))
                    .find_map(|t| self.find_nonlinear(t, independent))
            }
            Expr::Chain { first, rest, .. } => {
                // a product: two factors with velocities, or one in a denominator
                let mut with_velocity: Vec<&Expr> = Vec::new();
                if self.has_velocity(first, independent) {
                    with_velocity.push(first);
                }
                for (op, _, f) in rest {
                    if self.has_velocity(f, independent) {
                        if *op == BinOp::Div {
                            return Some((f, "divides by a velocity".into()));
                        }
                        with_velocity.push(f);
                    }
                }
                // a factor that is nonlinear by itself (a power, a function) first
                for f in &with_velocity {
                    if let Some(r) = self.find_nonlinear(f, independent) {
                        return Some(r);
                    }
                }
                match with_velocity.as_slice() {
                    [] | [_] => None,
                    [_, ..] => Some((x, "multiplies velocities together".into())),
                }
            }
            Expr::Pow { base, .. } => {
                if self.has_velocity(base, independent) {
                    Some((x, "is a power of a velocity".into()))
                } else if self.has_velocity(x, independent) {
                    Some((x, "has a velocity in an exponent".into()))
                } else {
                    None
                }
            }
            Expr::Call { func, args, .. } if *func == Function::Dot && args.len() == 1 => {
                // `dot(NAME)` of a `let` with velocities is already an error
                None
            }
            Expr::Call { func, args, .. } => {
                if !self.has_velocity(x, independent) {
                    return None;
                }
                let why = match Function::of(func) {
                    Some(Function::Abs) if args.len() == 1 => {
                        let a = args[0].to_source();
                        let minus = match &args[0] {
                            Expr::Call { .. } | Expr::Name(_) => format!("-{a}"),
                            _ => format!("-({a})"),
                        };
                        format!("is the absolute value of a velocity: it is `{a}` where `{a}` ≥ 0 and `{minus}` where it is negative, a different linear constraint for each sign; write the one that holds")
                    }
                    Some(Function::Sqrt) => "is a square root of velocities, which is not linear (the root of a square is an absolute value, `sqrt(dot(x)^2)` = `abs(dot(x))`, and the root of a sum of squares is a speed)".to_string(),
                    Some(Function::KineticEnergy) => "is a kinetic energy, quadratic in the velocities".to_string(),
                    Some(
                        Function::Omega
                        | Function::OmegaBody
                        | Function::Cross
                        | Function::Dot
                        | Function::Norm,
                    ) => "is not linear in the velocities".to_string(),
                    _ => format!("has a velocity inside the function `{func}`"),
                };
                Some((x, why))
            }
            Expr::Name(id) => {
                // a `let` with velocities that are not linear
                let Some(Binding::Let(i)) = self.scope.get(&id.to_string()).copied() else {
                    return None;
                };
                let Some(Value::Scalar(v)) = self.lets[i].value.clone() else {
                    return None;
                };
                let moving = independent
                    .iter()
                    .any(|&j| self.e.depends_on(v, self.coords[j].velocity));
                (moving && !self.is_linear_in_velocities(v)).then(|| {
                    (
                        x,
                        format!(
                            "is a `let` that is not linear in the velocities (`{}`)",
                            short(self.e.display_capped(v, 60))
                        ),
                    )
                })
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::testing::{SLED, close, lowered, sled_at, value};

    /// The sled's constraint `dot(y) = tan(theta)*dot(x)` lowers to the
    /// dependent velocity ẏ = tan θ ẋ, and its Lagrangian's velocities to
    /// the velocity symbols: L = m/2 (ẋ² + ẏ²) + J/2 θ̇².
    #[test]
    fn the_sleds_velocities_lower_to_their_symbols() {
        let (model, engine) = lowered(SLED);
        let at = sled_at();
        let ydot = 0.3f64.tan() * 0.7;
        let c = &model.constraints[0];
        assert_eq!(model.coordinates[c.dependent].name, "y");
        assert!(close(value(&model, &engine, c.velocity, &at), ydot));
        let l = value(&model, &engine, model.lagrangian_folded, &at);
        assert!(close(l, 1.0 * (0.49 + ydot * ydot) + 0.25 * 1.21));
    }
}
