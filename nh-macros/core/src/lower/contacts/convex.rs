//! A strictly convex body given by its support function,
//! `rolls(BODY, support_function: h(x, y, z)[, centre: G])`: h(d) =
//! max over the body's points p of p·d, in body axes from G, for any
//! direction d = (x, y, z). It is positively homogeneous of degree 1, and
//! the body's point farthest along d is ∇h(d) (a closed form wherever h is
//! smooth). The body touches a ground of normal N at its point farthest
//! along −N: P − G = R ∇h(γ), γ = −Rᵀ N. The ellipsoid's h is
//! √(a²x² + b²y² + c²z²); a body rounded by ρ adds ρ √(x² + y² + z²)
//! (a Minkowski sum), an egg or a cam has its own.

use super::super::{Binding, Lowerer};
use super::{Contact, Ground};
use crate::lower::values::{Rotation, Vec3, mat_vec, unit};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, SymId};
use crate::words::RollingField;
use rustc_hash::FxHashMap as HashMap;

/// A support function over the direction symbols d: h(d) and ∇h(d).
struct Support {
    direction: [SymId; 3],
    value: ExprId,
    gradient: Vec3,
}

/// The directions at which the support function is checked to be convex.
const CONVEXITY_SAMPLES: usize = 24;

impl Lowerer<'_> {
    /// The contact of `rolls(BODY, support_function: h[, centre: G])`.
    pub(super) fn convex_contact(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        x: &Expr,
        ground: Option<&Ground>,
    ) -> Option<Contact> {
        let mut fine = true;
        for (f, y) in fields {
            let why = match f {
                RollingField::Radius
                | RollingField::Axle
                | RollingField::Tube
                | RollingField::SemiAxes => {
                    "needs no other shape (its contact point follows from it)"
                }
                RollingField::Inside | RollingField::Outside => {
                    "rolls on a plane, a support or a surface `on: z = h(x, y)`, not inside or outside a sphere or cylinder (only a ball does)"
                }
                _ => continue,
            };
            self.cx.error(
                y.range(),
                format!("a body given by its `support_function` {why}: remove `{f}`"),
            );
            fine = false;
        }
        let gradient = self.support_gradient(x);
        let (rot, centre) = self.rolling_body(def, fields, "the body's centre")?;
        let (rot, gradient) = (&*rot, gradient?);
        if !fine {
            return None;
        }
        // the point farthest along −N lies where the body's outward
        // normal is −N: ∇h at γ = −Rᵀ N (∇h is of degree 0, so any
        // positive multiple of N does)
        let normal = ground.map_or(unit(2), |g| g.normals().1.0);
        let offset = self.farthest_point(rot, &gradient, normal);
        let shape = format!(
            "a convex body of support function `{}`",
            super::super::short(x.to_source())
        );
        if let Some(g) = ground {
            return Some(self.on_ground(def, &shape, rot, centre, offset, g));
        }
        let (contact, _) = self.contact_at(rot, centre, offset);
        let line = format!(
            "- `rolls({}, ..)`: {shape} (body axes); its lowest point P = G + R ∇h(−Rᵀ e_z) = {}; no slip: the x and y components of its material velocity vanish; its height `{}` = 0 is a holonomic constraint",
            def.body,
            self.show3(contact.point),
            self.e.display_capped(contact.point[2], 160),
        );
        self.description.push(line);
        Some(contact)
    }

    /// h and ∇h of the support function `x` over the direction symbols, after
    /// the checks that h depends on the direction and the parameters
    /// only, is positively homogeneous of degree 1 and strictly convex.
    fn support_gradient(&mut self, x: &Expr) -> Option<Support> {
        let names = ["x", "y", "z"];
        let d = names.map(|n| self.e.symbol(&format!("__nh_direction_{n}")));
        let bound = [0, 1, 2].map(|i| (names[i], Binding::Bound(d[i])));
        let h = self.lower_bound(x, &bound)?;
        let src = super::super::short(x.to_source());
        if let Some((m, _)) = self.moving_symbol(h, &d, false) {
            self.cx.error(x.range(), format!("a support function is fixed in the body: it may depend on the direction `x`, `y`, `z` (body axes) and the parameters only, but `{src}` depends on {m}"));
            return None;
        }
        let gradient = d.map(|s| self.e.diff(h, s));
        if !self.homogeneous(h, d) {
            self.cx.error(x.range(), format!("a support function is positively homogeneous of degree 1, h(λ d) = λ h(d) for λ > 0, and `{src}` is not: write it for every direction, not only unit ones (an ellipsoid's is `sqrt(a^2*x^2 + b^2*y^2 + c^2*z^2)`)"));
            return None;
        }
        if let Some(at) = self.not_convex(gradient, d) {
            self.cx.error(x.range(), format!("`{src}` is not the support function of a strictly convex body: across the direction ({:.3}, {:.3}, {:.3}) (with the parameters between 0.3 and 1.4) its curvature is not positive, so the body has a flat, an edge or a dent there and no single point touches a plane; give a strictly convex body (a flat face or edge is not modelled)", at[0], at[1], at[2]));
            return None;
        }
        Some(Support {
            direction: d,
            value: h,
            gradient,
        })
    }

    /// Whether h(2d) − 2h(d) vanishes at random points.
    fn homogeneous(&mut self, h: ExprId, d: [SymId; 3]) -> bool {
        let two = self.e.int(2);
        let mut map = HashMap::default();
        for s in d {
            let x = self.e.sym(s);
            map.insert(s, self.e.mul(two, x));
        }
        let scaled = self.e.subst(h, &map, &mut Default::default());
        let twice = self.e.mul(two, h);
        let gap = self.e.sub(scaled, twice);
        crate::sym::random_points::vanish_at_random_points(&self.e, self.pi_sym, &[gap])
    }

    /// A direction (of random ones, the parameters random in [0.3, 1.4))
    /// across which h's Hessian is not positive definite, if any.
    fn not_convex(&mut self, gradient: Vec3, d: [SymId; 3]) -> Option<[f64; 3]> {
        let hessian: [Vec3; 3] = gradient.map(|g| d.map(|s| self.e.diff(g, s)));
        let mut rng = crate::sym::Rng::new(0x1357_9BDF_2468_ACE1);
        for _ in 0..CONVEXITY_SAMPLES {
            let mut vals = rng.point(self.e.num_symbols(), self.pi_sym);
            let dir = [0; 3].map(|_| 2.0 * rng.next_f64() - 1.0);
            for (s, v) in d.iter().zip(dir) {
                vals[s.index()] = crate::sym::dd::Dd::from_f64(v);
            }
            let h: [[f64; 3]; 3] = hessian.map(|row| row.map(|x| self.e.eval(x, &vals).to_f64()));
            if !curved_across(&h, dir) {
                return Some(dir);
            }
        }
        None
    }

    /// R ∇h(−Rᵀ N): the body's point farthest along −N, from G.
    fn farthest_point(&mut self, rot: &Rotation, support: &Support, normal: Vec3) -> Vec3 {
        let d = support.direction;
        let r = rot.matrix;
        let mut map = HashMap::default();
        for (i, s) in d.iter().enumerate() {
            let column = [r[0][i], r[1][i], r[2][i]];
            let g = crate::lower::values::dot3(&mut self.e, column, normal);
            map.insert(*s, self.e.neg(g));
        }
        let mut cache = Default::default();
        let body = (support.gradient).map(|g| self.e.subst(g, &map, &mut cache));
        let mut offset = mat_vec(&mut self.e, &r, body);
        if normal == unit(2) {
            // o·N = ∇h(γ)·(−γ) = −h(γ) (Euler's theorem, h of degree 1):
            // the height's shorter form, as an ellipsoid's −s
            let h = self.e.subst(support.value, &map, &mut cache);
            offset[2] = self.e.neg(h);
        }
        offset
    }
}

/// Whether the Hessian `h` is positive definite on the plane across `d`
/// (to 1e-9 of its size): the 2 × 2 form on two unit tangents.
fn curved_across(h: &[[f64; 3]; 3], d: [f64; 3]) -> bool {
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    // the axis least along d
    let k = (0..3)
        .min_by(|&i, &j| d[i].abs().total_cmp(&d[j].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let t1 = cross(d, e);
    let t1 = t1.map(|c| c / norm(t1));
    let t2 = cross(d, t1);
    let t2 = t2.map(|c| c / norm(t2));
    let form = |a: [f64; 3], b: [f64; 3]| {
        (0..3)
            .map(|i| (0..3).map(|j| a[i] * h[i][j] * b[j]).sum::<f64>())
            .sum::<f64>()
    };
    let (a, b, c) = (form(t1, t1), form(t1, t2), form(t2, t2));
    let size = h.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    let tol = 1e-9 * size;
    a.is_finite() && c.is_finite() && a > tol && c > tol && a * c - b * b > tol * tol
}
