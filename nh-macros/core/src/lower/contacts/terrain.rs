//! A body rolling on a fixed surface given as the graph of its height,
//! `rolls(BODY, .., on: z = h(x, y), contact: [u, v])`. The contact point
//! has no closed form on such a surface; the coordinates u, v the user
//! declares for it carry it instead (contact coordinates). With
//! N = (−h_x, −h_y, 1)/√(1 + h_x² + h_y²) the surface's upward normal at
//! (u, v), the body's point P = G + o(N) whose outward normal is −N (the
//! shape's lowest point along −N, as on a support) is on the surface at
//! (u, v): three holonomic rows, P_z − h(u, v) (the height), P_x − u and
//! P_y − v. No slip: the x and y components of the velocity of the body's
//! material point at P vanish; with the height row (whose rate says that
//! the material velocity has no component along N, N_z > 0 on a graph)
//! that is all of it.

use super::super::{Binding, Lowerer};
use super::Contact;
use crate::lower::values::{Rotation, Vec3};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, Rational};
use crate::words::RollingField;

/// A fixed surface z = h(x, y) and the coordinates of the contact point.
pub(crate) struct Terrain {
    /// h(u, v), the surface's height at the contact point.
    height: ExprId,
    /// u and v, the contact point's x and y.
    at: [ExprId; 2],
    /// Their symbols.
    symbols: [crate::sym::SymId; 2],
    /// Their names, for the docs.
    names: [String; 2],
    /// The unit normal N at (u, v), upwards.
    pub(crate) normal: Vec3,
    /// Its multiple M = (−h_x, −h_y, 1) and |M|² = 1 + h_x² + h_y².
    pub(crate) direction: (Vec3, ExprId),
}

