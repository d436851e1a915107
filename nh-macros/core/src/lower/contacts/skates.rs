//! A skate or knife edge (`skates(BODY, across: d[, at: p])`): the body's
//! material point p (body axes, from the centre of mass; by default the
//! centre of mass) has no velocity along the body-fixed direction d. With
//! R the orientation, C the centre and ω the angular velocity, the row is
//! (Ċ + ω × R p)·(R d) = 0: the Chaplygin sleigh's blade is
//! `skates(sled, across: [0, 1, 0], at: [a, 0, 0])`.

use super::super::Lowerer;
use crate::lower::values::{dot3, mat_vec};
use crate::parse::RollingDef;
use crate::sym::{ExprId, ZERO};
use crate::words::SkateField;

impl Lowerer<'_> {
    /// The row of a `skates(..)` line.
    pub(in crate::lower) fn skate_row(&mut self, def: &RollingDef) -> Option<ExprId> {
        let fields = self.fields::<SkateField>(&def.fields, "`skates`", &def.body, None)?;
        let get = |n: SkateField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let across = match get(SkateField::Across) {
            Some(x) => {
                let what = ("the direction `across`", "the body", "body axes");
                let zero = "give the body-fixed direction the point may not move along, e.g. `[0, 1, 0]` for a blade along the body's x axis";
                self.fixed_direction(x, what, zero)
            }
            None => {
                self.cx.error(def.range, format!("`skates({}, ..)` needs the body-fixed direction its point may not move along: `across: [0, 1, 0]` for a blade along the body's x axis", def.body));
                None
            }
        };
        let at = get(SkateField::At).map(|x| self.lower_position_vector(x, "the skate's point"));
        let b = self.body(&def.body)?;
        let across = across?;
        let at = match at {
            Some(p) => p?,
            None => [ZERO; 3],
        };
        let Some((rot, _)) = &b.rotation else {
            self.cx.error(def.range, format!("body `{}` is a point mass: a skate needs the body's `orientation` (its blade turns with it)", def.body));
            return None;
        };
        let offset = mat_vec(&mut self.e, &rot.matrix, at);
        let (_, _, v) = self.material_velocity(rot, b.centre, offset);
        let d = mat_vec(&mut self.e, &rot.matrix, across);
        let row = dot3(&mut self.e, v, d);
        let line = format!(
            "- `skates({}, ..)`: the body point {} (body axes) does not move along {} (body axes): `{}` = 0",
            def.body,
            self.show3(at),
            self.show3(across),
            self.e.display_capped(row, 240),
        );
        self.description.push(line);
        Some(row)
    }
}
