//! An interpreter of the code `nonholonomic_system!` generates.
//!
//! [`Expansion::new`] reads an expansion (the token stream
//! `nh_core::expand` returns) once: the system's constants, the parameters
//! of `new`, and every method of `impl<T> NAME<T>` and of the trait impls
//! for `NAME<T>`, parsed and compiled into straight-line register code.
//! [`Expansion::call`] runs a method in any [`Scalar`]: for `f64` it makes
//! exactly the operations the compiled method makes, in the same order,
//! with the same functions (nalgebra's `RealField` for `f64` forwards
//! `sin_cos`, `powi`, `atan2`, ... to `std`'s, as `Scalar for f64` does), so
//! its results are the compiled method's bit for bit.
//!
//! The subset of Rust understood is the one the engine emits: `let`
//! bindings (names, tuples, `mut`, `let x;` assigned later), blocks whose
//! values are tuples (the chunks of large functions), `if`/`else` on
//! comparisons (the sign of a value, the cache's validity), assignments to
//! variables, array elements and matrix entries (`+=` too), `for` over an
//! array (unrolled), the arithmetic of `T`, `T::zero()`, `T::one()`,
//! `T::pi()`, `Self::__nh_c(c)`, the methods `sin cos tan sin_cos sqrt exp
//! ln abs asin acos atan atan2 sinh cosh tanh powi powf`, indexing (`q[1]`,
//! `m[(i, j)]`, `cache[3]`), `x.fixed_rows::<n>(i).into_owned()`, tuple
//! fields, the constructors `SVector::from([..])`,
//! `SMatrix::from_row_slice(&[..])`, `zeros()` and `Option::Some(..)`, the
//! parameters `self.p`, the cache `self.__nh_cache`, and calls of the
//! system's own methods (`self.m(..)`, `NAME::m(self, ..)`). A method using
//! anything else cannot be called, and [`Expansion::unsupported`] lists it
//! with the tokens where reading stopped: in the engine's output today,
//! only methods that compute no numbers (`new` and the other associated
//! functions, the states by name, `parameters`, `project` with its closure
//! and `&mut` argument, `crossed_pole`, `sensitivities`).
//!
//! Comparisons are made on the nearest `f64`s: exact for `f64` and for the
//! sign of a double-double; the largest of double-doubles that round to
//! the same `f64` (`constraint_residual`) may be either.
//!
//! [`Expansion::bind`] fixes the parameters: the cache of the values that
//! depend on them alone is then computed once, as the compiled `new` does,
//! instead of at every [`Expansion::call`].

mod ast;
mod compile;
mod eval;
mod items;
mod lex;
mod parse;

use crate::Scalar;
use ast::Ty;
use compile::{Program, Table};
use items::{FnSrc, Items, const_ints, const_strs, const_variants};
use lex::Tok;
use proc_macro2::TokenStream;
use std::sync::Arc;

/// An argument of a generated method.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg<S> {
    /// A scalar (`t`).
    Scalar(S),
    /// A vector's entries (`q`, `rdot`, `u`, `x`, `speeds`), or a matrix's
    /// entries column-major (`s_p`, `s_x0`).
    Vector(Vec<S>),
}

/// The shape of an argument of a generated method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A scalar: [`Arg::Scalar`].
    Scalar,
    /// A vector or matrix of this many entries: [`Arg::Vector`].
    Entries(usize),
}

/// A system's expansion, read once and ready to run its methods.
#[derive(Debug)]
pub struct Expansion {
    name: String,
    parameters: Vec<String>,
    coordinates: Vec<String>,
    independent: Vec<usize>,
    dependent: Vec<usize>,
    inputs: Vec<String>,
    speeds: Vec<String>,
    cyclic: Vec<usize>,
    conserved: Vec<String>,
    declared_conserved: Vec<String>,
    methods: Vec<(String, Result<Arc<Program>, String>)>,
    cache: Option<Arc<Program>>,
}

/// The methods of a system bound to parameter values: the cache of values
/// that depend on the parameters alone is computed once, and the registers
/// are reused from call to call (faster than [`Expansion::call`] when a
/// system is evaluated many times).
#[derive(Debug)]
pub struct Bound<'e, S> {
    exp: &'e Expansion,
    params: Vec<S>,
    cache: Option<Vec<S>>,
    regs: Vec<S>,
}

