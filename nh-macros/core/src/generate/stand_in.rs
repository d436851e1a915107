//! The shape of the API read from the definition as written, before (or
//! without) lowering: the generated code starts from it, and the stand-in
//! emitted next to the errors of a rejected system is built from it alone.
//!
//! For the stand-in, the shape is the one the user meant, so that the code
//! that uses the system raises no follow-up errors: every constraint line
//! written removes an independent velocity even if it was rejected, a
//! parameter or coordinate list with a syntax error still declares its
//! names, a misspelled block (`constraint { .. }`) counts as the block it
//! was taken for, a misspelled output (`energie`) gives the method of the
//! output it was taken for, and `kinematics` without `speeds` uses the
//! undeclared names of its right sides as the speeds.

use crate::api::Shape;
use crate::parse::{Expr, SystemDef};
use crate::words::{Block, BodyField, Constant, Function, Output};
use proc_macro2::Ident;
use syn::ext::IdentExt;

/// The shape of the API for a definition, as far as it could be parsed
/// (used for the stand-in of a system with errors).
pub fn shape_of(def: &SystemDef) -> Shape<'_> {
    let coords = declared(def, &def.coordinates, Block::Coordinates);
    let dependent = dependent_coordinates(def, &coords, rows_meant(def));
    let independent = (0..coords.len())
        .filter(|i| !dependent.contains(i))
        .collect();
    // an unknown or malformed parameter list leaves no fields: fine for a stand-in
    Shape {
        attrs: &def.attrs,
        krate: &def.krate,
        vis: &def.vis,
        name: &def.name,
        params: declared(def, &def.parameters, Block::Parameters),
        coords: as_written(&coords),
        inputs: as_written(&declared(def, &def.inputs, Block::Inputs)),
        independent,
        dependent,
        outputs: outputs_meant(def),
        integrable: false,
        speeds: as_written(&speeds_meant(def)),
        dependent_doc: None,
        affine: false,
        rheonomic: constraints_mention_time(def),
        contacts: (def.rolling.iter())
            .filter(|r| r.kind == crate::parse::ContactKind::Rolls)
            .count()
            + def.rejected.rolling_lines,
        sensitivity_params: sensitivity_parameters(def),
        atlas: Vec::new(),
        // the verdicts need the derivation: none in a stand-in
        momenta: Vec::new(),
        symmetries: symmetry_names(def),
        symmetry_momenta: Vec::new(),
        momentum_names: (def.momenta.iter())
            .flat_map(|(_, list)| list.iter().map(|s| s.name.to_string()))
            .collect(),
        declared_momenta: Vec::new(),
    }
}

/// The shape of the stand-in for a definition with errors: [`shape_of`],
/// with `rows` constraint rows when lowering counted them (a contact's
/// height row and the rows a contact repeats are known only there).
pub fn stand_in_shape(def: &SystemDef, rows: Option<usize>) -> Shape<'_> {
    let mut shape = shape_of(def);
    if let Some(rows) = rows {
        let coords = declared(def, &def.coordinates, Block::Coordinates);
        shape.dependent = dependent_coordinates(def, &coords, rows);
        shape.independent = (0..coords.len())
            .filter(|i| !shape.dependent.contains(i))
            .collect();
    }
    shape
}

/// The names of the declared symmetries.
fn symmetry_names(def: &SystemDef) -> Vec<String> {
    (def.symmetries.iter())
        .flat_map(|(_, list)| list.iter().map(|s| s.name.to_string()))
        .collect()
}

/// The parameters `sensitivities` differentiates by: those listed,
/// `sensitivities(m, k)` (as written, known or not: the stand-in keeps the
/// dimensions meant), or every parameter.
fn sensitivity_parameters(def: &SystemDef) -> Vec<Ident> {
    let listed = def
        .output_arguments
        .iter()
        .find(|(o, _)| o.meant() == Some(Output::Sensitivities));
    match listed {
        Some((_, list)) => list.clone(),
        None => declared(def, &def.parameters, Block::Parameters),
    }
}

/// The names of a block: as parsed, or as meant if the block was rejected.
fn declared(def: &SystemDef, block: &Option<(Ident, Vec<Ident>)>, which: Block) -> Vec<Ident> {
    match block {
        Some((_, names)) => names.clone(),
        None => def
            .rejected
            .names_of(which)
            .map(<[Ident]>::to_vec)
            .unwrap_or_default(),
    }
}

fn as_written(names: &[Ident]) -> Vec<String> {
    names.iter().map(|c| c.unraw().to_string()).collect()
}

