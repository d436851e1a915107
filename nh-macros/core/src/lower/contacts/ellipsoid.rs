//! An ellipsoid rolling on the plane z = 0 (`rolls(BODY, semi_axes: [a, b,
//! c])`): with D = diag(a, b, c) in body axes, R the orientation and
//! γ = Rᵀ e_z the vertical in body axes, the lowest point is where the
//! outward normal is −e_z: P − G = −R D² γ / s with s = √(γᵀ D² γ) (the
//! support function in the direction −e_z), and P_z = G_z − s.

use super::super::Lowerer;
use super::{Contact, Ground};
use crate::lower::values::{Rotation, Vec3, dot3, unit};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, Rational};
use crate::words::RollingField;

impl Lowerer<'_> {
    /// The contact of `rolls(BODY, semi_axes: [a, b, c][, centre: G])`.
    pub(super) fn ellipsoid_contact(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        axes: &Expr,
        ground: Option<&Ground>,
    ) -> Option<Contact> {
        let mut fine = true;
        for (f, x) in fields {
            if matches!(
                f,
                RollingField::Radius | RollingField::Axle | RollingField::Tube
            ) {
                self.cx.error(x.range(), format!("an ellipsoid is given by its `semi_axes` alone (its lowest point follows from them): remove `{f}`"));
                fine = false;
            }
        }
        let semi = self.semi_axes(axes);
        let (rot, centre) = self.rolling_body(def, fields, "the ellipsoid's centre")?;
        let (rot, semi) = (&*rot, semi?);
        if !fine {
            return None;
        }
        // the lowest point depends on the normal's direction alone
        let normal = ground.map_or(unit(2), |g| g.normals().1.0);
        let (offset, s) = self.ellipsoid_offset(rot, semi, normal);
        if let Some(g) = ground {
            let shape = format!("an ellipsoid of semi-axes {}", self.show3(semi));
            return Some(self.on_ground(def, &shape, rot, centre, offset, g));
        }
        let (contact, _) = self.contact_at(rot, centre, offset);
        let line = format!(
            "- `rolls({}, ..)`: an ellipsoid of semi-axes {} (body axes); its lowest point P = G − R D² γ / s with γ = Rᵀ e_z and s = `{}`; no slip: the x and y components of its material velocity vanish; its height `{}` = 0 is a holonomic constraint",
            def.body,
            self.show3(semi),
            self.e.display_capped(s, 160),
            self.e.display_capped(contact.point[2], 160),
        );
        self.description.push(line);
        Some(contact)
    }

    /// The semi-axes `[a, b, c]`: three lengths of the parameters.
    fn semi_axes(&mut self, x: &Expr) -> Option<Vec3> {
        let items = match x {
            Expr::Vector { items, .. } if items.len() == 3 => items,
            _ => {
                self.cx.error(x.range(), format!("give the ellipsoid's semi-axes along the body's x, y and z axes as `[a, b, c]`, not `{}`", super::super::short(x.to_source())));
                return None;
            }
        };
        let lengths: Vec<Option<ExprId>> = (items.iter())
            .map(|a| self.rolling_length(a, RollingField::SemiAxes))
            .collect();
        Some([lengths[0]?, lengths[1]?, lengths[2]?])
    }

    /// o = P − G = −R D² γ / s and s = √(γᵀ D² γ), γ = Rᵀ N the plane's
    /// normal in body axes (o_z = −s on the plane z = 0).
    fn ellipsoid_offset(&mut self, rot: &Rotation, semi: Vec3, normal: Vec3) -> (Vec3, ExprId) {
        let r = rot.matrix;
        let gamma: Vec3 = [0, 1, 2].map(|i| {
            let column = [r[0][i], r[1][i], r[2][i]];
            dot3(&mut self.e, column, normal)
        });
        // D² γ
        let scaled: Vec3 = [0, 1, 2].map(|i| {
            let a2 = self.e.mul(semi[i], semi[i]);
            self.e.mul(a2, gamma[i])
        });
        let s2 = dot3(&mut self.e, gamma, scaled);
        let s = self.e.pow(s2, Rational::new(1, 2).unwrap_or(Rational::ONE));
        let inv = self.e.pow(s, Rational::MINUS_ONE);
        let level = normal == unit(2);
        let offset = [0, 1, 2].map(|row| {
            if level && row == 2 {
                return self.e.neg(s);
            }
            let sum = dot3(&mut self.e, r[row], scaled);
            let o = self.e.mul(sum, inv);
            self.e.neg(o)
        });
        (offset, s)
    }
}
