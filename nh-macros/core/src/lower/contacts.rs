//! Rolling contacts (DESIGN §10): the contact point of a `rolls(..)` line's
//! body on the plane z = 0, its material velocity (the no-slip rows) and
//! its height (a holonomic row where it does not vanish identically), with
//! the checks of the line's fields.

mod convex;
mod ellipsoid;
mod rail;
mod skates;
mod slides;
mod support;
mod surfaces;
mod terrain;

use super::values::{Rotation, Vec3, add3, cross3, dot3, mat_vec, scale3, sub3, unit};
use super::{Binding, Lowerer};
use crate::parse::{Expr, RollingDef};
use crate::sym::{ExprId, ONE, Rational, ZERO};
use crate::words::{BodyField, RollingField};

/// What a `rolls(..)` line gives: its velocity rows and its contact.
pub(crate) struct Contact {
    /// The no-slip rows: the x and y components of the contact point's
    /// material velocity.
    pub(crate) velocity: [ExprId; 2],
    /// The contact point's height, if not identically zero (a holonomic
    /// constraint).
    pub(crate) height: Option<ExprId>,
    /// The contact point, world components.
    pub(crate) point: Vec3,
    /// The body's geometric centre G, world components.
    pub(crate) centre: Vec3,
    /// For a contact kept to a rail: the rail's row (holonomic) and the
    /// velocity row along the rail, which replace the two no-slip rows.
    pub(crate) rail: Option<[ExprId; 2]>,
    /// On a surface z = h(x, y): the rows P_x − u and P_y − v that make the
    /// coordinates of `contact: [u, v]` the contact point's x and y
    /// (holonomic).
    pub(crate) located: Option<[ExprId; 2]>,
    /// |e_z × n| of a wheel (zero when it lies flat), for the chart check.
    pub(crate) chart: Option<ExprId>,
    /// Its kinematics, for the rows' derivatives in closed form (a round
    /// body's); `None` for a body whose rows are derived as written rows.
    pub(crate) kinematics: Option<crate::model::ContactKinematics>,
}

impl Contact {
    /// A contact whose rows are derived as written rows: no rail, no chart
    /// factor, no closed-form kinematics.
    pub(super) fn written(
        velocity: [ExprId; 2],
        height: Option<ExprId>,
        point: Vec3,
        centre: Vec3,
    ) -> Contact {
        Contact {
            velocity,
            height,
            point,
            centre,
            rail: None,
            located: None,
            chart: None,
            kinematics: None,
        }
    }
}

/// What a body rolls on other than the fixed plane z = 0.
pub(crate) enum Ground {
    /// A plane that tilts or moves, `on: F`, `origin: O`.
    Support(support::Support),
    /// A fixed surface `on: z = h(x, y)`.
    Terrain(terrain::Terrain),
}

impl Ground {
    /// The unit normal N at the contact, towards the body, and a positive
    /// multiple M of it with |M|², for a shape whose contact depends on
    /// N's direction alone (see [`Lowerer::round_offset`]).
    fn normals(&self) -> (Vec3, (Vec3, ExprId)) {
        match self {
            Ground::Support(sp) => (sp.normal, (sp.normal, ONE)),
            Ground::Terrain(tr) => (tr.normal, tr.direction),
        }
    }
}

