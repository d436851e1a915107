//! A recursive-descent parser of the Rust subset the engine emits: types,
//! paths, expressions, statements and blocks. Anything else is an error
//! that quotes the tokens where parsing stopped.

use super::ast::{BinOp, Block, Expr, GenArg, Pat, Seg, Sig, Stmt, StmtKind, Ty, UnOp};
use super::lex::{Delim, Tok, in_stmt, lit_int, show};

/// How deeply expressions may nest (the generated code nests a few levels).
const MAX_DEPTH: usize = 200;

/// How much of the remaining tokens an error quotes.
const QUOTE: usize = 160;

/// A parser over one token list (a group's contents).
pub(super) struct Parser<'t> {
    toks: &'t [Tok],
    i: usize,
    depth: usize,
}

type R<T> = Result<T, String>;

impl<'t> Parser<'t> {
    /// A parser at the start of `toks`.
    pub(super) fn new(toks: &'t [Tok]) -> Self {
        Parser {
            toks,
            i: 0,
            depth: 0,
        }
    }

    fn nested(&self, toks: &'t [Tok]) -> R<Parser<'t>> {
        if self.depth >= MAX_DEPTH {
            return Err(self.err("nesting too deep"));
        }
        Ok(Parser {
            toks,
            i: 0,
            depth: self.depth + 1,
        })
    }

    fn peek(&self) -> Option<&'t Tok> {
        self.toks.get(self.i)
    }

    fn peek_at(&self, k: usize) -> Option<&'t Tok> {
        self.toks.get(self.i + k)
    }

    fn at_end(&self) -> bool {
        self.i >= self.toks.len()
    }

    fn is_punct(&self, p: &str) -> bool {
        matches!(self.peek(), Some(Tok::Punct(x)) if x == p)
    }

    fn is_ident(&self, w: &str) -> bool {
        matches!(self.peek(), Some(Tok::Ident(x)) if x == w)
    }

    fn eat_punct(&mut self, p: &str) -> bool {
        let yes = self.is_punct(p);
        self.i += usize::from(yes);
        yes
    }

    fn eat_ident(&mut self, w: &str) -> bool {
        let yes = self.is_ident(w);
        self.i += usize::from(yes);
        yes
    }

    fn expect_punct(&mut self, p: &str) -> R<()> {
        if self.eat_punct(p) {
            Ok(())
        } else {
            Err(self.err(&format!("expected `{p}`")))
        }
    }

    fn ident(&mut self) -> R<String> {
        match self.peek() {
            Some(Tok::Ident(x)) => {
                self.i += 1;
                Ok(x.clone())
            }
            _ => Err(self.err("expected a name")),
        }
    }

    fn group(&mut self, d: Delim) -> Option<&'t [Tok]> {
        match self.peek() {
            Some(Tok::Group(x, inner)) if *x == d => {
                self.i += 1;
                Some(inner)
            }
            _ => None,
        }
    }

    /// An error quoting the tokens from the current position.
    pub(super) fn err(&self, what: &str) -> String {
        let rest = &self.toks[self.i.min(self.toks.len())..];
        if rest.is_empty() {
            format!("{what} at the end of `{}`", show(self.toks, QUOTE))
        } else {
            format!("{what} at `{}`", show(rest, QUOTE))
        }
    }

    /// Fails unless every token was used.
    pub(super) fn finish(&self) -> R<()> {
        if self.at_end() {
            Ok(())
        } else {
            Err(self.err("unexpected tokens"))
        }
    }
}

// ---------------------------------------------------------------- types

