//! The symbolic engine: a hash-consed expression graph in a canonical
//! expanded form, with exact rational coefficients and memoised derivatives.
//!
//! # Representation
//!
//! Every expression is a sum of monomials with rational coefficients (an
//! [`ExprId`]); a monomial is a product of atoms raised to rational powers (a
//! [`MonoId`]); an atom is a symbol, a function of an expression, or an
//! expression used as the base of a power that cannot be expanded (a sum to a
//! negative or fractional power). All three are interned: each distinct
//! expression, monomial and atom is stored once and compared by id.
//!
//! The canonical form is: products distributed over sums, like monomials
//! collected, constants folded, sums sorted by monomial id, monomials sorted by
//! atom id, and trigonometric polynomials reduced modulo `sin² + cos² = 1`
//! (every `cos(u)^k` with `k ≥ 2` becomes `cos(u)^(k mod 2) (1 - sin(u)²)^(k div 2)`).
//! Two expressions that are equal as polynomials in their atoms, modulo the
//! Pythagorean identity, therefore have the same id, and zero is recognised
//! exactly for the trigonometric polynomials that mechanics produces.
//! `tan`, `cot`, `sec` and `csc` are quotients of `sin` and `cos`; odd
//! functions take the sign out of their argument and even ones drop it;
//! `|u|` distributes over the factors of a monomial, its even powers are
//! powers of `u`, and an even power under a root is a power of `|u|`
//! (`sqrt(x²)` is `|x|`).
//!
//! Coefficients are exact rationals of any size. Arithmetic never panics:
//! expression swell or a constant power beyond [`Rational::MAX_DIGITS`] digits
//! exceeds one of the engine's limits ([`Limit`]), which abandons the
//! derivation ([`Engine::overflowed`]) and keeps the limit with the part of
//! the input the stages named as under way ([`Engine::exceeded`]); the
//! caller turns it into a compile error there.
//!
//! # Layout
//!
//! [`Engine`] is defined here with its limits; its operations are in one
//! file each: `graph` (the ids, node types and interners), `arith` (sums,
//! products, functions, constant folding), `funcs` (the functions beyond
//! sin, cos, tan, exp and ln, and `atan2`), `power` (integer and rational
//! powers), `normal` (the normal form of a monomial), `kept` (products kept
//! unexpanded), `diff` (derivatives), `subst` (substitution), `limits`
//! (the measures bounded and the first exceeded), `eval`
//! (numeric evaluation in any [`Scalar`]) and `display` (text).

mod arith;
pub mod dd;
mod diff;
mod display;
pub mod dual;
mod eval;
mod funcs;
mod graph;
mod kept;
mod limits;
mod normal;
mod power;
pub mod random_points;
pub mod rational;
mod subst;

use rustc_hash::FxHashMap as HashMap;

pub use eval::{EvalMemo, Scalar};
pub use funcs::{exact_atan2, exact_value};
pub(crate) use graph::id_type;
pub use graph::{Atom, AtomId, ExprId, Fun, MonoId, SymId};
use graph::{Factors, Terms};
pub use limits::{Exceeded, Limit};
pub use rational::Rational;

/// The expression graph with its interners and memo tables.
#[derive(Default)]
pub struct Engine {
    sym_names: Vec<String>,
    atoms: Vec<Atom>,
    atom_ix: HashMap<Atom, AtomId>,
    atom_syms: Vec<Vec<SymId>>,
    monos: Vec<Factors>,
    mono_ix: HashMap<Factors, MonoId>,
    /// The symbols each monomial depends on, sorted.
    mono_syms: Vec<Vec<SymId>>,
    exprs: Vec<Terms>,
    expr_ix: HashMap<Terms, ExprId>,
    expr_syms: Vec<Vec<SymId>>,
    memo_mul: HashMap<(ExprId, ExprId), ExprId>,
    memo_diff: HashMap<(ExprId, SymId), ExprId>,
    /// Whether a limit was exceeded: the derivation is abandoned (read on
    /// every product and derivative, so a flag of its own).
    abandoned: bool,
    /// The first limit exceeded, with the site named then.
    exceeded: Option<Exceeded>,
    /// The part of the input being derived (see [`Engine::enter`]).
    site: Option<crate::ctxt::Site>,
    work: usize,
    /// The work a derivation may do ([`MAX_WORK`]).
    max_work: usize,
    /// Products under way, one inside another (see [`MAX_NESTING`]).
    nesting: usize,
    /// Products of sums up to this many term products are expanded
    /// ([`EXPAND_LIMIT`] by default; see [`Engine::set_expansion_limits`]).
    expand_limit: usize,
    /// Sums longer than this become atoms in kept products ([`ATOM_MIN`]).
    atom_min: usize,
    /// Counts of work done, for statistics and tests of what is derived.
    pub counters: Counters,
}

/// Work counters of the engine.
#[derive(Default, Clone, Debug)]
pub struct Counters {
    /// Number of derivative computations that were not memo hits.
    pub derivatives: usize,
    /// Number of polynomial products that were not memo hits.
    pub products: usize,
}

