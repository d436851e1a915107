//! What computing a set of outputs takes: the live nodes, their operation
//! count and estimated cost, and the values that depend on parameters alone
//! (hoisted into a cache).

use super::{Dag, Node, Op, cost};
use crate::sym::Fun;
use proc_macro2::TokenStream;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

impl Dag {
    /// Number of operations needed to compute `outputs` (each shared node once).
    pub fn op_count(&self, outputs: &[Node]) -> usize {
        let live = self.live(outputs);
        live.iter().map(|&n| cost(&self.ops[n.index()])).sum()
    }

    /// Estimated run time of computing `outputs`, in units of one addition:
    /// divisions and square roots about 4, elementary functions about 15
    /// (sin and cos of one angle together about 20, as one `sin_cos`; `abs` and
    /// the sign about 2). Used to
    /// choose between the derivation routes; the figures are rough latencies
    /// of current x86-64 cores, confirmed by `cargo bench -p nh-lab --bench routes`.
    pub fn cost_estimate(&self, outputs: &[Node]) -> usize {
        let live = self.live(outputs);
        let live_set: HashSet<Node> = live.iter().copied().collect();
        let mut total = 0;
        for &n in &live {
            total += match &self.ops[n.index()] {
                Op::Div(..) | Op::Sqrt(_) => 4,
                Op::Powf(..) => 40,
                Op::Call(Fun::Cos, a) => {
                    if live_set.contains(
                        &self
                            .ix
                            .get(&Op::Call(Fun::Sin, *a))
                            .copied()
                            .unwrap_or(Node::from_index(u32::MAX as usize)),
                    ) {
                        5
                    } else {
                        15
                    }
                }
                Op::Call(Fun::Abs | Fun::Sign, _) => 2,
                Op::Call(..) | Op::Atan2(..) => 15,
                op => cost(op),
            };
        }
        total
    }

    fn live(&self, outputs: &[Node]) -> Vec<Node> {
        self.live_until(outputs, &HashMap::default())
    }

    /// The nodes `outputs` need, not looking behind the nodes in `stop`.
    pub(super) fn live_until(
        &self,
        outputs: &[Node],
        stop: &HashMap<Node, TokenStream>,
    ) -> Vec<Node> {
        // a dense mark per node: the graph's ids are consecutive
        let mut seen = vec![false; self.ops.len()];
        let mut stack: Vec<Node> = outputs.iter().map(|&o| self.resolved(o)).collect();
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n.index()], true) || stop.contains_key(&n) {
                continue;
            }
            stack.extend(self.children(n).into_iter().flatten());
        }
        (0..self.ops.len())
            .filter(|&i| seen[i])
            .map(Node::from_index)
            .collect()
    }

    /// The values among those `outputs` need that depend on parameters alone
    /// and are worth keeping (an operation, not a leaf or constant), maximal:
    /// each is used by a value that is not parameter-only, or is an output.
    pub fn hoistable(&self, outputs: &[Node]) -> Vec<Node> {
        let live = self.live_until(outputs, &HashMap::default());
        let mut param_only = vec![false; self.ops.len()];
        for &n in &live {
            param_only[n.index()] = match &self.ops[n.index()] {
                Op::Leaf(_) => self.param_leaves.contains(&n),
                Op::Const(_) | Op::Pi => true,
                _ => self
                    .children(n)
                    .iter()
                    .flatten()
                    .all(|c| param_only[c.index()]),
            };
        }
        let mut used_outside = vec![false; self.ops.len()];
        for &o in outputs {
            used_outside[self.resolved(o).index()] = true;
        }
        for &n in &live {
            if !param_only[n.index()] {
                for c in self.children(n).into_iter().flatten() {
                    used_outside[c.index()] = true;
                }
            }
        }
        live.into_iter()
            .filter(|&n| {
                param_only[n.index()] && used_outside[n.index()] && cost(&self.ops[n.index()]) > 0
            })
            .collect()
    }
}
