//! A support that moves or tilts (`rolls(BODY, .., on: F[, origin: O])`):
//! the body rolls on the plane z = 0 of the frame F through O — a rotation
//! (a `let` of t, of the coordinates or constant: a turntable, a tilting
//! plate, an incline) or a body of the system (a platform it drives), O
//! by default the origin (the body's centre). With N = F e_z the plane's
//! normal, the contact point is the body's lowest point along −N, its
//! height (P − O)·N, and rolling means that the material velocities of the
//! two surfaces agree at P: v = Ġ + ω × (P − G) − (Ȯ + ω_F × (P − O)) has
//! no component along the plane.

use super::super::{Binding, Lowerer};
use super::Contact;
use crate::lower::values::{Mat3, Rotation, Vec3, add3, cross3, dot3, mat_vec, sub3, unit};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, ONE, ZERO};
use std::rc::Rc;

/// The plane a body rolls on, and how it moves.
pub(crate) struct Support {
    /// The unit normal N, world components.
    pub(crate) normal: Vec3,
    /// The plane's axes F e_x, F e_y; `None` when N is e_z identically
    /// (a support turning about the vertical: the rows along world x, y).
    tangents: Option<[Vec3; 2]>,
    /// The point O of the plane.
    pub(crate) origin: Vec3,
    /// F's matrix, `None` for the world's plane moved by `origin` alone.
    pub(crate) frame: Option<Mat3>,
    /// ω_F, world components.
    omega: Vec3,
    /// What the support is, for the docs.
    pub(crate) name: String,
}

impl Lowerer<'_> {
    /// The support of `on: F` and `origin: O` (either may be absent).
    pub(super) fn support(&mut self, on: Option<&Expr>, origin: Option<&Expr>) -> Option<Support> {
        let body = on.and_then(|x| match x {
            Expr::Name(id) => match self.scope.get(&id.to_string()) {
                Some(Binding::Body(_)) => Some(id.clone()),
                _ => None,
            },
            _ => None,
        });
        let (rot, default_origin, name): (Option<Rc<Rotation>>, Vec3, String) = match (on, body) {
            (Some(x), Some(id)) => {
                let b = self.body(&id)?;
                let Some((r, _)) = &b.rotation else {
                    self.cx.error(x.range(), format!("body `{id}` is a point mass: a support needs an `orientation` (its plane is the body's z = 0)"));
                    return None;
                };
                (Some(r.clone()), b.centre, format!("body `{id}`"))
            }
            (Some(x), None) => {
                let v = self.lower_value(x, 0)?;
                let r = self.rotation_of(v, x, "the support `on` (a rotation, whose plane z = 0 the body rolls on, or a body of the system)")?;
                (
                    Some(r),
                    [ZERO; 3],
                    format!("`{}`", super::super::short(x.to_source())),
                )
            }
            (None, _) => (None, [ZERO; 3], "the world".to_string()),
        };
        let origin = match origin {
            Some(x) => self.lower_position_vector(x, "the support's origin")?,
            None => default_origin,
        };
        let (normal, tangents, omega) = match &rot {
            Some(r) => {
                let n = mat_vec(&mut self.e, &r.matrix, unit(2));
                let level = n == [ZERO, ZERO, ONE];
                let t = [0, 1].map(|k| mat_vec(&mut self.e, &r.matrix, unit(k)));
                (n, (!level).then_some(t), self.angular_velocity(r, true))
            }
            None => (unit(2), None, [ZERO; 3]),
        };
        Some(Support {
            normal,
            tangents,
            frame: rot.as_ref().map(|r| r.matrix),
            origin,
            omega,
            name,
        })
    }

    /// The contact of a body turned by `rot`, centre G, lowest point
    /// P = G + `offset` (along −N), on the support `sp`.
    pub(super) fn on_support(
        &mut self,
        rot: &Rotation,
        centre: Vec3,
        offset: Vec3,
        sp: &Support,
    ) -> Contact {
        let (point, _, body) = self.material_velocity(rot, centre, offset);
        // the support's material velocity at P: Ȯ + ω_F × (P − O)
        let odot = sp.origin.map(|c| self.time_derivative(c));
        let arm = sub3(&mut self.e, point, sp.origin);
        let turn = cross3(&mut self.e, sp.omega, arm);
        let support = add3(&mut self.e, odot, turn);
        let slip = sub3(&mut self.e, body, support);
        let velocity = match &sp.tangents {
            None => [slip[0], slip[1]],
            Some(t) => t.map(|t| dot3(&mut self.e, slip, t)),
        };
        let h = dot3(&mut self.e, arm, sp.normal);
        let height = self.height_row(h);
        Contact::written(velocity, height, point, centre)
    }
}

impl Support {
    /// The components in the plane's axes (those of the no-slip rows) of
    /// a world vector d of the plane.
    pub(crate) fn plane_components(&self, e: &mut crate::sym::Engine, d: Vec3) -> [ExprId; 2] {
        match &self.tangents {
            Some(t) => t.map(|t| dot3(e, d, t)),
            None => [d[0], d[1]],
        }
    }
}

impl Lowerer<'_> {
    /// Whether the support's fields make a contact on other than the fixed
    /// plane z = 0.
    pub(super) fn moved(on: Option<&Expr>, origin: Option<&Expr>) -> bool {
        on.is_some() || origin.is_some()
    }

    /// The docs' line of a contact on a support.
    pub(super) fn describe_supported(
        &mut self,
        def: &RollingDef,
        shape: &str,
        c: &Contact,
        sp: &Support,
    ) {
        let height = match c.height {
            Some(h) => format!(
                "; its height above the plane `{}` = 0 is a holonomic constraint",
                self.e.display_capped(h, 240)
            ),
            None => String::new(),
        };
        let along = if sp.tangents.is_some() {
            "along the plane's axes"
        } else {
            "along x and y"
        };
        let line = format!(
            "- `rolls({}, ..)`: {shape} on the plane z = 0 of {} (normal {}); contact point P = {}; no slip: the velocity of the body's material point at P relative to the support's, `{}` and `{}` {along}, vanishes{height}",
            def.body,
            sp.name,
            self.show3(sp.normal),
            self.show3(c.point),
            self.e.display_capped(c.velocity[0], 240),
            self.e.display_capped(c.velocity[1], 240),
        );
        self.description.push(line);
    }
}
