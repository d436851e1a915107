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
//!
//! Coefficients are exact rationals of any size. Arithmetic never panics:
//! expression swell or a constant power beyond [`Rational::MAX_DIGITS`] digits
//! sets a flag ([`Engine::overflowed`]) that the caller turns into a compile
//! error.

pub mod dd;
pub mod rational;

use rustc_hash::FxHashMap as HashMap;

pub use rational::Rational;

/// Defines an id type: a `u32` index into one table, distinct from the ids
/// of every other table, so that mixing them up is a type error.
macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
        pub struct $name(u32);

        impl $name {
            /// The position in the table this id indexes.
            #[inline(always)]
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The id of position `i` of its table.
            #[inline(always)]
            pub(crate) const fn from_index(i: usize) -> Self {
                Self(i as u32)
            }
        }
    };
}
pub(crate) use id_type;

id_type! {
    /// Index of a symbol (parameter, coordinate, velocity, input, time, π).
    SymId
}
id_type! {
    /// Index of an interned atom.
    AtomId
}
id_type! {
    /// Index of an interned monomial.
    MonoId
}
id_type! {
    /// Index of an interned expression.
    ExprId
}

/// The elementary functions the input language supports (`sqrt` is a power).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub enum Fun {
    /// sine
    Sin,
    /// cosine
    Cos,
    /// tangent
    Tan,
    /// exponential
    Exp,
    /// natural logarithm
    Ln,
}

impl Fun {
    /// The name as written in the input language.
    pub fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Exp => "exp",
            Fun::Ln => "ln",
        }
    }

    fn eval(self, x: f64) -> f64 {
        match self {
            Fun::Sin => x.sin(),
            Fun::Cos => x.cos(),
            Fun::Tan => x.tan(),
            Fun::Exp => x.exp(),
            Fun::Ln => x.ln(),
        }
    }
}

/// An atom: what a monomial is a product of.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum Atom {
    /// A symbol.
    Sym(SymId),
    /// `f(arg)`.
    Func(Fun, ExprId),
    /// An expression used as the base of a power that is not expanded.
    Base(ExprId),
}

type Factors = Vec<(AtomId, Rational)>;
type Terms = Vec<(MonoId, Rational)>;

/// The expression graph with its interners and memo tables.
#[derive(Default)]
pub struct Engine {
    sym_names: Vec<String>,
    atoms: Vec<Atom>,
    atom_ix: HashMap<Atom, AtomId>,
    atom_syms: Vec<Vec<SymId>>,
    monos: Vec<Factors>,
    mono_ix: HashMap<Factors, MonoId>,
    exprs: Vec<Terms>,
    expr_ix: HashMap<Terms, ExprId>,
    expr_syms: Vec<Vec<SymId>>,
    memo_mul: HashMap<(ExprId, ExprId), ExprId>,
    memo_diff: HashMap<(ExprId, SymId), ExprId>,
    overflow: bool,
    work: usize,
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

impl Engine {
    /// A fresh engine with `0` and `1` interned.
    pub fn new() -> Engine {
        let mut e = Engine {
            expand_limit: EXPAND_LIMIT,
            atom_min: ATOM_MIN,
            ..Engine::default()
        };
        let one = e.intern_mono(Vec::new());
        debug_assert_eq!(one, MONO_ONE);
        let z = e.intern_expr(Vec::new());
        let o = e.intern_expr(vec![(MONO_ONE, Rational::ONE)]);
        debug_assert_eq!((z, o), (ZERO, ONE));
        e
    }

