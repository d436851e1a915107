//! Test support for the stages' unit tests: a system lowered from its
//! source, and its expressions evaluated at values given by name.

use crate::ctxt::Ctxt;
use crate::model::Model;
use crate::sym::{Engine, ExprId};

/// The Chaplygin sled with its blade at the centre of mass: L = m/2 (ẋ² +
/// ẏ²) + J/2 θ̇², ẏ = tan θ ẋ (y dependent).
pub const SLED: &str = "pub struct Sled {
    parameters { m, J }
    coordinates { x, theta, y }
    lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
    constraints { dot(y) = tan(theta)*dot(x); }
}";

/// The same sled in generalized speeds: ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω.
pub const SLED_SPEEDS: &str = "pub struct SledSpeeds {
    parameters { m, J }
    coordinates { x, theta, y }
    lagrangian = m/2*(dot(x)^2 + dot(y)^2) + J/2*dot(theta)^2;
    speeds { v, omega }
    kinematics { dot(x) = v*cos(theta); dot(y) = v*sin(theta); dot(theta) = omega; }
}";

/// The rolling disc written with a body and a rolling contact (shared
/// with `tests/bodies.rs`).
pub const DISC: &str = include_str!("../tests/data/disc_body.txt");

/// The same disc with its Lagrangian written out by hand.
pub const DISC_BY_HAND: &str = include_str!("../tests/data/disc_by_hand.txt");

/// A three-wheeled cart (two wheels on an axle and a caster) whose
/// rolling rows are solved as one block by LU (DESIGN §9).
pub const CART: &str = "pub struct Cart {
    parameters { k }
    coordinates { q0, q1, q2, q3, q4, q5, q6 }
    let H = rot_z(q0);
    let O = [q5, q6, k];
    body wheel0 { mass: k/2, centre: O + H*[0, k, 0], orientation: H*rot_y(q1), inertia: diag(1, 1 + k, 1) }
    body wheel1 { mass: k, centre: O + H*[0, -k, 0], orientation: H*rot_y(q2), inertia: diag(1, 1 + k, 1) }
    body caster { mass: k, centre: O + H*[k, 0, 0], orientation: H*rot_z(q4)*rot_y(q3), inertia: diag(1, 1, 1) }
    body chassis { mass: k, centre: O + H*[k/2, 0, 1/5], orientation: H, inertia: diag(2, 1 + k, 1) }
    lagrangian = kinetic_energy(wheel0) + kinetic_energy(wheel1) + kinetic_energy(caster)
        + kinetic_energy(chassis) + k/4*dot(q4)^2;
    constraints {
        rolls(wheel0, radius: k, axle: [0, 1, 0]);
        rolls(wheel1, radius: k, axle: [0, 1, 0]);
        rolls(caster, radius: k, axle: [0, 1, 0]);
    }
}";

/// The model and engine of `src`, which must lower without errors.
pub fn lowered(src: &str) -> (Model, Engine) {
    let mut cx = Ctxt::new();
    let def = crate::parse::parse_system(src.parse().expect("lexes"), &mut cx);
    let lowered = def.as_ref().and_then(|d| crate::lower::lower(d, &mut cx));
    if let Err(e) = cx.finish() {
        panic!("{src} does not lower: {e}");
    }
    lowered.expect("lowers")
}

/// The value of `e` with the coordinates (`"x"`), velocities (`"dot(x)"`),
/// parameters, inputs and `"t"` given by name; π has its value and any
/// other symbol is NaN (so that a value that should not depend on it
/// shows).
pub fn value(model: &Model, engine: &Engine, e: ExprId, at: &[(&str, f64)]) -> f64 {
    let mut vals = vec![f64::NAN; engine.num_symbols()];
    vals[model.pi.index()] = std::f64::consts::PI;
    for &(name, v) in at {
        let named = |n: &proc_macro2::Ident| n == name;
        let sym = if name == "t" {
            model.time
        } else if let Some(c) = name.strip_prefix("dot(").and_then(|r| r.strip_suffix(')')) {
            model
                .coordinates
                .iter()
                .find(|q| q.name == c)
                .expect("a coordinate")
                .velocity
        } else if let Some(q) = model.coordinates.iter().find(|q| named(&q.name)) {
            q.position
        } else if let Some(p) = model.parameters.iter().find(|p| named(&p.name)) {
            p.sym
        } else if let Some(sp) = &model.speeds
            && let Some(i) = sp.names.iter().position(named)
        {
            sp.syms[i]
        } else {
            model
                .inputs
                .iter()
                .find(|u| named(&u.name))
                .expect("a name")
                .sym
        };
        vals[sym.index()] = v;
    }
    engine.eval(e, &vals)
}

/// The sled's state used by the tests: θ = 0.3, ẋ = 0.7, θ̇ = −1.1, ẏ =
/// tan θ ẋ from the constraint, m = 2, J = 0.5.
pub fn sled_at() -> Vec<(&'static str, f64)> {
    vec![
        ("x", 0.2),
        ("theta", 0.3),
        ("y", -0.4),
        ("dot(x)", 0.7),
        ("dot(theta)", -1.1),
        ("dot(y)", 0.3f64.tan() * 0.7),
        ("m", 2.0),
        ("J", 0.5),
    ]
}

/// [`sled_at`] without ẏ, which a graph solves from the constraint.
pub fn without_ydot() -> Vec<(&'static str, f64)> {
    sled_at()
        .into_iter()
        .filter(|(k, _)| *k != "dot(y)")
        .collect()
}

/// Whether `a` and `b` agree to 1e-12 relative to the larger.
pub fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
}

/// The names of a graph's leaves for values given as to [`value`]:
/// `"x"` → `q_x`, `"dot(x)"` → `dot_x`, a parameter `"m"` → `p_m`.
pub fn leaf_names(model: &Model, at: &[(&str, f64)]) -> Vec<(String, f64)> {
    at.iter()
        .map(|&(name, v)| {
            let leaf = if let Some(c) = name.strip_prefix("dot(").and_then(|r| r.strip_suffix(')'))
            {
                format!("dot_{c}")
            } else if model.coordinates.iter().any(|q| q.name == name) {
                format!("q_{name}")
            } else if model.parameters.iter().any(|p| p.name == name) {
                format!("p_{name}")
            } else {
                format!("u_{name}")
            };
            (leaf, v)
        })
        .collect()
}

/// The value of a graph's node at values given as to [`value`].
pub fn node_value(
    model: &Model,
    d: &crate::emit::Dag,
    n: crate::emit::Node,
    at: &[(&str, f64)],
) -> f64 {
    let named = leaf_names(model, at);
    let named: Vec<(&str, f64)> = named.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    d.value_at(n, &named)
}
