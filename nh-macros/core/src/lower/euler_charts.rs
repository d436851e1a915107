//! The charts of a free rotation (DESIGN §9.4). A rotation written as three
//! elementary rotations of three coordinates, `rot_a(α)*rot_b(β)*rot_c(γ)`,
//! is singular where its middle angle lines the first and last axes up
//! (gimbal lock: `cos β = 0` for Tait–Bryan angles, `sin β = 0` for proper
//! Euler angles), a singularity of the coordinates, not of the motion. When
//! the three angles appear nowhere else in the system, the same coordinates
//! can be read as the angles of other sequences, singular elsewhere: the
//! system gets three more charts, each the same definition with the
//! rotation written in its sequence, and the runtime moves between them
//! (DESIGN §6.7) through the rotation and its angular velocity.

use super::Lowerer;
use crate::parse::{BinOp, Expr, SystemDef};
use crate::sym::{ExprId, Fun};
use crate::words::{BodyField, Function};
use proc_macro2::Ident;

/// Where the rotation is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Site {
    /// The value of the `let` at this index.
    Let(usize),
    /// A body's `orientation` field: (body, field).
    Orientation(usize, usize),
}

/// A rotation `rot_a(q_i)*rot_b(q_j)*rot_c(q_k)` of three coordinates that
/// appear nowhere else, read in the sequence `axes`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EulerChart {
    /// Where it is written.
    pub site: Site,
    /// The axes of the sequence (0 for x, 1 for y, 2 for z).
    pub axes: [usize; 3],
    /// The coordinates (indices in q), in the order of the factors.
    pub angles: [usize; 3],
    /// Whether the system writes the rotation's angular velocity in world
    /// components only (`omega(Q)` of a `let`, never `omega_body(Q)` nor a
    /// body's orientation): the runtime's canonical coordinates then carry
    /// it in world components.
    pub world: bool,
}

impl EulerChart {
    /// Whether the last axis is the first (proper Euler angles).
    fn is_proper(&self) -> bool {
        self.axes[0] == self.axes[2]
    }

    /// The sequences of the other charts, all Tait–Bryan. A sequence
    /// p-q-r is singular where world axis p is body axis r (R_pr = ±1).
    /// This one's pole is (a, c) for Tait–Bryan angles a-b-c, (a, a) for
    /// proper Euler angles a-b-a (then c is the third axis); the others'
    /// are (a, b) — in row a with this one's, so where one of the two is
    /// singular the other is not, and one of them has |cos β| ≥ 1/√2
    /// everywhere — and (c, a), (b, a): the body axis a, about which a spin
    /// with that axis horizontal takes the body's other axes through the
    /// vertical in turn, the poles of the first two.
    pub fn others(&self) -> [EulerChart; 3] {
        let [a, b, c] = self.axes;
        let c = if self.is_proper() { 3 - a - b } else { c };
        let first = if self.is_proper() {
            [a, b, c]
        } else {
            [a, c, b]
        };
        [first, [c, b, a], [b, c, a]].map(|axes| EulerChart {
            axes,
            ..self.clone()
        })
    }

    /// The regularity `cos β` (Tait–Bryan) or `sin β` (proper Euler) of
    /// the middle angle β, whose position symbol is `beta`.
    fn regularity(&self, e: &mut crate::sym::Engine, beta: ExprId) -> ExprId {
        let f = if self.is_proper() { Fun::Sin } else { Fun::Cos };
        e.func(f, beta)
    }

    /// The rotation as written in this chart's sequence: `rot_z(phi)*..`.
    pub fn product(&self, names: &[&str]) -> String {
        let factors: Vec<String> = (0..3)
            .map(|i| format!("{}({})", AXES[self.axes[i]], names[self.angles[i]]))
            .collect();
        factors.join("*")
    }

    /// "the angles of `rot_z(phi)*rot_y(theta)*rot_x(psi)`".
    pub fn name(&self, names: &[&str]) -> String {
        format!("the angles of `{}`", self.product(names))
    }

    /// Where the chart is singular: "cos(theta) = 0".
    pub fn singular(&self, names: &[&str]) -> String {
        let f = if self.is_proper() { "sin" } else { "cos" };
        format!(
            "{f}({}) = 0 (gimbal lock of `{}`)",
            names[self.angles[1]],
            self.product(names)
        )
    }

    /// The runtime's `EulerSequence` constant of the sequence: `ZYX`.
    pub fn sequence(&self) -> String {
        self.axes.iter().map(|&k| ["X", "Y", "Z"][k]).collect()
    }