    /// True if a constant power exceeded [`Rational::MAX_DIGITS`] digits or
    /// the work exceeded [`MAX_TERMS`] or [`MAX_WORK`]; results are then
    /// meaningless.
    pub fn overflowed(&self) -> bool {
        self.overflow
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

    // ------------------------------------------------------------ interning

    fn intern_atom(&mut self, a: Atom) -> AtomId {
        if let Some(&id) = self.atom_ix.get(&a) {
            return id;
        }
        let syms = match &a {
            Atom::Sym(s) => vec![*s],
            Atom::Func(_, e) | Atom::Base(e) => self.expr_syms[e.index()].clone(),
        };
        let id = AtomId::from_index(self.atoms.len());
        self.atoms.push(a.clone());
        self.atom_syms.push(syms);
        self.atom_ix.insert(a, id);
        id
    }

    fn intern_mono(&mut self, f: Factors) -> MonoId {
        if let Some(&id) = self.mono_ix.get(&f) {
            return id;
        }
        let id = MonoId::from_index(self.monos.len());
        self.monos.push(f.clone());
        self.mono_ix.insert(f, id);
        id
    }

    fn intern_expr(&mut self, t: Terms) -> ExprId {
        if let Some(&id) = self.expr_ix.get(&t) {
            return id;
        }
        if t.len() > MAX_TERMS {
            self.overflow = true;
            return ZERO;
        }
        let mut syms: Vec<SymId> = Vec::new();
        for (m, _) in &t {
            for (a, _) in &self.monos[m.index()] {
                syms.extend_from_slice(&self.atom_syms[a.index()]);
            }
        }
        syms.sort_unstable();
        syms.dedup();
        let id = ExprId::from_index(self.exprs.len());
        self.exprs.push(t.clone());
        self.expr_syms.push(syms);
        self.expr_ix.insert(t, id);
        id
    }

    // ------------------------------------------------------------ accessors

    /// The terms `(monomial, coefficient)` of an expression, sorted.
    pub fn terms(&self, e: ExprId) -> &[(MonoId, Rational)] {
        &self.exprs[e.index()]
    }

    /// The factors `(atom, exponent)` of a monomial, sorted.
    pub fn factors(&self, m: MonoId) -> &[(AtomId, Rational)] {
        &self.monos[m.index()]
    }

    /// An atom.
    pub fn atom(&self, a: AtomId) -> &Atom {
        &self.atoms[a.index()]
    }

    /// Free symbols of an expression, sorted.
    pub fn free_symbols(&self, e: ExprId) -> &[SymId] {
        &self.expr_syms[e.index()]
    }

    /// Free symbols of an atom, sorted.
    pub fn atom_symbols(&self, a: AtomId) -> &[SymId] {
        &self.atom_syms[a.index()]
    }

    /// Does `e` depend on symbol `s`?
    pub fn depends_on(&self, e: ExprId, s: SymId) -> bool {
        self.expr_syms[e.index()].binary_search(&s).is_ok()
    }

    /// The constant value if `e` is a rational constant.
    pub fn as_constant(&self, e: ExprId) -> Option<Rational> {
        match self.terms(e) {
            [] => Some(Rational::ZERO),
            [(MONO_ONE, c)] => Some(*c),
            _ => None,
        }
    }

    /// Number of terms of an expression.
    pub fn num_terms(&self, e: ExprId) -> usize {
        self.exprs[e.index()].len()
    }

    // ------------------------------------------------------------ rational helpers

    /// Counts arithmetic on big coefficients as work (see [`MAX_WORK`]): a
    /// product of two values of `a` and `b` words costs about `a·b` word
    /// operations plus the reduction.
    fn big_work(&mut self, a: Rational, b: Rational) {
        if a.to_i128_parts().is_none() || b.to_i128_parts().is_none() {
            let (wa, wb) = (a.size_words(), b.size_words());
            let cost = 8u64.saturating_mul(wa + 1).saturating_mul(wb + 1);
            self.work = self
                .work
                .saturating_add(usize::try_from(cost).unwrap_or(usize::MAX));
        }
    }

    fn qmul(&mut self, a: Rational, b: Rational) -> Rational {
        self.big_work(a, b);
        a.checked_mul(b).unwrap_or_else(|| {
            self.overflow = true;
            Rational::ZERO
        })
    }

    fn qpowi(&mut self, a: Rational, e: i64) -> Rational {
        a.checked_powi(e).unwrap_or_else(|| {
            self.overflow = true;
            Rational::ZERO
        })
    }

    // ------------------------------------------------------------ constructors

    /// The rational constant `c`.
    pub fn constant(&mut self, c: Rational) -> ExprId {
        if c.is_zero() {
            ZERO
        } else {
            self.intern_expr(vec![(MONO_ONE, c)])
        }
    }

    /// The integer constant `n`.
    pub fn int(&mut self, n: i128) -> ExprId {
        self.constant(Rational::int(n))
    }

    /// The expression consisting of symbol `s`.
    pub fn sym(&mut self, s: SymId) -> ExprId {
        let a = self.intern_atom(Atom::Sym(s));
        self.atom_power(a, Rational::ONE)
    }

    fn atom_power(&mut self, a: AtomId, e: Rational) -> ExprId {
        let m = self.intern_mono(vec![(a, e)]);
        self.intern_expr(vec![(m, Rational::ONE)])
    }

    /// Builds an expression from unsorted terms, collecting like monomials.
    fn collect(&mut self, mut acc: Vec<(MonoId, Rational)>) -> ExprId {
        acc.sort_unstable_by_key(|t| t.0);
        let mut out: Terms = Vec::with_capacity(acc.len());
        for (m, c) in acc {
            match out.last_mut() {
                Some((lm, lc)) if *lm == m => {
                    if lc.to_i128_parts().is_none() || c.to_i128_parts().is_none() {
                        let w = lc.size_words() + c.size_words() + 1;
                        self.work = self
                            .work
                            .saturating_add(usize::try_from(8 * w * w).unwrap_or(usize::MAX));
                    }
                    *lc = lc.checked_add(c).unwrap_or_else(|| {
                        self.overflow = true;
                        Rational::ZERO
                    })
                }
                _ => out.push((m, c)),
            }
        }
        out.retain(|(_, c)| !c.is_zero());
        self.intern_expr(out)
    }

    /// `a + b`.
    pub fn add(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if a == ZERO {
            return b;
        }
        if b == ZERO {
            return a;
        }
        let mut acc = self.exprs[a.index()].clone();
        acc.extend_from_slice(&self.exprs[b.index()]);
        self.collect(acc)
    }

    /// Sum of many expressions.
    pub fn sum(&mut self, items: &[ExprId]) -> ExprId {
        let mut acc = Vec::new();
        for &i in items {
            acc.extend_from_slice(&self.exprs[i.index()]);
        }
        self.collect(acc)
    }

    /// `c * a` for a rational `c`.
    pub fn scale(&mut self, a: ExprId, c: Rational) -> ExprId {
        if c.is_zero() {
            return ZERO;
        }
        if c.is_one() {
            return a;
        }
        let t: Terms = self.exprs[a.index()].clone();
        let t = t.into_iter().map(|(m, k)| (m, self.qmul(k, c))).collect();
        self.collect(t)
    }

    /// `-a`.
    pub fn neg(&mut self, a: ExprId) -> ExprId {
        self.scale(a, Rational::MINUS_ONE)
    }

    /// `a - b`.
    pub fn sub(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let nb = self.neg(b);
        self.add(a, nb)
    }

    /// `a * b`, distributed and normalised.
    pub fn mul(&mut self, a: ExprId, b: ExprId) -> ExprId {
        if a == ZERO || b == ZERO {
            return ZERO;
        }
        if a == ONE {
            return b;
        }
        if b == ONE {
            return a;
        }
        let key = if a <= b { (a, b) } else { (b, a) };
        if let Some(&r) = self.memo_mul.get(&key) {
            return r;
        }
        if self.overflow {
            return ZERO;
        }
        let (la, lb) = (self.exprs[a.index()].len(), self.exprs[b.index()].len());
        // kept: at least one factor becomes an atom (longer than `atom_min`), so
        // the product of the parts is a monomial times a sum
        let keep = la >= 2
            && lb >= 2
            && la.max(lb) > self.atom_min
            && la.saturating_mul(lb) > self.expand_limit;
        // products nest (a kept product takes contents, a normalised monomial
        // multiplies its expansions): past MAX_NESTING the input is swell
        // beyond reason, reported as such rather than overflowing the stack
        if self.nesting >= MAX_NESTING {
            self.overflow = true;
            return ZERO;
        }
        self.nesting += 1;
        let r = if keep {
            self.kept_product(a, b)
        } else {
            self.expanded_product(a, b)
        };
        self.nesting -= 1;
        if !self.overflow {
            self.memo_mul.insert(key, r);
        }
        r
    }

    /// `a · b` distributed over the terms of both factors and normalised.
    fn expanded_product(&mut self, a: ExprId, b: ExprId) -> ExprId {
        self.counters.products += 1;
        let ta = self.exprs[a.index()].clone();
        let tb = self.exprs[b.index()].clone();
        self.work = self.work.saturating_add(ta.len().saturating_mul(tb.len()));
        if self.work > MAX_WORK {
            self.overflow = true;
            return ZERO;
        }
        let mut acc: Vec<(MonoId, Rational)> = Vec::with_capacity(ta.len() * tb.len());
        let mut extra: Vec<ExprId> = Vec::new();
        for &(ma, ca) in &ta {
            for &(mb, cb) in &tb {
                let c = self.qmul(ca, cb);
                let f = merge_factors(&self.monos[ma.index()], &self.monos[mb.index()]);
                match self.normal_mono(f) {
                    Normal::Mono(m, k) => {
                        let c2 = self.qmul(c, k);
                        acc.push((m, c2))
                    }
                    Normal::Expr(e) => {
                        let e2 = self.scale(e, c);
                        extra.push(e2)
                    }
                }
                if acc.len() > MAX_TERMS {
                    self.overflow = true;
                    return ZERO;
                }
            }
        }
        for e in extra {
            acc.extend_from_slice(&self.exprs[e.index()]);
        }
        self.collect(acc)
    }

    /// `a · b` for two sums whose expansion would not pay (more than
    /// [`EXPAND_LIMIT`] products of terms): each sum is split into its
    /// content (a rational times a monomial) and its primitive rest, and the
    /// rests stay unexpanded, as atoms of one monomial. The rest of a sum is
    /// one atom wherever it occurs, so shared factors stay shared (in the
    /// graph and in the emitted code), and a `let` chain or a product of
    /// long sums grows additively instead of multiplicatively.
    fn kept_product(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let (ga, ra) = self.content(a).unwrap_or((ONE, a));
        let (gb, rb) = self.content(b).unwrap_or((ONE, b));
        let xa = self.kept_factor(ra);
        let xb = self.kept_factor(rb);
        let g = self.mul(ga, gb);
        let x = self.mul(xa, xb);
        self.mul(g, x)
    }

    /// A primitive sum as a factor of a kept product: one atom if it is
    /// longer than [`ATOM_MIN`] terms, else the sum itself (distributed over
    /// the other factor, which is then an atom).
    fn kept_factor(&mut self, s: ExprId) -> ExprId {
        if self.exprs[s.index()].len() <= self.atom_min {
            return s;
        }
        let x = self.intern_atom(Atom::Base(s));
        self.atom_power(x, Rational::ONE)
    }

    /// Is `s^k` (a sum to a positive integer power) kept unexpanded? A sum
    /// of more than [`ATOM_MIN`] terms always is; a shorter one when the
    /// expansion would exceed [`EXPAND_LIMIT`] products of terms.
    fn power_is_kept(&self, s: ExprId, k: i64) -> bool {
        let len = self.exprs[s.index()].len();
        if len > self.atom_min {
            return true;
        }
        let mut size: usize = 1;
        for _ in 0..k.clamp(0, 64) {
            size = size.saturating_mul(len);
            if size > self.expand_limit {
                return true;
            }
        }
        k > 64 && len >= 2
    }

    /// Normalises a merged factor list: folds constant bases into the
    /// coefficient, expands integer powers of sums, distributes integer powers
    /// of monomial bases and reduces `cos²`.
    fn normal_mono(&mut self, f: Factors) -> Normal {
        let needs =
            f.iter().any(|&(a, e)| self.factor_needs_work(a, e)) || self.sin_over_cos(&f).is_some();
        if !needs {
            let m = self.intern_mono(f);
            return Normal::Mono(m, Rational::ONE);
        }
        let mut kept: Factors = Vec::new();
        let mut coef = Rational::ONE;
        let mut multiplicands: Vec<ExprId> = Vec::new();
        // sin(u)^a cos(u)^b with a ≥ 2 and b < 0: sin² = 1 − cos² (this keeps
        // the Laurent part in the basis {cos^b, sin·cos^b}, so that, e.g.,
        // tan² + 1 becomes cos⁻²). Split into the two monomials directly:
        // multiplying by 1 − cos² would canonicalise back to sin².
        if let Some((si, u)) = self.sin_over_cos(&f) {
            let mut f1 = f.clone();
            f1[si].1 = f1[si]
                .1
                .checked_sub(Rational::int(2))
                .unwrap_or(Rational::ZERO);
            let mut f2 = f1.clone();
            if let Some(&c) = self.atom_ix.get(&Atom::Func(Fun::Cos, u))
                && let Some(slot) = f2.iter_mut().find(|x| x.0 == c)
            {
                slot.1 = slot
                    .1
                    .checked_add(Rational::int(2))
                    .unwrap_or(Rational::ZERO);
            }
            let e1 = self.normal_expr(f1);
            let e2 = self.normal_expr(f2);
            return Normal::Expr(self.sub(e1, e2));
        }
        for (a, e) in f {
            if e.is_zero() {
                continue;
            }
            match self.atoms[a.index()].clone() {
                Atom::Func(Fun::Cos, u) if e.is_integer() && e >= Rational::int(2) => {
                    let k = e.to_integer().unwrap_or(0);
                    if k % 2 == 1 {
                        kept.push((a, Rational::ONE));
                    }
                    // (1 - sin(u)^2)^(k div 2)
                    let s = self.func(Fun::Sin, u);
                    let s2 = self.mul(s, s);
                    let one_minus = self.sub(ONE, s2);
                    let half = self.exponent_count(k / 2);
                    let p = self.pow_int(one_minus, half);
                    multiplicands.push(p);
                }
                Atom::Base(b) => {
                    if let Some(c) = self.as_constant(b) {
                        // c^e = c^floor(e) * c^(e - floor(e))
                        let k = floor(e);
                        let ck = self.qpowi(c, k);
                        coef = self.qmul(coef, ck);
                        let frac = e
                            .checked_sub(Rational::int(k as i128))
                            .unwrap_or(Rational::ZERO);
                        if !frac.is_zero() {
                            kept.push((a, frac));
                        }
                    } else if self.exprs[b.index()].len() == 1 {
                        // a monomial base: integer part distributes
                        let k = floor(e);
                        let frac = e
                            .checked_sub(Rational::int(k as i128))
                            .unwrap_or(Rational::ZERO);
                        let p = self.pow_signed(b, k);
                        multiplicands.push(p);
                        if !frac.is_zero() {
                            kept.push((a, frac));
                        }
                    } else if e >= Rational::ONE && !self.power_is_kept(b, floor(e)) {
                        let k = floor(e);
                        let frac = e
                            .checked_sub(Rational::int(k as i128))
                            .unwrap_or(Rational::ZERO);
                        let kk = self.exponent_count(k);
                        let p = self.pow_int(b, kk);
                        multiplicands.push(p);
                        if !frac.is_zero() {
                            kept.push((a, frac));
                        }
                    } else {
                        kept.push((a, e));
                    }
                }
                _ => kept.push((a, e)),
            }
        }
        let m = self.intern_mono(kept);
        let base = self.intern_expr(vec![(m, Rational::ONE)]);
        let mut r = self.scale(base, coef);
        for p in multiplicands {
            r = self.mul(r, p);
        }
        Normal::Expr(r)
    }

    /// A factor list as a normalised expression.
    fn normal_expr(&mut self, f: Factors) -> ExprId {
        match self.normal_mono(f) {
            Normal::Mono(m, k) => {
                let e = self.intern_expr(vec![(m, Rational::ONE)]);
                self.scale(e, k)
            }
            Normal::Expr(e) => e,
        }
    }

    /// In a factor list, the position of `sin(u)^a` (a ≥ 2) whose `cos(u)`
    /// has a negative exponent, and `u`.
    fn sin_over_cos(&self, f: &[(AtomId, Rational)]) -> Option<(usize, ExprId)> {
        for (i, &(a, e)) in f.iter().enumerate() {
            if let Atom::Func(Fun::Sin, u) = self.atoms[a.index()]
                && e.is_integer()
                && e >= Rational::int(2)
                && let Some(&c) = self.atom_ix.get(&Atom::Func(Fun::Cos, u))
                && f.iter().any(|&(x, ex)| x == c && ex.is_negative())
            {
                return Some((i, u));
            }
        }
        None
    }

    fn factor_needs_work(&self, a: AtomId, e: Rational) -> bool {
        if e.is_zero() {
            return true;
        }
        match &self.atoms[a.index()] {
            Atom::Func(Fun::Cos, _) => e.is_integer() && e >= Rational::int(2),
            Atom::Base(b) => {
                // normal exponents: in (0, 1) for constant and monomial bases,
                // below 1 for sums, except a sum whose power is kept
                // unexpanded (see `kept_product`)
                if self.exprs[b.index()].len() <= 1 {
                    !(e > Rational::ZERO && e < Rational::ONE)
                } else {
                    e >= Rational::ONE && !self.power_is_kept(*b, floor(e))
                }
            }
            Atom::Sym(_) | Atom::Func(..) => false,
        }
    }

    /// An integer exponent to expand by; beyond 2³² it is expression swell
    /// (flagged, and 0 returned).
    fn exponent_count(&mut self, k: i64) -> u32 {
        u32::try_from(k).unwrap_or_else(|_| {
            self.overflow = true;
            0
        })
    }

    /// `a^k` for a non-negative integer `k`, by repeated squaring.
    pub fn pow_int(&mut self, a: ExprId, k: u32) -> ExprId {
        let mut acc = ONE;
        let mut b = a;
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                acc = self.mul(acc, b);
            }
            k >>= 1;
            if k > 0 {
                b = self.mul(b, b);
            }
        }
        acc
    }