/// The number of constraint rows as written: one per constraint line
/// (rejected or not) and two per rolling contact (a contact's height that
/// is not identically zero adds one, and a row implied by the rows before
/// it is dropped, which only lowering can tell); with `dependent { .. }`,
/// which names one coordinate per implicit or holonomic row (every
/// contact's rows among them), the explicit lines and those names.
fn rows_meant(def: &SystemDef) -> usize {
    let lines = def.constraints.as_ref().map_or(0, |(_, l)| l.len());
    // a rejected `rolls(..)` line: two rows (one counted with the lines)
    // a `rolls(..)` line has two rows, a `skates(..)` or `slides(..)` one
    let contact_rows: usize = (def.rolling.iter())
        .map(|r| match r.kind {
            crate::parse::ContactKind::Rolls => 2,
            _ => 1,
        })
        .sum();
    let written = lines + def.rejected.constraint_lines + def.rejected.rolling_lines + contact_rows;
    match &def.dependent {
        Some((_, names)) if !def.rolling.is_empty() => {
            let explicit = def
                .constraints
                .iter()
                .flat_map(|(_, list)| list)
                .filter(|c| matches!(c.lhs.call1(Function::Dot), Some(Expr::Name(_))))
                .count();
            explicit + names.len()
        }
        _ => written,
    }
}

/// The indices of the `wanted` dependent coordinates, those the lines or
/// `dependent` name first (the last coordinates stand in for the others:
/// the rule's choice is not known without lowering, but the API's
/// dimensions depend only on their number).
fn dependent_coordinates(def: &SystemDef, coords: &[Ident], wanted: usize) -> Vec<usize> {
    let wanted = wanted.min(coords.len());
    let explicit = def
        .constraints
        .iter()
        .flat_map(|(_, list)| list)
        .filter_map(|c| match c.lhs.call1(Function::Dot) {
            Some(Expr::Name(id)) => Some(id),
            _ => None,
        });
    // the coordinates named for the implicit and holonomic constraints
    let named = def.dependent.iter().flat_map(|(_, names)| names);
    let mut dependent: Vec<usize> = Vec::new();
    for id in explicit.chain(named) {
        if let Some(i) = coords.iter().position(|x| x == id)
            && !dependent.contains(&i)
            && dependent.len() < wanted
        {
            dependent.push(i);
        }
    }
    for i in (0..coords.len()).rev() {
        if dependent.len() >= wanted {
            break;
        }
        if !dependent.contains(&i) {
            dependent.push(i);
        }
    }
    dependent.sort_unstable();
    dependent
}

/// The outputs asked for; a misspelled one counts as the output it is
/// closest to (its error says "did you mean ..?").
fn outputs_meant(def: &SystemDef) -> crate::model::Outputs {
    let mut outputs = crate::model::Outputs::default();
    let written = match &def.outputs {
        Some((_, list)) => Some(list),
        None => def.rejected.outputs.as_ref(),
    };
    for o in written.into_iter().flatten() {
        if let Some(meant) = o.meant() {
            outputs.set(meant);
        }
    }
    outputs.with_implied()
}

/// The speeds: as declared, or, for `kinematics` without `speeds`, the
/// names its right sides use that nothing declares, in order of first use.
fn speeds_meant(def: &SystemDef) -> Vec<Ident> {
    let declared_speeds = declared(def, &def.speeds, Block::Speeds);
    let Some((_, lines)) = def
        .kinematics
        .as_ref()
        .filter(|_| declared_speeds.is_empty())
    else {
        return declared_speeds;
    };
    let known: Vec<&Ident> = [&def.parameters, &def.coordinates, &def.inputs]
        .into_iter()
        .flat_map(|b| b.iter().flat_map(|(_, names)| names))
        .chain(def.lets.iter().map(|l| &l.name))
        .collect();
    let mut used = Vec::new();
    for line in lines {
        names_in(&line.rhs, &mut used);
    }
    let mut speeds: Vec<Ident> = Vec::new();
    for id in used {
        if !known.contains(&&id) && !is_constant(&id) && !speeds.contains(&id) {
            speeds.push(id);
        }
    }
    speeds
}

/// `t` and `pi`: names of the language that are not declared.
fn is_constant(id: &Ident) -> bool {
    Constant::of(id).is_some()
}

/// Whether a constraint depends on time explicitly, directly or through a
/// `let` (then `dependent_velocities` and `energy` take `t`): an equation,
/// or a rolling contact through its fields or its body's (a centre or an
/// orientation that moves with `t`).
fn constraints_mention_time(def: &SystemDef) -> bool {
    let mut timed: Vec<&Ident> = Vec::new();
    for l in &def.lets {
        if mentions(&l.value, |id| *id == Constant::Time || timed.contains(&id)) {
            timed.push(&l.name);
        }
    }
    let Some((_, lines)) = &def.constraints else {
        return false;
    };
    let is_timed = |id: &Ident| *id == Constant::Time || timed.contains(&id);
    let equations = lines
        .iter()
        .any(|c| [&c.lhs, &c.rhs].into_iter().any(|e| mentions(e, is_timed)));
    let contacts = def.rolling.iter().any(|r| {
        let body = def.bodies.iter().filter(|b| b.name == r.body);
        let placing = |f: &&crate::parse::Field| {
            matches!(
                BodyField::of(&f.name),
                Some(BodyField::Centre | BodyField::Orientation)
            )
        };
        r.fields
            .iter()
            .chain(body.flat_map(|b| b.fields.iter().filter(placing)))
            .any(|f| mentions(&f.value, is_timed))
    });
    equations || contacts
}