impl Lowerer<'_> {
    /// The contact of a `rolls(..)` line: the lowest point of a round body
    /// on the plane z = 0 and its material velocity.
    pub(super) fn rolling_contact(&mut self, def: &RollingDef) -> Option<Contact> {
        let fields = self.fields(&def.fields, "`rolls`", &def.body, Some(RollingField::On))?;
        let get = |n: RollingField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let ground = self.ground(def, &fields)?;
        let contact = self.shaped_contact(def, &fields, ground.as_ref())?;
        match (get(RollingField::Rail), &ground) {
            (None, _) => Some(contact),
            (Some(d), Some(Ground::Terrain(_))) => {
                self.cx.error(d.range(), "`rail` on a surface `z = h(x, y)`: a rail is a line of a plane the body rolls on; remove `rail`, or roll on a plane (`on: F` for a tilted one)");
                None
            }
            (Some(d), Some(Ground::Support(sp))) => {
                self.on_rail(def, &fields, contact, d, Some(sp))
            }
            (Some(d), None) => self.on_rail(def, &fields, contact, d, None),
        }
    }

    /// What the line's body rolls on: a surface `on: z = h(x, y)`, a
    /// support `on: F` or `origin: O`, or (`None`) the plane z = 0.
    fn ground(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
    ) -> Option<Option<Ground>> {
        let get = |n: RollingField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let surface = def.fields.iter().find_map(|f| {
            let on = RollingField::parse(&f.name.to_string()) == Some(RollingField::On);
            f.equals.as_ref().filter(|_| on).map(|rhs| (&f.value, rhs))
        });
        if let Some((lhs, rhs)) = surface {
            return Some(Some(Ground::Terrain(self.terrain(def, fields, lhs, rhs)?)));
        }
        if let Some(c) = get(RollingField::Contact) {
            self.cx.error(c.range(), "`contact: [u, v]` names the coordinates of the contact point on a surface `on: z = h(x, y)`, and this line rolls on a plane: remove `contact`, or give the surface");
            return None;
        }
        let (on, origin) = (get(RollingField::On), get(RollingField::Origin));
        Some(match Self::moved(on, origin) {
            true => Some(Ground::Support(self.support(on, origin)?)),
            false => None,
        })
    }

    /// The contact of the body's shape (its fields) on the plane z = 0,
    /// a support or a curved surface.
    fn shaped_contact(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        ground: Option<&Ground>,
    ) -> Option<Contact> {
        let get = |n: RollingField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        if let Some(h) = get(RollingField::SupportFunction) {
            return self.convex_contact(def, fields, h, ground);
        }
        if let Some(axes) = get(RollingField::SemiAxes) {
            return self.ellipsoid_contact(def, fields, axes, ground);
        }
        let curved = [RollingField::Inside, RollingField::Outside]
            .into_iter()
            .find_map(|f| get(f).map(|x| (f, x)));
        if let Some((which, x)) = curved {
            return self.ball_on(def, fields, which, x);
        }
        let b = self.body(&def.body);
        let radius = match get(RollingField::Radius) {
            Some(x) => self.rolling_length(x, RollingField::Radius),
            None => {
                self.cx.error(def.range, format!("`rolls({}, ..)` needs the wheel's `radius: r` (and `axle: [..]` for a disc or torus; none for a sphere)", def.body));
                None
            }
        };
        let tube = get(RollingField::Tube).map(|x| self.rolling_length(x, RollingField::Tube));
        let axle = get(RollingField::Axle).map(|x| self.constant_axle(x));
        let centre =
            get(RollingField::Centre).map(|x| self.lower_position_vector(x, "the wheel's centre"));
        let b = b?;
        let radius = radius?;
        // an optional field: absent, or given and lowered without error
        fn given<T>(x: Option<Option<T>>) -> Option<Option<T>> {
            x.map_or(Some(None), |v| v.map(Some))
        }
        let tube = given(tube)?;
        let axle = given(axle)?;
        let centre = given(centre)?.unwrap_or(b.centre);
        let Some((rot, _)) = &b.rotation else {
            self.cx.error(def.range, format!("body `{}` is a point mass: a rolling body needs an `orientation` and an `inertia`", def.body));
            return None;
        };
        if tube.is_some() && axle.is_none() {
            self.cx
                .error(def.range, "a torus (`tube: ..`) needs its `axle: [..]`");
            return None;
        }
        if let Some(g) = ground {
            return self.round_on_ground(def, rot, centre, (radius, axle, tube), g);
        }
        if let (Some(a), Some(x)) = (axle, get(RollingField::Axle))
            && self.always_vertical(rot, a)
        {
            self.cx.error(x.range(), format!("the axle `{}` is vertical in every configuration (the body's orientation only turns it about the vertical): a wheel on it lies flat and touches the plane z = 0 along its whole rim, with no single contact point; give the wheel's axis of symmetry in body axes (for an upright wheel that turns about its body y axis, `[0, 1, 0]`), or leave `axle` out for a sphere", super::short(x.to_source())));
            return None;
        }
        let contact = self.contact(rot, centre, radius, axle, tube);
        if let Some(h) = contact.height
            && self.misplaced_centre(def, get(RollingField::Centre), &contact, h, radius, tube)
        {
            return None;
        }
        let height = match contact.height {
            Some(h) => format!(
                "; its height `{}` = 0 is a holonomic constraint",
                self.e.display_capped(h, 240)
            ),
            None => String::new(),
        };
        let line = format!(
            "- `rolls({}, ..)`: contact point P = {}; no slip: the x and y components of its material velocity, `{}` and `{}`, vanish{height}",
            def.body,
            self.show3(contact.point),
            self.e.display_capped(contact.velocity[0], 240),
            self.e.display_capped(contact.velocity[1], 240),
        );
        self.description.push(line);
        Some(contact)
    }

    /// The orientation of a `rolls(..)` line's body and its geometric
    /// centre (`centre:`, described as `what`, or the centre of mass); an
    /// error for a point mass.
    fn rolling_body(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        what: &str,
    ) -> Option<(std::rc::Rc<Rotation>, Vec3)> {
        let centre = (fields.iter().find(|f| f.0 == RollingField::Centre))
            .map(|f| self.lower_position_vector(f.1, what));
        let b = self.body(&def.body)?;
        let centre = centre.unwrap_or(Some(b.centre))?;
        let Some((rot, _)) = &b.rotation else {
            self.cx.error(def.range, format!("body `{}` is a point mass: a rolling body needs an `orientation` and an `inertia`", def.body));
            return None;
        };
        Some((rot.clone(), centre))
    }

    /// A radius or tube radius of a rolling contact: a constant of the
    /// parameters (no coordinate, velocity, input or `t`), neither zero
    /// nor a negative constant; else an error at its field. (Parameters
    /// are not assumed positive: `R` or `-R` is taken as given.)
    fn rolling_length(&mut self, x: &Expr, which: RollingField) -> Option<ExprId> {
        let what = match which {
            RollingField::Tube => "the tube radius of a torus",
            RollingField::SemiAxes => "a semi-axis of an ellipsoid",
            _ => "the radius of a rolling body",
        };
        let v = self.lower(x, 0)?;
        let src = super::short(x.to_source());
        let fs = self.e.free_symbols(v).to_vec();
        if let Some((m, _)) = self.moving_symbol(v, &[], false) {
            let (keeps, noun) = match which {
                RollingField::SemiAxes => {
                    ("a rolling body keeps its shape", "semi-axis".to_string())
                }
                _ => ("a wheel keeps its size", which.to_string()),
            };
            self.cx.error(x.range(), format!("{what} is a constant of the parameters ({keeps}), but `{src}` depends on {m}; write the {noun} with parameters and numbers only"));
            return None;
        }
        let note = self.value_note(x, v);
        if v == ZERO
            || crate::sym::random_points::vanish_at_random_points(&self.e, self.pi_sym, &[v])
        {
            let fix = match which {
                RollingField::Tube => "leave `tube` out for a thin wheel",
                RollingField::SemiAxes => {
                    "an ellipsoid has three semi-axes of positive length (a flat body has no single lowest point)"
                }
                _ => "a body rolls on a rim of positive radius",
            };
            self.cx
                .error(x.range(), format!("{what} is zero{note}: {fix}"));
            return None;
        }
        if fs.iter().all(|&s| s == self.pi_sym) {
            let mut vals = vec![0.0f64; self.e.num_symbols()];
            vals[self.pi_sym.index()] = std::f64::consts::PI;
            let value = self.e.eval(v, &vals);
            if value < 0.0 {
                let note = if note.is_empty() && self.e.as_constant(v).is_none() {
                    format!(": `{src}` is {value:.6}")
                } else {
                    note
                };
                self.cx.error(
                    x.range(),
                    format!(
                        "{what} is negative{note}: give its length, a positive {}",
                        if which == RollingField::SemiAxes {
                            "semi-axis".to_string()
                        } else {
                            which.to_string()
                        }
                    ),
                );
                return None;
            }
        }
        Some(v)
    }

    /// The scalar `x` lowered with the names of `bound` bound as given
    /// (a surface's point, a support function's direction), the scope as
    /// it was afterwards.
    pub(super) fn lower_bound(&mut self, x: &Expr, bound: &[(&str, Binding)]) -> Option<ExprId> {
        let saved: Vec<_> = bound
            .iter()
            .map(|(n, _)| self.scope.get(*n).copied())
            .collect();
        for &(n, b) in bound {
            self.scope.insert(n.to_string(), b);
        }
        let v = self.lower(x, 0);
        for (&(n, _), old) in bound.iter().zip(saved) {
            match old {
                Some(b) => self.scope.insert(n.to_string(), b),
                None => self.scope.remove(n),
            };
        }
        v
    }

    /// What `e` depends on besides the symbols `allowed`, the parameters
    /// and (if `timed`) the time: the first such symbol named for a
    /// message ("the coordinate `x`"), with the coordinate's name if it is
    /// one; `None` if nothing.
    pub(super) fn moving_symbol(
        &self,
        e: ExprId,
        allowed: &[crate::sym::SymId],
        timed: bool,
    ) -> Option<(String, Option<String>)> {
        self.e.free_symbols(e).iter().find_map(|&s| {
            if allowed.contains(&s) {
                return None;
            }
            if s == self.t_sym {
                return (!timed).then(|| ("the time `t`".to_string(), None));
            }
            self.coords.iter().find_map(|c| {
                let name = c.name.to_string();
                if c.position == s {
                    Some((format!("the coordinate `{name}`"), Some(name)))
                } else if c.velocity == s {
                    Some((format!("the velocity `dot({name})`"), None))
                } else {
                    None
                }
            })
        })
    }

    /// Whether the world axle R a is vertical in every configuration:
    /// 1 − n_z² vanishes identically (then |e_z × n| = 0 and the wheel has
    /// no lowest point).
    fn always_vertical(&mut self, rot: &Rotation, a: Vec3) -> bool {
        let n = mat_vec(&mut self.e, &rot.matrix, a);
        let nz2 = self.e.mul(n[2], n[2]);
        let one = self.e.int(1);
        let s2 = self.e.sub(one, nz2);
        s2 == ZERO
            || crate::sym::random_points::vanish_at_random_points(&self.e, self.pi_sym, &[s2])
    }

    /// Whether the contact's height P_z = G_z − r w_z − ρ cannot vanish
    /// whatever the coordinates: it is free of them (a nonzero constant),
    /// or, for a wheel, a constant multiple of |e_z × n| (it would vanish
    /// only with the wheel flat). Then the centre is not at the height a
    /// body of this radius rolling on z = 0 has it, and the error, at the
    /// centre, says the height found and the height expected.
    fn misplaced_centre(
        &mut self,
        def: &RollingDef,
        centre_field: Option<&Expr>,
        contact: &Contact,
        h: ExprId,
        radius: ExprId,
        tube: Option<ExprId>,
    ) -> bool {
        let coords: Vec<_> = self.coords.iter().map(|c| c.position).collect();
        let free_of_coordinates =
            |e: &crate::sym::Engine, x: ExprId| !coords.iter().any(|&q| e.depends_on(x, q));
        let inconsistent = free_of_coordinates(&self.e, h)
            || contact.chart.is_some_and(|s| {
                let inv = self.e.pow(s, Rational::MINUS_ONE);
                let ratio = self.e.mul(h, inv);
                free_of_coordinates(&self.e, ratio)
            });
        if !inconsistent {
            return false;
        }
        let g = contact.centre[2];
        let rim = match contact.chart {
            Some(s) => self.e.mul(radius, s),
            None => radius,
        };
        let expected = match tube {
            Some(rho) => self.e.add(rim, rho),
            None => rim,
        };
        let body_centre = self
            .body_defs
            .iter()
            .find(|b| b.name == def.body)
            .and_then(|b| {
                b.fields
                    .iter()
                    .find(|f| BodyField::of(&f.name) == Some(BodyField::Centre))
            })
            .map(|f| f.value.clone());
        let (at, which) = match (centre_field, &body_centre) {
            (Some(c), _) => (
                c.range(),
                format!("the centre `{}`", super::short(c.to_source())),
            ),
            (None, Some(c)) => (
                c.range(),
                format!(
                    "the centre of body `{}`, `{}`,",
                    def.body,
                    super::short(c.to_source())
                ),
            ),
            (None, None) => (def.range, format!("the centre of body `{}`", def.body)),
        };
        let shape = match (contact.chart.is_some(), tube.is_some()) {
            (false, _) => "a sphere of this radius",
            (true, false) => "a wheel of this radius on this axle",
            (true, true) => "a torus of these radii on this axle",
        };
        let show = |e: &crate::sym::Engine, x: ExprId| super::short(e.display_capped(x, 60));
        let (found, wanted) = (show(&self.e, g), show(&self.e, expected));
        let lift = if tube.is_some() {
            " (the radius times |e_z × n| for the world axle n, plus the tube)"
        } else if contact.chart.is_some() {
            " (the radius times |e_z × n| for the world axle n)"
        } else {
            ""
        };
        self.cx.error(at, format!("the rolling contact of `{}` is not on the plane z = 0 in any configuration: {which} is at height `{found}`, but {shape} touches the plane z = 0 with its centre at height `{wanted}`{lift}; put the centre at that height, or give the radius that matches it", def.body));
        true
    }

    /// A wheel's axle: a constant nonzero vector in body axes, made unit.
    fn constant_axle(&mut self, x: &Expr) -> Option<Vec3> {
        let zero = "give the wheel's axis of symmetry in body axes, e.g. `[0, 1, 0]`";
        self.fixed_direction(x, ("the axle", "the body", "body axes"), zero)
    }

    /// A direction fixed in a frame: a constant nonzero vector, made unit;
    /// `what` names it, the frame and its axes for the messages, `zero`
    /// says what to give instead of the zero vector.
    pub(super) fn fixed_direction(
        &mut self,
        x: &Expr,
        what: (&str, &str, &str),
        zero: &str,
    ) -> Option<Vec3> {
        let (name, frame, axes) = what;
        let v = self.lower_value(x, 0)?;
        let a = self.vector_of(v, x, &format!("{name} must be a vector"))?;
        if a.iter().any(|&c| self.e.as_constant(c).is_none()) {
            self.cx.error(x.range(), format!("{name} is fixed in {frame}: give constant components in {axes}, e.g. `[0, 1, 0]`, not `{}`", super::short(x.to_source())));
            return None;
        }
        if a.iter().all(|&c| c == ZERO) {
            self.cx
                .error(x.range(), format!("{name} is the zero vector: {zero}"));
            return None;
        }
        let n2 = dot3(&mut self.e, a, a);
        let inv = self.e.pow(n2, Rational::new(-1, 2)?);
        Some(scale3(&mut self.e, inv, a))
    }

    /// The contact point P of a body turned by `rot`, with geometric centre
    /// G: P − G = −r w − ρ e_z, where w = (e_z − n_z n)/|e_z × n| is the
    /// direction to the lowest point of the rim (n the world axle; a sphere
    /// has w = e_z). Its material velocity is Ġ + ω × (P − G).
    fn contact(
        &mut self,
        rot: &Rotation,
        centre: Vec3,
        radius: ExprId,
        axle: Option<Vec3>,
        tube: Option<ExprId>,
    ) -> Contact {
        let (offset, chart, world_axle) =
            self.round_offset(rot, radius, axle, tube, (unit(2), (unit(2), ONE)));
        let (contact, omega) = self.contact_at(rot, centre, offset);
        Contact {
            chart,
            kinematics: Some(crate::model::ContactKinematics {
                centre,
                omega,
                axle: world_axle,
                radius,
                tube: tube.unwrap_or(ZERO),
                factors: rot.factors.clone(),
            }),
            ..contact
        }
    }

    /// The contact of `rolls(BALL, radius: r, inside: S)` (or `outside`):
    /// a sphere on a fixed curved surface S.
    fn ball_on(
        &mut self,
        def: &RollingDef,
        fields: &[(RollingField, &Expr)],
        which: RollingField,
        x: &Expr,
    ) -> Option<Contact> {
        let mut fine = true;
        for (f, y) in fields {
            let other = match f {
                RollingField::Axle | RollingField::Tube => {
                    "only a ball rolls on a curved surface (a wheel or torus on one is not modelled)"
                }
                RollingField::On | RollingField::Origin => {
                    "a curved surface is fixed: it takes no `on` or `origin`"
                }
                RollingField::Inside | RollingField::Outside if *f != which => {
                    "a ball rolls on one surface"
                }
                _ => continue,
            };
            self.cx.error(
                y.range(),
                format!("`{f}` with `{which}`: {other}; remove `{f}`"),
            );
            fine = false;
        }
        let get = |n: RollingField| fields.iter().find(|f| f.0 == n).map(|f| f.1);
        let surface = self.surface(which, x);
        let radius = match get(RollingField::Radius) {
            Some(r) => self.rolling_length(r, RollingField::Radius),
            None => {
                self.cx.error(
                    def.range,
                    format!(
                        "`rolls({}, ..)` on a curved surface needs the ball's `radius: r`",
                        def.body
                    ),
                );
                None
            }
        };
        let centre =
            get(RollingField::Centre).map(|c| self.lower_position_vector(c, "the ball's centre"));
        let b = self.body(&def.body)?;
        let (surface, radius) = (surface?, radius?);
        let centre = match centre {
            Some(c) => c?,
            None => b.centre,
        };
        let Some((rot, _)) = &b.rotation else {
            self.cx.error(def.range, format!("body `{}` is a point mass: a rolling body needs an `orientation` and an `inertia`", def.body));
            return None;
        };
        fine.then(|| self.ball_on_surface(def, rot, centre, radius, &surface))
    }

    /// o = P − G of a round body turned by `rot` on a plane of unit normal
    /// N: −r w − ρ N with w = (N − (N·n) n)/|N × n| the direction to the
    /// rim's lowest point (n the world axle; a sphere has w = N); the
    /// rim's |N × n| and the world axle with it, for a wheel. `rim` is the
    /// normal w is formed from, (M, |M|²) for any positive multiple M of N
    /// (w does not change; a surface's unnormalised normal keeps its root
    /// out of w), (N, 1) on a plane.
    fn round_offset(
        &mut self,
        rot: &Rotation,
        radius: ExprId,
        axle: Option<Vec3>,
        tube: Option<ExprId>,
        (normal, rim): (Vec3, (Vec3, ExprId)),
    ) -> (Vec3, Option<ExprId>, Option<(Vec3, ExprId)>) {
        let (w, chart, world_axle) = match axle {
            None => (normal, None, None),
            Some(a) => {
                let (m, m2) = rim;
                let n = mat_vec(&mut self.e, &rot.matrix, a);
                let nz = dot3(&mut self.e, m, n);
                let nz_n = scale3(&mut self.e, nz, n);
                let towards = sub3(&mut self.e, m, nz_n);
                let s = self.rim_scale(nz, m2);
                let inv = self.e.pow(s, Rational::MINUS_ONE);
                (scale3(&mut self.e, inv, towards), Some(s), Some((n, s)))
            }
        };
        let mut offset = scale3(&mut self.e, radius, w);
        if let Some(rho) = tube {
            let down = scale3(&mut self.e, rho, normal);
            offset = add3(&mut self.e, offset, down);
        }
        let offset = offset.map(|c| self.e.neg(c));
        (offset, chart, world_axle)
    }

    /// The contact of a sphere, disc or torus (`shape`: radius, axle,
    /// tube) on a support or a surface.
    fn round_on_ground(
        &mut self,
        def: &RollingDef,
        rot: &Rotation,
        centre: Vec3,
        shape: (ExprId, Option<Vec3>, Option<ExprId>),
        ground: &Ground,
    ) -> Option<Contact> {
        let (radius, axle, tube) = shape;
        let (offset, chart, _) = self.round_offset(rot, radius, axle, tube, ground.normals());
        if chart.is_some_and(|s| {
            s == ZERO
                || crate::sym::random_points::vanish_at_random_points(&self.e, self.pi_sym, &[s])
        }) {
            self.cx.error(def.range, format!("the axle of `{}` is normal to the {} in every configuration: the wheel lies flat on it, touching it along its whole rim; give the wheel's axis of symmetry in body axes", def.body, match ground { Ground::Support(_) => "support's plane", Ground::Terrain(_) => "surface" }));
            return None;
        }
        let what = match (axle, tube) {
            (None, _) => "a sphere",
            (Some(_), None) => "a wheel",
            (Some(_), Some(_)) => "a torus",
        };
        let contact = self.on_ground(def, what, rot, centre, offset, ground);
        let chart = match (chart, contact.chart) {
            (Some(a), Some(b)) => Some(self.e.mul(a, b)),
            (a, b) => a.or(b),
        };
        Some(Contact { chart, ..contact })
    }

    /// The contact of a body (`shape` for the docs) turned by `rot`, centre
    /// G, whose point P = G + `offset` touches `ground`.
    fn on_ground(
        &mut self,
        def: &RollingDef,
        shape: &str,
        rot: &Rotation,
        centre: Vec3,
        offset: Vec3,
        ground: &Ground,
    ) -> Contact {
        match ground {
            Ground::Support(sp) => {
                let contact = self.on_support(rot, centre, offset, sp);
                self.describe_supported(def, shape, &contact, sp);
                contact
            }
            Ground::Terrain(tr) => {
                let contact = self.on_terrain(rot, centre, offset, tr);
                self.describe_terrain(def, shape, &contact, tr);
                contact
            }
        }
    }

    /// The contact point P = G + o of a body turned by `rot` with centre
    /// G, its material velocity Ġ + ω × o and its height P_z where that
    /// does not vanish identically; and ω.
    pub(super) fn contact_at(
        &mut self,
        rot: &Rotation,
        centre: Vec3,
        offset: Vec3,
    ) -> (Contact, Vec3) {
        let (point, omega, v) = self.material_velocity(rot, centre, offset);
        let height = self.height_row(point[2]);
        (Contact::written([v[0], v[1]], height, point, centre), omega)
    }

    /// The point P = G + o of a body turned by `rot` with centre G, ω, and
    /// the velocity of the body's material point at P, Ġ + ω × o.
    pub(super) fn material_velocity(
        &mut self,
        rot: &Rotation,
        centre: Vec3,
        offset: Vec3,
    ) -> (Vec3, Vec3, Vec3) {
        let point = add3(&mut self.e, centre, offset);
        let omega = self.angular_velocity(rot, true);
        let gdot = centre.map(|c| self.time_derivative(c));
        let spin = cross3(&mut self.e, omega, offset);
        let v = add3(&mut self.e, gdot, spin);
        (point, omega, v)
    }

    /// A contact's height h as its holonomic row, unless h vanishes
    /// identically.
    pub(super) fn height_row(&mut self, h: ExprId) -> Option<ExprId> {
        (h != ZERO
            && !crate::sym::random_points::vanish_at_random_points(&self.e, self.pi_sym, &[h]))
        .then_some(h)
    }

    /// |e_z × n| = √(1 − n_z²) for a unit axle n: cos u when 1 − n_z² is
    /// cos²u and u vanishes at the reference configuration (all coordinates
    /// and t zero: an upright wheel), valid until the wheel lies flat; the
    /// square root otherwise. Along a normal M of squared length `m2`
    /// (n_z = M·n), |M × n| = √(m2 − n_z²).
    fn rim_scale(&mut self, nz: ExprId, m2: ExprId) -> ExprId {
        let nz2 = self.e.mul(nz, nz);
        let s2 = self.e.sub(m2, nz2);
        if let Some((c, u)) = self.e.as_scaled_cos_square(s2) {
            let mut at_rest = rustc_hash::FxHashMap::default();
            for c in &self.coords {
                at_rest.insert(c.position, ZERO);
            }
            at_rest.insert(self.t_sym, ZERO);
            if self.e.subst(u, &at_rest, &mut Default::default()) == ZERO && c > Rational::ZERO {
                let root = self.e.constant(c);
                let root = self
                    .e
                    .pow(root, Rational::new(1, 2).unwrap_or(Rational::ONE));
                let cos = self.e.func(crate::sym::Fun::Cos, u);
                return self.e.mul(root, cos);
            }
        }
        self.e.pow(s2, Rational::new(1, 2).unwrap_or(Rational::ONE))
    }
}
