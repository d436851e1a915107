//! Compilation of the parsed methods into straight-line register code.
//!
//! Every value lives in a method's frame of registers: the parameters of
//! the system first (registers `0..P`, in the order of `new`), then the
//! method's arguments, its variables and, when it reads `self.__nh_cache`,
//! a copy of the cache; the temporaries of a statement live in a scratch
//! area after them that every statement reuses. A compound value (vector,
//! matrix, array, tuple) occupies consecutive registers, matrices
//! column-major as nalgebra stores them. Reading a variable, an element or
//! a slice costs nothing: the compiled code names its registers.

use super::ast::{MAX_SIZE, Ty};
use super::items::FnSrc;
use super::lex::in_stmt;
use super::parse::Parser;
use std::collections::HashMap;
use std::sync::Arc;

mod call;
mod expr;
mod index;
mod stmt;

/// A register of a frame.
pub(super) type Reg = u32;

/// Marks a scratch register until the frame's layout is final.
const SCRATCH: Reg = 1 << 31;

/// The most instructions a method may compile to.
const MAX_CODE: usize = 1 << 22;

type R<T> = Result<T, String>;

/// A function of one scalar, a method of `T: RealField`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum F1 {
    Sin,
    Cos,
    Tan,
    Sqrt,
    Exp,
    Ln,
    Abs,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
}

impl F1 {
    fn of(name: &str) -> Option<F1> {
        Some(match name {
            "sin" => F1::Sin,
            "cos" => F1::Cos,
            "tan" => F1::Tan,
            "sqrt" => F1::Sqrt,
            "exp" => F1::Exp,
            "ln" => F1::Ln,
            "abs" => F1::Abs,
            "asin" => F1::Asin,
            "acos" => F1::Acos,
            "atan" => F1::Atan,
            "sinh" => F1::Sinh,
            "cosh" => F1::Cosh,
            "tanh" => F1::Tanh,
            _ => return None,
        })
    }
}

/// A comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Cmp {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

/// One instruction: destination first.
#[derive(Debug)]
pub(super) enum Ins {
    Const(Reg, f64),
    Pi(Reg),
    Copy(Reg, Reg),
    CopyN(Reg, Reg, u32),
    Add(Reg, Reg, Reg),
    Sub(Reg, Reg, Reg),
    Mul(Reg, Reg, Reg),
    Div(Reg, Reg, Reg),
    Neg(Reg, Reg),
    Fun(F1, Reg, Reg),
    SinCos(Reg, Reg, Reg),
    Atan2(Reg, Reg, Reg),
    Powi(Reg, Reg, i32),
    Powf(Reg, Reg, Reg),
    Cmp(Cmp, Reg, Reg, Reg),
    Not(Reg, Reg),
    And(Reg, Reg, Reg),
    Or(Reg, Reg, Reg),
    Jump(u32),
    JumpIfFalse(Reg, u32),
    Call(Box<CallIns>),
}

/// A call of another method: its arguments are copied from the caller's
/// registers (`src`, callee's `dst`, length) into the frame after the
/// caller's, and its result back to `dst`.
#[derive(Debug)]
pub(super) struct CallIns {
    pub prog: Arc<Program>,
    pub args: Vec<(Reg, Reg, u32)>,
    pub dst: Reg,
}

/// A named value at a place in a frame.
#[derive(Clone, Debug)]
pub(super) struct Slot {
    pub name: String,
    pub ty: Ty,
    pub base: Reg,
}

/// A compiled method.
#[derive(Debug)]
pub(super) struct Program {
    /// The arguments, in declared order.
    pub args: Vec<Slot>,
    /// Where the result is when the code has run.
    pub ret: Slot,
    pub code: Vec<Ins>,
    /// Registers of the frame.
    pub size: usize,
    /// Registers of the frame and of the deepest chain of calls from it.
    pub deep: usize,
    /// Where the frame holds the cache, if the method reads it.
    pub cache: Option<Reg>,
}