    /// `a^k` for an integer `k` of either sign.
    fn pow_signed(&mut self, a: ExprId, k: i64) -> ExprId {
        if k >= 0 {
            let kk = self.exponent_count(k);
            return self.pow_int(a, kk);
        }
        self.pow(a, Rational::int(k as i128))
    }

    /// `a^q` for a rational exponent, following real-valued semantics: the
    /// exponents of a power are multiplied only where that is an identity on
    /// the reals (`(x²)^(1/2)` stays as written; it is `|x|`).
    pub fn pow(&mut self, a: ExprId, q: Rational) -> ExprId {
        if q.is_zero() {
            return ONE;
        }
        if q.is_one() {
            return a;
        }
        if q.is_integer()
            && a != ZERO
            && let Some(c) = self.as_constant(a)
        {
            // a constant to an integer power: exact, bounded in size
            let v = match q.to_integer() {
                Some(k) => self.qpowi(c, k),
                None if c.is_one() => Rational::ONE,
                None if c == Rational::MINUS_ONE => {
                    let even = q
                        .checked_div(Rational::int(2))
                        .is_some_and(|h| h.is_integer());
                    if even {
                        Rational::ONE
                    } else {
                        Rational::MINUS_ONE
                    }
                }
                None => {
                    self.overflow = true;
                    Rational::ZERO
                }
            };
            return self.constant(v);
        }
        if q.is_integer() && !q.is_negative() {
            let k = q.to_integer().unwrap_or(i64::MAX);
            let kk = self.exponent_count(k);
            return self.pow_int(a, kk);
        }
        if a == ZERO {
            // 0^q = 0 for q > 0 (sqrt(0) = 0); 0 to a negative power is a
            // division by zero, which the caller reports: keep it symbolic.
            if !q.is_negative() {
                return ZERO;
            }
            let b = self.intern_atom(Atom::Base(ZERO));
            return self.atom_power(b, q);
        }
        let terms = self.exprs[a.index()].clone();
        if let [(m, c)] = terms.as_slice() {
            let factors = self.monos[m.index()].clone();
            let distributable = q.is_integer()
                || (!c.is_negative()
                    && factors
                        .iter()
                        .all(|&(_, e)| !e.is_integer() || e.abs().is_one()));
            if distributable {
                // coefficient part
                let cpart = if c.is_one() {
                    ONE
                } else if q.is_integer() {
                    let v = self.qpowi(*c, q.to_integer().unwrap_or(0));
                    self.constant(v)
                } else {
                    let cc = self.constant(*c);
                    let b = self.intern_atom(Atom::Base(cc));
                    self.atom_power_normal(b, q)
                };
                let mut prod: Factors = Vec::with_capacity(factors.len());
                for (at, e) in factors {
                    let ne = self.qmul(e, q);
                    prod.push((at, ne));
                }
                let mono = match self.normal_mono(prod) {
                    Normal::Mono(m, k) => {
                        let e = self.intern_expr(vec![(m, Rational::ONE)]);
                        self.scale(e, k)
                    }
                    Normal::Expr(e) => e,
                };
                return self.mul(cpart, mono);
            }
        }
        // an integer power of a sum: take its content (the rational gcd and the
        // monomial common to all terms) out first, so that a factor such as
        // m R² of a pivot cancels against the numerator
        if q.is_integer()
            && let Some((g, rest)) = self.content(a)
        {
            let gq = self.pow(g, q);
            let rq = self.pow(rest, q);
            return self.mul(gq, rq);
        }
        // c·(1 − sin²u) is c·cos²u: an integer power of it is a power of cos
        // (the Pythagorean normal form keeps cos² as 1 − sin², so pivots of
        // a reduced mass matrix come out in this shape)
        if q.is_integer()
            && let Some((c, u)) = self.scaled_one_minus_sin2(a)
        {
            let cq = self.pow(c, q);
            let cu = self.func(Fun::Cos, u);
            let k = q.checked_mul(Rational::int(2)).unwrap_or(q);
            let cp = self.atom_power_normal_of(cu, k);
            return self.mul(cq, cp);
        }
        let b = self.intern_atom(Atom::Base(a));
        self.atom_power_normal(b, q)
    }

