//! Expressions: operators, names, fields, indices, literals of arrays and tuples, `if`.

use super::index::{arith, comparison, const_index, is_self, sub_index, tuple_part};
use super::{Compiler, Flag, Ins, Loc, R, Reg, Want, ty_of};
use crate::interp::ast::{BinOp, Block, Expr, Ty, UnOp};

impl Compiler<'_, '_> {
    /// Compiles an expression; with `Want::Into(r)` its value ends at `r`.
    pub(super) fn expr(&mut self, e: &Expr<'_>, want: Want) -> R<Loc> {
        let v = self.expr_inner(e, want)?;
        let Want::Into(r) = want else {
            return Ok(v);
        };
        if let Loc::Reg(_, at, _) = &v
            && *at == r
        {
            return Ok(v);
        }
        let ty = ty_of(&v);
        self.store(&v, r)?;
        Ok(Loc::Reg(ty, r, Flag::Own))
    }

    pub(super) fn expr_inner(&mut self, e: &Expr<'_>, want: Want) -> R<Loc> {
        match e {
            Expr::Lit(l) if crate::interp::lex::lit_str(l).is_some() => Ok(Loc::Unit),
            Expr::Lit(l) => Err(format!("unsupported bare literal `{l}`")),
            Expr::Bool(b) => {
                Ok(self.op(want, Ty::Bool, |d| Ins::Const(d, f64::from(u8::from(*b)))))
            }
            Expr::Path(segs) => match segs.as_slice() {
                [s] if s.args.is_empty() => self.name(&s.name),
                _ => Err(format!("unsupported path {segs:?}")),
            },
            Expr::Unary(op, a) => self.unary(*op, a, want),
            Expr::Binary(op, a, b) => self.binary(*op, a, b, want),
            Expr::Call(f, args) => self.call(f, args, want),
            Expr::Method(recv, name, gens, args) => self.method(recv, name, gens, args, want),
            Expr::Field(base, name) => self.field(base, name),
            Expr::Index(base, idx) => self.index(base, idx),
            Expr::Tuple(items) => self.tuple(items, want),
            Expr::Paren(a) => self.expr(a, want),
            Expr::Array(items) => self.array(items, want),
            Expr::Repeat(item, n) => self.repeat(item, n, want),
            Expr::Block(b) => self.block(b, want),
            Expr::If(c, t, e) => self.if_expr(c, t, e.as_deref(), want),
        }
    }

    /// An instruction writing one register.
    pub(super) fn op(&mut self, want: Want, ty: Ty, f: impl FnOnce(Reg) -> Ins) -> Loc {
        let d = self.alloc(want, 1);
        let ins = f(d);
        self.emit(ins);
        Loc::Reg(ty, d, Flag::Own)
    }

    pub(super) fn typed(&mut self, e: &Expr<'_>, want: &Ty) -> R<Reg> {
        match self.expr(e, Want::Scratch)? {
            Loc::Reg(ty, at, _) if ty == *want => Ok(at),
            v => Err(format!("expected {want:?}, found {:?} in {e:?}", ty_of(&v))),
        }
    }

    pub(super) fn scalar(&mut self, e: &Expr<'_>) -> R<Reg> {
        self.typed(e, &Ty::Scalar)
    }

    pub(super) fn unary(&mut self, op: UnOp, a: &Expr<'_>, want: Want) -> R<Loc> {
        match op {
            UnOp::Ref => self.expr(a, want),
            UnOp::Neg => {
                let a = self.scalar(a)?;
                Ok(self.op(want, Ty::Scalar, |d| Ins::Neg(d, a)))
            }
            UnOp::Not => {
                let a = self.typed(a, &Ty::Bool)?;
                Ok(self.op(want, Ty::Bool, |d| Ins::Not(d, a)))
            }
            UnOp::Deref => Err("unsupported `*`".into()),
        }
    }

    pub(super) fn binary(&mut self, op: BinOp, a: &Expr<'_>, b: &Expr<'_>, want: Want) -> R<Loc> {
        if matches!(op, BinOp::And | BinOp::BitAnd | BinOp::Or | BinOp::BitOr) {
            let x = self.typed(a, &Ty::Bool)?;
            let y = self.typed(b, &Ty::Bool)?;
            let and = matches!(op, BinOp::And | BinOp::BitAnd);
            return Ok(self.op(want, Ty::Bool, |d| {
                if and {
                    Ins::And(d, x, y)
                } else {
                    Ins::Or(d, x, y)
                }
            }));
        }
        let cmp = comparison(op);
        if cmp.is_none() && arith(op, 0, 0, 0).is_none() {
            return Err(format!("unsupported operator {op:?}"));
        }
        let x = self.scalar(a)?;
        let y = self.scalar(b)?;
        let d = self.alloc(want, 1);
        let (ins, ty) = match cmp {
            Some(c) => (Some(Ins::Cmp(c, d, x, y)), Ty::Bool),
            None => (arith(op, d, x, y), Ty::Scalar),
        };
        if let Some(ins) = ins {
            self.emit(ins);
        }
        Ok(Loc::Reg(ty, d, Flag::Own))
    }