impl<'t> Parser<'t> {
    /// A type.
    pub(super) fn ty(&mut self) -> R<Ty> {
        if self.eat_punct("&") {
            if matches!(self.peek(), Some(Tok::Life(_))) {
                self.i += 1;
            }
            if self.eat_ident("mut") {
                let inner = self.ty()?;
                return Ok(Ty::Other(format!("&mut {inner:?}")));
            }
            return self.ty();
        }
        if let Some(inner) = self.group(Delim::Bracket) {
            return self.array_ty(inner);
        }
        if let Some(inner) = self.group(Delim::Paren) {
            return self.tuple_ty(inner);
        }
        let segs = self.path(true)?;
        let ty = ty_of_path(&segs);
        if !ty.fits() {
            return Err(self.err("a type too large"));
        }
        Ok(ty)
    }

    fn array_ty(&self, inner: &'t [Tok]) -> R<Ty> {
        let mut p = self.nested(inner)?;
        let elem = p.ty()?;
        p.expect_punct(";")?;
        let n = p.count()?;
        p.finish()?;
        let ty = Ty::Array(n, Box::new(elem));
        if !ty.fits() {
            return Err(p.err("an array too large"));
        }
        Ok(ty)
    }

    fn tuple_ty(&self, inner: &'t [Tok]) -> R<Ty> {
        let mut p = self.nested(inner)?;
        let mut tys = Vec::new();
        let mut comma = false;
        while !p.at_end() {
            tys.push(p.ty()?);
            comma = p.eat_punct(",");
            if !comma {
                p.finish()?;
            }
        }
        let ty = match (tys.len(), comma) {
            (0, _) => Ty::Unit,
            (1, false) => tys.remove(0),
            _ => Ty::Tuple(tys),
        };
        if !ty.fits() {
            return Err(p.err("a tuple too large"));
        }
        Ok(ty)
    }

    /// An integer literal used as a size or index.
    fn count(&mut self) -> R<usize> {
        match self.peek() {
            Some(Tok::Lit(l)) => {
                let n = lit_int(l).and_then(|n| usize::try_from(n).ok());
                let n = n.ok_or_else(|| self.err("expected a size"))?;
                self.i += 1;
                Ok(n)
            }
            _ => Err(self.err("expected a size")),
        }
    }

    /// A path: `a::b::<T, 2usize>::c`, or in a type `a::B<T>`. A leading
    /// `::` is dropped.
    pub(super) fn path(&mut self, in_type: bool) -> R<Vec<Seg>> {
        self.eat_punct("::");
        let mut segs = Vec::new();
        loop {
            let name = self.ident()?;
            let mut args = Vec::new();
            if in_type && self.is_punct("<") {
                args = self.generics()?;
            }
            segs.push(Seg { name, args });
            if !self.eat_punct("::") {
                return Ok(segs);
            }
            if self.is_punct("<") {
                let args = self.generics()?;
                if let Some(last) = segs.last_mut() {
                    last.args = args;
                }
                if !self.eat_punct("::") {
                    return Ok(segs);
                }
            }
        }
    }

    /// `<A, B, ..>`.
    fn generics(&mut self) -> R<Vec<GenArg>> {
        self.expect_punct("<")?;
        let mut args = Vec::new();
        while !self.eat_punct(">") {
            let arg = match self.peek() {
                Some(Tok::Lit(_)) => GenArg::Num(self.count()?),
                Some(Tok::Life(_)) => {
                    self.i += 1;
                    GenArg::Life
                }
                _ => GenArg::Ty(self.ty()?),
            };
            args.push(arg);
            if !self.eat_punct(",") {
                self.expect_punct(">")?;
                break;
            }
        }
        Ok(args)
    }
}

/// The type a path names.
pub(super) fn ty_of_path(segs: &[Seg]) -> Ty {
    let Some(last) = segs.last() else {
        return Ty::Other(String::new());
    };
    let nums: Vec<usize> = (last.args.iter())
        .filter_map(|a| match a {
            GenArg::Num(n) => Some(*n),
            _ => None,
        })
        .collect();
    match (last.name.as_str(), nums.as_slice(), last.args.first()) {
        ("T" | "f64", [], _) => Ty::Scalar,
        ("bool", [], _) => Ty::Bool,
        ("str", [], _) => Ty::Str,
        ("SVector", [n], _) => Ty::Mat(*n, 1),
        ("SMatrix", [r, c], _) => Ty::Mat(*r, *c),
        ("Option", [], Some(GenArg::Ty(inner))) => inner.clone(),
        (name, ..) => Ty::Other(name.to_string()),
    }
}

