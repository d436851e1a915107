//! The checks of a system's consistency, in one place: that it has
//! coordinates and an independent one, that the outputs it asks for exist
//! and can be derived for it, and that the derivation is well posed (a
//! regular reduced mass matrix, constants `f64` can hold). Each stage calls
//! the checks of what it has just built, so every error is reported where
//! it was found, in the order of the input.

use crate::ctxt::{Ctxt, SpanRange};
use crate::emit::{Node, ZERO_NODE};
use crate::mechanics::Derivation;
use crate::mechanics::Scene;
use crate::model::{Output, Outputs};
use crate::names;
use crate::parse::SystemDef;
use crate::sym::{Engine, ZERO};
use crate::words::Block;
use proc_macro2::Span;

/// A system declares at least one coordinate.
pub fn coordinates_declared(def: &SystemDef, cx: &mut Ctxt) {
    match &def.coordinates {
        // a list that did not parse: already reported
        None if def.rejected.names_of(Block::Coordinates).is_some() => {}
        None => cx.error_at(
            def.name.span(),
            "missing `coordinates { .. }`: list the generalized coordinates, e.g. `coordinates { x, y, theta }`",
        ),
        Some((kw, list)) if list.is_empty() => cx.error_at(
            kw.span(),
            "`coordinates` is empty: a system needs at least one coordinate",
        ),
        Some(_) => {}
    }
}

/// The constraints leave at least one coordinate independent.
pub fn independent_left(
    def: &SystemDef,
    n: usize,
    independent: &[usize],
    constraints_span: Option<Span>,
    cx: &mut Ctxt,
) {
    if n > 0 && independent.is_empty() {
        cx.error_at(
            constraints_span.unwrap_or(def.name.span()),
            "every coordinate is constrained: no independent coordinate is left; a system needs at least one coordinate that is not on the left side of a constraint",
        );
    }
}

/// The outputs requested: each known, and listed once.
pub fn outputs(def: &SystemDef, cx: &mut Ctxt) -> Outputs {
    let mut outputs = Outputs::default();
    let Some((_, list)) = &def.outputs else {
        return outputs;
    };
    for o in list {
        let name = o.to_string();
        match o.word {
            Some(output) => {
                if outputs.set(output) {
                    cx.error_at(
                        o.ident.span(),
                        format!("output `{name}` is listed twice: remove one"),
                    );
                }
            }
            None => {
                let all = Output::ALL.map(Output::name);
                let hint = Output::suggest(&name);
                cx.error_at(
                    o.ident.span(),
                    format!(
                        "unknown output `{name}`{hint}; the outputs are {}",
                        all.map(|s| format!("`{s}`")).join(", ")
                    ),
                );
            }
        }
    }
    output_arguments(def, cx);
    outputs.with_implied()
}