impl Ins {
    fn map_regs(&mut self, f: &impl Fn(Reg) -> Reg) {
        match self {
            Ins::Const(d, _) | Ins::Pi(d) => *d = f(*d),
            Ins::Copy(d, a) | Ins::CopyN(d, a, _) | Ins::Neg(d, a) | Ins::Fun(_, d, a) => {
                (*d, *a) = (f(*d), f(*a));
            }
            Ins::Not(d, a) | Ins::Powi(d, a, _) => (*d, *a) = (f(*d), f(*a)),
            Ins::Add(d, a, b)
            | Ins::Sub(d, a, b)
            | Ins::Mul(d, a, b)
            | Ins::Div(d, a, b)
            | Ins::SinCos(d, a, b)
            | Ins::Atan2(d, a, b)
            | Ins::Powf(d, a, b)
            | Ins::Cmp(_, d, a, b)
            | Ins::And(d, a, b)
            | Ins::Or(d, a, b) => (*d, *a, *b) = (f(*d), f(*a), f(*b)),
            Ins::Jump(_) => {}
            Ins::JumpIfFalse(c, _) => *c = f(*c),
            Ins::Call(c) => {
                c.dst = f(c.dst);
                for (src, _, _) in &mut c.args {
                    *src = f(*src);
                }
            }
        }
    }
}

// ---------------------------------------------------------------- the table

enum State {
    Todo,
    Busy,
    Done(R<Arc<Program>>),
}

/// The methods of a system, compiled on demand (a method before the
/// methods that call it).
pub(super) struct Table<'t> {
    system: String,
    params: Vec<String>,
    fns: Vec<FnSrc<'t>>,
    index: HashMap<String, usize>,
    state: Vec<State>,
}

impl<'t> Table<'t> {
    /// The methods `fns` (the first of a name wins) of system `system`
    /// with the parameters `params`.
    pub(super) fn new(system: String, params: Vec<String>, fns: Vec<FnSrc<'t>>) -> Self {
        let mut index = HashMap::new();
        let mut kept = Vec::new();
        for f in fns {
            if !index.contains_key(&f.name) {
                index.insert(f.name.clone(), kept.len());
                kept.push(f);
            }
        }
        let state = kept.iter().map(|_| State::Todo).collect();
        Table {
            system,
            params,
            fns: kept,
            index,
            state,
        }
    }

    /// The names of the methods, in table order.
    pub(super) fn names(&self) -> Vec<String> {
        self.fns.iter().map(|f| f.name.clone()).collect()
    }

    /// Method `name`'s index.
    pub(super) fn find(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    /// The compiled method `i`, or why it cannot be interpreted.
    pub(super) fn program(&mut self, i: usize) -> R<Arc<Program>> {
        match &self.state[i] {
            State::Done(r) => return r.clone(),
            State::Busy => return Err(format!("`{}` calls itself", self.fns[i].name)),
            State::Todo => {}
        }
        self.state[i] = State::Busy;
        let r = compile_fn(self, i).map(Arc::new);
        self.state[i] = State::Done(r.clone());
        r
    }
}

/// Whether the interpreter models every part of a type.
fn modeled(ty: &Ty) -> bool {
    match ty {
        Ty::Other(_) => false,
        Ty::Array(_, e) => modeled(e),
        Ty::Tuple(ts) => ts.iter().all(modeled),
        _ => true,
    }
}

fn compile_fn(table: &mut Table<'_>, i: usize) -> R<Program> {
    let (sig, body) = (table.fns[i].sig, table.fns[i].body);
    let sig = Parser::new(sig).sig()?;
    if !sig.has_self {
        return Err("an associated function (no `self`)".into());
    }
    for (name, ty) in &sig.params {
        if !modeled(ty) {
            return Err(format!("parameter `{name}` of unsupported type {ty:?}"));
        }
    }
    if !modeled(&sig.ret) {
        return Err(format!("unsupported result type {:?}", sig.ret));
    }
    let body = Parser::new(body).block()?;
    let mut c = Compiler::new(table);
    let args = c.declare_args(&sig.params);
    let v = c.block(&body, Want::Scratch)?;
    let got = ty_of(&v);
    if got.size() != sig.ret.size() {
        return Err(format!("the body gives {got:?} for {:?}", sig.ret));
    }
    let (_, at, _) = c.contiguous(v, Want::Scratch)?;
    if c.too_big {
        return Err(format!(
            "more than {MAX_SIZE} registers or {MAX_CODE} instructions"
        ));
    }
    let ret = Slot {
        name: "result".into(),
        ty: sig.ret,
        base: at,
    };
    Ok(c.finish(args, ret))
}

// ---------------------------------------------------------------- values

/// How a value's registers may be used by a binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Flag {
    /// Written by the expression just compiled: a binding may take them.
    Own,
    /// Another immutable value's: a binding may share them.
    Alias,
    /// A mutable variable's: a binding copies them.
    Volatile,
}