    /// The content of a sum — `g` (a monomial times a rational, positive
    /// leading coefficient of the rest) and the primitive rest with `e = g·rest`
    /// — or `None` if the content is 1.
    fn content(&mut self, e: ExprId) -> Option<(ExprId, ExprId)> {
        let terms = self.exprs[e.index()].clone();
        if terms.len() < 2 {
            return None;
        }
        // rational part
        let mut c = terms[0].1.abs();
        for t in &terms[1..] {
            c = c.gcd(t.1)?;
        }
        if terms[0].1.is_negative() {
            c = c.checked_neg()?;
        }
        // monomial part: atoms in every term, at their least exponent
        let mut common: Factors = self.monos[terms[0].0.index()].clone();
        for (m, _) in &terms[1..] {
            let f = &self.monos[m.index()];
            common.retain_mut(|(a, e)| match f.iter().find(|(b, _)| b == a) {
                Some((_, e2)) => {
                    if *e2 < *e {
                        *e = *e2;
                    }
                    true
                }
                None => false,
            });
        }
        // only whole powers of plain atoms are taken out (exact division)
        common.retain(|(a, e)| e.is_integer() && !matches!(self.atoms[a.index()], Atom::Base(_)));
        if c.is_one() && common.is_empty() {
            return None;
        }
        let cm = self.intern_mono(common.clone());
        let g_mono = self.intern_expr(vec![(cm, Rational::ONE)]);
        let g = self.scale(g_mono, c);
        let inv: Factors = common
            .iter()
            .map(|&(a, e)| (a, e.checked_neg().unwrap_or(e)))
            .collect();
        let ginv_mono = match self.normal_mono(inv) {
            Normal::Mono(m, k) => {
                let x = self.intern_expr(vec![(m, Rational::ONE)]);
                self.scale(x, k)
            }
            Normal::Expr(x) => x,
        };
        let cinv = c.checked_recip()?;
        let ginv = self.scale(ginv_mono, cinv);
        // distributed, never kept: the rest of a kept product is taken here
        let rest = self.expanded_product(e, ginv);
        Some((g, rest))
    }