impl Lowerer<'_> {
    /// The surface of `on: z = h(x, y)` (`lhs = rhs`) and the coordinates
    /// of `contact: [u, v]`.
    pub(super) fn terrain(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        lhs: &Expr,
        rhs: &Expr,
    ) -> Option<Terrain> {
        let get = |n: RollingField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let mut fine = true;
        if let Some(o) = get(RollingField::Origin) {
            self.cx.error(o.range(), "a surface `z = h(x, y)` is fixed in the world and takes no `origin`: remove it (for a surface that moves, roll on a plane `on: F`)");
            fine = false;
        }
        fine &= self.graph_side(lhs);
        let at = match get(RollingField::Contact) {
            Some(c) => self.contact_coordinates(c),
            None => {
                self.cx.error(def.range, format!("`rolls({}, .., on: z = h(x, y))` needs coordinates for the contact point, which has no closed form on such a surface: declare two coordinates for its x and y and name them, `contact: [u, v]`", def.body));
                None
            }
        };
        let at = at?;
        let plane = at.map(|i| self.coords[i].position);
        let height = self.surface_height(rhs, at.map(Binding::Coord), plane, false)?;
        fine.then(|| self.graph(height, at))
    }

    /// Whether the left side of `on: z = h(x, y)` is `z`; else an error
    /// there.
    pub(super) fn graph_side(&mut self, lhs: &Expr) -> bool {
        let z = matches!(lhs, Expr::Name(id) if id == "z");
        if !z {
            self.cx.error(lhs.range(), format!("a surface is written as the graph of its height over the plane, `on: z = h(x, y)`: the left side is `z`, not `{}`", super::super::short(lhs.to_source())));
        }
        z
    }

    /// The coordinates of `contact: [u, v]`: two different coordinates.
    fn contact_coordinates(&mut self, x: &Expr) -> Option<[usize; 2]> {
        let usage =
            "name the two coordinates that are the contact point's x and y, `contact: [u, v]`";
        let Expr::Vector { items, .. } = x else {
            self.cx.error(x.range(), usage);
            return None;
        };
        if items.len() != 2 {
            self.cx
                .error(x.range(), format!("{usage}, not {} names", items.len()));
            return None;
        }
        let mut at = [0; 2];
        for (k, item) in items.iter().enumerate() {
            let coordinate = match item {
                Expr::Name(id) => match self.scope.get(&id.to_string()) {
                    Some(Binding::Coord(i)) => Some(*i),
                    _ => None,
                },
                _ => None,
            };
            let Some(i) = coordinate else {
                self.cx.error(item.range(), format!("`{}` is not a coordinate: {usage}, each declared in `coordinates {{ .. }}`", super::super::short(item.to_source())));
                return None;
            };
            at[k] = i;
        }
        if at[0] == at[1] {
            self.cx.error(
                items[1].range(),
                "the contact point's x and y are two different coordinates",
            );
            return None;
        }
        Some(at)
    }

    /// h: the right side of `z = h(x, y)` with `x` and `y` bound as
    /// `bind` (whose symbols are `plane`); it may depend on them, the
    /// parameters and, if `timed`, the time only.
    pub(super) fn surface_height(
        &mut self,
        rhs: &Expr,
        bind: [Binding; 2],
        plane: [crate::sym::SymId; 2],
        timed: bool,
    ) -> Option<ExprId> {
        let h = self.lower_bound(rhs, &[("x", bind[0]), ("y", bind[1])])?;
        let moving = self.moving_symbol(h, &plane, timed).map(|(m, name)| {
            match name.as_deref() {
                Some("z") => format!("{m} (a surface that is not the graph of a height over the plane, such as a sphere or a cylinder, is `inside: ..` or `outside: ..`)"),
                _ => m,
            }
        });
        if let Some(m) = moving {
            let (fixed, and_t) = match timed {
                true => ("may move with time but not with the system", ", the time"),
                false => ("is fixed", ""),
            };
            self.cx.error(rhs.range(), format!("the surface `z = h(x, y)` {fixed}: its height may depend on x and y (the point's on it){and_t} and the parameters, but `{}` depends on {m}", super::super::short(rhs.to_source())));
            return None;
        }
        Some(h)
    }

    /// The surface z = h(u, v) with its normal at (u, v).
    fn graph(&mut self, height: ExprId, at: [usize; 2]) -> Terrain {
        let names = at.map(|i| self.coords[i].name.to_string());
        let at = at.map(|i| self.coords[i].position);
        let slope = at.map(|s| self.e.diff(height, s));
        let one = self.e.int(1);
        let mut n2 = one;
        for d in slope {
            let d2 = self.e.mul(d, d);
            n2 = self.e.add(n2, d2);
        }
        let inv = self
            .e
            .pow(n2, Rational::new(-1, 2).unwrap_or(Rational::ONE));
        let [mx, my] = slope.map(|d| self.e.neg(d));
        let [sx, sy] = [mx, my].map(|d| self.e.mul(d, inv));
        Terrain {
            height,
            at: at.map(|s| self.e.sym(s)),
            symbols: at,
            names,
            normal: [sx, sy, inv],
            direction: ([mx, my, one], n2),
        }
    }

    /// The contact of a body turned by `rot`, centre G, whose point
    /// P = G + `offset` (outward normal −N) touches the surface `tr`.
    pub(super) fn on_terrain(
        &mut self,
        rot: &Rotation,
        centre: Vec3,
        offset: Vec3,
        tr: &Terrain,
    ) -> Contact {
        let (point, _, v) = self.material_velocity(rot, centre, offset);
        let gap = self.e.sub(point[2], tr.height);
        let located = [0, 1].map(|k| self.e.sub(point[k], tr.at[k]));
        let rows = [located[0], located[1], gap];
        let height = self.height_row(gap);
        Contact {
            located: Some(located),
            chart: Some(self.fit(rows, tr)),
            ..Contact::written([v[0], v[1]], height, point, centre)
        }
    }

    /// Whether the contact coordinates follow the body: the triple product
    /// [∂F/∂u, ∂F/∂v, M] of the contact's holonomic rows F = P − S(u, v)
    /// (both columns tangent to the surface) with the normal M, 1 where a
    /// ball lies on a plane; it vanishes where the surface curves as much
    /// as the body (a ball in a hollow of its own radius), past which the
    /// body would touch the surface elsewhere, and joins the chart's
    /// regularity, so that a run ends `Singular` there.
    fn fit(&mut self, rows: Vec3, tr: &Terrain) -> ExprId {
        let columns = tr.symbols.map(|s| rows.map(|f| self.e.diff(f, s)));
        let across = crate::lower::values::cross3(&mut self.e, columns[0], columns[1]);
        crate::lower::values::dot3(&mut self.e, across, tr.direction.0)
    }

    /// The docs' line of a contact on a surface.
    pub(super) fn describe_terrain(
        &mut self,
        def: &RollingDef,
        shape: &str,
        c: &Contact,
        tr: &Terrain,
    ) {
        let [u, v] = &tr.names;
        let line = format!(
            "- `rolls({}, ..)`: {shape} on the surface z = `{}`, touching it at ({u}, {v}) (the coordinates of `contact`), where its normal is {}; contact point P = {}; the holonomic rows P_z = h({u}, {v}), P_x = {u}, P_y = {v}; no slip: the x and y components of the velocity of the body's material point at P, `{}` and `{}`, vanish",
            def.body,
            self.e.display_capped(tr.height, 160),
            self.show3(tr.normal),
            self.show3(c.point),
            self.e.display_capped(c.velocity[0], 240),
            self.e.display_capped(c.velocity[1], 240),
        );
        self.description.push(line);
    }
}
