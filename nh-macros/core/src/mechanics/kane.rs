//! Kane's form of the Euler–Lagrange terms of a Lagrangian of bodies
//! (DESIGN §10): body by body, the generalized inertia forces from each
//! body's centre and rotation, for the multiplier route.

use super::chains::{Chain, Frame};
use super::composite::{self, Wheel};
use super::scene::Scene;
use crate::sym::{ExprId, ZERO};

/// The Euler–Lagrange terms of a Lagrangian Σ_b T_b + L_rest, body by
/// body: with v_b = J_b q̇ and ω_b = W_b q̇, d/dt ∂T_b/∂q̇ − ∂T_b/∂q =
/// m J_bᵀ a_b + W_bᵀ (I α_b + ω_b × I ω_b), a_b = J_b q̈ + J̇_b q̇ and
/// α_b = W_b q̈ + Ẇ_b q̇ (Kane's generalized inertia forces).
pub struct BodyTerms {
    /// The bodies.
    pub bodies: Vec<BodyKinematics>,
    /// M and h (forces included) of L_rest.
    pub rest_mass: Vec<Vec<ExprId>>,
    /// See `rest_mass`.
    pub rest_bias: Vec<ExprId>,
    /// A uniform gravity −γ Σ m_b C_b,k along world axis k taken out of
    /// L_rest, as γ e_k in the axes of the centres' partial velocities:
    /// its projected force is Σ m_b V_bᵀ γ e_k.
    pub gravity: Option<[ExprId; 3]>,
    /// ψ̇ when the centres' Jacobians are in the heading's frame (see
    /// [`BlockTerms::heading_rate`]).
    pub heading_rate: Option<ExprId>,
    /// The coordinates (x, y) of the block's [`Planar`] translation when it
    /// moves every centre too: the bodies' sums then take the dependent
    /// velocities and accelerations of x and y as u (heading frame), and
    /// the Jacobians' columns of x and y as e_x, e_y.
    pub planar: Option<[usize; 2]>,
}

/// One body's kinematics for [`BodyTerms`].
pub struct BodyKinematics {
    /// m.
    pub mass: ExprId,
    /// J = ∂C/∂q, 3 × n (the centre's rate J̇ q̇ at q̈ = 0 is computed on
    /// the graph: `generate::motion`); `None` for a body whose centre of
    /// mass was folded into another's, empty rows when its chain's frames
    /// give it as screws (DESIGN §10).
    pub jacobian: Option<[Vec<ExprId>; 3]>,
    /// The chain the centre's acceleration follows from a contact's centre,
    /// sparing its own J̇ q̇.
    pub anchor: Option<Chain>,
    /// The chain of a centre one link from a fixed point, which does not
    /// anchor the body's own sums (its expanded J is as cheap) but puts it
    /// in its chain's composite inertias.
    pub short_chain: Option<Chain>,
    /// Its rotation, unless it is a point mass.
    pub rotation: Option<BodyRotation>,
}

/// A body's rotation for [`BodyKinematics`], in body axes.
pub struct BodyRotation {
    /// ω_b(q, q̇).
    pub omega: [ExprId; 3],
    /// W = ∂ω_b/∂q̇, 3 × n.
    pub jacobian: [Vec<ExprId>; 3],
    /// I about the centre of mass.
    pub inertia: Inertia,
    /// For a body symmetric about axis k of its last factor R_k(θ) (a
    /// wheel), the vectors above are turned by R_k(θ), which frees them of
    /// θ, and the torque gains −θ̇ I (e_k × ω'): (k, θ̇).
    pub spin: Option<(usize, ExprId)>,
    /// The wheels folded into this body, with ∂θ̇/∂q̇ (1 × n) each.
    pub wheels: Vec<(Wheel, Vec<ExprId>)>,
    /// Its frame as elementary rotations (not for a wheel's spin).
    pub frame: Option<Frame>,
    /// For a body with a spin, its frame with the spin's factor (its own
    /// sums turn the spin out; the composite inertias take its inertia,
    /// symmetric about the spin's axis, in these axes instead).
    pub spun_frame: Option<Frame>,
}

/// A body's inertia about its centre of mass as it is built (DESIGN §10):
/// T (I + Σ μ(|d|² 1 − d dᵀ)) Tᵀ, I its own inertia with its wheels'
/// transverse moments, a parallel-axis term per centre folded into it and
/// T the trailing constant factors of its orientation. The generated code
/// forms the sums and the turn from their parts, where the expanded entries
/// would multiply every offset by every sine of T.
pub struct Inertia {
    /// I, body axes.
    pub own: [[ExprId; 3]; 3],
    /// (μ, d) of each centre folded in, d in body axes.
    pub masses: Vec<(ExprId, [ExprId; 3])>,
    /// T, if the body's axes are turned by trailing constant factors.
    pub tail: Option<[[ExprId; 3]; 3]>,
}

