//! Human-readable text of expressions, for messages and debugging.

use super::{Atom, Engine, ExprId, MonoId};

impl Engine {
    /// Human-readable form, for messages and debugging.
    pub fn display(&self, e: ExprId) -> String {
        let mut s = String::new();
        self.write_expr(e, usize::MAX, &mut s);
        s
    }

    /// [`Engine::display`] cut after about `cap` characters (with `...`),
    /// without writing out the rest of a long expression.
    pub fn display_capped(&self, e: ExprId, cap: usize) -> String {
        let mut s = String::new();
        self.write_expr(e, cap, &mut s);
        if s.chars().count() <= cap {
            return s;
        }
        let head: String = s.chars().take(cap.saturating_sub(3)).collect();
        format!("{head}...")
    }

    /// Appends the text of `e` to `s`, stopping once `s` is longer than `cap`.
    fn write_expr(&self, e: ExprId, cap: usize, s: &mut String) {
        let terms = &self.exprs[e.index()];
        if terms.is_empty() {
            s.push('0');
            return;
        }
        for (i, &(m, c)) in terms.iter().enumerate() {
            if s.len() > cap {
                return;
            }
            let neg = c.is_negative();
            let ac = c.abs();
            if i == 0 {
                if neg {
                    s.push('-');
                }
            } else {
                s.push_str(if neg { " - " } else { " + " });
            }
            let empty = self.monos[m.index()].is_empty();
            if empty || !ac.is_one() {
                s.push_str(&ac.to_string());
            }
            if !empty {
                if !ac.is_one() {
                    s.push('*');
                }
                self.write_mono(m, cap, s);
            }
        }
    }

    fn write_mono(&self, m: MonoId, cap: usize, s: &mut String) {
        for (i, &(a, e)) in self.monos[m.index()].iter().enumerate() {
            if s.len() > cap {
                return;
            }
            if i > 0 {
                s.push('*');
            }
            match &self.atoms[a.index()] {
                Atom::Sym(x) => s.push_str(&self.sym_names[x.index()]),
                Atom::Func(f, u) => {
                    s.push_str(f.name());
                    s.push('(');
                    self.write_expr(*u, cap, s);
                    s.push(')');
                }
                Atom::Base(b) => {
                    s.push('(');
                    self.write_expr(*b, cap, s);
                    s.push(')');
                }
                Atom::Atan2(y, x) => {
                    s.push_str("atan2(");
                    self.write_expr(*y, cap, s);
                    s.push_str(", ");
                    self.write_expr(*x, cap, s);
                    s.push(')');
                }
            }
            if e.is_integer() && !e.is_negative() && !e.is_one() {
                s.push_str(&format!("^{e}"));
            } else if !e.is_one() {
                s.push_str(&format!("^({e})"));
            }
        }
    }
}