fn mentions(e: &Expr, is_timed: impl Fn(&Ident) -> bool) -> bool {
    let mut names = Vec::new();
    names_in(e, &mut names);
    names.iter().any(is_timed)
}

/// Every name an expression uses (function names excluded), in order.
fn names_in(e: &Expr, out: &mut Vec<Ident>) {
    match e {
        Expr::Num(..) => {}
        Expr::Name(id) => out.push(id.clone()),
        Expr::Call { args: items, .. } | Expr::Vector { items, .. } => {
            items.iter().for_each(|a| names_in(a, out))
        }
        Expr::Component { base, .. } | Expr::Neg(base, _) => names_in(base, out),
        Expr::Chain { first, rest, .. } => {
            names_in(first, out);
            rest.iter().for_each(|(_, _, x)| names_in(x, out));
        }
        Expr::Pow { base, exp, .. } => {
            names_in(base, out);
            names_in(exp, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::shape_of;
    use crate::model::Output;

    /// (parameters, coordinates, independent, speeds, inputs) of the
    /// stand-in for a definition, and whether it has errors.
    fn dims(src: &str) -> ((usize, usize, usize, usize, usize), bool) {
        let mut cx = crate::ctxt::Ctxt::new();
        let def = crate::parse::parse_system(src.parse().unwrap(), &mut cx).unwrap();
        let s = shape_of(&def);
        let d = (
            s.params.len(),
            s.coords.len(),
            s.independent.len(),
            s.speeds.len(),
            s.inputs.len(),
        );
        (d, !cx.is_empty())
    }

    #[test]
    fn rejected_lines_keep_the_dimensions_meant() {
        // a list missing a comma, a constraint without its right side
        let src = "struct S { parameters { m k } coordinates { x, y, z }
            lagrangian = m*dot(x)^2; constraints { dot(y) = ; dot(z) = x*dot(x); } }";
        assert_eq!(dims(src), ((2, 3, 1, 0, 0), true));
        // `parameters { m, 2 }` meant two parameters
        let src = "struct S { parameters { m, 2 } coordinates { x } lagrangian = m*dot(x)^2; }";
        assert_eq!(dims(src), ((2, 1, 1, 0, 0), true));
        // a misspelled block counts as the block it was taken for
        let src = "struct S { parameter { m } coordinates { x, y } inputs { F }
            lagrangian = dot(x)^2; constraint { dot(y) = x*dot(x); } }";
        assert_eq!(dims(src), ((1, 2, 1, 0, 1), true));
        // `dependent` names no more coordinates than there are constraints
        let src = "struct S { coordinates { x, theta, y } lagrangian = dot(x)^2;
            constraints { cos(theta)*dot(y) - sin(theta)*dot(x) = 0; } dependent { y, x } }";
        assert_eq!(dims(src), ((0, 3, 2, 0, 0), false));
    }

    #[test]
    fn kinematics_without_speeds_uses_the_undeclared_names() {
        let src = "struct S { parameters { b } coordinates { x, theta } lagrangian = dot(x)^2;
            let c = cos(theta);
            kinematics { dot(x) = v*c + b*t; dot(theta) = omega + pi*v; } }";
        assert_eq!(dims(src), ((1, 2, 2, 2, 0), false));
    }

    #[test]
    fn a_misspelled_output_gives_the_method_meant() {
        let src =
            "struct S { coordinates { x } lagrangian = dot(x)^2; outputs { energie, jacobian } }";
        let mut cx = crate::ctxt::Ctxt::new();
        let def = crate::parse::parse_system(src.parse().unwrap(), &mut cx).unwrap();
        let outputs = shape_of(&def).outputs;
        assert!(outputs.contains(Output::Energy) && outputs.contains(Output::Jacobian));
        assert!(!outputs.contains(Output::Multipliers));
    }

    #[test]
    fn time_in_a_constraint_or_its_lets_makes_it_rheonomic() {
        let rheonomic = |src: &str| {
            let mut cx = crate::ctxt::Ctxt::new();
            let def = crate::parse::parse_system(src.parse().unwrap(), &mut cx).unwrap();
            shape_of(&def).rheonomic
        };
        let head = "struct S { coordinates { x, y } lagrangian = dot(x)^2;";
        assert!(rheonomic(&format!(
            "{head} constraints {{ dot(y) = t*dot(x); }} }}"
        )));
        let via_let = "let w = 2*t; let a = w^2; constraints { dot(y) = a*dot(x); } }";
        assert!(rheonomic(&format!("{head} {via_let}")));
        assert!(!rheonomic(&format!(
            "{head} constraints {{ dot(y) = x*dot(x); }} }}"
        )));
    }
}
