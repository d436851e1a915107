//! Large functions: their statements in blocks that hand the values later
//! blocks need out as tuples.

use super::{Dag, Node};
use rustc_hash::FxHashSet as HashSet;

/// Statements in one block of a large function (see `Dag::chunked`).
pub const CHUNK_LETS: usize = 1000;

impl Dag {
    /// The statements of a large function in blocks of [`CHUNK_LETS`]: each
    /// block hands the values later blocks or the outputs need out as one
    /// tuple. Thousands of `let`s in one scope nest thousands of scopes,
    /// which overflows rustc's stack when it emits debug information (seen
    /// at ~20,000); a stack array instead costs LLVM gigabytes of memory.
    pub(super) fn chunked(
        &self,
        stmts: &[(Vec<Node>, String)],
        outputs: &[Node],
        inline: &HashSet<Node>,
    ) -> String {
        let chunks: Vec<&[(Vec<Node>, String)]> = stmts.chunks(CHUNK_LETS).collect();
        let mut chunk_of = vec![usize::MAX; self.ops.len()];
        for (c, chunk) in chunks.iter().enumerate() {
            for (ns, _) in chunk.iter() {
                for &n in ns {
                    chunk_of[n.index()] = c;
                }
            }
        }
        // a value is handed out if a later block or an output reads it
        let mut exported = vec![false; self.ops.len()];
        for &o in outputs {
            exported[o.index()] = true;
        }
        for (c, chunk) in chunks.iter().enumerate() {
            for (ns, _) in chunk.iter() {
                for &n in ns {
                    self.each_bound_read(n, inline, &mut |r| {
                        if chunk_of[r.index()] != usize::MAX && chunk_of[r.index()] < c {
                            exported[r.index()] = true;
                        }
                    });
                }
            }
        }
        let mut text = String::new();
        for chunk in &chunks {
            let out: Vec<String> = chunk
                .iter()
                .flat_map(|(ns, _)| ns.iter())
                .filter(|&&n| exported[n.index()])
                .map(|&n| self.name(n))
                .collect();
            let body: String = chunk.iter().map(|(_, t)| t.as_str()).collect();
            let names = out.join(", ");
            let types = vec!["T"; out.len()].join(", ");
            let comma = if out.len() == 1 { "," } else { "" };
            text.push_str(&format!(
                "let ({names}{comma}): ({types}{comma}) = {{\n{body}({names}{comma})\n}};\n"
            ));
        }
        text
    }

    /// Calls `f` with every bound (not inlined) value the statement of `n`
    /// reads, looking through the values written inline.
    fn each_bound_read(&self, n: Node, inline: &HashSet<Node>, f: &mut dyn FnMut(Node)) {
        for c in self.children(n).into_iter().flatten() {
            if inline.contains(&c) {
                self.each_bound_read(c, inline, f);
            } else {
                f(c);
            }
        }
    }
}