/// Where a value is.
#[derive(Clone, Debug)]
enum Loc {
    /// Consecutive registers.
    Reg(Ty, Reg, Flag),
    /// A tuple whose parts are anywhere.
    Tuple(Vec<Loc>),
    /// No value (`()`, a label).
    Unit,
    /// `self`.
    SelfRef,
}

fn ty_of(v: &Loc) -> Ty {
    match v {
        Loc::Reg(ty, ..) => ty.clone(),
        Loc::Tuple(ls) => Ty::Tuple(ls.iter().map(ty_of).collect()),
        Loc::Unit => Ty::Unit,
        Loc::SelfRef => Ty::Other("self".into()),
    }
}

fn reflag(v: Loc, flag: Flag) -> Loc {
    match v {
        Loc::Reg(ty, at, _) => Loc::Reg(ty, at, flag),
        Loc::Tuple(ls) => Loc::Tuple(ls.into_iter().map(|l| reflag(l, flag)).collect()),
        other => other,
    }
}

/// Where the result of an expression goes.
#[derive(Clone, Copy, Debug)]
enum Want {
    /// Anywhere; temporaries of the statement.
    Scratch,
    /// Registers of its own for the rest of the method (a `let`).
    Persist,
    /// These registers.
    Into(Reg),
}

/// A variable: its value (`None` for `let x;` before its assignment).
struct Var {
    loc: Option<Loc>,
    mutable: bool,
}

// ---------------------------------------------------------------- the compiler

struct Compiler<'a, 't> {
    table: &'a mut Table<'t>,
    code: Vec<Ins>,
    persist: Reg,
    scratch: Reg,
    max_scratch: Reg,
    vars: HashMap<String, Vec<Var>>,
    scopes: Vec<Vec<String>>,
    cache: Option<Reg>,
    deep: usize,
    /// Set when the frame or the code outgrows its bound.
    too_big: bool,
}

impl<'a, 't> Compiler<'a, 't> {
    fn new(table: &'a mut Table<'t>) -> Self {
        let persist = table.params.len() as Reg;
        Compiler {
            table,
            code: Vec::new(),
            persist,
            scratch: 0,
            max_scratch: 0,
            vars: HashMap::new(),
            scopes: vec![Vec::new()],
            cache: None,
            deep: 0,
            too_big: false,
        }
    }

    fn declare_args(&mut self, params: &[(String, Ty)]) -> Vec<Slot> {
        let mut slots = Vec::new();
        for (name, ty) in params {
            let base = self.alloc(Want::Persist, ty.size());
            let loc = Loc::Reg(ty.clone(), base, Flag::Alias);
            self.declare(name, Some(loc), false);
            slots.push(Slot {
                name: name.clone(),
                ty: ty.clone(),
                base,
            });
        }
        slots
    }

