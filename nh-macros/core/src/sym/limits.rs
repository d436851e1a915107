//! The engine's limits: the measures it bounds so that a derivation that
//! swells stops instead of running without bound, which one was exceeded
//! first, and where. The stages name the part of the input they are
//! working on ([`Engine::enter`]); when a limit is first exceeded the
//! engine keeps that site with the limit ([`Engine::exceeded`]), so that
//! the error points at the culprit and names the measure (DESIGN §5).

use super::{Engine, MAX_NESTING, MAX_TERMS, Rational};
use crate::ctxt::Site;

/// A measure the engine bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// The work of one derivation, [`MAX_WORK`](super::MAX_WORK) units:
    /// one per pair of terms multiplied, one per factor of each monomial
    /// formed, and the word operations of arithmetic on big coefficients.
    Work,
    /// The same work, passed in arithmetic on coefficients too long for
    /// 128 bits (about 38 digits): exact constants too large, not swell.
    Constants,
    /// The terms of one expression, [`MAX_TERMS`].
    Terms,
    /// Products nested inside products, [`MAX_NESTING`] deep.
    Nesting,
    /// The digits of an exact constant, [`Rational::MAX_DIGITS`].
    Digits,
    /// An integer exponent to expand by, at most `u32::MAX`.
    Exponent,
}

impl Limit {
    /// The limit of this measure: the figure past which the engine stops
    /// (for [`Limit::Work`], the engine's own, by default
    /// [`MAX_WORK`](super::MAX_WORK)).
    fn bound(self, max_work: usize) -> usize {
        match self {
            Limit::Work | Limit::Constants => max_work,
            Limit::Terms => MAX_TERMS,
            Limit::Nesting => MAX_NESTING,
            Limit::Digits => Rational::MAX_DIGITS as usize,
            Limit::Exponent => u32::MAX as usize,
        }
    }

    /// Whether exceeding it is expression swell (rather than a constant
    /// too large to compute exactly).
    pub fn is_swell(self) -> bool {
        matches!(self, Limit::Work | Limit::Terms | Limit::Nesting)
    }
}

/// `n` with its thousands separated by commas: 50,000,000.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The first limit a derivation exceeded, with the site the stages had
/// named then (`None` if no site was named).
#[derive(Clone, Debug)]
pub struct Exceeded {
    /// The measure exceeded.
    pub limit: Limit,
    /// Its limit.
    pub bound: usize,
    /// The part of the input being derived, and what was being done.
    pub site: Option<Site>,
}

impl Exceeded {
    /// The limit with its figure, as a message says it: "50,000,000
    /// units of work (..)".
    pub fn measure(&self) -> String {
        let n = thousands(self.bound);
        match self.limit {
            Limit::Work => format!(
                "{n} units of work (one per pair of terms multiplied and per factor of a term formed)"
            ),
            Limit::Constants => format!(
                "{n} units of work, passed in arithmetic on exact constants of more than 38 digits"
            ),
            Limit::Terms => format!("{n} terms in one expression"),
            Limit::Nesting => format!("{n} products nested in one another"),
            Limit::Digits => format!("{n} digits in an exact constant"),
            Limit::Exponent => format!("{n} for an exponent to expand"),
        }
    }
}

impl Engine {
    /// Records that `limit` is exceeded: the derivation is abandoned (its
    /// results are meaningless from here on) and, the first time, the
    /// limit is kept with the current site.
    pub(super) fn exceed(&mut self, limit: Limit) {
        self.abandoned = true;
        if self.exceeded.is_none() {
            self.exceeded = Some(Exceeded {
                limit,
                bound: limit.bound(self.max_work),
                site: self.site.clone(),
            });
        }
    }

    /// True once a limit is exceeded: the derivation is abandoned.
    #[inline(always)]
    pub(super) fn abandoned(&self) -> bool {
        self.abandoned
    }

    /// Names the part of the input the work that follows derives; returns
    /// the site named before, for [`Engine::leave`] when that work is done.
    pub fn enter(&mut self, site: Site) -> Option<Site> {
        self.site.replace(site)
    }

    /// Restores the site named before [`Engine::enter`].
    pub fn leave(&mut self, previous: Option<Site>) {
        self.site = previous;
    }

    /// The first limit exceeded and where, if one was.
    pub fn exceeded(&self) -> Option<&Exceeded> {
        self.exceeded.as_ref()
    }

    /// The state of the limits before a derivation that has a fallback
    /// ([`Engine::attempt`]).
    fn limit_mark(&self) -> (bool, bool, usize) {
        (self.abandoned, self.exceeded.is_some(), self.work)
    }

    /// `f` on the engine if it stays within the limits; else `None`, with
    /// the limits as they were before it (the caller derives the value
    /// another way). Products formed while the derivation was abandoned are
    /// not memoised, so nothing of it is reused.
    pub fn attempt<R>(&mut self, f: impl FnOnce(&mut Engine) -> R) -> Option<R> {
        let (abandoned, exceeded, work) = self.limit_mark();
        let r = f(self);
        if self.abandoned && !abandoned {
            self.abandoned = false;
            if !exceeded {
                self.exceeded = None;
            }
            self.work = work;
            return None;
        }
        Some(r)
    }
}

#[cfg(test)]
mod tests {
    use super::{Limit, thousands};
    use crate::ctxt::{Site, SpanRange};
    use crate::sym::Engine;
    use proc_macro2::Span;

    #[test]
    fn figures_have_their_thousands_separated() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(200), "200");
        assert_eq!(thousands(10_000), "10,000");
        assert_eq!(thousands(200_000), "200,000");
        assert_eq!(thousands(50_000_000), "50,000,000");
    }

    /// The site kept is the one named when the limit is first exceeded;
    /// later limits and sites do not replace it.
    #[test]
    fn the_first_limit_keeps_the_site_named_then() {
        let mut e = Engine::new();
        let site = |task: &str| Site::new(SpanRange::single(Span::call_site()), task);
        let outer = e.enter(site("outer"));
        assert!(outer.is_none() && e.exceeded().is_none());
        let before = e.enter(site("inner"));
        e.exceed(Limit::Nesting);
        e.leave(before);
        e.exceed(Limit::Work);
        let ex = e.exceeded().expect("exceeded");
        assert_eq!(ex.limit, Limit::Nesting);
        assert_eq!(ex.measure(), "200 products nested in one another");
        assert_eq!(ex.site.as_ref().map(|s| s.task.as_str()), Some("inner"));
        assert!(e.overflowed());
    }
}