impl Scene<'_> {
    /// Kane's form of the bodies' Euler–Lagrange terms (DESIGN §10), when
    /// the Lagrangian adds up kinetic energies of bodies: per body the
    /// Jacobians of its centre and angular velocity and their rates, and
    /// the terms of the rest of the Lagrangian (with the forces).
    pub(crate) fn body_terms(&mut self) -> Option<BodyTerms> {
        if self.model.speeds.is_some() {
            return None;
        }
        let split = self.model.kinetic.as_ref()?;
        let rest = split.rest;
        let mut parts: Vec<composite::Part> = split
            .bodies
            .iter()
            .map(|b| composite::Part {
                mass: b.mass,
                centre: Some(b.centre),
                rotation: b.rotation.map(|(omega, inertia)| (omega, inertia, b.spin)),
                orientation: b.orientation,
                masses: Vec::new(),
                wheels: Vec::new(),
                factors: b.factors.clone(),
            })
            .collect();
        let (gravity, rest) = match self.gravity(&parts, rest) {
            Some((g, r)) => (Some(g), r),
            None => (None, rest),
        };
        self.fold_fixed_centres(&mut parts);
        self.fold_wheels(&mut parts);
        let frame = self.heading_frame();
        let centres: Vec<[ExprId; 3]> = parts.iter().filter_map(|p| p.centre).collect();
        let mut tree = None;
        let bodies = parts
            .into_iter()
            .map(|part| {
                let (anchor, short_chain) = self.anchor(&part, &frame, (&mut tree, &centres));
                // a chain of frames gives the partial velocities as screws
                let screwed = (anchor.as_ref())
                    .is_some_and(|chain| chain.links.iter().all(|l| l.frame.is_some()));
                let jacobian = part.centre.map(|centre| match screwed {
                    true => Default::default(),
                    false => {
                        let jacobian = centre.map(|x| self.positional_jacobian(x));
                        self.in_frame(&frame, jacobian)
                    }
                });
                let wheels = part
                    .wheels
                    .iter()
                    .map(|w| (*w, self.velocity_jacobian(w.rate)));
                let wheels = wheels.collect();
                let turned_out = frame.is_some();
                let rotation = part.rotation.map(|(omega, own, spin)| {
                    let inertia = Inertia {
                        own,
                        masses: part.masses.clone(),
                        tail: None,
                    };
                    let rot = BodyRotation {
                        wheels,
                        ..self.body_rotation(omega, inertia, spin)
                    };
                    match spin {
                        None => self.without_tail(rot, &part.factors, turned_out),
                        Some(_) => BodyRotation {
                            spun_frame: self.frame_of(&part.factors, turned_out),
                            ..rot
                        },
                    }
                });
                BodyKinematics {
                    mass: part.mass,
                    jacobian,
                    anchor,
                    short_chain,
                    rotation,
                }
            })
            .collect();
        let (rest_mass, rest_bias) = self.euler_lagrange_terms(rest, true);
        let planar = self.planar_bodies(&centres, (&rest_mass, &rest_bias));
        Some(BodyTerms {
            bodies,
            rest_mass,
            rest_bias,
            gravity,
            heading_rate: self.heading_rate(),
            planar,
        })
    }

    /// The coordinates (x, y) of the block's [`Planar`] translation if they
    /// also translate every body's centre (∂C/∂x = e_x, ∂C/∂y = e_y) and
    /// the rest of the Lagrangian has no terms in them.
    pub(crate) fn planar_bodies(
        &mut self,
        centres: &[[ExprId; 3]],
        (rest_mass, rest_bias): (&[Vec<ExprId>], &[ExprId]),
    ) -> Option<[usize; 2]> {
        let planar = self.block.as_ref()?.planar?;
        let coords = planar.columns.map(|a| self.model.constraints[a].dependent);
        for (axis, &i) in coords.iter().enumerate() {
            let q = self.model.coordinates[i].position;
            if !centres.iter().all(|c| self.translates(c, q, axis)) {
                return None;
            }
            let row = rest_mass[i].iter().chain(rest_mass.iter().map(|r| &r[i]));
            if rest_bias[i] != ZERO || row.copied().any(|x| x != ZERO) {
                return None;
            }
        }
        Some(coords)
    }

    /// A body's rotation for Kane's form; a wheel's vectors turned by its
    /// spin R_k(θ).
    pub(crate) fn body_rotation(
        &mut self,
        omega: [ExprId; 3],
        inertia: Inertia,
        spin: Option<(usize, ExprId)>,
    ) -> BodyRotation {
        let (omega, spin) = match spin {
            Some((k, angle)) => {
                let e = &mut *self.engine;
                let turn = crate::lower::values::elementary(e, k, angle);
                let omega = crate::lower::values::mat_vec(e, &turn, omega);
                (omega, Some((k, self.along_motion(angle))))
            }
            None => (omega, None),
        };
        BodyRotation {
            jacobian: omega.map(|w| self.velocity_jacobian(w)),
            omega,
            inertia,
            spin,
            wheels: Vec::new(),
            frame: None,
            spun_frame: None,
        }
    }

    /// A body's rotation in the axes of its orientation without the
    /// trailing constant factors T (DESIGN §10): ω_b' = T ω_b from the
    /// other factors and I' = T I Tᵀ, when its wheels turn about the axis of
    /// every factor of T (which leaves their part of I as it is).
    pub(crate) fn without_tail(
        &mut self,
        rot: BodyRotation,
        factors: &[(usize, ExprId)],
        heading_out: bool,
    ) -> BodyRotation {
        let (kept, Some(tail)) = self.trimmed(factors) else {
            return BodyRotation {
                frame: self.frame_of(factors, heading_out),
                ..rot
            };
        };
        let axes_kept = rot
            .wheels
            .iter()
            .all(|(w, _)| factors[kept.len()..].iter().all(|&(k, _)| k == w.axis));
        let Some(frame) = self.frame_of(&kept, heading_out).filter(|_| axes_kept) else {
            return BodyRotation {
                frame: self.frame_of(factors, heading_out),
                ..rot
            };
        };
        let omega = self.body_omega(&kept);
        let inertia = Inertia {
            tail: Some(tail),
            ..rot.inertia
        };
        BodyRotation {
            jacobian: omega.map(|w| self.velocity_jacobian(w)),
            omega,
            inertia,
            frame: Some(frame),
            ..rot
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use crate::testing::{DISC, SLED, lowered};

    /// The disc written as a body takes Kane's form (one body, its rotation
    /// with the inertia as written); the sled, without bodies, does not.
    #[test]
    fn a_body_takes_kanes_form_and_a_plain_lagrangian_does_not() {
        let (model, mut engine) = lowered(DISC);
        let mut scene = Scene::new(&model, &mut engine);
        let terms = scene.body_terms().expect("Kane's form for the disc");
        assert_eq!(terms.bodies.len(), 1);
        let body = &terms.bodies[0];
        assert!(body.rotation.is_some());
        assert_eq!(terms.rest_mass.len(), 5);
        let (model, mut engine) = lowered(SLED);
        assert!(Scene::new(&model, &mut engine).body_terms().is_none());
    }

    /// A planar chain of `n` links, as the scaling benchmark writes it.
    fn chain(n: usize) -> String {
        let mut s = format!(
            "pub struct Chain {{ parameters {{ m, l, J, g }} coordinates {{ {} }} ",
            (1..=n)
                .map(|i| format!("th{i}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        for i in 1..=n {
            let (parent, start) = match i {
                1 => (String::new(), String::new()),
                _ => (format!("R{}*", i - 1), format!("E{} + ", i - 1)),
            };
            s += &format!(
                "let R{i} = {parent}rot_z(th{i}); let C{i} = {start}R{i}*[l/2, 0, 0]; \
                 let E{i} = {start}R{i}*[l, 0, 0]; \
                 body b{i} {{ mass: m, centre: C{i}, orientation: R{i}, inertia: diag(J, J, J) }} "
            );
        }
        let kinetic: Vec<String> = (1..=n).map(|i| format!("kinetic_energy(b{i})")).collect();
        let heights: Vec<String> = (1..=n).map(|i| format!("C{i}.y")).collect();
        s + &format!(
            "lagrangian = {} - m*g*({}); }}",
            kinetic.join(" + "),
            heights.join(" + ")
        )
    }

    /// The far links of a long chain keep their kinetic energies folded
    /// (their expansions are large); a short chain and the disc fold none.
    /// Expanded on demand, L holds none of the symbols (its values are
    /// checked against SymPy's energy in the root crate's `tests/chains.rs`).
    #[test]
    fn large_kinetic_energies_are_folded_and_expanded_on_demand() {
        let folded = |src: &str| {
            let (model, _) = lowered(src);
            let bodies = &model.kinetic.as_ref().expect("a split").bodies;
            bodies.iter().filter(|b| b.folded.is_some()).count()
        };
        assert_eq!(folded(DISC), 0);
        assert_eq!(folded(&chain(3)), 0);
        let (model, mut engine) = lowered(&chain(10));
        let bodies = &model.kinetic.as_ref().expect("a split").bodies;
        let count = bodies.iter().filter(|b| b.folded.is_some()).count();
        assert!((1..10).contains(&count), "{count} of 10 folded");
        let folded_l = model.lagrangian_folded;
        let mut scene = Scene::new(&model, &mut engine);
        let l = scene.lagrangian();
        assert_ne!(l, folded_l);
        let symbols: Vec<_> = bodies.iter().filter_map(|b| b.folded).collect();
        assert!(symbols.iter().all(|&s| !scene.engine.depends_on(l, s)));
        assert!(
            symbols
                .iter()
                .all(|&s| scene.engine.depends_on(folded_l, s))
        );
    }
}