// ---------------------------------------------------------------- signatures

impl<'t> Parser<'t> {
    /// A method's signature after its name: `(params) -> RET` (no generics,
    /// no `where`).
    pub(super) fn sig(&mut self) -> R<Sig> {
        if self.is_punct("<") {
            return Err(self.err("generic method"));
        }
        let inner = self
            .group(Delim::Paren)
            .ok_or_else(|| self.err("expected the parameters"))?;
        let (has_self, params) = self.nested(inner)?.params()?;
        let ret = if self.eat_punct("->") {
            self.ty()?
        } else {
            Ty::Unit
        };
        self.finish()?;
        Ok(Sig {
            has_self,
            params,
            ret,
        })
    }

    fn params(&mut self) -> R<(bool, Vec<(String, Ty)>)> {
        let mut has_self = false;
        let mut params = Vec::new();
        while !self.at_end() {
            let by_ref = self.eat_punct("&");
            let by_mut = self.eat_ident("mut");
            if self.eat_ident("self") {
                has_self = true;
            } else {
                if by_ref {
                    return Err(self.err("unsupported parameter pattern"));
                }
                let name = self.ident()?;
                self.expect_punct(":")?;
                let ty = self.ty()?;
                let ty = if by_mut {
                    Ty::Other(format!("mut {ty:?}"))
                } else {
                    ty
                };
                params.push((name, ty));
            }
            if !self.eat_punct(",") {
                self.finish()?;
            }
        }
        Ok((has_self, params))
    }
}

// ---------------------------------------------------------------- expressions

/// The binary operator at a token, with its precedence (higher binds tighter).
fn binop(t: Option<&Tok>) -> Option<(BinOp, u8)> {
    let Some(Tok::Punct(p)) = t else {
        return None;
    };
    Some(match p.as_str() {
        "||" => (BinOp::Or, 1),
        "&&" => (BinOp::And, 2),
        "==" => (BinOp::Eq, 3),
        "!=" => (BinOp::Ne, 3),
        "<" => (BinOp::Lt, 3),
        ">" => (BinOp::Gt, 3),
        "<=" => (BinOp::Le, 3),
        ">=" => (BinOp::Ge, 3),
        "|" => (BinOp::BitOr, 4),
        "^" => (BinOp::BitXor, 5),
        "&" => (BinOp::BitAnd, 6),
        "+" => (BinOp::Add, 8),
        "-" => (BinOp::Sub, 8),
        "*" => (BinOp::Mul, 9),
        "/" => (BinOp::Div, 9),
        "%" => (BinOp::Rem, 9),
        _ => return None,
    })
}

