//! Constants, indices and small conversions of the compiler.

use super::{Cmp, Ins, R, Reg};
use crate::interp::ast::{BinOp, Expr, GenArg, MAX_SIZE, Seg, Ty, UnOp};
use crate::interp::lex::{lit_float, lit_int};

/// An index: `[i]` or `[(i, j)]`.
#[derive(Debug)]
pub(super) enum Index {
    One(usize),
    Two(usize, usize),
}

pub(super) fn is_self(segs: &[Seg]) -> bool {
    matches!(segs, [s] if s.name == "self")
}

pub(super) fn strip<'e, 't>(e: &'e Expr<'t>) -> &'e Expr<'t> {
    match e {
        Expr::Paren(x) | Expr::Unary(UnOp::Ref, x) => strip(x),
        _ => e,
    }
}

/// A constant written as a literal, possibly negated.
pub(super) fn const_value(e: &Expr<'_>) -> R<f64> {
    match strip(e) {
        Expr::Lit(l) => lit_float(l)
            .or_else(|| lit_int(l).map(|n| n as f64))
            .ok_or_else(|| format!("unsupported literal `{l}`")),
        Expr::Unary(UnOp::Neg, x) => const_value(x).map(|v| -v),
        other => Err(format!("not a constant: {other:?}")),
    }
}

pub(super) fn const_int(e: &Expr<'_>) -> R<i64> {
    match strip(e) {
        Expr::Lit(l) => lit_int(l).ok_or_else(|| format!("not an integer: `{l}`")),
        Expr::Unary(UnOp::Neg, x) => const_int(x).map(|v| -v),
        other => Err(format!("not an integer constant: {other:?}")),
    }
}

pub(super) fn const_index(e: &Expr<'_>) -> R<usize> {
    const_int(e).and_then(|n| usize::try_from(n).map_err(|_| format!("negative index {n}")))
}

pub(super) fn index_of(e: &Expr<'_>) -> R<Index> {
    match strip(e) {
        Expr::Tuple(items) if items.len() == 2 => {
            Ok(Index::Two(const_index(&items[0])?, const_index(&items[1])?))
        }
        other => Ok(Index::One(const_index(other)?)),
    }
}

/// The element type and offset of an index into a value of type `ty`.
pub(super) fn sub_index(ty: &Ty, idx: &Expr<'_>) -> R<(Ty, Reg)> {
    let ix = index_of(idx)?;
    let found = match (ty, &ix) {
        (Ty::Array(n, e), Index::One(i)) if i < n => {
            i.checked_mul(e.size()).map(|o| ((**e).clone(), o))
        }
        (Ty::Mat(r, c), Index::One(i)) if *i < r.saturating_mul(*c) => Some((Ty::Scalar, *i)),
        (Ty::Mat(r, c), Index::Two(i, j)) if i < r && j < c => {
            j.checked_mul(*r).map(|o| (Ty::Scalar, o + i))
        }
        _ => None,
    };
    match found {
        Some((elem, off)) if off <= MAX_SIZE => Ok((elem, off as Reg)),
        _ => Err(format!("unsupported index {ix:?} into {ty:?}")),
    }
}

/// The offset and type of part `k` of a tuple type.
pub(super) fn tuple_part(tys: &[Ty], k: usize) -> Option<(Ty, Reg)> {
    let off: usize = tys.get(..k)?.iter().map(Ty::size).sum();
    Some((tys.get(k)?.clone(), off as Reg))
}

/// The dimensions named by `SVector::<T, n>` or `SMatrix::<T, r, c>`.
pub(super) fn dims(seg: &Seg) -> R<(usize, usize)> {
    let nums: Vec<usize> = (seg.args.iter())
        .filter_map(|a| match a {
            GenArg::Num(n) => Some(*n),
            _ => None,
        })
        .collect();
    let (r, c) = match (seg.name.as_str(), nums.as_slice()) {
        ("SVector", [n]) => (*n, 1),
        ("SMatrix", [r, c]) => (*r, *c),
        _ => return Err(format!("unsupported matrix type {seg:?}")),
    };
    match Ty::Mat(r, c).fits() {
        true => Ok((r, c)),
        false => Err(format!("a {r}×{c} matrix is too large")),
    }
}

pub(super) fn arith(op: BinOp, d: Reg, a: Reg, b: Reg) -> Option<Ins> {
    Some(match op {
        BinOp::Add => Ins::Add(d, a, b),
        BinOp::Sub => Ins::Sub(d, a, b),
        BinOp::Mul => Ins::Mul(d, a, b),
        BinOp::Div => Ins::Div(d, a, b),
        _ => return None,
    })
}

pub(super) fn comparison(op: BinOp) -> Option<Cmp> {
    Some(match op {
        BinOp::Lt => Cmp::Lt,
        BinOp::Le => Cmp::Le,
        BinOp::Gt => Cmp::Gt,
        BinOp::Ge => Cmp::Ge,
        BinOp::Eq => Cmp::Eq,
        BinOp::Ne => Cmp::Ne,
        _ => return None,
    })
}
