//! Shrinking a failing system: simplifications of its tree are tried one
//! at a time (an expression replaced by 0, by 1 or by one of its parts, a
//! rotation or vector product by one factor, a force, a constraint or an
//! output removed) and kept while the check still fails, until none is.
//! What is left is a small system to reason about and to keep as a
//! regression case.

use crate::check::{self, Finding};
use crate::model::{Constraint, Ex, LetValue, Rx, System, Vx};

/// The smallest system found from `sys` for which `fails` holds.
pub fn shrink(sys: &System, fails: &dyn Fn(&System) -> bool) -> System {
    let mut best = sys.clone();
    loop {
        let mut improved = false;
        let mut k = 0;
        while let Some(candidates) = variants(&best, k) {
            for c in candidates {
                if fails(&c) {
                    best = c;
                    improved = true;
                }
            }
            k += 1;
        }
        if !improved {
            return best;
        }
    }
}

/// Whether the check of `sys` (as the system of `seed`: its states) is a
/// disagreement.
pub fn disagrees(sys: &System, seed: u64) -> bool {
    match check::check_system(sys, seed).finding {
        Finding::Disagree(what) => !what.starts_with("the constraints' rows"),
        _ => false,
    }
}

/// The simplifications of site `k` of `sys`, or `None` past the last site.
fn variants(sys: &System, k: usize) -> Option<Vec<System>> {
    let structural = 3;
    match k {
        0 => Some(
            (0..sys.forces.len())
                .map(|i| {
                    let mut s = sys.clone();
                    s.forces.remove(i);
                    s
                })
                .collect(),
        ),
        1 => Some(
            (0..sys.constraints.len())
                .map(|i| {
                    let mut s = sys.clone();
                    s.constraints.remove(i);
                    s.dependent = None;
                    s
                })
                .collect(),
        ),
        2 => Some(
            (0..sys.outputs.len())
                .map(|i| {
                    let mut s = sys.clone();
                    s.outputs.remove(i);
                    s
                })
                .collect(),
        ),
        _ => {
            let site = k - structural;
            let (mut probe, mut count) = (sys.clone(), 0);
            if edit(&mut probe, site, &mut count, &mut |_| Vec::new()).is_some() {
                return None;
            }
            let mut out = Vec::new();
            for choice in 0..6 {
                let mut s = sys.clone();
                let mut count = 0;
                let mut taken = false;
                edit(&mut s, site, &mut count, &mut |node| {
                    let all = match node {
                        Node::Ex(e) => ex_choices(e),
                        Node::Vx(v) => vx_choices(v),
                        Node::Rx(r) => rx_choices(r),
                    };
                    match all.into_iter().nth(choice) {
                        Some(r) => {
                            taken = true;
                            vec![r]
                        }
                        None => Vec::new(),
                    }
                });
                if taken {
                    out.push(s);
                }
            }
            Some(out)
        }
    }
}

