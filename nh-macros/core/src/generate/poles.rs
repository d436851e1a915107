//! The poles and domain edges of a system's expressions as written (DESIGN
//! §9.2): every division by an expression of the state, and every function
//! argument at the edge of its domain, becomes a *guard* g(t, x) that is
//! nonzero and of one sign on each side of the singularity: a denominator,
//! the argument of `ln` or of a root, 1 − a² for `asin(a)` and `acos(a)`,
//! x² + y² for `atan2(y, x)`. The generated `crossed_pole` evaluates the
//! guards at both ends of a step; a guard whose sign is not the same at
//! both (or that vanishes, or is not finite) ends the run in
//! `SimError::Singular` instead of carrying the solution across.
//!
//! Guards free of the state (parameters only) and guards seen to be
//! positive everywhere (positive constants plus even powers, `exp`,
//! `cosh`) are left out; a system without guards keeps the runtime's
//! default (no check, no cost).

use super::graph::{Args, bound_dag};
use crate::mechanics::Scene;
use crate::sym::{Atom, Engine, ExprId, Fun, Rational, SymId};
use proc_macro2::TokenStream;
use quote::quote;
use rustc_hash::FxHashSet as HashSet;

/// A guard: the expression whose sign change or zero is a singularity,
/// and how it reads in messages.
pub struct Guard {
    /// g.
    pub value: ExprId,
    /// "1/cos(theta)", "ln(x)", ..: what has the singularity.
    pub text: String,
}

/// The guards of the expressions the model was written with.
pub fn guards(m: &mut Scene<'_>) -> Vec<Guard> {
    let state: HashSet<SymId> = (m.coordinates.iter())
        .flat_map(|c| [c.position, c.velocity])
        .chain([m.time])
        .chain(m.speeds.iter().flat_map(|s| s.syms.iter().copied()))
        .collect();
    let mut walk = Walk {
        e: m.engine,
        state,
        seen: HashSet::default(),
        found: Vec::new(),
    };
    for &x in &m.model.written {
        walk.expr(x);
    }
    walk.found
}

struct Walk<'a> {
    e: &'a mut Engine,
    state: HashSet<SymId>,
    seen: HashSet<ExprId>,
    found: Vec<Guard>,
}

impl Walk<'_> {
    pub(crate) fn expr(&mut self, x: ExprId) {
        if !self.seen.insert(x) {
            return;
        }
        let terms = self.e.terms(x).to_vec();
        for (mono, _) in terms {
            let factors = self.e.factors(mono).to_vec();
            for (atom, exponent) in factors {
                self.factor(atom, exponent);
            }
        }
    }

    pub(crate) fn factor(&mut self, atom: crate::sym::AtomId, exponent: Rational) {
        let a = self.e.atom(atom).clone();
        let base = match &a {
            Atom::Sym(s) => self.e.sym(*s),
            Atom::Func(f, arg) => self.e.func(*f, *arg),
            Atom::Atan2(y, x) => self.e.atan2(*y, *x),
            Atom::Base(b) => *b,
        };
        if exponent.is_negative() {
            let text = format!("1/{}", self.e.display_capped(base, 80));
            self.guard(base, text);
        } else if !exponent.is_integer() {
            let text = format!("the root of {}", self.e.display_capped(base, 80));
            self.guard(base, text);
        }
        match a {
            Atom::Sym(_) => {}
            Atom::Func(f, arg) => {
                self.function(f, arg);
                self.expr(arg);
            }
            Atom::Atan2(y, x) => {
                let (yy, xx) = (self.e.mul(y, y), self.e.mul(x, x));
                let r2 = self.e.add(xx, yy);
                let text = format!("atan2 at the origin, {}", self.e.display_capped(r2, 80));
                self.guard(r2, text);
                self.expr(y);
                self.expr(x);
            }
            Atom::Base(b) => self.expr(b),
        }
    }

    /// The domain edge of `f(arg)`, if it has one.
    pub(crate) fn function(&mut self, f: Fun, arg: ExprId) {
        let shown = self.e.display_capped(arg, 80);
        match f {
            Fun::Ln => self.guard(arg, format!("ln({shown})")),
            Fun::Asin | Fun::Acos => {
                let sq = self.e.mul(arg, arg);
                let one = self.e.int(1);
                let edge = self.e.sub(one, sq);
                self.guard(edge, format!("{}({shown})", f.name()));
            }
            _ => {}
        }
    }

    pub(crate) fn guard(&mut self, g: ExprId, text: String) {
        let free = self.e.free_symbols(g);
        if !free.iter().any(|s| self.state.contains(s)) || self.e.seen_positive(g) {
            return;
        }
        if self.found.iter().any(|h| h.value == g) {
            return;
        }
        self.found.push(Guard { value: g, text });
    }
}

/// The runtime hook `crossed_pole` for state type `xty`; nothing for a
/// system without guards.
pub fn method(m: &mut Scene<'_>, xty: &TokenStream) -> TokenStream {
    let guards = guards(m);
    if guards.is_empty() {
        return TokenStream::new();
    }
    let count = guards.len();
    let texts: Vec<&str> = guards.iter().map(|g| g.text.as_str()).collect();
    let mut d = bound_dag(m, &Args::state(m));
    let nodes: Vec<_> = guards.iter().map(|g| d.expr(m.engine, g.value)).collect();
    let (stmts, outs) = d.emit(&nodes);
    quote! {
        /// The first pole or domain edge of the system's expressions
        /// between the two states: the guard (denominator, argument of `ln`
        /// or of a root, 1 − a² of `asin`/`acos`, x² + y² of `atan2`) whose
        /// sign differs at the two ends, or that vanishes or is not finite
        /// at either.
        #[inline]
        fn crossed_pole(&self, t0: T, x0: &#xty, t1: T, x1: &#xty) -> ::core::option::Option<&'static str> {
            const __NH_POLES: [&str; #count] = [#(#texts),*];
            let __nh_guards = |t: T, x: &#xty| -> [T; #count] {
                let _ = (t, x);
                #stmts
                [#(#outs),*]
            };
            let (__nh_a, __nh_b) = (__nh_guards(t0, x0), __nh_guards(t1, x1));
            for __nh_i in 0..#count {
                let (__nh_g0, __nh_g1) = (__nh_a[__nh_i], __nh_b[__nh_i]);
                let __nh_same = (__nh_g0 > T::zero() && __nh_g1 > T::zero())
                    || (__nh_g0 < T::zero() && __nh_g1 < T::zero());
                if !__nh_same {
                    return ::core::option::Option::Some(__NH_POLES[__nh_i]);
                }
            }
            ::core::option::Option::None
        }
    }
}