impl Expansion {
    /// Reads an expansion: its constants, the parameters of `new` and its
    /// methods. Fails if it defines no system (a `compile_error!`, or no
    /// `impl NAME<f64>` with the constants, or no `new`); a method the
    /// interpreter cannot read fails only when called.
    pub fn new(tokens: &TokenStream) -> Result<Expansion, String> {
        let toks = lex::lex(tokens.clone());
        let mut items = Items::default();
        items::scan(&toks, &mut items);
        if let Some(e) = items.compile_error {
            return Err(format!("the expansion is an error: {e}"));
        }
        let name = (items.name.clone()).ok_or("no `impl NAME<f64>` in the expansion")?;
        let consts = Consts(&items.consts);
        let parameters = new_params(&items.inherent)?;
        let mut exp = Expansion {
            coordinates: consts.strs("COORDINATES")?.ok_or("no COORDINATES")?,
            independent: consts.ints("INDEPENDENT")?.unwrap_or_default(),
            dependent: consts.ints("DEPENDENT")?.unwrap_or_default(),
            inputs: consts.strs("INPUTS")?.unwrap_or_default(),
            speeds: consts.strs("SPEEDS")?.unwrap_or_default(),
            cyclic: consts.ints("CYCLIC")?.unwrap_or_default(),
            conserved: consts.variants("CONSERVED")?.unwrap_or_default(),
            declared_conserved: consts.variants("MOMENTUM_CONSERVED")?.unwrap_or_default(),
            name: name.clone(),
            parameters: parameters.clone(),
            methods: Vec::new(),
            cache: None,
        };
        let traits = items.traits.into_iter().filter(|(t, _)| *t == name);
        let fns: Vec<FnSrc<'_>> = items
            .inherent
            .into_iter()
            .chain(traits.map(|(_, f)| f))
            .collect();
        let mut table = Table::new(name, parameters, fns);
        for (i, m) in table.names().into_iter().enumerate() {
            exp.methods.push((m, table.program(i)));
        }
        exp.cache = (table.find("__nh_compute_cache")).and_then(|i| table.program(i).ok());
        Ok(exp)
    }

    /// The system's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The parameters, in the order of `new` (raw identifiers without `r#`).
    pub fn parameters(&self) -> &[String] {
        &self.parameters
    }

    /// `COORDINATES`.
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }

    /// `INDEPENDENT` (empty for a system in generalized speeds).
    pub fn independent(&self) -> &[usize] {
        &self.independent
    }

    /// `DEPENDENT` (empty for a system in generalized speeds).
    pub fn dependent(&self) -> &[usize] {
        &self.dependent
    }

    /// `INPUTS`.
    pub fn inputs(&self) -> &[String] {
        &self.inputs
    }

    /// `SPEEDS` (empty unless the system is written in generalized speeds).
    pub fn speeds(&self) -> &[String] {
        &self.speeds
    }

    /// `CYCLIC`: the cyclic coordinates, with `outputs { momenta }`.
    pub fn cyclic(&self) -> &[usize] {
        &self.cyclic
    }

    /// The verdicts of `CONSERVED` by their variants' names (`Conserved`,
    /// `NotConserved`, `Undecided`), in the order of [`Self::cyclic`].
    pub fn conserved(&self) -> &[String] {
        &self.conserved
    }

    /// The verdicts of `MOMENTUM_CONSERVED` (`momenta { .. }`) by their
    /// variants' names, in declared order.
    pub fn declared_conserved(&self) -> &[String] {
        &self.declared_conserved
    }

    /// Whether the expansion defines a method `name` (of the system or of
    /// one of its trait impls), whether or not it can be interpreted.
    pub fn has_method(&self, name: &str) -> bool {
        self.methods.iter().any(|(m, _)| m == name)
    }

    /// The names of the methods defined.
    pub fn methods(&self) -> impl Iterator<Item = &str> {
        self.methods.iter().map(|(m, _)| m.as_str())
    }

    /// The arguments method `name` takes, in order, with their shapes.
    pub fn arguments(&self, name: &str) -> Result<Vec<(&str, Shape)>, String> {
        let prog = self.program(name)?;
        let shape = |ty: &Ty| match ty {
            Ty::Scalar => Shape::Scalar,
            other => Shape::Entries(other.size()),
        };
        Ok(prog
            .args
            .iter()
            .map(|s| (s.name.as_str(), shape(&s.ty)))
            .collect())
    }

    /// The methods that cannot be interpreted, with the reason (quoting the
    /// tokens where reading stopped).
    pub fn unsupported(&self) -> impl Iterator<Item = (&str, &str)> {
        (self.methods.iter())
            .filter_map(|(m, r)| r.as_ref().err().map(|e| (m.as_str(), e.as_str())))
    }

    /// Evaluates method `name` with the given parameter values (in declared
    /// order) and arguments by name (every argument of the method, no
    /// other: `"t"` a scalar; `"q"`, `"rdot"`, `"u"`, `"x"`, `"speeds"`
    /// vectors; `"s_p"`, `"s_x0"` matrices column-major).
    ///
    /// Returns the entries of the result: a scalar as one entry; a vector's
    /// entries; a matrix's entries column-major (as nalgebra stores them);
    /// an array or a tuple as its parts one after the other (`curvature`:
    /// B^0's entries, then B^1's, ...; `linearization`: A then B);
    /// `Some(x)` as x; a `bool` as 1 or 0.
    pub fn call<S: Scalar>(
        &self,
        name: &str,
        params: &[S],
        args: &[(&str, Arg<S>)],
    ) -> Result<Vec<S>, String> {
        self.bind(params)?.call(name, args)
    }

    /// The methods at the given parameter values (declared order).
    pub fn bind<S: Scalar>(&self, params: &[S]) -> Result<Bound<'_, S>, String> {
        if params.len() != self.parameters.len() {
            return Err(format!(
                "{} parameters given, {} has {} ({})",
                params.len(),
                self.name,
                self.parameters.len(),
                self.parameters.join(", ")
            ));
        }
        Ok(Bound {
            exp: self,
            params: params.to_vec(),
            cache: None,
            regs: Vec::new(),
        })
    }

    fn program(&self, name: &str) -> Result<&Program, String> {
        match self.methods.iter().find(|(m, _)| m == name) {
            Some((_, Ok(p))) => Ok(p),
            Some((_, Err(e))) => Err(format!(
                "`{}::{name}` cannot be interpreted: {e}",
                self.name
            )),
            None => Err(format!("`{}` has no method `{name}`", self.name)),
        }
    }
}