impl<'t> Parser<'t> {
    /// An expression.
    pub(super) fn expr(&mut self) -> R<Expr<'t>> {
        self.binary(0)
    }

    fn binary(&mut self, min: u8) -> R<Expr<'t>> {
        let mut lhs = self.unary()?;
        let mut chain = 0;
        while let Some((op, prec)) = binop(self.peek()) {
            if prec < min {
                break;
            }
            chain += 1;
            if self.depth + chain >= MAX_DEPTH {
                return Err(self.err("an expression too long"));
            }
            self.i += 1;
            let rhs = self.binary(prec + 1)?;
            lhs = Expr::Binary(op, Box::new(lhs), Box::new(rhs));
        }
        Ok(lhs)
    }

    fn unary(&mut self) -> R<Expr<'t>> {
        if self.depth >= MAX_DEPTH {
            return Err(self.err("nesting too deep"));
        }
        let op = match self.peek() {
            Some(Tok::Punct(p)) if p == "-" => UnOp::Neg,
            Some(Tok::Punct(p)) if p == "!" => UnOp::Not,
            Some(Tok::Punct(p)) if p == "*" => UnOp::Deref,
            Some(Tok::Punct(p)) if p == "&" || p == "&&" => {
                self.i += 1;
                if self.is_ident("mut") {
                    return Err(self.err("unsupported `&mut`"));
                }
                return Ok(Expr::Unary(UnOp::Ref, Box::new(self.deeper(Self::unary)?)));
            }
            _ => return self.postfix(),
        };
        self.i += 1;
        Ok(Expr::Unary(op, Box::new(self.deeper(Self::unary)?)))
    }

    fn deeper<X>(&mut self, f: impl FnOnce(&mut Self) -> R<X>) -> R<X> {
        self.depth += 1;
        let r = f(self);
        self.depth -= 1;
        r
    }

    fn postfix(&mut self) -> R<Expr<'t>> {
        let mut e = self.primary()?;
        for chain in self.depth.. {
            if chain >= MAX_DEPTH {
                return Err(self.err("a chain of calls too long"));
            }
            if self.eat_punct(".") {
                e = self.dotted(e)?;
            } else if let Some(inner) = self.group(Delim::Bracket) {
                let mut p = self.nested(inner)?;
                let idx = p.expr()?;
                p.finish()?;
                e = Expr::Index(Box::new(e), Box::new(idx));
            } else if let Some(inner) = self.group(Delim::Paren) {
                e = Expr::Call(Box::new(e), self.nested(inner)?.list()?);
            } else if self.is_punct("?") {
                return Err(self.err("unsupported `?`"));
            } else {
                break;
            }
        }
        Ok(e)
    }

    /// After `recv.`: a method call, a named field or a tuple field.
    fn dotted(&mut self, recv: Expr<'t>) -> R<Expr<'t>> {
        if let Some(Tok::Lit(l)) = self.peek() {
            self.i += 1;
            let mut e = recv;
            for part in l.split('.') {
                e = Expr::Field(Box::new(e), part.to_string());
            }
            return Ok(e);
        }
        let name = self.ident()?;
        let mut gens = Vec::new();
        if self.eat_punct("::") {
            gens = self.generics()?;
        }
        match self.group(Delim::Paren) {
            Some(inner) => {
                let args = self.nested(inner)?.list()?;
                Ok(Expr::Method(Box::new(recv), name, gens, args))
            }
            None if gens.is_empty() => Ok(Expr::Field(Box::new(recv), name)),
            None => Err(self.err("expected a method's arguments")),
        }
    }

    /// Comma-separated expressions filling the parser (a trailing comma allowed).
    fn list(&mut self) -> R<Vec<Expr<'t>>> {
        let mut items = Vec::new();
        while !self.at_end() {
            items.push(self.expr()?);
            if !self.eat_punct(",") {
                self.finish()?;
            }
        }
        Ok(items)
    }

    fn primary(&mut self) -> R<Expr<'t>> {
        match self.peek() {
            Some(Tok::Lit(l)) => {
                self.i += 1;
                Ok(Expr::Lit(l.clone()))
            }
            Some(Tok::Ident(w)) => self.word(w),
            Some(Tok::Punct(p)) if p == "<" => self.qualified(),
            Some(Tok::Punct(p)) if p == "::" => Ok(Expr::Path(self.path(false)?)),
            Some(Tok::Group(Delim::Paren, inner)) => {
                self.i += 1;
                self.nested(inner)?.parens()
            }
            Some(Tok::Group(Delim::Bracket, inner)) => {
                self.i += 1;
                self.nested(inner)?.array()
            }
            Some(Tok::Group(Delim::Brace, inner)) => {
                self.i += 1;
                Ok(Expr::Block(self.nested(inner)?.block()?))
            }
            _ => Err(self.err("unsupported expression")),
        }
    }

    fn word(&mut self, w: &str) -> R<Expr<'t>> {
        match w {
            "true" | "false" => {
                self.i += 1;
                Ok(Expr::Bool(w == "true"))
            }
            "if" => {
                self.i += 1;
                self.if_rest()
            }
            "match" | "loop" | "while" | "return" | "break" | "continue" | "move" | "unsafe"
            | "let" | "for" | "async" => Err(self.err(&format!("unsupported `{w}`"))),
            _ if matches!(self.peek_at(1), Some(Tok::Punct(p)) if p == "!") => {
                Err(self.err("unsupported macro"))
            }
            _ => Ok(Expr::Path(self.path(false)?)),
        }
    }

    /// `<Type>::rest`: the type's path followed by the rest.
    fn qualified(&mut self) -> R<Expr<'t>> {
        self.expect_punct("<")?;
        let mut segs = self.path(true)?;
        self.expect_punct(">")?;
        self.expect_punct("::")?;
        segs.extend(self.path(false)?);
        Ok(Expr::Path(segs))
    }

    /// The contents of parentheses: `()`, `(e)` or a tuple.
    fn parens(&mut self) -> R<Expr<'t>> {
        let mut items = Vec::new();
        let mut comma = false;
        while !self.at_end() {
            items.push(self.expr()?);
            comma = self.eat_punct(",");
            if !comma {
                self.finish()?;
            }
        }
        Ok(match (items.len(), comma) {
            (1, false) => Expr::Paren(Box::new(items.remove(0))),
            _ => Expr::Tuple(items),
        })
    }

    /// The contents of brackets: `[a, b]` or `[e; n]`.
    fn array(&mut self) -> R<Expr<'t>> {
        if self.at_end() {
            return Ok(Expr::Array(Vec::new()));
        }
        let first = self.expr()?;
        if self.eat_punct(";") {
            let n = self.expr()?;
            self.finish()?;
            return Ok(Expr::Repeat(Box::new(first), Box::new(n)));
        }
        let mut items = vec![first];
        if self.eat_punct(",") {
            items.extend(self.list()?);
        } else {
            self.finish()?;
        }
        Ok(Expr::Array(items))
    }

    /// After `if`: the condition, the block and any `else`.
    fn if_rest(&mut self) -> R<Expr<'t>> {
        if self.is_ident("let") {
            return Err(self.err("unsupported `if let`"));
        }
        let cond = self.expr()?;
        let then = self.brace_block()?;
        let els = if self.eat_ident("else") {
            if self.eat_ident("if") {
                Some(Box::new(self.deeper(Self::if_rest)?))
            } else {
                Some(Box::new(Expr::Block(self.brace_block()?)))
            }
        } else {
            None
        };
        Ok(Expr::If(Box::new(cond), then, els))
    }

    fn brace_block(&mut self) -> R<Block<'t>> {
        let inner = self
            .group(Delim::Brace)
            .ok_or_else(|| self.err("expected a block"))?;
        self.nested(inner)?.block()
    }
}