/// The lists of outputs written with one, `sensitivities(m, k)`: only
/// `sensitivities` takes one, a non-empty list of declared parameters, each
/// once; and `sensitivities` is for systems without inputs.
fn output_arguments(def: &SystemDef, cx: &mut Ctxt) {
    for (output, list) in &def.output_arguments {
        match output.word {
            Some(Output::Sensitivities) => {}
            Some(_) => {
                cx.error_at(
                    output.ident.span(),
                    format!("output `{output}` takes no list of names: write `{output}` alone"),
                );
                continue;
            }
            None => continue,
        }
        if list.is_empty() {
            cx.error_at(
                output.ident.span(),
                "`sensitivities()` lists no parameter: name the parameters to differentiate by, `sensitivities(m, k)`, or write `sensitivities` for all of them",
            );
        }
        let params: Vec<String> = def
            .parameters
            .iter()
            .flat_map(|(_, names)| names.iter().map(|p| p.to_string()))
            .collect();
        let candidates: Vec<&str> = params.iter().map(String::as_str).collect();
        for (i, p) in list.iter().enumerate() {
            let name = p.to_string();
            if list[..i].contains(p) {
                cx.error_at(
                    p.span(),
                    format!(
                        "parameter `{name}` is listed twice in `sensitivities(..)`: remove one"
                    ),
                );
            } else if !candidates.contains(&name.as_str()) {
                let hint = names::suggest(&name, &candidates);
                let known = if candidates.is_empty() {
                    "the system declares none".to_string()
                } else {
                    format!(
                        "the parameters are {}",
                        candidates
                            .iter()
                            .map(|c| format!("`{c}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                cx.error_at(
                    p.span(),
                    format!("`{name}` in `sensitivities(..)` is not a parameter{hint}; {known}"),
                );
            }
        }
    }
}

/// The outputs requested fit the system's form: `reaction_forces` only in
/// generalized speeds; `multipliers`, `curvature`, `constraint_matrix` and
/// `routes` only with constraints (DESIGN §9).
pub fn outputs_for_form(def: &SystemDef, cx: &mut Ctxt) {
    let Some((_, list)) = &def.outputs else {
        return;
    };
    // a list of speeds that did not parse still makes a system in speeds
    let in_speeds = def.speeds.is_some() || def.rejected.names_of(Block::Speeds).is_some();
    for o in list {
        let why = match (o.word, in_speeds) {
            (Some(Output::Multipliers), true) => {
                "a system in generalized speeds has no Lagrange multipliers: the constraint forces are `reaction_forces` (E − Q, orthogonal to the columns of S)"
            }
            (Some(Output::Curvature), true) => {
                "a system in generalized speeds has no constraint connection to take the curvature of: its kinematics q̇ = S u + σ are given directly"
            }
            (Some(Output::ConstraintMatrix), true) => {
                "a system in generalized speeds has no constraint matrix A: its kinematic matrix S is the derivative of `velocities` with respect to the speeds"
            }
            (Some(Output::Routes), true) => {
                "a system in generalized speeds has one derivation, Maggi's equations (Sᵀ M S) u̇ = Sᵀ(Q − h − M(Ṡ u + σ̇)): there are no routes to compare"
            }
            (Some(Output::Momenta), true) => {
                "the momenta conjugate to cyclic coordinates (§5.5) are derived from the constrained Lagrangian of coordinates r, s and `constraints`; a system in generalized speeds has its kinematics instead"
            }
            (Some(Output::ContactPoints), _)
                if def
                    .rolling
                    .iter()
                    .all(|r| r.kind != crate::parse::ContactKind::Rolls)
                    && def.rejected.rolling_lines == 0 =>
            {
                "`contact_points` gives the points of the rolling contacts, and this system has none (`rolls(BODY, radius: .., ..);` in `constraints`)"
            }
            (Some(Output::Sensitivities), _)
                if def.inputs.as_ref().is_some_and(|(_, l)| !l.is_empty()) =>
            {
                "the sensitivities are derived for systems without inputs, x' = f(t, x; p); to differentiate a motion under a constant input, declare the input as a parameter instead"
            }
            (Some(Output::ReactionForces), false) => {
                "`reaction_forces` is for systems in generalized speeds (`speeds` and `kinematics`); with `constraints`, the constraint forces are the `multipliers`"
            }
            _ => continue,
        };
        cx.error_at(
            o.ident.span(),
            format!("output `{o}` is not available here: {why}; remove it from `outputs`"),
        );
    }
}

/// The derivation stayed within the engine's limits. Otherwise one error,
/// at the part of the input the engine was deriving when it first exceeded
/// one (the site a stage named, or the system's name), saying what was
/// being done, which measure was exceeded with its limit, and what to do.
/// False after an error.
pub fn within_limits(def: &SystemDef, engine: &Engine, cx: &mut Ctxt) -> bool {
    let Some(exceeded) = engine.exceeded() else {
        return true;
    };
    let (range, task) = match &exceeded.site {
        Some(site) => (site.range, site.task.as_str()),
        None => (SpanRange::single(def.name.span()), "deriving the system"),
    };
    let limit = exceeded.limit;
    let fix = if limit.is_swell() {
        "the expressions swell; use fewer levels of `let`s built on one another and of functions of functions, and fewer long sums multiplied together, or split the system"
    } else {
        "use a smaller exponent, or make the constant a parameter"
    };
    cx.error(
        range,
        format!(
            "{task} exceeded the engine's limit of {}: {fix}",
            exceeded.measure()
        ),
    );
    false
}

/// Every independent velocity carries kinetic energy, and the outputs
/// requested can be generated for this Lagrangian. False after an error.
pub fn derivation(def: &SystemDef, m: &Scene<'_>, dv: &Derivation, cx: &mut Ctxt) -> bool {
    let name = &def.name;
    let outputs_span = def
        .outputs
        .as_ref()
        .map(|o| o.0.span())
        .unwrap_or(name.span());
    // a coordinate whose velocity is absent from the constrained Lagrangian
    for (a, &i) in m.independent().iter().enumerate() {
        if dv.silent[a] {
            let c = &m.coordinates[i].name;
            cx.error_at(
                c.span(),
                format!(
                    "the velocity of `{c}` appears nowhere in the Lagrangian (after the constraints are substituted), so the reduced mass matrix is singular and its acceleration is undetermined; give `{c}` a kinetic energy term or make it dependent through a constraint"
                ),
            );
        }
    }
    // a speed that carries no kinetic energy
    if let Some(sp) = &m.speeds {
        for (a, u) in sp.names.iter().enumerate() {
            if dv.reduced.mass[a][a] == ZERO {
                cx.error_at(u.span(), format!("the speed `{u}` carries no kinetic energy (the Lagrangian does not depend on it once q̇ = S u + σ is substituted), so the mass matrix Sᵀ M S is singular and its rate is undetermined; give the velocities it moves a kinetic energy term or remove it"));
            }
        }
    }
    if let Some(en) = dv.energy
        && m.engine.depends_on(en, m.time)
        && !m.rheonomic()
    {
        let msg = if m.speeds.is_some() {
            "output `energy` needs a Lagrangian and kinematics that do not depend on time `t` explicitly (the method takes no `t`): remove `energy` from `outputs`"
        } else {
            "output `energy` needs a Lagrangian that does not depend on time `t` explicitly: remove `energy` from `outputs`"
        };
        cx.error_at(outputs_span, msg);
    }
    if m.outputs.contains(Output::MassMatrix) {
        let varying = dv.multiplier_route.mass.iter().flatten().any(|&e| {
            m.coordinates
                .iter()
                .any(|c| m.engine.depends_on(e, c.velocity))
                || m.engine.depends_on(e, m.time)
        }) || (m.speeds.is_some()
            && dv
                .reduced
                .mass
                .iter()
                .flatten()
                .any(|&e| m.engine.depends_on(e, m.time)));
        if varying {
            let msg = if m.speeds.is_some() {
                "output `mass_matrix` needs a Lagrangian quadratic in the velocities with time-independent coefficients and kinematics whose coefficients of the speeds do not depend on `t` (the method takes only `q`)"
            } else {
                "output `mass_matrix` needs a Lagrangian quadratic in the velocities with time-independent coefficients (the method takes only `q`)"
            };
            cx.error_at(outputs_span, msg);
        }
    }
    cx.is_empty()
}

/// The outputs requested are defined for the forms of the constraints:
/// `curvature` and `routes` need homogeneous, time-independent velocity
/// constraints, `energy` time-independent ones. False after an error.
pub fn forms(def: &SystemDef, m: &Scene<'_>, cx: &mut Ctxt) -> bool {
    let Some((kw, list)) = &def.outputs else {
        return true;
    };
    let time_dependent = m.rheonomic();
    for o in list {
        let name = o.to_string();
        let why = match o.word {
            Some(Output::Curvature | Output::Routes) if !m.homogeneous => format!("output `{name}` needs homogeneous, time-independent velocity constraints (the curvature route (5.12)–(5.21) has no terms for an affine or time-dependent part, nor for holonomic constraints); this system uses the multiplier route alone: remove `{name}` from `outputs`"),
            Some(Output::ConstraintMatrix) if time_dependent => "output `constraint_matrix` takes only `q`, but a constraint depends on time `t`: remove `constraint_matrix` from `outputs` (`dependent_velocities(t, q, rdot)` gives ṡ)".to_string(),
            Some(Output::Energy) if time_dependent => "output `energy` needs time-independent constraints: the constraint forces of a moving constraint do work, so E is not a constant of the motion; remove `energy` from `outputs`".to_string(),
            _ => continue,
        };
        cx.error_at(o.ident.span(), why);
    }
    let _ = kw;
    cx.is_empty()
}

/// The cyclic coordinates, when `outputs { momenta }` can be derived
/// (§5.5): the constraints are homogeneous, time-independent velocity rows
/// solved in closed form, and some independent coordinate is cyclic
/// ([`Scene::cyclic`]). `None` after an error, at the output's name, or
/// when `momenta` is not asked for.
pub fn momenta(def: &SystemDef, m: &mut Scene<'_>, cx: &mut Ctxt) -> Option<Vec<(usize, bool)>> {
    let o = def
        .outputs
        .iter()
        .flat_map(|(_, list)| list)
        .find(|o| o.word == Some(Output::Momenta))?;
    let why = if !m.model.homogeneous {
        "the rates (5.36) are for homogeneous, time-independent velocity constraints (no affine or time-dependent part, no holonomic rows); this system has other constraints".to_string()
    } else if m.block.is_some() {
        "the rates (5.36) need the constraints solved for the dependent velocities in closed form, and this system's are solved numerically (a block of implicit rows)".to_string()
    } else {
        let cyclic = m.cyclic();
        if !cyclic.is_empty() {
            return Some(cyclic);
        }
        not_cyclic(m)
    };
    cx.error_at(
        o.ident.span(),
        format!("output `momenta` is not available here: {why}; remove it from `outputs`"),
    );
    None
}

/// The declared symmetries are symmetries (§4.1 of DESIGN): the
/// Lagrangian, the forces and the constraint distribution invariant under
/// each group's flow, the constraints homogeneous, time-independent rows
/// solved in closed form, and some direction of the groups' generators
/// allowed by the constraints. False after an error, each at the name of
/// the symmetry (or of the block) it concerns.
pub fn symmetries(def: &SystemDef, m: &mut Scene<'_>, cx: &mut Ctxt) -> bool {
    let Some((kw, _)) = &def.symmetries else {
        return false;
    };
    if !momentum_equation_available(kw, m, cx) {
        return false;
    }
    let mut ok = true;
    for i in 0..m.model.symmetries.len() {
        let Some(broken) = m.broken(i) else { continue };
        let name = &m.model.symmetries[i].name;
        let what = match broken {
            crate::mechanics::Broken::Lagrangian => {
                "the Lagrangian: δL = ⟨∂L/∂q, ξ⟩ + ⟨∂L/∂q̇, ξ̇⟩ does not vanish".to_string()
            }
            crate::mechanics::Broken::Force(j) => format!(
                "the force on `{}` (its Lie derivative along the generator does not vanish)",
                m.model.coordinates[j].name
            ),
            crate::mechanics::Broken::Constraint(a) => format!(
                "the constraint `{}` (the Lie derivative of its row along the generator does not vanish on the constrained velocities)",
                m.model.constraints[a].source
            ),
        };
        cx.error_at(name.span(), format!("`{name}` is not a symmetry of this system: its flow changes {what}; check the generator's rates, or remove `{name}`"));
        ok = false;
    }
    ok
}

/// Whether the momentum equation can be derived for `m` (homogeneous,
/// time-independent rows solved in closed form, in coordinates), else an
/// error at the block's keyword `kw`.
fn momentum_equation_available(kw: &proc_macro2::Ident, m: &Scene<'_>, cx: &mut Ctxt) -> bool {
    let why = if m.model.speeds.is_some() {
        Some(format!(
            "a system in generalized speeds has its kinematics instead of constraints; declare {kw} of a system with `constraints`"
        ))
    } else if !m.model.homogeneous {
        Some(
            "the momentum equation is derived for homogeneous, time-independent velocity constraints (no affine or time-dependent part, no holonomic rows)".to_string(),
        )
    } else if m.block.is_some() {
        Some(
            "the momentum equation needs the constraints solved for the dependent velocities in closed form, and this system's are solved numerically (a block of implicit rows)".to_string(),
        )
    } else {
        None
    };
    if let Some(why) = why {
        cx.error_at(kw.span(), format!("`{kw}` is not available here: {why}"));
        return false;
    }
    true
}

/// The declared momenta's directions are motions the constraints allow
/// (§4.1 of DESIGN), under the symmetries' conditions on the constraints.
/// False after an error, each at the name of the momentum (or of the
/// block) it concerns.
pub fn declared_momenta(def: &SystemDef, m: &mut Scene<'_>, cx: &mut Ctxt) -> bool {
    let Some((kw, list)) = &def.momenta else {
        return false;
    };
    if !momentum_equation_available(kw, m, cx) {
        return false;
    }
    let mut ok = true;
    for (i, declared) in list.iter().enumerate() {
        let x = m.model.momentum_directions[i].generator.clone();
        let Some(a) = m.leaves_distribution(&x) else {
            continue;
        };
        let name = &declared.name;
        let row = &m.model.constraints[a].source;
        cx.error_at(name.span(), format!("`{name}` is not along a motion the constraints allow: its direction breaks the constraint `{row}`, so the constraint forces work along it and its momentum has no equation of its own; add to its direction the rates the constraint requires of the dependent coordinates"));
        ok = false;
    }
    ok
}

/// Why no independent coordinate of `m` is cyclic: where each appears.
fn not_cyclic(m: &mut Scene<'_>) -> String {
    let map = m.constrained_velocities();
    let model = m.model;
    let mut memo = rustc_hash::FxHashMap::default();
    let l = m.lagrangian();
    let lc = m.engine.subst(l, &map, &mut memo);
    let forces: Vec<_> = (model.coordinates.iter())
        .map(|c| (&c.name, m.engine.subst(c.force, &map, &mut memo)))
        .collect();
    let places: Vec<String> = model
        .independent()
        .iter()
        .map(|&i| {
            let c = &model.coordinates[i];
            let force = forces
                .iter()
                .find(|(_, f)| m.engine.depends_on(*f, c.position));
            let place = match force {
                _ if m.engine.depends_on(lc, c.position) => {
                    "the constrained Lagrangian".to_string()
                }
                Some((name, _)) => format!("the force on `{name}`"),
                None => "nothing".to_string(),
            };
            format!("`{}` appears in {place}", c.name)
        })
        .collect();
    format!(
        "no independent coordinate is cyclic (§5.5: the constrained Lagrangian Lc and the forces free of it): {}",
        places.join(", ")
    )
}

/// The reduced mass matrix is regular: no pivot of its factorisation, by
/// either route, is structurally zero. False after an error.
pub fn regular(def: &SystemDef, pivots: &[Node], cx: &mut Ctxt) -> bool {
    let structurally_singular = pivots.contains(&ZERO_NODE);
    if structurally_singular {
        cx.error_at(
            def.name.span(),
            "the reduced mass matrix is structurally singular: some combination of independent velocities carries no kinetic energy; check the Lagrangian and the choice of dependent coordinates",
        );
    }
    !structurally_singular
}

/// Every constant of the generated code is within the range of `f64`.
/// False after an error.
pub fn representable(def: &SystemDef, m: &Scene<'_>, cx: &mut Ctxt) -> bool {
    let Some(c) = crate::emit::take_unrepresentable() else {
        return true;
    };
    let msg = format!(
        "the generated code needs the constant {} (after exact simplification), which is beyond the range of `f64` (about ±1.8e308): rescale the units or the parameters",
        c.sci()
    );
    match m.huge_constant {
        Some(r) => cx.error(r, msg),
        None => cx.error_at(def.name.span(), msg),
    }
    false
}