impl<S: Scalar> Bound<'_, S> {
    /// Evaluates method `name` with the arguments by name: as
    /// [`Expansion::call`].
    pub fn call(&mut self, name: &str, args: &[(&str, Arg<S>)]) -> Result<Vec<S>, String> {
        let prog = self.exp.program(name)?;
        if self.regs.len() < prog.deep {
            self.regs.resize(prog.deep, S::zero());
        }
        place_args(prog, args, &mut self.regs).map_err(|e| format!("`{name}`: {e}"))?;
        let mut ctx = eval::Ctx {
            params: &self.params,
            cache_prog: self.exp.cache.as_deref(),
            cache: self.cache.take(),
        };
        eval::run(&mut ctx, prog, &mut self.regs);
        self.cache = ctx.cache;
        let (at, n) = (prog.ret.base as usize, prog.ret.ty.size());
        Ok(self.regs[at..at + n].to_vec())
    }
}

/// Copies the arguments into a method's frame, checking their shapes.
fn place_args<S: Scalar>(
    prog: &Program,
    args: &[(&str, Arg<S>)],
    regs: &mut [S],
) -> Result<(), String> {
    let names = || {
        prog.args
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some((extra, _)) = args
        .iter()
        .find(|(n, _)| !prog.args.iter().any(|s| s.name == *n))
    {
        return Err(format!("no argument `{extra}` (it takes {})", names()));
    }
    for slot in &prog.args {
        let (_, given) = (args.iter().find(|(n, _)| *n == slot.name))
            .ok_or_else(|| format!("missing argument `{}` (it takes {})", slot.name, names()))?;
        let at = slot.base as usize;
        match (given, &slot.ty) {
            (Arg::Scalar(x), Ty::Scalar) => regs[at] = *x,
            (Arg::Vector(v), ty) if *ty != Ty::Scalar && v.len() == ty.size() => {
                regs[at..at + v.len()].copy_from_slice(v);
            }
            _ => return Err(format!("argument `{}` must be {:?}", slot.name, slot.ty)),
        }
    }
    Ok(())
}

/// The parameters of `new`, in order.
fn new_params(fns: &[FnSrc<'_>]) -> Result<Vec<String>, String> {
    let new = fns.iter().find(|f| f.name == "new").ok_or("no `new`")?;
    let sig = parse::Parser::new(new.sig)
        .sig()
        .map_err(|e| format!("`new`: {e}"))?;
    Ok(sig.params.into_iter().map(|(name, _)| name).collect())
}

/// The constants of `impl NAME<f64>`.
struct Consts<'a, 't>(&'a [(String, &'t [Tok])]);

impl Consts<'_, '_> {
    fn value(&self, name: &str) -> Option<&[Tok]> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    fn strs(&self, name: &str) -> Result<Option<Vec<String>>, String> {
        self.value(name)
            .map(|v| const_strs(v).ok_or_else(|| format!("cannot read {name}")))
            .transpose()
    }

    fn variants(&self, name: &str) -> Result<Option<Vec<String>>, String> {
        self.value(name)
            .map(|v| const_variants(v).ok_or_else(|| format!("cannot read {name}")))
            .transpose()
    }

    fn ints(&self, name: &str) -> Result<Option<Vec<usize>>, String> {
        self.value(name)
            .map(|v| const_ints(v).ok_or_else(|| format!("cannot read {name}")))
            .transpose()
    }
}