    /// `def` with the rotation written in this chart's sequence (the same
    /// coordinates, the same spans).
    pub fn rewrite(&self, def: &mut SystemDef) {
        let expr = match self.site {
            Site::Let(i) => def.lets.get_mut(i).map(|l| &mut l.value),
            Site::Orientation(b, f) => def
                .bodies
                .get_mut(b)
                .and_then(|b| b.fields.get_mut(f))
                .map(|f| &mut f.value),
        };
        let Some(Expr::Chain { first, rest, .. }) = expr else {
            return;
        };
        let calls = std::iter::once(&mut **first).chain(rest.iter_mut().map(|r| &mut r.2));
        for (call, &k) in calls.zip(&self.axes) {
            if let Expr::Call { func, .. } = call {
                *func = Ident::new(AXES[k], func.span());
            }
        }
    }
}

/// The elementary rotations' names by axis.
const AXES: [&str; 3] = ["rot_x", "rot_y", "rot_z"];

/// The coordinates of `expr` if it is `rot_a(q)*rot_b(q')*rot_c(q'')` of
/// three distinct coordinates (names in `coords`) with a ≠ b ≠ c: (axes,
/// coordinate indices).
fn three_angles(expr: &Expr, coords: &[&str]) -> Option<([usize; 3], [usize; 3])> {
    let Expr::Chain { first, rest, .. } = expr else {
        return None;
    };
    if rest.len() != 2 || rest.iter().any(|r| r.0 != BinOp::Mul) {
        return None;
    }
    let mut axes = [0; 3];
    let mut angles = [0; 3];
    let factors = std::iter::once(&**first).chain(rest.iter().map(|r| &r.2));
    for (i, f) in factors.enumerate() {
        let Expr::Call { func, args, .. } = f else {
            return None;
        };
        let ([Expr::Name(q)], Some(k)) = (
            args.as_slice(),
            Function::of(func).and_then(Function::rotation_axis),
        ) else {
            return None;
        };
        axes[i] = k;
        angles[i] = coords.iter().position(|c| q == c)?;
    }
    let distinct = angles[0] != angles[1] && angles[1] != angles[2] && angles[0] != angles[2];
    (distinct && axes[0] != axes[1] && axes[1] != axes[2]).then_some((axes, angles))
}

/// Adds to `counts` the uses of each coordinate (names in `coords`) in `expr`.
fn count_uses(expr: &Expr, coords: &[&str], counts: &mut [usize]) {
    expr.visit(&mut |e| {
        if let Expr::Name(id) = e
            && let Some(i) = coords.iter().position(|c| id == c)
        {
            counts[i] += 1;
        }
    });
}

/// Every expression of `def` but the forces'.
fn expressions(def: &SystemDef) -> Vec<&Expr> {
    let mut exprs: Vec<&Expr> = Vec::new();
    exprs.extend(def.lets.iter().map(|l| &l.value));
    exprs.extend(
        def.bodies
            .iter()
            .flat_map(|b| b.fields.iter().map(|f| &f.value)),
    );
    exprs.extend(
        def.rolling
            .iter()
            .flat_map(|r| r.fields.iter().map(|f| &f.value)),
    );
    exprs.extend(def.lagrangians.iter().map(|l| &l.1));
    for block in [&def.constraints, &def.kinematics].into_iter().flatten() {
        exprs.extend(block.1.iter().flat_map(|c| [&c.lhs, &c.rhs]));
    }
    exprs
}

/// How often each coordinate is named anywhere in `def` (expressions,
/// forces, `dependent`).
fn uses(def: &SystemDef, coords: &[&str]) -> Vec<usize> {
    let mut counts = vec![0; coords.len()];
    let mut exprs = expressions(def);
    for f in def.forces.iter().flat_map(|f| &f.1) {
        exprs.push(&f.value);
        let named = [f.coordinate.clone()];
        count_names(&named, coords, &mut counts);
    }
    if let Some((_, names)) = &def.dependent {
        count_names(names, coords, &mut counts);
    }
    for e in exprs {
        count_uses(e, coords, &mut counts);
    }
    counts
}

/// Adds the coordinates among `names` to `counts`.
fn count_names(names: &[Ident], coords: &[&str], counts: &mut [usize]) {
    for id in names {
        if let Some(i) = coords.iter().position(|c| id == c) {
            counts[i] += 1;
        }
    }
}

/// The first free rotation of `def`: a `let` or a body's `orientation`
/// written as three elementary rotations of three coordinates named
/// nowhere else.
pub fn free_rotation(def: &SystemDef, coords: &[&str]) -> Option<EulerChart> {
    let mut sites: Vec<(Site, &Expr)> = Vec::new();
    sites.extend(
        def.lets
            .iter()
            .enumerate()
            .map(|(i, l)| (Site::Let(i), &l.value)),
    );
    for (b, body) in def.bodies.iter().enumerate() {
        for (f, field) in body.fields.iter().enumerate() {
            if field.name == BodyField::Orientation {
                sites.push((Site::Orientation(b, f), &field.value));
            }
        }
    }
    let counts = uses(def, coords);
    sites.into_iter().find_map(|(site, expr)| {
        let (axes, angles) = three_angles(expr, coords)?;
        angles
            .iter()
            .all(|&q| counts[q] == 1)
            .then_some(EulerChart {
                site,
                axes,
                angles,
                world: world_rates(def, site),
            })
    })
}

