//! A ball rolling on a fixed sphere or cylinder, inside or outside
//! (`rolls(BALL, radius: r, inside: sphere(R0[, O]))`, `outside:
//! cylinder(R0, axis[, O])`). With d the part of G − O normal to the
//! surface (G − O for a sphere; its component across the axis for a
//! cylinder) and ρ = |d|, the surface's normal towards the ball is
//! N = d/ρ outside and −d/ρ inside, the contact point P = G − r N, and the
//! ball's centre keeps its distance from the surface: ρ = R0 + r outside,
//! ρ = R0 − r inside (the height row). The no-slip rows are two tangent
//! components of the velocity of the ball's material point at P: along
//! the axis and around it for a cylinder; the horizontal ones for a sphere,
//! which with the height row say all of no slip except where the contact
//! is on the sphere's equator (N_z = 0): N_z joins the chart's regularity,
//! so a run that gets there ends `Singular`.

use super::super::Lowerer;
use super::Contact;
use crate::lower::values::{Rotation, Vec3, cross3, dot3, scale3, sub3};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, Rational, ZERO};
use crate::words::RollingField;

/// A fixed surface of revolution a ball rolls on.
pub(crate) struct Surface {
    /// Inside (a bowl, a pipe) or outside (a dome, a log).
    inside: bool,
    /// Its radius R0.
    radius: ExprId,
    /// Its centre, or a point of its axis.
    centre: Vec3,
    /// A cylinder's unit axis; `None` for a sphere.
    axis: Option<Vec3>,
}

impl Lowerer<'_> {
    /// `sphere(R0[, O])` or `cylinder(R0, axis[, O])` of an `inside` or
    /// `outside` field.
    pub(super) fn surface(&mut self, which: RollingField, x: &Expr) -> Option<Surface> {
        let inside = which == RollingField::Inside;
        let usage = "`sphere(R0)` or `sphere(R0, O)` (its radius and centre), or `cylinder(R0, axis)` or `cylinder(R0, axis, O)` (its radius, the direction of its axis and a point on it)";
        let Expr::Call { func, args, .. } = x else {
            self.cx.error(
                x.range(),
                format!("`{which}` takes the surface a ball rolls on: {usage}"),
            );
            return None;
        };
        let sphere = match (func.to_string().as_str(), args.len()) {
            ("sphere", 1..=2) => true,
            ("cylinder", 2..=3) => false,
            _ => {
                self.cx.error(
                    x.range(),
                    format!("`{which}` takes the surface a ball rolls on: {usage}"),
                );
                return None;
            }
        };
        let radius = self.rolling_length(&args[0], RollingField::Radius);
        let axis = (!sphere).then(|| {
            let what = ("the cylinder's axis", "the world", "world axes");
            let zero = "give the direction of the cylinder's axis, e.g. `[1, 0, 0]`";
            self.fixed_direction(&args[1], what, zero)
        });
        let centre = match args.get(if sphere { 1 } else { 2 }) {
            Some(o) => self.lower_position_vector(o, "the surface's centre"),
            None => Some([ZERO; 3]),
        };
        let axis = match axis {
            Some(a) => Some(a?),
            None => None,
        };
        Some(Surface {
            inside,
            radius: radius?,
            centre: centre?,
            axis,
        })
    }

    /// The contact of a ball of radius r, centre G, on `sf`.
    pub(super) fn ball_on_surface(
        &mut self,
        def: &RollingDef,
        rot: &Rotation,
        centre: Vec3,
        r: ExprId,
        sf: &Surface,
    ) -> Contact {
        let mut d = sub3(&mut self.e, centre, sf.centre);
        if let Some(a) = sf.axis {
            let along = dot3(&mut self.e, d, a);
            let part = scale3(&mut self.e, along, a);
            d = sub3(&mut self.e, d, part);
        }
        let rho2 = dot3(&mut self.e, d, d);
        let rho = self
            .e
            .pow(rho2, Rational::new(1, 2).unwrap_or(Rational::ONE));
        let inv = self.e.pow(rho, Rational::MINUS_ONE);
        // −r N = ∓ r d/ρ
        let k = if sf.inside {
            self.e.mul(r, inv)
        } else {
            let k = self.e.mul(r, inv);
            self.e.neg(k)
        };
        let offset = scale3(&mut self.e, k, d);
        let (point, _, v) = self.material_velocity(rot, centre, offset);
        let (velocity, chart) = match sf.axis {
            Some(a) => {
                let around = cross3(&mut self.e, a, d);
                (
                    [dot3(&mut self.e, v, a), dot3(&mut self.e, v, around)],
                    None,
                )
            }
            None => {
                // N_z, positive where the ball is on the side it starts on
                let nz = self.e.mul(d[2], inv);
                let nz = if sf.inside { self.e.neg(nz) } else { nz };
                ([v[0], v[1]], Some(nz))
            }
        };
        let gap = if sf.inside {
            let keep = self.e.sub(sf.radius, r);
            self.e.sub(keep, rho)
        } else {
            let keep = self.e.add(sf.radius, r);
            self.e.sub(rho, keep)
        };
        let height = self.height_row(gap);
        let shape = match (sf.axis.is_some(), sf.inside) {
            (false, true) => "inside a sphere",
            (false, false) => "outside a sphere",
            (true, true) => "inside a cylinder",
            (true, false) => "outside a cylinder",
        };
        let line = format!(
            "- `rolls({}, ..)`: a ball {shape} of radius `{}`; contact point P = {}; no slip: {} of the velocity of its material point at P vanish; its distance from the surface `{}` = 0 is a holonomic constraint",
            def.body,
            self.e.display_capped(sf.radius, 60),
            self.show3(point),
            if sf.axis.is_some() {
                "the components along the axis and around it"
            } else {
                "the x and y components"
            },
            self.e.display_capped(gap, 160),
        );
        self.description.push(line);
        Contact {
            chart,
            ..Contact::written(velocity, height, point, centre)
        }
    }
}
