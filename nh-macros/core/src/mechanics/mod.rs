//! The mechanics stage (DESIGN §4): derived symbolically from the
//! immutable model, each piece once and only when asked for. One room per
//! formulation — the multiplier route (`multipliers`), Kane's form of its
//! terms for bodies (`kane`), the curvature route (`curvature`), Maggi's
//! equations for a system in generalized speeds (`maggi`) — with the
//! contacts (`contacts`, `block`, `chains`, `composite`), integrability and
//! the energy in rooms of their own. [`derive`] is the stage's entry.

mod block;
mod chains;
mod composite;
mod contacts;
mod curvature;
mod declared_momenta;
mod energy;
mod frames;
mod integrability;
mod kane;
mod maggi;
mod momenta;
mod multipliers;
mod reduced;
mod scene;
mod symmetries;
mod tree;

pub use block::{BlockTerms, ContactTerms, RowTerms};
pub use chains::{Chain, Frame, FrameStep, Link};
pub use composite::Wheel;
pub use kane::{BodyKinematics, BodyRotation, BodyTerms, Inertia};
pub use maggi::MaggiTerms;
pub use momenta::{Momenta, Verdict};
pub use multipliers::MultiplierRoute;
pub use reduced::Reduced;
pub use scene::Scene;
pub use symmetries::{Broken, SymmetryMomentum};

use crate::model::Output;
use crate::sym::{ExprId, ZERO};

/// The formulation that gives a system's equations of motion (DESIGN §9),
/// decided once per system: Maggi's equations for a system written in
/// generalized speeds; otherwise the route to r̈ that costs less.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// The multiplier route (5.9)/(5.10): the Euler–Lagrange terms of the
    /// whole Lagrangian ([`MultiplierRoute`], or Kane's form of them for
    /// bodies), reduced on the graph.
    Multipliers,
    /// The curvature route (5.20): the constrained Lagrangian's reduced
    /// equations ([`Reduced`]).
    Curvature,
    /// Maggi's equations of a system in generalized speeds ([`Reduced`],
    /// with [`MaggiTerms`] for the reaction forces).
    Maggi,
}

/// Everything derived symbolically for one system, each piece once.
pub struct Derivation {
    /// The multiplier route's pieces.
    pub multiplier_route: MultiplierRoute,
    /// Kane's form of the multiplier route's terms, for a Lagrangian of
    /// bodies (DESIGN §10).
    pub kane: Option<BodyTerms>,
    /// B^b_{αβ} of (5.21), p × k × k.
    pub curvature: Vec<Vec<Vec<ExprId>>>,
    /// The reduced equations Mc r̈ = f of the curvature route (its reduced
    /// mass matrix alone when only the multiplier route is derived), or
    /// Maggi's (Sᵀ M S) u̇ = −Sᵀ (h + M a) for a system in speeds: the
    /// shape both formulations that reduce symbolically return.
    pub reduced: Reduced,
    /// The energy, when `outputs { energy }` asks for it (derived once the
    /// rest is known to be within the engine's limits).
    pub energy: Option<ExprId>,
    /// The momenta of the cyclic coordinates and their rates, when
    /// `outputs { momenta }` asks for them (derived with the energy).
    pub momenta: Option<Momenta>,
    /// The momenta along the directions the constraints allow of the
    /// declared symmetries (`symmetries { .. }`), once they are checked.
    pub symmetries: Vec<SymmetryMomentum>,
    /// The declared momenta (`momenta { .. }`), in declared order.
    pub declared_momenta: Vec<SymmetryMomentum>,
    /// Whether every curvature entry is identically zero.
    pub integrable: bool,
    /// Whether that was proved symbolically (otherwise numerically).
    pub integrable_proved: bool,
    /// Per independent velocity, whether its entry of the reduced mass
    /// matrix Cᵀ M C vanishes (it appears nowhere in the constrained
    /// Lagrangian).
    pub silent: Vec<bool>,
}

/// The multiplier route, the curvature and the curvature route (only its
/// reduced mass matrix unless `both_routes`), and whether the constraints
/// are integrable.
pub fn derive(m: &mut Scene<'_>, both_routes: bool) -> Derivation {
    let (multiplier_route, kane) = m.multiplier_route();
    let places = m.model.places;
    // the full curvature when a route or the output uses it; otherwise
    // only as many entries as it takes to see that one does not vanish
    let task = "deriving the curvature of the constraints";
    let (curvature, (integrable, integrable_proved)) = m.at(places.constraints, task, |m| {
        if both_routes || m.model.outputs.contains(Output::Curvature) {
            let curvature = m.curvature();
            let integrability = m.integrability(&curvature);
            (curvature, integrability)
        } else {
            (Vec::new(), m.integrability_entry_by_entry())
        }
    });
    let task = "deriving the reduced equations (the Lagrangian with the constraints substituted)";
    let reduced = m.at(places.lagrangian, task, |m| {
        if both_routes {
            m.curvature_route(&curvature)
        } else {
            Reduced {
                mass: Vec::new(),
                rhs: Vec::new(),
                solution: None,
            }
        }
    });
    let task = "deriving the reduced mass matrix";
    let silent = m.at(places.lagrangian, task, |m| {
        if both_routes {
            (0..m.model.k())
                .map(|a| reduced.mass[a][a] == ZERO)
                .collect()
        } else {
            m.silent_velocities(&multiplier_route.mass)
        }
    });
    Derivation {
        silent,
        multiplier_route,
        kane,
        curvature,
        reduced,
        energy: None,
        momenta: None,
        symmetries: Vec::new(),
        declared_momenta: Vec::new(),
        integrable,
        integrable_proved,
    }
}

/// The derivation of a system in generalized speeds: Maggi's equations as
/// the reduced system (in the curvature route's slot), the multiplier
/// route's M and h, and the terms of the reaction forces.
pub fn derive_maggi(m: &mut Scene<'_>) -> (Derivation, MaggiTerms) {
    let task = "deriving Maggi's equations (the Lagrangian in the speeds)";
    let (multiplier_route, reduced, terms) =
        m.at(m.model.places.lagrangian, task, |m| m.maggi_equations());
    let k = reduced.mass.len();
    let silent = (0..k).map(|a| reduced.mass[a][a] == ZERO).collect();
    let derivation = Derivation {
        silent,
        multiplier_route,
        kane: None,
        curvature: Vec::new(),
        reduced,
        energy: None,
        momenta: None,
        symmetries: Vec::new(),
        declared_momenta: Vec::new(),
        integrable: false,
        integrable_proved: false,
    };
    (derivation, terms)
}
