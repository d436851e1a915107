//! Emission as text: the live nodes in topological order as `let`
//! statements, values used once written inline, `sin` and `cos` of one angle
//! as one `sin_cos`, constants as correctly rounded `f64`; the text is parsed
//! into tokens once.

use super::{Dag, Node, Op, cost};
use crate::sym::{Fun, Rational};
use proc_macro2::TokenStream;
use quote::quote;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

impl Dag {
    /// Emits the statements computing `outputs`, and the expression naming
    /// each output. The scalar type is `T`.
    pub fn emit(&self, outputs: &[Node]) -> (TokenStream, Vec<TokenStream>) {
        self.emit_with(outputs, &HashMap::default())
    }

    /// Like [`Dag::emit`], with the nodes of `given` taken from the given
    /// tokens instead of computed (hoisted values read from a cache).
    ///
    /// The statements are written as text and parsed once: building them
    /// token by token costs most of an expansion in an unoptimised proc
    /// macro (users' crates build proc macros without optimisation), while
    /// the compiler's own lexer reads the text at full speed. Every name is
    /// generated (`v12`, leaf names, `__nh_` helpers), so nothing the text
    /// holds needs a span of its own.
    pub fn emit_with(
        &self,
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> (TokenStream, Vec<TokenStream>) {
        let (text, outs) = self.emit_text(outputs, given);
        let stmts = parse_text(&text);
        let outs = outs.iter().map(|t| parse_text(t)).collect();
        (stmts, outs)
    }

    /// The statements of [`Dag::emit_with`] as text, with the names of the
    /// outputs.
    pub fn emit_text(
        &self,
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> (String, Vec<String>) {
        let outputs: Vec<Node> = outputs.iter().map(|&o| self.resolved(o)).collect();
        let outputs = &outputs[..];
        let live = self.live_until(outputs, given);
        let pair_of = self.sin_cos_pairs(&live, given);
        let inline = self.inlined(&live, outputs, given, &pair_of);
        let mut inline_text: HashMap<Node, String> = HashMap::default();
        // one statement per bound value (or sin_cos pair): (values, text)
        let mut stmts: Vec<(Vec<Node>, String)> = Vec::new();
        let mut done: HashSet<Node> = HashSet::default();
        for &n in &live {
            if done.contains(&n) {
                continue;
            }
            if let Some(&(s, c)) = pair_of.get(&n) {
                let Op::Call(_, a) = self.ops[s.index()] else {
                    continue;
                };
                let mut text = String::new();
                self.label_text(s, &mut text);
                self.label_text(c, &mut text);
                let (sv, cv, a) = (self.name(s), self.name(c), self.text_of(a, &inline_text));
                text.push_str(&format!("let ({sv}, {cv}): (T, T) = {a}.sin_cos();\n"));
                stmts.push((vec![s, c], text));
                done.extend([s, c]);
                continue;
            }
            let rhs = match given.get(&n) {
                Some(tokens) => tokens.to_string(),
                None => self.op_text(n, &|c| self.text_of(c, &inline_text)),
            };
            if inline.contains(&n) {
                let atomic = matches!(
                    self.ops[n.index()],
                    Op::Const(_)
                        | Op::Pi
                        | Op::Call(..)
                        | Op::Atan2(..)
                        | Op::Sqrt(_)
                        | Op::Powf(..)
                ) && !rhs.starts_with('-');
                inline_text.insert(n, if atomic { rhs } else { format!("({rhs})") });
                continue;
            }
            let mut text = String::new();
            self.label_text(n, &mut text);
            text.push_str(&format!("let {}: T = {rhs};\n", self.name(n)));
            stmts.push((vec![n], text));
        }
        let text = if stmts.len() > MAX_LETS {
            self.chunked(&stmts, outputs, &inline)
        } else {
            stmts.iter().map(|(_, t)| t.as_str()).collect()
        };
        let outs = outputs
            .iter()
            .map(|&n| self.text_of(n, &inline_text))
            .collect();
        (text, outs)
    }

    /// The name a bound value is known by. `__nh_`: out of the way of the
    /// user's constants (a `let` pattern naming a constant would match it
    /// instead of binding).
    pub(super) fn name(&self, n: Node) -> String {
        let n = self.resolved(n);
        match &self.ops[n.index()] {
            Op::Leaf(i) if self.leaves[*i].1.is_some() => {
                format!("__nh_{}", self.leaves[*i].1.as_deref().unwrap_or("leaf"))
            }
            _ => format!("__nh_v{}", self.number(n)),
        }
    }

    /// A value as text: its expression if it is written inline, else its name.
    fn text_of(&self, n: Node, inline_text: &HashMap<Node, String>) -> String {
        let n = self.resolved(n);
        match inline_text.get(&n) {
            Some(t) => t.clone(),
            None => self.name(n),
        }
    }

    /// The values written into the expression that uses them instead of a
    /// `let` of their own: used once, not an output, not named (a leaf, a
    /// labelled value, half of a `sin_cos` pair), and small enough that the
    /// statement stays readable (at most [`MAX_INLINE_OPS`] operations).
    fn inlined(
        &self,
        live: &[Node],
        outputs: &[Node],
        given: &HashMap<Node, TokenStream>,
        pair_of: &HashMap<Node, (Node, Node)>,
    ) -> HashSet<Node> {
        let mut uses = vec![0usize; self.ops.len()];
        for &n in live {
            if given.contains_key(&n) {
                continue;
            }
            // a power is written as repeated products of its base
            let times = if matches!(self.ops[n.index()], Op::Powi(..)) {
                2
            } else {
                1
            };
            for c in self.children(n).into_iter().flatten() {
                uses[c.index()] += times;
            }
        }
        for &o in outputs {
            uses[o.index()] += 2;
        }
        let mut size = vec![0usize; self.ops.len()];
        let mut inline = HashSet::default();
        for &n in live {
            let op = &self.ops[n.index()];
            if given.contains_key(&n) || pair_of.contains_key(&n) || matches!(op, Op::Leaf(_)) {
                continue;
            }
            let own = cost(op).max(1)
                + self
                    .children(n)
                    .into_iter()
                    .flatten()
                    .map(|c| size[c.index()])
                    .sum::<usize>();
            if uses[n.index()] == 1 && !self.labels.contains_key(&n) && own <= MAX_INLINE_OPS {
                inline.insert(n);
                size[n.index()] = own;
            }
        }
        inline
    }

    /// sin and cos of one angle, both live: computed by one `sin_cos` call.
    fn sin_cos_pairs(
        &self,
        live: &[Node],
        given: &HashMap<Node, TokenStream>,
    ) -> HashMap<Node, (Node, Node)> {
        let live_set: HashSet<Node> = live.iter().copied().collect();
        let mut pair_of: HashMap<Node, (Node, Node)> = HashMap::default();
        for &n in live {
            if let Op::Call(Fun::Sin, a) = self.ops[n.index()]
                && let Some(&c) = self.ix.get(&Op::Call(Fun::Cos, a))
                && live_set.contains(&c)
                && !given.contains_key(&n)
                && !given.contains_key(&c)
            {
                pair_of.insert(n, (n, c));
                pair_of.insert(c, (n, c));
            }
        }
        pair_of
    }

    /// A label as a string statement (free at run time, visible under
    /// `cargo expand`).
    fn label_text(&self, n: Node, text: &mut String) {
        if let Some(label) = self.labels.get(&n) {
            let escaped = label.replace('\\', "\\\\").replace('"', "\\\"");
            text.push_str(&format!("let _ = \"{escaped}\";\n"));
        }
    }

    /// The right side computing node `n`, as text.
    fn op_text(&self, n: Node, name: &dyn Fn(Node) -> String) -> String {
        match &self.ops[n.index()] {
            Op::Const(q) => const_text(*q),
            Op::Pi => "T::pi()".into(),
            Op::Leaf(i) => self.leaves[*i].0.to_string(),
            Op::Add(a, b) => format!("{} + {}", name(*a), name(*b)),
            Op::Sub(a, b) => format!("{} - {}", name(*a), name(*b)),
            Op::Mul(a, b) => format!("{} * {}", name(*a), name(*b)),
            Op::Div(a, b) => format!("{} / {}", name(*a), name(*b)),
            Op::Neg(a) => format!("-{}", name(*a)),
            Op::Call(f, a) => call_text(*f, &name(*a)),
            Op::Atan2(y, x) => format!("{}.atan2({})", name(*y), name(*x)),
            Op::Sqrt(a) => format!("{}.sqrt()", name(*a)),
            Op::Powi(a, k) => powi_text(&name(*a), *k),
            Op::Powf(a, b) => format!("{}.powf({})", name(*a), name(*b)),
            Op::Opaque(a) => name(*a),
        }
    }
}

/// A parser of generated text into tokens, supplied by the proc-macro crate
/// for the duration of one expansion (see [`with_text_parser`]).
pub type TextParser = fn(&str) -> Option<TokenStream>;

thread_local! {
    static TEXT_PARSER: std::cell::Cell<Option<TextParser>> = const { std::cell::Cell::new(None) };
}

/// Runs `f` with generated text parsed by `parser`. Inside the compiler the
/// proc-macro crate passes the compiler's own lexer: `proc_macro2` would
/// first lex the text again with its own lexer to validate it, which in an
/// unoptimised proc macro costs more than the rest of an expansion. The text
/// is generated (names, numbers, operators), so it is valid by construction.
pub fn with_text_parser<R>(parser: TextParser, f: impl FnOnce() -> R) -> R {
    let previous = TEXT_PARSER.with(|p| p.replace(Some(parser)));
    let r = f();
    TEXT_PARSER.with(|p| p.set(previous));
    r
}

/// Parses generated text (with the compiler's lexer when one was supplied).
pub fn parse_text(text: &str) -> TokenStream {
    let parsed = match TEXT_PARSER.with(|p| p.get()) {
        Some(parser) => parser(text),
        None => text.parse().ok(),
    };
    parsed.unwrap_or_else(|| {
        let msg = "nonholonomic_system!: internal error: generated code does not lex";
        quote!(::core::compile_error!(#msg);)
    })
}

/// Most operations written in one statement by inlining values used once.
pub const MAX_INLINE_OPS: usize = 6;

/// Most statements a generated function holds in one block; beyond, they
/// are split into blocks of [`CHUNK_LETS`](super::CHUNK_LETS) (see
/// `Dag::chunked`).
pub const MAX_LETS: usize = 2000;

/// `f(a)` as text: a method of `T: RealField` (`ComplexField`'s `abs`,
/// `sinh`, `asin`, ...); the sign, which has none that is 0 at 0 (`signum`
/// is 1 at +0), by comparisons, NaN passed through; `cot`, `sec` and `csc`
/// (which the engine rewrites into powers of `sin` and `cos` before this)
/// by quotients.
fn call_text(f: Fun, a: &str) -> String {
    match f {
        Fun::Sign => format!(
            "({{ let __nh_sg: T = {a}; if __nh_sg > T::zero() {{ T::one() }} else if __nh_sg < T::zero() {{ -T::one() }} else {{ __nh_sg }} }})"
        ),
        Fun::Cot => format!("({a}.cos() / {a}.sin())"),
        Fun::Sec => format!("(T::one() / {a}.cos())"),
        Fun::Csc => format!("(T::one() / {a}.sin())"),
        _ => format!("{a}.{}()", f.name()),
    }
}

fn powi_text(a: &str, k: u32) -> String {
    match k {
        2 => format!("{a} * {a}"),
        3 => format!("{a} * {a} * {a}"),
        4 => format!("{{ let __nh_sq = {a} * {a}; __nh_sq * __nh_sq }}"),
        _ => format!("{a}.powi({})", k as i32),
    }
}

thread_local! {
    /// The largest constant generated code needed but `f64` cannot hold,
    /// since the last [`take_unrepresentable`].
    static UNREPRESENTABLE: std::cell::Cell<Option<Rational>> = const { std::cell::Cell::new(None) };
}

/// The largest constant (in magnitude) that generated code needed but `f64`
/// cannot hold (beyond ±`f64::MAX`) since the last call, and resets it.
pub fn take_unrepresentable() -> Option<Rational> {
    UNREPRESENTABLE.try_with(|c| c.take()).ok().flatten()
}

/// The correctly rounded `f64` of a constant of the generated code, or
/// `None` (recorded for [`take_unrepresentable`]) beyond the range of `f64`.
fn representable(q: Rational) -> Option<f64> {
    let v = q.to_f64();
    if v.is_finite() {
        return Some(v);
    }
    let _ = UNREPRESENTABLE.try_with(|c| {
        if c.get().is_none_or(|old| old.abs() < q.abs()) {
            c.set(Some(q));
        }
    });
    None
}

/// Text converting a rational constant to `T` (through the generated
/// `__nh_c`, which names the facade's nalgebra): the correctly rounded
/// `f64` in its shortest round-trip form, exact for `T = f64`.
fn const_text(q: Rational) -> String {
    if q.is_zero() {
        return "T::zero()".into();
    }
    if q.is_one() {
        return "T::one()".into();
    }
    match representable(q) {
        Some(v) => format!("Self::__nh_c({v:?}f64)"),
        None => "T::zero()".into(),
    }
}