/// Whether the rotation at `site` is a `let` whose angular velocity `def`
/// writes as `omega(Q)` and never as `omega_body(Q)`, and which no body
/// takes as its orientation.
fn world_rates(def: &SystemDef, site: Site) -> bool {
    let Site::Let(i) = site else {
        return false;
    };
    let Some(name) = def.lets.get(i).map(|l| &l.name) else {
        return false;
    };
    let mut counts = [0usize; 2];
    for e in expressions(def) {
        count_calls(e, name, &mut counts);
    }
    let oriented = def.bodies.iter().flat_map(|b| &b.fields).any(|f| {
        f.name == BodyField::Orientation && matches!(&f.value, Expr::Name(n) if n == name)
    });
    counts[0] > 0 && counts[1] == 0 && !oriented
}

/// Adds to `counts` the calls `omega(name)` and `omega_body(name)` in `expr`.
fn count_calls(expr: &Expr, name: &Ident, counts: &mut [usize; 2]) {
    expr.visit(&mut |e| {
        if let Expr::Call { func, args, .. } = e
            && let [Expr::Name(arg)] = args.as_slice()
            && arg == name
        {
            match Function::of(func) {
                Some(Function::Omega) => counts[0] += 1,
                Some(Function::OmegaBody) => counts[1] += 1,
                _ => {}
            }
        }
    });
}

/// The constraints' regularity at least this large somewhere on the pole
/// of the rotation: the second chart is worth having.
const REGULAR: f64 = 1e-3;

impl Lowerer<'_> {
    /// The charts of a free rotation, for a system whose constraints need
    /// no atlas of their own (`constraint_atlas` false; DESIGN §9.4): its
    /// own sequence and three others, each with where it is singular, and the
    /// rotation's regularity multiplied into the chart's, `chart`. In a
    /// chart of another system's atlas (`def.euler_chart`), the regularity
    /// only. Nothing when the angles are not all independent (`dependent`:
    /// the coordinates the constraints make dependent), the system is in
    /// speeds, or the constraints are singular wherever the rotation is.
    pub(super) fn euler_charts(
        &mut self,
        def: &SystemDef,
        dependent: &[usize],
        chart: &mut Option<ExprId>,
        constraint_atlas: bool,
    ) -> Option<Vec<(EulerChart, String)>> {
        if def.speeds.is_some() || constraint_atlas || (def.one_chart && !def.euler_chart) {
            return None;
        }
        let names: Vec<String> = self.coords.iter().map(|c| c.name.to_string()).collect();
        let coords: Vec<&str> = names.iter().map(String::as_str).collect();
        let rotation = free_rotation(def, &coords)?;
        if rotation.angles.iter().any(|q| dependent.contains(q)) {
            return None;
        }
        let beta = self.coords[rotation.angles[1]].position;
        if !def.euler_chart && !self.regular_on_pole(*chart, &rotation, beta.index()) {
            return None;
        }
        let beta = self.e.sym(beta);
        let factor = rotation.regularity(&mut self.e, beta);
        *chart = Some(match *chart {
            Some(c) => self.e.mul(c, factor),
            None => factor,
        });
        if def.euler_chart {
            return None;
        }
        let mut charts = vec![(rotation.clone(), rotation.singular(&coords))];
        for other in rotation.others() {
            let singular = other.singular(&coords);
            charts.push((other, singular));
        }
        Some(charts)
    }

    /// Whether the constraints' regularity `chart` (none: always regular)
    /// is at least [`REGULAR`] at one of 4 random points on the rotation's
    /// pole (the middle angle, symbol `beta`, at π/2 or 0).
    fn regular_on_pole(&self, chart: Option<ExprId>, rotation: &EulerChart, beta: usize) -> bool {
        let Some(chart) = chart else {
            return true;
        };
        let pole = if rotation.is_proper() {
            0.0
        } else {
            std::f64::consts::FRAC_PI_2
        };
        let mut rng = crate::sym::Rng::new(0x2545_F491_4F6C_DD1D);
        (0..4).any(|_| {
            let mut vals: Vec<f64> = (rng.point(self.e.num_symbols(), self.pi_sym).iter())
                .map(|v| v.to_f64())
                .collect();
            vals[beta] = pole;
            let mut memo = crate::sym::EvalMemo::default();
            let rho = self.e.eval_memo(chart, &vals, &mut memo);
            rho.is_finite() && rho.abs() >= REGULAR
        })
    }
}
