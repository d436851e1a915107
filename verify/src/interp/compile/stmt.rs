//! Statements: bindings, assignments, loops and blocks.

use super::index::{arith, sub_index, tuple_part};
use super::{Compiler, Flag, Loc, R, Reg, SCRATCH, Want, in_stmt, modeled, ty_of};
use crate::interp::ast::{BinOp, Block, Expr, Pat, Stmt, StmtKind, Ty};

impl Compiler<'_, '_> {
    pub(super) fn block(&mut self, b: &Block<'_>, want: Want) -> R<Loc> {
        self.scopes.push(Vec::new());
        let r = self.block_body(b, want);
        self.pop_scope();
        r
    }

    pub(super) fn block_body(&mut self, b: &Block<'_>, want: Want) -> R<Loc> {
        for s in &b.stmts {
            self.stmt(s)?;
        }
        match &b.tail {
            Some(e) => self.expr(e, want),
            None => Ok(Loc::Unit),
        }
    }

    pub(super) fn stmt(&mut self, s: &Stmt<'_>) -> R<()> {
        let mark = self.scratch;
        let r = match &s.kind {
            StmtKind::Let(pat, ty, Some(e)) => self.let_stmt(pat, ty.as_ref(), e),
            StmtKind::Let(pat, _, None) => {
                self.declare_deferred(pat);
                Ok(())
            }
            StmtKind::Expr(e) => self.expr(e, Want::Scratch).map(|_| ()),
            StmtKind::Assign(place, op, e) => self.assign(place, *op, e),
            StmtKind::For(pat, iter, body) => self.for_loop(pat, iter, body),
        };
        self.scratch = mark;
        r.map_err(|e| in_stmt(e, s.src))
    }

    pub(super) fn let_stmt(&mut self, pat: &Pat, ty: Option<&Ty>, e: &Expr<'_>) -> R<()> {
        let want = if matches!(pat, Pat::Wild) {
            Want::Scratch
        } else {
            Want::Persist
        };
        let v = self.expr(e, want)?;
        if let Some(ty) = ty {
            let got = ty_of(&v);
            if !modeled(ty) || ty.size() != got.size() {
                return Err(format!("a value of {got:?} for {ty:?}"));
            }
        }
        self.bind(pat, v)
    }

    pub(super) fn declare_deferred(&mut self, pat: &Pat) {
        match pat {
            Pat::Wild => {}
            Pat::Bind(name, _) => self.declare(name, None, true),
            Pat::Tuple(pats) => pats.iter().for_each(|p| self.declare_deferred(p)),
        }
    }

    pub(super) fn bind(&mut self, pat: &Pat, v: Loc) -> R<()> {
        match pat {
            Pat::Wild => Ok(()),
            Pat::Bind(name, mutable) => {
                let loc = self.settle(v, *mutable)?;
                self.declare(name, Some(loc), *mutable);
                Ok(())
            }
            Pat::Tuple(pats) => {
                let parts = split_tuple(v, pats.len())?;
                pats.iter()
                    .zip(parts)
                    .try_for_each(|(p, l)| self.bind(p, l))
            }
        }
    }

    /// A value a variable can keep: in registers no later statement writes
    /// (copied there unless it already is).
    pub(super) fn settle(&mut self, v: Loc, mutable: bool) -> R<Loc> {
        match v {
            Loc::Reg(ty, at, flag) => {
                let shared = match flag {
                    Flag::Own => false,
                    Flag::Alias => mutable,
                    Flag::Volatile => true,
                };
                if at & SCRATCH == 0 && !shared {
                    return Ok(Loc::Reg(ty, at, flag));
                }
                let d = self.alloc(Want::Persist, ty.size());
                self.copy(d, at, ty.size());
                Ok(Loc::Reg(ty, d, Flag::Own))
            }
            Loc::Tuple(_) => {
                let (ty, at, _) = self.contiguous(v, Want::Persist)?;
                Ok(Loc::Reg(ty, at, Flag::Own))
            }
            other => Ok(other),
        }
    }