/// A node of the tree, for the choice of its replacements.
enum Node<'a> {
    Ex(&'a Ex),
    Vx(&'a Vx),
    Rx(&'a Rx),
}

/// A replacement of a node.
enum Repl {
    Ex(Ex),
    Vx(Vx),
    Rx(Rx),
}

fn ex_choices(e: &Ex) -> Vec<Repl> {
    let mut v = Vec::new();
    match e {
        Ex::Num(0, _) => return v,
        Ex::Num(..) => {}
        _ => v.push(Repl::Ex(Ex::Num(1, 1))),
    }
    v.push(Repl::Ex(Ex::Num(0, 1)));
    let parts: Vec<Ex> = match e {
        Ex::Add(x) | Ex::Mul(x) => x.clone(),
        Ex::Sub(a, b) | Ex::Div(a, b) | Ex::Atan2(a, b) => vec![(**a).clone(), (**b).clone()],
        Ex::Neg(a) | Ex::Pow(a, ..) | Ex::Call(_, a) => vec![(**a).clone()],
        _ => Vec::new(),
    };
    v.extend(parts.into_iter().map(Repl::Ex));
    v
}

fn vx_choices(x: &Vx) -> Vec<Repl> {
    match x {
        Vx::Add(a, b) | Vx::Sub(a, b) => vec![Repl::Vx((**a).clone()), Repl::Vx((**b).clone())],
        Vx::Scale(_, v) | Vx::Rot(_, v) => vec![Repl::Vx((**v).clone())],
        _ => Vec::new(),
    }
}

fn rx_choices(r: &Rx) -> Vec<Repl> {
    match r {
        Rx::Mul(a, b) => vec![Repl::Rx((**a).clone()), Repl::Rx((**b).clone())],
        Rx::Transpose(a) => vec![Repl::Rx((**a).clone())],
        _ => Vec::new(),
    }
}

type Chooser<'a> = dyn FnMut(Node<'_>) -> Vec<Repl> + 'a;

/// Visits the nodes of `sys` in a fixed order and applies `choose` to the
/// `site`-th; `count` ends as the number of nodes visited.
fn edit(sys: &mut System, site: usize, count: &mut usize, choose: &mut Chooser<'_>) -> Option<()> {
    for (_, v) in sys.lets.iter_mut() {
        match v {
            LetValue::Scalar(e) => walk_ex(e, site, count, choose)?,
            LetValue::Vector(x) => walk_vx(x, site, count, choose)?,
            LetValue::Rotation(r) => walk_rx(r, site, count, choose)?,
        }
    }
    for (_, b) in sys.bodies.iter_mut() {
        walk_ex(&mut b.mass, site, count, choose)?;
        walk_vx(&mut b.centre, site, count, choose)?;
        if let Some((r, i)) = &mut b.rotation {
            walk_rx(r, site, count, choose)?;
            for e in i.iter_mut().flatten() {
                walk_ex(e, site, count, choose)?;
            }
        }
    }
    walk_ex(&mut sys.lagrangian, site, count, choose)?;
    for (_, f) in sys.forces.iter_mut() {
        walk_ex(f, site, count, choose)?;
    }
    for c in sys.constraints.iter_mut() {
        match c {
            Constraint::Explicit { rhs, .. } => walk_ex(rhs, site, count, choose)?,
            Constraint::Implicit { lhs, rhs } | Constraint::Holonomic { lhs, rhs } => {
                walk_ex(lhs, site, count, choose)?;
                walk_ex(rhs, site, count, choose)?;
            }
            Constraint::Rolls { .. } => {}
        }
    }
    Some(())
}

/// `None` once the site is reached (and edited), to stop the walk.
fn visit(site: usize, count: &mut usize) -> bool {
    let here = *count == site;
    *count += 1;
    here
}

fn walk_ex(e: &mut Ex, site: usize, count: &mut usize, choose: &mut Chooser<'_>) -> Option<()> {
    if visit(site, count) {
        if let Some(Repl::Ex(r)) = choose(Node::Ex(e)).into_iter().next() {
            *e = r;
        }
        return None;
    }
    match e {
        Ex::Add(v) | Ex::Mul(v) => v
            .iter_mut()
            .try_for_each(|x| walk_ex(x, site, count, choose)),
        Ex::Sub(a, b) | Ex::Div(a, b) | Ex::Atan2(a, b) => {
            walk_ex(a, site, count, choose)?;
            walk_ex(b, site, count, choose)
        }
        Ex::Neg(a) | Ex::Pow(a, ..) | Ex::Call(_, a) => walk_ex(a, site, count, choose),
        Ex::Comp(v, _) => walk_vx(v, site, count, choose),
        _ => Some(()),
    }
}

fn walk_vx(x: &mut Vx, site: usize, count: &mut usize, choose: &mut Chooser<'_>) -> Option<()> {
    if visit(site, count) {
        if let Some(Repl::Vx(r)) = choose(Node::Vx(x)).into_iter().next() {
            *x = r;
        }
        return None;
    }
    match x {
        Vx::Lit(c) => c
            .iter_mut()
            .try_for_each(|e| walk_ex(e, site, count, choose)),
        Vx::Add(a, b) | Vx::Sub(a, b) => {
            walk_vx(a, site, count, choose)?;
            walk_vx(b, site, count, choose)
        }
        Vx::Scale(s, v) => {
            walk_ex(s, site, count, choose)?;
            walk_vx(v, site, count, choose)
        }
        Vx::Rot(r, v) => {
            walk_rx(r, site, count, choose)?;
            walk_vx(v, site, count, choose)
        }
        Vx::Let(_) => Some(()),
    }
}

fn walk_rx(r: &mut Rx, site: usize, count: &mut usize, choose: &mut Chooser<'_>) -> Option<()> {
    if visit(site, count) {
        if let Some(Repl::Rx(x)) = choose(Node::Rx(r)).into_iter().next() {
            *r = x;
        }
        return None;
    }
    match r {
        Rx::Elem(_, a) => walk_ex(a, site, count, choose),
        Rx::Mul(a, b) => {
            walk_rx(a, site, count, choose)?;
            walk_rx(b, site, count, choose)
        }
        Rx::Transpose(a) => walk_rx(a, site, count, choose),
        Rx::Let(_) => Some(()),
    }
}
