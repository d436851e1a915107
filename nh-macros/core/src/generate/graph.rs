//! The graph a method's code is built on: its arguments, and the model's
//! symbols bound to them (coordinates, velocities, parameters, inputs, the
//! dependent velocities solved from the constraints).

use crate::algebra;
use crate::emit::Dag;
use crate::mechanics::Scene;
use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// Where the values of a function's arguments come from.
pub(crate) struct Args {
    pub(crate) coord: Vec<TokenStream>,
    pub(crate) rvel: Vec<TokenStream>,
    /// The dependent velocities as C ṙ, for graphs that need C anyway
    /// (the accelerations and what derives from them); else solved on
    /// their own, which is cheaper without C.
    pub(crate) columns: bool,
}

impl Args {
    /// The arguments `q` and `rdot` (`speeds`, in generalized speeds).
    pub(crate) fn vectors(m: &Scene<'_>) -> Args {
        let vel = velocity_arg(m);
        Args {
            coord: (0..m.n()).map(|i| quote!(q[#i])).collect(),
            rvel: (0..m.k()).map(|j| quote!(#vel[#j])).collect(),
            columns: false,
        }
    }

    /// The same arguments for a graph of the accelerations.
    pub(crate) fn moving(self) -> Args {
        Args {
            columns: true,
            ..self
        }
    }

    /// The state `x` = [q, ṙ] (or [q, u]).
    pub(crate) fn state(m: &Scene<'_>) -> Args {
        let (n, k) = (m.n(), m.k());
        Args {
            coord: (0..n).map(|i| quote!(x[#i])).collect(),
            rvel: (0..k)
                .map(|j| {
                    let ix = n + j;
                    quote!(x[#ix])
                })
                .collect(),
            columns: false,
        }
    }
}

/// The argument holding the state's velocity part: `rdot`, or `speeds`.
pub(crate) fn velocity_arg(m: &Scene<'_>) -> Ident {
    crate::api::velocity_argument(m.speeds.is_some())
}

/// A graph with every symbol of the model bound to its source.
pub(crate) fn bound_dag(m: &Scene<'_>, args: &Args) -> Dag {
    let mut d = Dag::new();
    for (i, c) in m.coordinates.iter().enumerate() {
        let l = d.leaf_named(
            args.coord[i].clone(),
            &format!("q_{}", syn::ext::IdentExt::unraw(&c.name)),
        );
        d.bind(c.position, l);
    }
    let mut rdot = Vec::with_capacity(m.k());
    for (j, &i) in m.independent().iter().enumerate() {
        let c = &m.coordinates[i];
        let l = d.leaf_named(
            args.rvel[j].clone(),
            &format!("dot_{}", syn::ext::IdentExt::unraw(&c.name)),
        );
        d.bind(c.velocity, l);
        rdot.push(l);
    }
    for p in &m.parameters {
        let name = &p.name;
        let l = d.leaf_param(
            quote!(self.#name),
            &format!("p_{}", syn::ext::IdentExt::unraw(name)),
        );
        d.bind(p.sym, l);
    }
    for (j, u) in m.inputs.iter().enumerate() {
        let l = d.leaf_named(
            quote!(u[#j]),
            &format!("u_{}", syn::ext::IdentExt::unraw(&u.name)),
        );
        d.bind(u.sym, l);
    }
    let t = d.leaf_named(quote!(t), "time");
    d.bind(m.time, t);
    let pi = d.pi();
    d.bind(m.pi, pi);
    if let Some(sp) = &m.speeds {
        bind_speeds(&mut d, m, sp, args);
    }
    // dependent velocities: computed from the constraints (5.3)
    if let Some(bt) = &m.block {
        let sdot = if args.columns {
            let columns = super::contacts::velocity_columns(&mut d, m, bt);
            (0..m.constraints.len())
                .map(|a| {
                    let pairs = columns.iter().zip(&rdot).map(|(c, &v)| (c[a], v));
                    algebra::dot(&mut d, pairs)
                })
                .collect()
        } else {
            super::contacts::dependent_velocities(&mut d, m, bt, &rdot)
        };
        for (c, v) in m.constraints.iter().zip(sdot) {
            let s = &m.coordinates[c.dependent];
            d.label(
                v,
                format!("dot({}): the block of velocity rows solved by LU", s.name),
            );
            let v = d.opaque(v);
            d.bind(s.velocity, v);
        }
        return d;
    }
    for c in &m.constraints {
        let s = &m.coordinates[c.dependent];
        let v = d.expr(m.engine, c.velocity);
        d.label(v, format!("dot({}): {}", s.name, c.kind.velocity_source()));
        // one node the rates along the motion can hold (Op::Opaque)
        let v = d.opaque(v);
        d.bind(s.velocity, v);
    }
    d
}

/// The speeds bound to the state's velocity part, and each q̇_i to its
/// kinematics (S u + σ)_i.
pub(crate) fn bind_speeds(d: &mut Dag, m: &Scene<'_>, sp: &crate::model::Speeds, args: &Args) {
    let mut leaves = Vec::with_capacity(sp.syms.len());
    for (j, (u, &sym)) in sp.names.iter().zip(&sp.syms).enumerate() {
        let name = format!("speed_{}", syn::ext::IdentExt::unraw(u));
        let l = d.leaf_named(args.rvel[j].clone(), &name);
        d.bind(sym, l);
        leaves.push(l);
    }
    for (c, &w) in m.coordinates.iter().zip(&sp.velocities) {
        let v = d.expr(m.engine, w);
        if !leaves.contains(&v) {
            d.label(
                v,
                format!("dot({}) from the kinematics q̇ = S u + σ", c.name),
            );
        }
        d.bind(c.velocity, v);
    }
}

#[cfg(test)]
mod tests {
    use super::{Args, bound_dag};
    use crate::mechanics::Scene;
    use crate::testing::{SLED, close, lowered, node_value, without_ydot};

    /// The sled's graph binds each coordinate, each independent velocity
    /// and the dependent velocity ẏ = tan θ ẋ, solved from the constraint.
    #[test]
    fn the_sleds_dependent_velocity_is_bound_to_its_solution() {
        let (model, mut engine) = lowered(SLED);
        let scene = Scene::new(&model, &mut engine);
        let d = bound_dag(&scene, &Args::vectors(&scene));
        let y = &model.coordinates[2];
        let ydot = d.bound(y.velocity).expect("ẏ bound");
        let at = without_ydot(); // the graph solves ẏ
        assert!(close(node_value(&model, &d, ydot, &at), 0.3f64.tan() * 0.7));
        assert!(
            model
                .coordinates
                .iter()
                .all(|c| d.bound(c.position).is_some())
        );
    }
}