    pub(super) fn tuple(&mut self, items: &[Expr<'_>], want: Want) -> R<Loc> {
        if items.is_empty() {
            return Ok(Loc::Unit);
        }
        let sub = if matches!(want, Want::Persist) {
            Want::Persist
        } else {
            Want::Scratch
        };
        let parts = items
            .iter()
            .map(|e| self.expr(e, sub))
            .collect::<R<Vec<_>>>()?;
        Ok(Loc::Tuple(parts))
    }

    pub(super) fn array(&mut self, items: &[Expr<'_>], want: Want) -> R<Loc> {
        let vals = items
            .iter()
            .map(|e| self.expr(e, Want::Scratch))
            .collect::<R<Vec<_>>>()?;
        let elem = vals.first().map_or(Ty::Scalar, ty_of);
        if let Some(v) = vals.iter().find(|v| ty_of(v) != elem) {
            return Err(format!("an array of {elem:?} and {:?}", ty_of(v)));
        }
        let at = self.alloc(want, elem.size().saturating_mul(vals.len()));
        for (k, v) in vals.iter().enumerate() {
            self.store(v, at + (k * elem.size()) as Reg)?;
        }
        Ok(Loc::Reg(
            Ty::Array(vals.len(), Box::new(elem)),
            at,
            Flag::Own,
        ))
    }

    pub(super) fn repeat(&mut self, item: &Expr<'_>, n: &Expr<'_>, want: Want) -> R<Loc> {
        let n = const_index(n)?;
        let v = self.expr(item, Want::Scratch)?;
        let elem = ty_of(&v);
        if !Ty::Array(n, Box::new(elem.clone())).fits() {
            return Err(format!("an array of {n} is too large"));
        }
        let at = self.alloc(want, elem.size() * n);
        for k in 0..n {
            self.store(&v, at + (k * elem.size()) as Reg)?;
        }
        Ok(Loc::Reg(Ty::Array(n, Box::new(elem)), at, Flag::Own))
    }

    pub(super) fn if_expr(
        &mut self,
        c: &Expr<'_>,
        then: &Block<'_>,
        els: Option<&Expr<'_>>,
        want: Want,
    ) -> R<Loc> {
        let c = self.typed(c, &Ty::Bool)?;
        let jump_else = self.code.len();
        self.emit(Ins::JumpIfFalse(c, 0));
        let tv = self.block(then, Want::Scratch)?;
        let ty = ty_of(&tv);
        let Some(els) = els else {
            self.patch(jump_else);
            return match ty.size() {
                0 => Ok(Loc::Unit),
                _ => Err("an `if` without `else` has a value".into()),
            };
        };
        let dst = self.alloc(
            if let Want::Into(r) = want {
                Want::Into(r)
            } else {
                Want::Persist
            },
            ty.size(),
        );
        self.store(&tv, dst)?;
        let jump_end = self.code.len();
        self.emit(Ins::Jump(0));
        self.patch(jump_else);
        let ev = self.expr(els, Want::Scratch)?;
        if ty_of(&ev).size() != ty.size() {
            return Err(format!("`if` branches of {ty:?} and {:?}", ty_of(&ev)));
        }
        self.store(&ev, dst)?;
        self.patch(jump_end);
        Ok(if ty.size() == 0 {
            Loc::Unit
        } else {
            Loc::Reg(ty, dst, Flag::Own)
        })
    }

    /// Points the jump at `at` to the next instruction.
    pub(super) fn patch(&mut self, at: usize) {
        let here = self.code.len() as u32;
        if let Some(Ins::Jump(t) | Ins::JumpIfFalse(_, t)) = self.code.get_mut(at) {
            *t = here;
        }
    }

    pub(super) fn field(&mut self, base: &Expr<'_>, name: &str) -> R<Loc> {
        if let Expr::Path(s) = base
            && is_self(s)
        {
            return self.self_field(name);
        }
        let v = self.expr(base, Want::Scratch)?;
        let k: usize = name
            .parse()
            .map_err(|_| format!("unsupported field `{name}`"))?;
        match v {
            Loc::Tuple(mut ls) if k < ls.len() => Ok(ls.swap_remove(k)),
            Loc::Reg(Ty::Tuple(tys), at, flag) => {
                let (ty, off) = tuple_part(&tys, k).ok_or_else(|| format!("no field {k}"))?;
                Ok(Loc::Reg(ty, at + off, flag))
            }
            other => Err(format!("field {k} of {:?}", ty_of(&other))),
        }
    }

    /// `self.NAME`: a parameter, the cache or the parameters it was computed for.
    pub(super) fn self_field(&mut self, name: &str) -> R<Loc> {
        match name {
            "__nh_cache" => self.cache_loc(),
            "__nh_cache_for" => {
                let p = self.table.params.len();
                Ok(Loc::Reg(Ty::Array(p, Box::new(Ty::Scalar)), 0, Flag::Alias))
            }
            _ => {
                let i = (self.table.params.iter().position(|x| x == name))
                    .ok_or_else(|| format!("unknown field `self.{name}`"))?;
                Ok(Loc::Reg(Ty::Scalar, i as Reg, Flag::Alias))
            }
        }
    }

    pub(super) fn cache_loc(&mut self) -> R<Loc> {
        let idx = (self.table.find("__nh_compute_cache")).ok_or("no `__nh_compute_cache`")?;
        let prog = self
            .table
            .program(idx)
            .map_err(|e| format!("the cache: {e}"))?;
        let n = prog.ret.ty.size();
        let at = match self.cache {
            Some(at) => at,
            None => {
                let at = self.alloc(Want::Persist, n);
                self.cache = Some(at);
                self.deep = self.deep.max(prog.deep);
                at
            }
        };
        Ok(Loc::Reg(
            Ty::Array(n, Box::new(Ty::Scalar)),
            at,
            Flag::Alias,
        ))
    }

    pub(super) fn index(&mut self, base: &Expr<'_>, idx: &Expr<'_>) -> R<Loc> {
        match self.expr(base, Want::Scratch)? {
            Loc::Reg(ty, at, flag) => {
                let (ty, off) = sub_index(&ty, idx)?;
                Ok(Loc::Reg(ty, at + off, flag))
            }
            other => Err(format!("index into {:?}", ty_of(&other))),
        }
    }
}
