//! Calls: constants, constructors, methods of values and of the system.

use super::index::{const_index, const_int, const_value, dims, is_self, strip};
use super::{CallIns, Compiler, F1, Flag, Ins, Loc, R, Reg, Want, ty_of};
use crate::interp::ast::{Expr, GenArg, Ty};

impl Compiler<'_, '_> {
    /// `path(args)`: constants, constructors and the system's methods.
    pub(super) fn call(&mut self, f: &Expr<'_>, args: &[Expr<'_>], want: Want) -> R<Loc> {
        let Expr::Path(segs) = f else {
            return Err(format!("unsupported call of {f:?}"));
        };
        let names: Vec<&str> = segs.iter().map(|s| s.name.as_str()).collect();
        match (names.as_slice(), args) {
            (["T", "zero"], []) => Ok(self.op(want, Ty::Scalar, |d| Ins::Const(d, 0.0))),
            (["T", "one"], []) => Ok(self.op(want, Ty::Scalar, |d| Ins::Const(d, 1.0))),
            (["T", "pi"], []) => Ok(self.op(want, Ty::Scalar, Ins::Pi)),
            (["Self", "__nh_c"], [x]) => {
                let v = const_value(x)?;
                Ok(self.op(want, Ty::Scalar, |d| Ins::Const(d, v)))
            }
            ([.., "Option", "Some"], [x]) => self.expr(x, want),
            ([.., "SVector" | "SMatrix", ctor], _) => {
                let (r, c) = dims(&segs[segs.len() - 2])?;
                self.matrix(r, c, ctor, args, want)
            }
            ([ty, method], [first, rest @ ..])
                if (*ty == "Self" || *ty == self.table.system)
                    && matches!(first, Expr::Path(s) if is_self(s)) =>
            {
                self.call_method(method, rest, want)
            }
            _ => Err(format!("unsupported function `{}`", names.join("::"))),
        }
    }

    pub(super) fn matrix(
        &mut self,
        r: usize,
        c: usize,
        ctor: &str,
        args: &[Expr<'_>],
        want: Want,
    ) -> R<Loc> {
        match (ctor, args) {
            ("zeros", []) => {
                let at = self.alloc(want, r * c);
                for k in 0..r * c {
                    self.emit(Ins::Const(at + k as Reg, 0.0));
                }
                Ok(Loc::Reg(Ty::Mat(r, c), at, Flag::Own))
            }
            ("from", [x]) => {
                let v = self.expr(x, want)?;
                let (ty, at, flag) = self.contiguous(v, want)?;
                match ty {
                    Ty::Array(n, e) if n == r * c && *e == Ty::Scalar => {
                        Ok(Loc::Reg(Ty::Mat(r, c), at, flag))
                    }
                    other => Err(format!("a {r}×{c} matrix from {other:?}")),
                }
            }
            ("from_row_slice", [x]) => self.row_major(r, c, strip(x), want),
            _ => Err(format!("unsupported matrix constructor `{ctor}`")),
        }
    }

    pub(super) fn row_major(&mut self, r: usize, c: usize, x: &Expr<'_>, want: Want) -> R<Loc> {
        let Expr::Array(items) = x else {
            return Err(format!("`from_row_slice` of {x:?}"));
        };
        if items.len() != r * c {
            return Err(format!("{} entries for a {r}×{c} matrix", items.len()));
        }
        let at = self.alloc(want, r * c);
        for (k, item) in items.iter().enumerate() {
            let (i, j) = (k / c, k % c);
            if !matches!(
                self.expr(item, Want::Into(at + (j * r + i) as Reg))?,
                Loc::Reg(Ty::Scalar, ..)
            ) {
                return Err(format!("entry {k} of a matrix is not a scalar"));
            }
        }
        Ok(Loc::Reg(Ty::Mat(r, c), at, Flag::Own))
    }

    /// A method call `recv.name::<gens>(args)`.
    pub(super) fn method(
        &mut self,
        recv: &Expr<'_>,
        name: &str,
        gens: &[GenArg],
        args: &[Expr<'_>],
        want: Want,
    ) -> R<Loc> {
        if let Expr::Path(s) = recv
            && is_self(s)
        {
            return self.call_method(name, args, want);
        }
        let v = self.expr(recv, Want::Scratch)?;
        match (&v, name, gens, args) {
            (_, "clone" | "into_owned", [], []) => Ok(v),
            (Loc::Reg(Ty::Scalar, a, _), ..) if gens.is_empty() => {
                self.scalar_method(*a, name, args, want)
            }
            (Loc::Reg(Ty::Mat(r, 1), at, flag), "fixed_rows", [GenArg::Num(n)], [off]) => {
                let off = const_index(off)?;
                if off.checked_add(*n).is_none_or(|end| end > *r) {
                    return Err(format!("{n} rows from {off} of {r}"));
                }
                Ok(Loc::Reg(Ty::Mat(*n, 1), at + off as Reg, *flag))
            }
            _ => Err(format!("unsupported method `{name}` on {:?}", ty_of(&v))),
        }
    }

    pub(super) fn scalar_method(
        &mut self,
        a: Reg,
        name: &str,
        args: &[Expr<'_>],
        want: Want,
    ) -> R<Loc> {
        if let (Some(f), []) = (F1::of(name), args) {
            return Ok(self.op(want, Ty::Scalar, |d| Ins::Fun(f, d, a)));
        }
        match (name, args) {
            ("sin_cos", []) => {
                let d = self.alloc(want, 2);
                self.emit(Ins::SinCos(d, d + 1, a));
                Ok(Loc::Reg(
                    Ty::Tuple(vec![Ty::Scalar, Ty::Scalar]),
                    d,
                    Flag::Own,
                ))
            }
            ("atan2", [x]) => {
                let x = self.scalar(x)?;
                Ok(self.op(want, Ty::Scalar, |d| Ins::Atan2(d, a, x)))
            }
            ("powf", [y]) => {
                let y = self.scalar(y)?;
                Ok(self.op(want, Ty::Scalar, |d| Ins::Powf(d, a, y)))
            }
            ("powi", [k]) => {
                let k = i32::try_from(const_int(k)?).map_err(|_| "`powi` exponent out of range")?;
                Ok(self.op(want, Ty::Scalar, |d| Ins::Powi(d, a, k)))
            }
            _ => Err(format!(
                "unsupported method `{name}` with {} arguments on T",
                args.len()
            )),
        }
    }

    /// A call of the system's method `name`.
    pub(super) fn call_method(&mut self, name: &str, args: &[Expr<'_>], want: Want) -> R<Loc> {
        let idx = (self.table.find(name)).ok_or_else(|| format!("no method `{name}`"))?;
        let callee = self
            .table
            .program(idx)
            .map_err(|e| format!("calls `{name}`: {e}"))?;
        if callee.args.len() != args.len() {
            return Err(format!(
                "`{name}` takes {} arguments, given {}",
                callee.args.len(),
                args.len()
            ));
        }
        let mut moves = Vec::new();
        for (a, slot) in args.iter().zip(&callee.args) {
            let v = self.expr(a, Want::Scratch)?;
            let (ty, at, _) = self.contiguous(v, Want::Scratch)?;
            if ty.size() != slot.ty.size() {
                return Err(format!(
                    "argument `{}` of `{name}`: {ty:?} for {:?}",
                    slot.name, slot.ty
                ));
            }
            moves.push((at, slot.base, ty.size() as u32));
        }
        let ty = callee.ret.ty.clone();
        let dst = self.alloc(want, ty.size());
        self.deep = self.deep.max(callee.deep);
        self.emit(Ins::Call(Box::new(CallIns {
            prog: callee,
            args: moves,
            dst,
        })));
        Ok(Loc::Reg(ty, dst, Flag::Own))
    }
}
