//! The store of the expression graph: the id types, the node types (atoms,
//! monomials, expressions) and their hash-consing interners, which keep each
//! distinct node once so that equal nodes have equal ids.

use super::{Engine, Limit, MAX_TERMS, MONO_ONE, Rational, ZERO};

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

/// The elementary functions of one argument (`sqrt` is a power, `atan2` an
/// atom of its own, [`Atom::Atan2`]). `Cot`, `Sec` and `Csc` are rewritten
/// into powers of `sin` and `cos` and `Tan` into `sin/cos` when built
/// ([`Engine::func`]), so they never occur in an atom; `Sign` is not in the
/// input language: it is the derivative of `Abs`.
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
    /// absolute value
    Abs,
    /// sign: −1, 0 or 1 (the derivative of `Abs`, taken as 0 at 0)
    Sign,
    /// cotangent, `cos/sin`
    Cot,
    /// secant, `1/cos`
    Sec,
    /// cosecant, `1/sin`
    Csc,
    /// hyperbolic sine
    Sinh,
    /// hyperbolic cosine
    Cosh,
    /// hyperbolic tangent
    Tanh,
    /// inverse sine, in [−π/2, π/2]
    Asin,
    /// inverse cosine, in [0, π]
    Acos,
    /// inverse tangent, in (−π/2, π/2)
    Atan,
}

impl Fun {
    /// The name as written in the input language (`sign` for the internal
    /// sign function).
    pub fn name(self) -> &'static str {
        match self {
            Fun::Sin => "sin",
            Fun::Cos => "cos",
            Fun::Tan => "tan",
            Fun::Exp => "exp",
            Fun::Ln => "ln",
            Fun::Abs => "abs",
            Fun::Sign => "sign",
            Fun::Cot => "cot",
            Fun::Sec => "sec",
            Fun::Csc => "csc",
            Fun::Sinh => "sinh",
            Fun::Cosh => "cosh",
            Fun::Tanh => "tanh",
            Fun::Asin => "asin",
            Fun::Acos => "acos",
            Fun::Atan => "atan",
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
    /// `atan2(y, x)`: the angle of the point (x, y), in (−π, π].
    Atan2(ExprId, ExprId),
    /// An expression used as the base of a power that is not expanded.
    Base(ExprId),
}

/// The factors `(atom, exponent)` of a monomial, sorted by atom.
pub(super) type Factors = Vec<(AtomId, Rational)>;
/// The terms `(monomial, coefficient)` of an expression, sorted by monomial.
pub(super) type Terms = Vec<(MonoId, Rational)>;

impl Engine {
    pub(super) fn intern_atom(&mut self, a: Atom) -> AtomId {
        if let Some(&id) = self.atom_ix.get(&a) {
            return id;
        }
        let syms = match &a {
            Atom::Sym(s) => vec![*s],
            Atom::Func(_, e) | Atom::Base(e) => self.expr_syms[e.index()].clone(),
            Atom::Atan2(y, x) => {
                let mut s = self.expr_syms[y.index()].clone();
                s.extend_from_slice(&self.expr_syms[x.index()]);
                s.sort_unstable();
                s.dedup();
                s
            }
        };
        let id = AtomId::from_index(self.atoms.len());
        self.atoms.push(a.clone());
        self.atom_syms.push(syms);
        self.atom_ix.insert(a, id);
        id
    }

    pub(super) fn intern_mono(&mut self, f: Factors) -> MonoId {
        // hashing and comparing a monomial is work in its length (nested
        // functions of long `let` chains make monomials of hundreds of
        // factors)
        self.work = self.work.saturating_add(f.len());
        if self.work > self.max_work {
            self.exceed(Limit::Work);
        }
        if let Some(&id) = self.mono_ix.get(&f) {
            return id;
        }
        let id = MonoId::from_index(self.monos.len());
        let syms = self.union_of_syms(f.iter().map(|(a, _)| &self.atom_syms[a.index()]));
        self.mono_syms.push(syms);
        self.monos.push(f.clone());
        self.mono_ix.insert(f, id);
        id
    }

    /// The sorted union of sets of symbols, as a bit set over the symbols
    /// (an expression's terms repeat the same few symbols many times).
    fn union_of_syms<'a>(&self, sets: impl Iterator<Item = &'a Vec<SymId>>) -> Vec<SymId> {
        let mut bits = vec![0u64; self.sym_names.len().div_ceil(64)];
        for s in sets.flatten() {
            bits[s.index() / 64] |= 1 << (s.index() % 64);
        }
        let mut syms = Vec::new();
        for (w, &word) in bits.iter().enumerate() {
            let mut word = word;
            while word != 0 {
                let b = word.trailing_zeros() as usize;
                syms.push(SymId::from_index(64 * w + b));
                word &= word - 1;
            }
        }
        syms
    }

    pub(super) fn intern_expr(&mut self, t: Terms) -> ExprId {
        if let Some(&id) = self.expr_ix.get(&t) {
            return id;
        }
        if t.len() > MAX_TERMS {
            self.exceed(Limit::Terms);
            return ZERO;
        }
        let syms = self.union_of_syms(t.iter().map(|(m, _)| &self.mono_syms[m.index()]));
        let id = ExprId::from_index(self.exprs.len());
        self.exprs.push(t.clone());
        self.expr_syms.push(syms);
        self.expr_ix.insert(t, id);
        id
    }

    /// The terms `(monomial, coefficient)` of an expression, sorted.
    pub fn terms(&self, e: ExprId) -> &[(MonoId, Rational)] {
        &self.exprs[e.index()]
    }

    /// The expression `c·m` of one term (`0` for `c = 0`).
    pub fn term(&mut self, m: MonoId, c: Rational) -> ExprId {
        if c.is_zero() {
            return ZERO;
        }
        self.intern_expr(vec![(m, c)])
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

    /// Whether every term of `g` is a positive constant times factors that
    /// cannot be negative (even integer powers, `exp`, `cosh`): then g > 0
    /// wherever it has a constant term, and g ≥ 0 otherwise (`false`).
    pub fn seen_positive(&self, g: ExprId) -> bool {
        let terms = self.terms(g);
        let constant = terms
            .iter()
            .any(|(m, c)| self.factors(*m).is_empty() && !c.is_negative());
        constant
            && terms.iter().all(|(m, c)| {
                !c.is_negative()
                    && self.factors(*m).iter().all(|&(a, k)| {
                        let even = k.to_integer().is_some_and(|k| k % 2 == 0);
                        even || matches!(self.atom(a), Atom::Func(Fun::Exp | Fun::Cosh, _))
                    })
            })
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
}

pub(super) fn merge_factors(a: &[(AtomId, Rational)], b: &[(AtomId, Rational)]) -> Factors {
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