// ---------------------------------------------------------------- statements

/// What [`Parser::stmt`] read.
enum Parsed<'t> {
    Stmt(StmtKind<'t>),
    Tail(Expr<'t>),
}

impl<'t> Parser<'t> {
    /// The contents of a block: statements and an optional final expression.
    pub(super) fn block(&mut self) -> R<Block<'t>> {
        let mut stmts = Vec::new();
        let mut tail = None;
        while !self.at_end() {
            if self.eat_punct(";") {
                continue;
            }
            if tail.is_some() {
                return Err(self.err("expected `;`"));
            }
            let start = self.i;
            let parsed = self.stmt().map_err(|e| in_stmt(e, self.up_to_semi(start)));
            match parsed? {
                Parsed::Stmt(kind) => stmts.push(Stmt {
                    kind,
                    src: &self.toks[start..self.i],
                }),
                Parsed::Tail(e) => tail = Some(Box::new(e)),
            }
        }
        Ok(Block { stmts, tail })
    }

    /// The tokens from `start` to the next `;` of this level (included).
    fn up_to_semi(&self, start: usize) -> &'t [Tok] {
        let rest = &self.toks[start.min(self.toks.len())..];
        let end = rest
            .iter()
            .position(|t| matches!(t, Tok::Punct(p) if p == ";"));
        &rest[..end.map_or(rest.len(), |e| e + 1)]
    }

    /// One statement, or the expression that ends the block.
    fn stmt(&mut self) -> R<Parsed<'t>> {
        if self.eat_ident("let") {
            return self.let_rest().map(Parsed::Stmt);
        }
        if self.eat_ident("for") {
            return self.for_rest().map(Parsed::Stmt);
        }
        if let Some(Tok::Ident(w)) = self.peek()
            && [
                "fn", "use", "struct", "impl", "const", "static", "mod", "type", "enum", "trait",
            ]
            .contains(&w.as_str())
        {
            return Err(self.err("unsupported item in a block"));
        }
        let block_like =
            self.is_ident("if") || matches!(self.peek(), Some(Tok::Group(Delim::Brace, _)));
        let e = if block_like {
            self.primary()?
        } else {
            self.expr()?
        };
        if self.at_end() {
            return Ok(Parsed::Tail(e));
        }
        if let Some(op) = self.assign_op() {
            let rhs = self.expr()?;
            self.end_stmt()?;
            return Ok(Parsed::Stmt(StmtKind::Assign(e, op, rhs)));
        }
        if !block_like {
            self.end_stmt()?;
        }
        Ok(Parsed::Stmt(StmtKind::Expr(e)))
    }

    fn end_stmt(&mut self) -> R<()> {
        if self.at_end() || self.eat_punct(";") {
            Ok(())
        } else {
            Err(self.err("expected `;`"))
        }
    }

    /// `=` (Some(None)) or a compound assignment (Some(Some(op))).
    fn assign_op(&mut self) -> Option<Option<BinOp>> {
        let op = match self.peek() {
            Some(Tok::Punct(p)) => match p.as_str() {
                "=" => None,
                "+=" => Some(BinOp::Add),
                "-=" => Some(BinOp::Sub),
                "*=" => Some(BinOp::Mul),
                "/=" => Some(BinOp::Div),
                _ => return None,
            },
            _ => return None,
        };
        self.i += 1;
        Some(op)
    }

    fn let_rest(&mut self) -> R<StmtKind<'t>> {
        let pat = self.pat()?;
        let ty = if self.eat_punct(":") {
            Some(self.ty()?)
        } else {
            None
        };
        let value = if self.eat_punct("=") {
            Some(self.expr()?)
        } else {
            None
        };
        if self.is_ident("else") {
            return Err(self.err("unsupported `let else`"));
        }
        self.end_stmt()?;
        Ok(StmtKind::Let(pat, ty, value))
    }

    fn for_rest(&mut self) -> R<StmtKind<'t>> {
        let pat = self.pat()?;
        if !self.eat_ident("in") {
            return Err(self.err("expected `in`"));
        }
        let iter = self.expr()?;
        let body = self.brace_block()?;
        Ok(StmtKind::For(pat, iter, body))
    }

    fn pat(&mut self) -> R<Pat> {
        if self.eat_ident("_") || self.eat_punct("_") {
            return Ok(Pat::Wild);
        }
        if let Some(inner) = self.group(Delim::Paren) {
            let mut p = self.nested(inner)?;
            let mut pats = Vec::new();
            while !p.at_end() {
                pats.push(p.pat()?);
                if !p.eat_punct(",") {
                    p.finish()?;
                }
            }
            return Ok(Pat::Tuple(pats));
        }
        if self.is_ident("ref") {
            return Err(self.err("unsupported pattern"));
        }
        let mutable = self.eat_ident("mut");
        Ok(Pat::Bind(self.ident()?, mutable))
    }
}
