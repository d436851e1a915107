//! A wheel on a rail (`rolls(.., rail: d)`): the contact point keeps to the
//! line through the plane's origin O along d (in the plane's axes: world
//! axes on the plane z = 0, F's on a support F), a holonomic row
//! (P − O)·(N × F d) = 0, and does not slip along it; the rail, not
//! friction, holds it sideways, so the sideways no-slip row is not
//! imposed. The rows are derived as written rows.

use super::super::Lowerer;
use super::Contact;
use super::support::Support;
use crate::lower::values::{cross3, dot3, mat_vec, sub3, unit};
use crate::parse::{Expr, RollingDef};
use crate::words::RollingField;

impl Lowerer<'_> {
    /// `contact` kept to the rail of direction `x`.
    pub(super) fn on_rail(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        contact: Contact,
        x: &Expr,
        support: Option<&Support>,
    ) -> Option<Contact> {
        if let Some((f, y)) =
            (fields.iter()).find(|(f, _)| matches!(f, RollingField::Inside | RollingField::Outside))
        {
            self.cx.error(y.range(), format!("`rail` with `{f}`: a rail is a line of a plane the body rolls on; remove `rail` or `{f}`"));
            return None;
        }
        let what = ("the rail", "the plane", "the plane's axes");
        let zero = "give the rail's direction in the plane, e.g. `[1, 0, 0]`";
        let d = self.fixed_direction(x, what, zero)?;
        let (normal, origin, d) = match support {
            Some(sp) => {
                let d = match &sp.frame {
                    Some(f) => mat_vec(&mut self.e, f, d),
                    None => d,
                };
                (sp.normal, sp.origin, d)
            }
            None => (unit(2), [crate::sym::ZERO; 3], d),
        };
        let along = match support {
            Some(sp) => sp.plane_components(&mut self.e, d),
            None => [d[0], d[1]],
        };
        let slip = {
            let a = self.e.mul(contact.velocity[0], along[0]);
            let b = self.e.mul(contact.velocity[1], along[1]);
            self.e.add(a, b)
        };
        let across = cross3(&mut self.e, normal, d);
        let arm = sub3(&mut self.e, contact.point, origin);
        let row = dot3(&mut self.e, arm, across);
        let Some(row) = self.height_row(row) else {
            self.cx.error(x.range(), format!("the contact of `{}` is on the rail in every configuration: the row it would add is zero; remove `rail`", def.body));
            return None;
        };
        self.description.push(format!(
            "- `rolls({}, ..)` on a rail: the contact point keeps to the line along {}: `{}` = 0 is a holonomic constraint",
            def.body,
            self.show3(d),
            self.e.display_capped(row, 160),
        ));
        Some(Contact {
            rail: Some([row, slip]),
            kinematics: None,
            ..contact
        })
    }
}