    /// `(c, u)` if `e` is `c − c·sin(u)²` for a rational `c ≠ 0`.
    fn scaled_one_minus_sin2(&mut self, e: ExprId) -> Option<(ExprId, ExprId)> {
        let terms = self.exprs[e.index()].clone();
        let [(m0, c0), (m1, c1)] = terms.as_slice() else {
            return None;
        };
        let (konst, other, c_other) = if *m0 == MONO_ONE {
            (*c0, *m1, *c1)
        } else if *m1 == MONO_ONE {
            (*c1, *m0, *c0)
        } else {
            return None;
        };
        if c_other.checked_neg() != Some(konst) {
            return None;
        }
        let [(at, ex)] = self.monos[other.index()].as_slice() else {
            return None;
        };
        match self.atoms[at.index()] {
            Atom::Func(Fun::Sin, u) if *ex == Rational::int(2) => Some((self.constant(konst), u)),
            _ => None,
        }
    }

    /// `x^k` for an expression `x` that is a single atom to the first power.
    fn atom_power_normal_of(&mut self, x: ExprId, k: Rational) -> ExprId {
        match self.exprs[x.index()].as_slice() {
            [(m, c)] if c.is_one() => match self.monos[m.index()].as_slice() {
                [(at, e)] if e.is_one() => {
                    let at = *at;
                    self.atom_power_normal(at, k)
                }
                _ => self.pow(x, k),
            },
            _ => self.pow(x, k),
        }
    }