/// The empty monomial, i.e. the constant 1.
pub const MONO_ONE: MonoId = MonoId::from_index(0);
/// The expression 0.
pub const ZERO: ExprId = ExprId::from_index(0);
/// The expression 1.
pub const ONE: ExprId = ExprId::from_index(1);

/// Largest number of terms a single expression may have before the engine
/// reports expression swell instead of growing without bound.
pub const MAX_TERMS: usize = 200_000;

/// Largest number of monomial products one derivation may compute: past it
/// the engine stops and reports expression swell (a few seconds of work).
pub const MAX_WORK: usize = 50_000_000;

/// Deepest nesting of products inside products (each kept product takes the
/// contents of its factors, each normalised monomial multiplies its
/// expansions); beyond it the derivation reports swell instead of
/// overflowing the stack.
pub const MAX_NESTING: usize = 200;

/// Largest number of term products a product of two sums (or an integer
/// power of a sum) is expanded into; beyond it the factors stay unexpanded
/// atoms (see `Engine::kept_product`). Small products are expanded so that
/// the canonical form can cancel them (the closed forms of small systems);
/// large ones are kept, so expression swell cannot set in.
pub const EXPAND_LIMIT: usize = 64;

/// Sums longer than this are kept as one atom when they are a factor of a
/// product that is not expanded (see [`EXPAND_LIMIT`]); shorter ones are
/// distributed over the other factor.
pub const ATOM_MIN: usize = 8;

/// A sum longer than this times a single term is kept as one atom times
/// that term, not distributed: a chain of rotations multiplies each
/// entry of the last product by the next factor's sines and cosines, and
/// distributed, the entries grow like the Fibonacci numbers (a chain of
/// links on universal joints: 121,393 terms at the 13th link); kept, they
/// grow by a few terms a link.
pub const SCALED_MIN: usize = 256;

impl Engine {
    /// A fresh engine with `0` and `1` interned.
    pub fn new() -> Engine {
        let mut e = Engine {
            expand_limit: EXPAND_LIMIT,
            atom_min: ATOM_MIN,
            max_work: MAX_WORK,
            ..Engine::default()
        };
        let one = e.intern_mono(Vec::new());
        debug_assert_eq!(one, MONO_ONE);
        let z = e.intern_expr(Vec::new());
        let o = e.intern_expr(vec![(MONO_ONE, Rational::ONE)]);
        debug_assert_eq!((z, o), (ZERO, ONE));
        e
    }

    /// True once one of the engine's limits is exceeded ([`Limit`]: the
    /// work, [`MAX_WORK`]; the terms of an expression, [`MAX_TERMS`]; ..):
    /// results are then meaningless ([`Engine::exceeded`] tells which limit,
    /// and where).
    pub fn overflowed(&self) -> bool {
        self.abandoned()
    }

    /// A fresh engine whose derivations may do `max_work` units of work
    /// instead of [`MAX_WORK`]: the tests of what exceeding it reports,
    /// in a fraction of the time.
    #[cfg(test)]
    pub(crate) fn with_work_limit(max_work: usize) -> Engine {
        let mut e = Engine::new();
        e.max_work = max_work;
        e
    }

    /// Sets how far products of sums are expanded: products of up to
    /// `expand` term pairs are expanded (so that the canonical form can cancel
    /// them), longer ones kept as products of atoms, with sums of more than
    /// `atom_min` terms as single atoms. Large systems use low limits: their
    /// expanded products swell, and their closed forms do not pay.
    pub fn set_expansion_limits(&mut self, expand: usize, atom_min: usize) {
        self.expand_limit = expand.max(1);
        self.atom_min = atom_min.max(1);
    }

    /// Declares a new symbol.
    pub fn symbol(&mut self, name: &str) -> SymId {
        self.sym_names.push(name.to_string());
        SymId::from_index(self.sym_names.len() - 1)
    }

    /// Name of a symbol.
    pub fn sym_name(&self, s: SymId) -> &str {
        &self.sym_names[s.index()]
    }

    /// Number of declared symbols.
    pub fn num_symbols(&self) -> usize {
        self.sym_names.len()
    }

    /// Number of distinct expressions stored (size of the graph).
    pub fn num_exprs(&self) -> usize {
        self.exprs.len()
    }
}

#[cfg(test)]
mod tests;

/// A deterministic pseudo-random sequence (xorshift*) for the numerical
/// tests at random points: the same verdict on every build.
pub struct Rng(u64);

impl Rng {
    /// A random point for the symbols of an engine of `len` symbols: each
    /// in [0.3, 1.4) (positive, so square roots and logarithms stay
    /// defined), drawn in symbol order, and the symbol `pi` at π.
    pub fn point(&mut self, len: usize, pi: SymId) -> Vec<dd::Dd> {
        let mut vals: Vec<dd::Dd> = (0..len)
            .map(|_| dd::Dd::from_f64(0.3 + 1.1 * self.next_f64()))
            .collect();
        vals[pi.index()] = dd::Dd::PI;
        vals
    }

    /// The sequence from `seed` (nonzero).
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next number, uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        let s = &mut self.0;
        *s ^= *s >> 12;
        *s ^= *s << 25;
        *s ^= *s >> 27;
        ((s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64) / (1u64 << 53) as f64
    }
}
