//! Human-readable text of expressions, for messages and debugging.

use super::{Atom, Engine, ExprId, MonoId};

impl Engine {
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
                Atom::Atan2(y, x) => format!("atan2({}, {})", self.display(*y), self.display(*x)),
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