    fn atom_power_normal(&mut self, a: AtomId, q: Rational) -> ExprId {
        match self.normal_mono(vec![(a, q)]) {
            Normal::Mono(m, k) => {
                let e = self.intern_expr(vec![(m, Rational::ONE)]);
                self.scale(e, k)
            }
            Normal::Expr(e) => e,
        }
    }

    /// `a / b`.
    pub fn div(&mut self, a: ExprId, b: ExprId) -> ExprId {
        let r = self.pow(b, Rational::MINUS_ONE);
        self.mul(a, r)
    }

    /// `f(a)`, with sign symmetries and values at zero folded.
    pub fn func(&mut self, f: Fun, a: ExprId) -> ExprId {
        if a == ZERO {
            return match f {
                Fun::Sin | Fun::Tan => ZERO,
                Fun::Cos | Fun::Exp => ONE,
                Fun::Ln => {
                    let at = self.intern_atom(Atom::Func(f, a));
                    self.atom_power(at, Rational::ONE)
                }
            };
        }
        if f == Fun::Ln && a == ONE {
            return ZERO;
        }
        let leading_negative = self.exprs[a.index()]
            .first()
            .is_some_and(|(_, c)| c.is_negative());
        if leading_negative && matches!(f, Fun::Sin | Fun::Tan | Fun::Cos) {
            let na = self.neg(a);
            let inner = self.func(f, na);
            return if f == Fun::Cos {
                inner
            } else {
                self.neg(inner)
            };
        }
        if f == Fun::Exp {
            return self.exp(a);
        }
        if f == Fun::Ln
            && let [(m, c)] = self.exprs[a.index()].as_slice()
            && c.is_one()
            && let [(at, e)] = self.monos[m.index()].as_slice()
            && let Atom::Func(Fun::Exp, u) = self.atoms[at.index()]
        {
            // ln(exp(u)^e) = e·u
            let e = *e;
            return self.scale(u, e);
        }
        if f == Fun::Tan {
            // tan = sin / cos, so that identities between tan, sin and cos cancel
            let s = self.func(Fun::Sin, a);
            let c = self.func(Fun::Cos, a);
            let ci = self.pow(c, Rational::MINUS_ONE);
            return self.mul(s, ci);
        }
        let at = self.intern_atom(Atom::Func(f, a));
        self.atom_power(at, Rational::ONE)
    }

    /// `exp(a)` in canonical form: exp(Σ c_i m_i) = Π exp(m_i)^c_i, so that
    /// exp(x)·exp(y) and exp(x + y) are one expression; exp(c·ln u) = u^c.
    fn exp(&mut self, a: ExprId) -> ExprId {
        let terms = self.exprs[a.index()].clone();
        let mut r = ONE;
        for (m, c) in terms {
            if let [(at, e)] = self.monos[m.index()].as_slice()
                && e.is_one()
                && let Atom::Func(Fun::Ln, u) = self.atoms[at.index()]
            {
                let p = self.pow(u, c);
                r = self.mul(r, p);
                continue;
            }
            let arg = self.intern_expr(vec![(m, Rational::ONE)]);
            let at = self.intern_atom(Atom::Func(Fun::Exp, arg));
            let p = self.atom_power_normal(at, c);
            r = self.mul(r, p);
        }
        r
    }

    // ------------------------------------------------------------ calculus

    /// `∂e/∂s`, memoised.
    pub fn diff(&mut self, e: ExprId, s: SymId) -> ExprId {
        if !self.depends_on(e, s) {
            return ZERO;
        }
        if let Some(&r) = self.memo_diff.get(&(e, s)) {
            return r;
        }
        if self.overflow {
            return ZERO;
        }
        self.counters.derivatives += 1;
        let terms = self.exprs[e.index()].clone();
        let mut parts = Vec::new();
        for (m, c) in terms {
            let dm = self.diff_mono(m, s);
            let t = self.scale(dm, c);
            parts.push(t);
        }
        let r = self.sum(&parts);
        self.memo_diff.insert((e, s), r);
        r
    }

