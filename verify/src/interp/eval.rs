//! Running compiled methods: one frame of registers per method, the frames
//! of its calls after it in the same buffer.

use super::compile::{CallIns, Cmp, F1, Ins, Program};
use crate::Scalar;

/// What a run shares across calls: the system's parameters and its cache
/// (computed by `__nh_compute_cache` when a method first reads it).
pub(super) struct Ctx<'a, S> {
    pub params: &'a [S],
    pub cache_prog: Option<&'a Program>,
    pub cache: Option<Vec<S>>,
}

/// Runs `prog` in `regs` (at least `prog.deep` long), whose frame already
/// holds the arguments.
pub(super) fn run<S: Scalar>(ctx: &mut Ctx<'_, S>, prog: &Program, regs: &mut [S]) {
    let (frame, rest) = regs.split_at_mut(prog.size);
    frame[..ctx.params.len()].copy_from_slice(ctx.params);
    if let Some(at) = prog.cache {
        load_cache(ctx, rest);
        let cache = ctx.cache.as_deref().unwrap_or(&[]);
        let at = at as usize;
        frame[at..at + cache.len()].copy_from_slice(cache);
    }
    exec(ctx, &prog.code, frame, rest);
}

fn load_cache<S: Scalar>(ctx: &mut Ctx<'_, S>, regs: &mut [S]) {
    if ctx.cache.is_some() {
        return;
    }
    let Some(cp) = ctx.cache_prog else {
        return;
    };
    run(ctx, cp, regs);
    let (at, n) = (cp.ret.base as usize, cp.ret.ty.size());
    ctx.cache = Some(regs[at..at + n].to_vec());
}

fn truth<S: Scalar>(b: bool) -> S {
    if b { S::one() } else { S::zero() }
}

fn is_true<S: Scalar>(x: S) -> bool {
    x.to_f64() != 0.0
}

/// A comparison as the generated code makes it (on the nearest `f64`s:
/// exact for `f64`, and for the sign of a double-double).
fn compare<S: Scalar>(c: Cmp, a: S, b: S) -> bool {
    let (a, b) = (a.to_f64(), b.to_f64());
    match c {
        Cmp::Lt => a < b,
        Cmp::Le => a <= b,
        Cmp::Gt => a > b,
        Cmp::Ge => a >= b,
        Cmp::Eq => a == b,
        Cmp::Ne => a != b,
    }
}

fn fun<S: Scalar>(f: F1, a: S) -> S {
    match f {
        F1::Sin => a.sin(),
        F1::Cos => a.cos(),
        F1::Tan => a.tan(),
        F1::Sqrt => a.sqrt(),
        F1::Exp => a.exp(),
        F1::Ln => a.ln(),
        F1::Abs => a.abs(),
        F1::Asin => a.asin(),
        F1::Acos => a.acos(),
        F1::Atan => a.atan(),
        F1::Sinh => a.sinh(),
        F1::Cosh => a.cosh(),
        F1::Tanh => a.tanh(),
    }
}

fn exec<S: Scalar>(ctx: &mut Ctx<'_, S>, code: &[Ins], f: &mut [S], rest: &mut [S]) {
    let mut pc = 0;
    while let Some(ins) = code.get(pc) {
        pc += 1;
        match *ins {
            Ins::Const(d, v) => f[d as usize] = S::from_f64(v),
            Ins::Pi(d) => f[d as usize] = S::pi(),
            Ins::Copy(d, a) => f[d as usize] = f[a as usize],
            Ins::CopyN(d, a, n) => f.copy_within(a as usize..(a + n) as usize, d as usize),
            Ins::Add(d, a, b) => f[d as usize] = f[a as usize] + f[b as usize],
            Ins::Sub(d, a, b) => f[d as usize] = f[a as usize] - f[b as usize],
            Ins::Mul(d, a, b) => f[d as usize] = f[a as usize] * f[b as usize],
            Ins::Div(d, a, b) => f[d as usize] = f[a as usize] / f[b as usize],
            Ins::Neg(d, a) => f[d as usize] = -f[a as usize],
            Ins::Fun(g, d, a) => f[d as usize] = fun(g, f[a as usize]),
            Ins::SinCos(s, c, a) => (f[s as usize], f[c as usize]) = f[a as usize].sin_cos(),
            Ins::Atan2(d, y, x) => f[d as usize] = f[y as usize].atan2(f[x as usize]),
            Ins::Powi(d, a, k) => f[d as usize] = f[a as usize].powi(k),
            Ins::Powf(d, a, b) => f[d as usize] = f[a as usize].powf(f[b as usize]),
            Ins::Cmp(c, d, a, b) => f[d as usize] = truth(compare(c, f[a as usize], f[b as usize])),
            Ins::Not(d, a) => f[d as usize] = truth(!is_true(f[a as usize])),
            Ins::And(d, a, b) => {
                f[d as usize] = truth(is_true(f[a as usize]) && is_true(f[b as usize]))
            }
            Ins::Or(d, a, b) => {
                f[d as usize] = truth(is_true(f[a as usize]) || is_true(f[b as usize]))
            }
            Ins::Jump(t) => pc = t as usize,
            Ins::JumpIfFalse(c, t) => {
                if !is_true(f[c as usize]) {
                    pc = t as usize;
                }
            }
            Ins::Call(ref c) => call(ctx, c, f, rest),
        }
    }
}

fn call<S: Scalar>(ctx: &mut Ctx<'_, S>, c: &CallIns, f: &mut [S], rest: &mut [S]) {
    for &(src, dst, n) in &c.args {
        let (src, dst, n) = (src as usize, dst as usize, n as usize);
        rest[dst..dst + n].copy_from_slice(&f[src..src + n]);
    }
    run(ctx, &c.prog, rest);
    let (at, n) = (c.prog.ret.base as usize, c.prog.ret.ty.size());
    let dst = c.dst as usize;
    f[dst..dst + n].copy_from_slice(&rest[at..at + n]);
}