    pub(super) fn assign(&mut self, place: &Expr<'_>, op: Option<BinOp>, rhs: &Expr<'_>) -> R<()> {
        if let (Expr::Path(s), None) = (place, op)
            && let [seg] = s.as_slice()
            && self.var(&seg.name).is_some_and(|v| v.loc.is_none())
        {
            let v = self.expr(rhs, Want::Persist)?;
            let loc = self.settle(v, true)?;
            if let Some(var) = self.vars.get_mut(&seg.name).and_then(|v| v.last_mut()) {
                var.loc = Some(loc);
            }
            return Ok(());
        }
        let (ty, at) = self.place(place)?;
        match op {
            None if ty == Ty::Scalar => match self.expr(rhs, Want::Into(at))? {
                Loc::Reg(Ty::Scalar, ..) => Ok(()),
                v => Err(format!("assigns {:?} to a scalar", ty_of(&v))),
            },
            None => {
                let v = self.expr(rhs, Want::Scratch)?;
                if ty_of(&v).size() != ty.size() {
                    return Err(format!("assigns {:?} to {ty:?}", ty_of(&v)));
                }
                self.store(&v, at).map(|_| ())
            }
            Some(op) if ty == Ty::Scalar => {
                let y = self.scalar(rhs)?;
                let ins = arith(op, at, at, y).ok_or("unsupported compound assignment")?;
                self.emit(ins);
                Ok(())
            }
            Some(_) => Err(format!("compound assignment to {ty:?}")),
        }
    }

    /// The registers an assignment writes.
    pub(super) fn place(&mut self, e: &Expr<'_>) -> R<(Ty, Reg)> {
        match e {
            Expr::Path(s) if s.len() == 1 => match self.name(&s[0].name)? {
                Loc::Reg(ty, at, _) => Ok((ty, at)),
                _ => Err(format!("cannot assign to `{}`", s[0].name)),
            },
            Expr::Index(b, i) => {
                let (ty, at) = self.place(b)?;
                let (ty, off) = sub_index(&ty, i)?;
                Ok((ty, at + off))
            }
            Expr::Field(b, k) => {
                let (ty, at) = self.place(b)?;
                let k: usize = k.parse().map_err(|_| format!("unsupported field `{k}`"))?;
                let part = match &ty {
                    Ty::Tuple(tys) => tuple_part(tys, k),
                    _ => None,
                };
                let (ty, off) = part.ok_or_else(|| format!("no field {k} of {ty:?}"))?;
                Ok((ty, at + off))
            }
            Expr::Paren(x) => self.place(x),
            other => Err(format!("unsupported assignment to {other:?}")),
        }
    }

    /// `for pat in array { body }`, unrolled.
    pub(super) fn for_loop(&mut self, pat: &Pat, iter: &Expr<'_>, body: &Block<'_>) -> R<()> {
        let v = self.expr(iter, Want::Scratch)?;
        let Loc::Reg(Ty::Array(n, elem), at, flag) = v else {
            return Err(format!("`for` over {:?}", ty_of(&v)));
        };
        for k in 0..n {
            self.scopes.push(Vec::new());
            let item = Loc::Reg((*elem).clone(), at + (k * elem.size()) as Reg, flag);
            let r = self
                .bind(pat, item)
                .and_then(|()| self.block(body, Want::Scratch));
            self.pop_scope();
            r?;
            if self.too_big {
                return Err("a loop too long".into());
            }
        }
        Ok(())
    }
}

pub(super) fn split_tuple(v: Loc, n: usize) -> R<Vec<Loc>> {
    match v {
        Loc::Tuple(ls) if ls.len() == n => Ok(ls),
        Loc::Reg(Ty::Tuple(tys), at, flag) if tys.len() == n => Ok((0..n)
            .filter_map(|k| tuple_part(&tys, k))
            .map(|(ty, off)| Loc::Reg(ty, at + off, flag))
            .collect()),
        other => Err(format!("a tuple pattern of {n} for {:?}", ty_of(&other))),
    }
}