    fn diff_mono(&mut self, m: MonoId, s: SymId) -> ExprId {
        let factors = self.monos[m.index()].clone();
        let mut parts = Vec::new();
        for (i, &(a, e)) in factors.iter().enumerate() {
            if self.atom_syms[a.index()].binary_search(&s).is_err() {
                continue;
            }
            let da = self.diff_atom(a, s);
            if da == ZERO {
                continue;
            }
            let mut f = factors.clone();
            let ne = e.checked_sub(Rational::ONE).unwrap_or_else(|| {
                self.overflow = true;
                Rational::ZERO
            });
            f[i].1 = ne;
            let rest = match self.normal_mono(f) {
                Normal::Mono(m, k) => {
                    let x = self.intern_expr(vec![(m, Rational::ONE)]);
                    self.scale(x, k)
                }
                Normal::Expr(x) => x,
            };
            let t = self.chain_rule_product(rest, da);
            let t = self.scale(t, e);
            parts.push(t);
        }
        self.sum(&parts)
    }

    /// `outer · inner` in a chain rule: an inner derivative longer than
    /// [`ATOM_MIN`] terms is kept as one atom instead of being distributed,
    /// so that nested derivatives (`let` chains, functions of functions)
    /// grow additively: d/dx of a_(n+1) = a_n + sin(a_n)/2 is then
    /// a_n' + cos(a_n)/2 · [a_n'] with [a_n'] one atom, not 2ⁿ terms.
    fn chain_rule_product(&mut self, outer: ExprId, inner: ExprId) -> ExprId {
        if self.exprs[inner.index()].len() <= self.atom_min || self.as_constant(outer).is_some() {
            return self.mul(outer, inner);
        }
        let (g, rest) = self.content(inner).unwrap_or((ONE, inner));
        let x = self.kept_factor(rest);
        let go = self.mul(outer, g);
        self.mul(go, x)
    }

    /// Derivative of an atom with respect to `s` (for `Base(b)`, the derivative of `b`).
    fn diff_atom(&mut self, a: AtomId, s: SymId) -> ExprId {
        match self.atoms[a.index()].clone() {
            Atom::Sym(x) => {
                if x == s {
                    ONE
                } else {
                    ZERO
                }
            }
            Atom::Base(b) => self.diff(b, s),
            Atom::Func(f, u) => {
                let du = self.diff(u, s);
                if du == ZERO {
                    return ZERO;
                }
                let outer = match f {
                    Fun::Sin => self.func(Fun::Cos, u),
                    Fun::Cos => {
                        let x = self.func(Fun::Sin, u);
                        self.neg(x)
                    }
                    Fun::Tan => {
                        let t = self.func(Fun::Tan, u);
                        let t2 = self.mul(t, t);
                        self.add(ONE, t2)
                    }
                    Fun::Exp => self.func(Fun::Exp, u),
                    Fun::Ln => self.pow(u, Rational::MINUS_ONE),
                };
                self.chain_rule_product(outer, du)
            }
        }
    }