    /// The program: scratch registers placed after the others.
    fn finish(mut self, args: Vec<Slot>, mut ret: Slot) -> Program {
        let base = self.persist;
        let fix = |r: Reg| {
            if r & SCRATCH != 0 {
                base + (r & !SCRATCH)
            } else {
                r
            }
        };
        for ins in &mut self.code {
            ins.map_regs(&fix);
        }
        ret.base = fix(ret.base);
        let size = (base + self.max_scratch) as usize;
        Program {
            args,
            ret,
            code: self.code,
            size,
            deep: size + self.deep,
            cache: self.cache,
        }
    }

    fn alloc(&mut self, want: Want, n: usize) -> Reg {
        let used = (self.persist as usize).saturating_add(self.max_scratch as usize);
        if n > MAX_SIZE || used.saturating_add(n) > MAX_SIZE {
            self.too_big = true;
            return 0;
        }
        let n = n as Reg;
        match want {
            Want::Into(r) => r,
            Want::Persist => {
                self.persist += n;
                self.persist - n
            }
            Want::Scratch => {
                self.scratch += n;
                self.max_scratch = self.max_scratch.max(self.scratch);
                SCRATCH | (self.scratch - n)
            }
        }
    }

    fn emit(&mut self, ins: Ins) {
        if self.code.len() < MAX_CODE {
            self.code.push(ins);
        } else {
            self.too_big = true;
        }
    }

    fn copy(&mut self, dst: Reg, src: Reg, n: usize) {
        match n {
            _ if dst == src => {}
            0 => {}
            1 => self.emit(Ins::Copy(dst, src)),
            _ => self.emit(Ins::CopyN(dst, src, n as u32)),
        }
    }

    /// Writes a value into the consecutive registers at `dst`; its size.
    fn store(&mut self, v: &Loc, dst: Reg) -> R<usize> {
        match v {
            Loc::Reg(ty, at, _) => {
                self.copy(dst, *at, ty.size());
                Ok(ty.size())
            }
            Loc::Tuple(ls) => {
                let mut off = 0;
                for l in ls {
                    off += self.store(l, dst + off as Reg)?;
                }
                Ok(off)
            }
            Loc::Unit => Ok(0),
            Loc::SelfRef => Err("`self` as a value".into()),
        }
    }

    /// The value in consecutive registers (copied there if needed).
    fn contiguous(&mut self, v: Loc, want: Want) -> R<(Ty, Reg, Flag)> {
        match (v, want) {
            (Loc::Reg(ty, at, _), Want::Into(r)) if at != r => {
                self.copy(r, at, ty.size());
                Ok((ty, r, Flag::Own))
            }
            (Loc::Reg(ty, at, flag), _) => Ok((ty, at, flag)),
            (other, _) => {
                let ty = ty_of(&other);
                let at = self.alloc(want, ty.size());
                self.store(&other, at)?;
                Ok((ty, at, Flag::Own))
            }
        }
    }

    fn declare(&mut self, name: &str, loc: Option<Loc>, mutable: bool) {
        self.vars
            .entry(name.to_string())
            .or_default()
            .push(Var { loc, mutable });
        if let Some(scope) = self.scopes.last_mut() {
            scope.push(name.to_string());
        }
    }

    fn pop_scope(&mut self) {
        for name in self.scopes.pop().unwrap_or_default() {
            if let Some(v) = self.vars.get_mut(&name) {
                v.pop();
            }
        }
    }

    fn var(&self, name: &str) -> Option<&Var> {
        self.vars.get(name).and_then(|v| v.last())
    }

    /// The value of a name.
    fn name(&self, name: &str) -> R<Loc> {
        if name == "self" {
            return Ok(Loc::SelfRef);
        }
        let var = self
            .var(name)
            .ok_or_else(|| format!("unknown name `{name}`"))?;
        let loc =
            (var.loc.clone()).ok_or_else(|| format!("`{name}` read before it is assigned"))?;
        Ok(reflag(
            loc,
            if var.mutable {
                Flag::Volatile
            } else {
                Flag::Alias
            },
        ))
    }
}
