//! A body point kept on a surface without friction, `slides(BODY[, at:
//! p][, on: ..])`: the point P = G + R p (body axes, from the centre of
//! mass; by default the centre of mass) stays on the plane z = 0, on the
//! surface `on: z = h(x, y)` (which may move with t: then the row is
//! rheonomic) or on the plane z = 0 of a support `on: F[, origin: O]`:
//! one holonomic row, P_z = 0, P_z − h(P_x, P_y) = 0 or (P − O)·N = 0.
//! Its multiplier is the normal force. A spinning top on a smooth table is
//! `slides(top, at: [0, 0, -l])`.

use super::super::{Binding, Lowerer};
use crate::lower::values::{Vec3, add3, dot3, mat_vec, sub3};
use crate::parse::{Expr, RollingDef};
use crate::sym::ExprId;
use crate::words::SlideField;
use rustc_hash::FxHashMap as HashMap;

impl Lowerer<'_> {
    /// The row of a `slides(..)` line.
    pub(in crate::lower) fn slide_row(&mut self, def: &RollingDef) -> Option<ExprId> {
        let fields = self.fields(&def.fields, "`slides`", &def.body, Some(SlideField::On))?;
        let get = |n: SlideField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let at = get(SlideField::At).map(|x| self.lower_position_vector(x, "the sliding point"));
        let b = self.body(&def.body)?;
        let point = match at {
            None => b.centre,
            Some(p) => {
                let p = p?;
                let Some((rot, _)) = &b.rotation else {
                    self.cx.error(def.range, format!("body `{}` is a point mass: the point `at` a body needs its `orientation` (it turns with the body); leave `at` out for the point mass itself", def.body));
                    return None;
                };
                let arm = mat_vec(&mut self.e, &rot.matrix, p);
                add3(&mut self.e, b.centre, arm)
            }
        };
        let surface = def.fields.iter().find_map(|f| {
            let on = SlideField::parse(&f.name.to_string()) == Some(SlideField::On);
            f.equals.as_ref().filter(|_| on).map(|rhs| (&f.value, rhs))
        });
        let (row, on) = match surface {
            Some((lhs, rhs)) => {
                if let Some(o) = get(SlideField::Origin) {
                    self.cx.error(o.range(), "a surface `z = h(x, y)` takes no `origin`: remove it (write a surface that moves with `t` in h)");
                    return None;
                }
                let row = self.on_graph(point, lhs, rhs)?;
                (
                    row,
                    format!("the surface z = `{}`", super::super::short(rhs.to_source())),
                )
            }
            None => self.on_plane(point, get(SlideField::On), get(SlideField::Origin))?,
        };
        let line = format!(
            "- `slides({}, ..)`: the point {} stays on {on}: `{}` = 0",
            def.body,
            self.show3(point),
            self.e.display_capped(row, 240),
        );
        self.description.push(line);
        Some(row)
    }

    /// P_z − h(P_x, P_y) for `z = h(x, y)` (`lhs = rhs`).
    fn on_graph(&mut self, point: Vec3, lhs: &Expr, rhs: &Expr) -> Option<ExprId> {
        let side = self.graph_side(lhs);
        let plane = ["x", "y"].map(|n| self.e.symbol(&format!("__nh_surface_{n}")));
        let h = self.surface_height(rhs, plane.map(Binding::Bound), plane, true);
        let h = h.filter(|_| side)?;
        let mut map = HashMap::default();
        map.insert(plane[0], point[0]);
        map.insert(plane[1], point[1]);
        let h = self.e.subst(h, &map, &mut Default::default());
        Some(self.e.sub(point[2], h))
    }

    /// (P − O)·N on the plane z = 0 of a support, or P_z on the world's.
    fn on_plane(
        &mut self,
        point: Vec3,
        on: Option<&Expr>,
        origin: Option<&Expr>,
    ) -> Option<(ExprId, String)> {
        if !Self::moved(on, origin) {
            return Some((point[2], "the plane z = 0".to_string()));
        }
        let sp = self.support(on, origin)?;
        let arm = sub3(&mut self.e, point, sp.origin);
        let row = dot3(&mut self.e, arm, sp.normal);
        Some((row, format!("the plane z = 0 of {}", sp.name)))
    }
}