    /// Substitutes expressions for symbols everywhere in `e`.
    pub fn subst(
        &mut self,
        e: ExprId,
        map: &HashMap<SymId, ExprId>,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> ExprId {
        if self.expr_syms[e.index()]
            .iter()
            .all(|s| !map.contains_key(s))
        {
            return e;
        }
        if let Some(&r) = memo.get(&e) {
            return r;
        }
        let terms = self.exprs[e.index()].clone();
        let mut parts = Vec::with_capacity(terms.len());
        for (m, c) in terms {
            let mut t = self.constant(c);
            for (a, ex) in self.monos[m.index()].clone() {
                let base = match self.atoms[a.index()].clone() {
                    Atom::Sym(s) => match map.get(&s) {
                        Some(&v) => v,
                        None => self.sym(s),
                    },
                    Atom::Func(f, u) => {
                        let u2 = self.subst(u, map, memo);
                        self.func(f, u2)
                    }
                    Atom::Base(b) => self.subst(b, map, memo),
                };
                let p = self.pow(base, ex);
                t = self.mul(t, p);
            }
            parts.push(t);
        }
        let r = self.sum(&parts);
        memo.insert(e, r);
        r
    }

    // ------------------------------------------------------------ evaluation

    /// Evaluates `e` in `f64` with `vals[s]` the value of symbol `s`.
    pub fn eval(&self, e: ExprId, vals: &[f64]) -> f64 {
        let mut memo = HashMap::default();
        self.eval_memo(e, vals, &mut memo)
    }

    /// Evaluates with a caller-held memo (for many expressions at one point).
    pub fn eval_memo(&self, e: ExprId, vals: &[f64], memo: &mut HashMap<ExprId, f64>) -> f64 {
        if let Some(&v) = memo.get(&e) {
            return v;
        }
        let mut acc = 0.0;
        for &(m, c) in &self.exprs[e.index()] {
            acc += self.eval_term(m, c, vals, memo);
        }
        memo.insert(e, acc);
        acc
    }

    fn eval_term(
        &self,
        m: MonoId,
        c: Rational,
        vals: &[f64],
        memo: &mut HashMap<ExprId, f64>,
    ) -> f64 {
        let mut t = c.to_f64();
        for &(a, ex) in &self.monos[m.index()] {
            let b = match &self.atoms[a.index()] {
                Atom::Sym(s) => vals[s.index()],
                Atom::Func(f, u) => f.eval(self.eval_memo(*u, vals, memo)),
                Atom::Base(b) => self.eval_memo(*b, vals, memo),
            };
            t *= match ex.to_integer() {
                Some(k) if k.abs() < i32::MAX as i64 => b.powi(k as i32),
                _ => b.powf(ex.to_f64()),
            };
        }
        t
    }

    /// Evaluates `e` and the sum of the absolute values of its terms (the
    /// scale against which cancellation to zero is judged).
    pub fn eval_with_scale(&self, e: ExprId, vals: &[f64]) -> (f64, f64) {
        let mut memo = HashMap::default();
        let mut value = 0.0;
        let mut scale = 0.0;
        for &(m, c) in &self.exprs[e.index()] {
            let t = self.eval_term(m, c, vals, &mut memo);
            value += t;
            scale += t.abs();
        }
        (value, scale)
    }

    /// Evaluates `e` in double-double arithmetic (about 32 digits) with the
    /// sum of the absolute values of its terms, as
    /// [`Engine::eval_with_scale`]; `vals[s]` is the value of symbol `s`.
    pub fn eval_with_scale_dd(&self, e: ExprId, vals: &[dd::Dd]) -> (dd::Dd, dd::Dd) {
        let mut memo = HashMap::default();
        let mut value = dd::Dd::ZERO;
        let mut scale = dd::Dd::ZERO;
        for &(m, c) in &self.exprs[e.index()] {
            let t = self.eval_term_dd(m, c, vals, &mut memo);
            value = value + t;
            scale = scale + t.abs();
        }
        (value, scale)
    }

    fn eval_dd(&self, e: ExprId, vals: &[dd::Dd], memo: &mut HashMap<ExprId, dd::Dd>) -> dd::Dd {
        if let Some(&v) = memo.get(&e) {
            return v;
        }
        let mut acc = dd::Dd::ZERO;
        for &(m, c) in &self.exprs[e.index()] {
            acc = acc + self.eval_term_dd(m, c, vals, memo);
        }
        memo.insert(e, acc);
        acc
    }

    fn eval_term_dd(
        &self,
        m: MonoId,
        c: Rational,
        vals: &[dd::Dd],
        memo: &mut HashMap<ExprId, dd::Dd>,
    ) -> dd::Dd {
        let mut t = dd::Dd::from_rational(c);
        for &(a, ex) in &self.monos[m.index()] {
            let b = match &self.atoms[a.index()] {
                Atom::Sym(s) => vals[s.index()],
                Atom::Func(f, u) => {
                    let x = self.eval_dd(*u, vals, memo);
                    match f {
                        Fun::Sin => x.sin_cos().0,
                        Fun::Cos => x.sin_cos().1,
                        Fun::Tan => {
                            let (s, c) = x.sin_cos();
                            s / c
                        }
                        Fun::Exp => x.exp(),
                        Fun::Ln => x.ln(),
                    }
                }
                Atom::Base(b) => self.eval_dd(*b, vals, memo),
            };
            t = t * match ex.to_integer() {
                Some(k) if k.abs() < i32::MAX as i64 => b.powi(k),
                _ => (b.ln() * dd::Dd::from_rational(ex)).exp(),
            };
        }
        t
    }

    // ------------------------------------------------------------ printing

    /// Human-readable form, for messages and debugging.
    pub fn display(&self, e: ExprId) -> String {
        let terms = &self.exprs[e.index()];
        if terms.is_empty() {
            return "0".to_string();
        }
        let mut s = String::new();
        for (i, &(m, c)) in terms.iter().enumerate() {
            let mono = self.display_mono(m);
            let neg = c.is_negative();
            let ac = c.abs();
            if i == 0 {
                if neg {
                    s.push('-');
                }
            } else {
                s.push_str(if neg { " - " } else { " + " });
            }
            match (mono.is_empty(), ac.is_one()) {
                (true, _) => s.push_str(&ac.to_string()),
                (false, true) => s.push_str(&mono),
                (false, false) => {
                    s.push_str(&ac.to_string());
                    s.push('*');
                    s.push_str(&mono)
                }
            }
        }
        s
    }

    fn display_mono(&self, m: MonoId) -> String {
        let mut parts = Vec::new();
        for &(a, e) in &self.monos[m.index()] {
            let base = match &self.atoms[a.index()] {
                Atom::Sym(s) => self.sym_names[s.index()].clone(),
                Atom::Func(f, u) => format!("{}({})", f.name(), self.display(*u)),
                Atom::Base(b) => format!("({})", self.display(*b)),
            };
            if e.is_one() {
                parts.push(base);
            } else if e.is_integer() && !e.is_negative() {
                parts.push(format!("{base}^{e}"));
            } else {
                parts.push(format!("{base}^({e})"));
            }
        }
        parts.join("*")
    }
}

enum Normal {
    Mono(MonoId, Rational),
    Expr(ExprId),
}

fn floor(e: Rational) -> i64 {
    let q = e.floor();
    q.to_integer().unwrap_or(if q.is_negative() {
        i64::MIN / 2
    } else {
        i64::MAX / 2
    })
}

fn merge_factors(a: &[(AtomId, Rational)], b: &[(AtomId, Rational)]) -> Factors {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].0.cmp(&b[j].0) {
            std::cmp::Ordering::Less => {
                out.push(a[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                out.push(b[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                // exponent sums of small rationals do not overflow in practice;
                // on overflow keep the first (the engine flags elsewhere).
                let e = a[i].1.checked_add(b[j].1).unwrap_or(a[i].1);
                out.push((a[i].0, e));
                i += 1;
                j += 1;
            }
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

#[cfg(test)]
mod tests;
