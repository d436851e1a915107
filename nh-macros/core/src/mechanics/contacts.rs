//! Rolling contacts (DESIGN §10): their rows' terms in closed form, the
//! block of velocity rows they belong to, the heading's frame and the
//! block's pivots.

mod pivots;

use super::block::{BlockTerms, ContactTerms, Planar, RowTerms};
use super::scene::Scene;
use crate::sym::dd::Dd;
use crate::sym::{ExprId, SymId, ZERO};

impl Scene<'_> {
    /// The block's terms, for a block of homogeneous velocity rows solved by
    /// elimination (`None` otherwise, or if no pivot order is regular at
    /// both test points).
    pub(crate) fn block_terms(&mut self) -> Option<BlockTerms> {
        // homogeneous, time-independent rows only: a row whose coefficients
        // move with t (not affine: b = 0) keeps the symbolic elimination,
        // whose dependent velocities take t
        let timed =
            (self.model.velocity_rows.iter()).any(|&g| self.engine.depends_on(g, self.model.time));
        if self.model.velocity_rows.is_empty()
            || self.model.affine
            || timed
            || self.model.speeds.is_some()
        {
            return None;
        }
        let planar = self.planar();
        let pivots = self.block_pivots(planar.as_ref())?;
        let frame = self.heading_frame();
        let contacts = self.model.contact_kinematics.clone();
        let chains = self.contact_chains.clone();
        let contacts = contacts
            .into_iter()
            .enumerate()
            .map(|(i, c)| {
                let centre_jacobian = c.centre.map(|x| self.positional_jacobian(x));
                let centre_jacobian = self.in_frame(&frame, centre_jacobian);
                let omega_jacobian = c.omega.map(|w| self.velocity_jacobian(w));
                let omega_jacobian = self.in_frame(&frame, omega_jacobian);
                let turn = |m: &mut Scene<'_>, v: [ExprId; 3]| match &frame {
                    Some(r) => crate::lower::values::mat_vec(m.engine, r, v),
                    None => v,
                };
                ContactTerms {
                    chain: chains.get(i).cloned().flatten(),
                    centre_jacobian,
                    omega: turn(self, c.omega),
                    omega_jacobian,
                    axle: c.axle.map(|(n, s)| (turn(self, n), s)),
                    rim: c.axle.and_then(|(n, s)| {
                        let n = turn(self, n);
                        self.rim_without_root(n, s)
                    }),
                    radius: c.radius,
                    tube: c.tube,
                    frame: self.frame_of(&c.factors, frame.is_some()),
                }
            })
            .collect();
        let rows = self.model.velocity_rows.clone();
        let rows = rows
            .iter()
            .zip(self.model.row_contacts.clone())
            .map(|(&g, source)| match source {
                Some((contact, component)) => RowTerms::Contact { contact, component },
                None => RowTerms::Written {
                    coefficients: self.velocity_jacobian(g),
                    along: self.along_motion(g),
                },
            })
            .collect();
        Some(BlockTerms {
            pivots,
            rows,
            contacts,
            heading_rate: self.heading_rate(),
            planar,
        })
    }

    /// The [`Planar`] translation of the block, if its rows are all
    /// contacts' in the heading's frame and two dependent coordinates
    /// translate every contact along e_x and e_y.
    pub(crate) fn planar(&mut self) -> Option<Planar> {
        let psi = self.heading()?;
        if self.model.row_contacts.iter().any(Option::is_none) {
            return None;
        }
        let contacts = self.model.contact_kinematics.clone();
        let along = |m: &mut Scene<'_>, axis: usize| {
            let dependent: Vec<usize> = m.constraints.iter().map(|con| con.dependent).collect();
            dependent.into_iter().position(|i| {
                let (q, v) = (m.coordinates[i].position, m.coordinates[i].velocity);
                contacts.iter().all(|k| {
                    let turns = k.omega.iter().any(|&w| m.engine.diff(w, v) != ZERO);
                    m.translates(&k.centre, q, axis) && !turns
                })
            })
        };
        let columns = [along(self, 0)?, along(self, 1)?];
        let r = crate::lower::values::elementary(self.engine, 2, psi);
        Some(Planar {
            columns,
            turn: [[r[0][0], r[0][1]], [r[1][0], r[1][1]]],
        })
    }

    /// Whether ∂p/∂q = e_axis exactly.
    pub(crate) fn translates(&mut self, p: &[ExprId; 3], q: SymId, axis: usize) -> bool {
        (0..3).all(|x| {
            let want = if x == axis { crate::sym::ONE } else { ZERO };
            self.engine.diff(p[x], q) == want
        })
    }

    /// w = (e_z − n_z n)/s (w_z = s) if s has no fractional powers.
    pub(crate) fn rim_without_root(&mut self, n: [ExprId; 3], s: ExprId) -> Option<[ExprId; 3]> {
        let e = &mut *self.engine;
        let rooted = e
            .terms(s)
            .iter()
            .any(|&(m, _)| e.factors(m).iter().any(|(_, p)| !p.is_integer()));
        if rooted {
            return None;
        }
        let w = [0, 1].map(|x| {
            let t = e.mul(n[2], n[x]);
            let t = e.div(t, s);
            e.neg(t)
        });
        Some([w[0], w[1], s])
    }

    /// The elimination steps (pivot row, column) of the block c_s
    /// (columns: the constraints' dependent velocities), chosen by
    /// [`pivots::Block::elimination_order`] from the entries' kinds and
    /// their values at the coordinates' zero (the usual operating point)
    /// and at a random state; `None` if a column has no pivot at either.
    pub(crate) fn block_pivots(&mut self, planar: Option<&Planar>) -> Option<Vec<(usize, usize)>> {
        let deps: Vec<SymId> = self
            .model
            .constraints
            .iter()
            .map(|c| self.model.coordinates[c.dependent].velocity)
            .collect();
        let rows = self.model.velocity_rows.clone();
        let mut block: Vec<Vec<ExprId>> = rows
            .iter()
            .map(|&g| deps.iter().map(|&v| self.engine.diff(g, v)).collect())
            .collect();
        if let Some(planar) = planar {
            block = self.planar_block(&block, planar)?;
        }
        let mut rng = crate::sym::Rng::new(0x1319_8A2E_0370_7344);
        let mut at = |zero: bool| -> Vec<Vec<f64>> {
            let mut vals = rng.point(self.engine.num_symbols(), self.model.pi);
            if zero {
                for c in &self.model.coordinates {
                    vals[c.position.index()] = Dd::ZERO;
                }
            }
            block
                .iter()
                .map(|r| {
                    r.iter()
                        .map(|&x| self.engine.eval(x, &vals).to_f64())
                        .collect()
                })
                .collect()
        };
        let (at_zero, at_random) = (at(true), at(false));
        let kinds = block
            .iter()
            .map(|r| {
                r.iter()
                    .map(|&x| match self.engine.as_constant(x) {
                        _ if x == ZERO => pivots::Entry::Zero,
                        Some(_) => pivots::Entry::Constant,
                        None => pivots::Entry::Varying,
                    })
                    .collect()
            })
            .collect();
        pivots::Block {
            kinds,
            at_zero,
            at_random,
        }
        .elimination_order()
    }

    /// The block as the generated code solves it with a [`Planar`]
    /// translation: each contact's rows turned into the heading's frame,
    /// the columns of x and y those of u (e_x, e_y).
    pub(crate) fn planar_block(
        &mut self,
        block: &[Vec<ExprId>],
        planar: &Planar,
    ) -> Option<Vec<Vec<ExprId>>> {
        let frame = self.heading_frame()?;
        let sources = self.model.row_contacts.clone();
        let row_of = |c: usize, x: usize| sources.iter().position(|s| *s == Some((c, x)));
        let mut out = Vec::with_capacity(block.len());
        for source in &sources {
            let (c, k) = (*source)?;
            let row: Vec<ExprId> = (0..block[0].len())
                .map(|col| {
                    if let Some(u) = planar.columns.iter().position(|&p| p == col) {
                        return if u == k { crate::sym::ONE } else { ZERO };
                    }
                    let terms: Vec<ExprId> = (0..3)
                        .filter(|&x| frame[k][x] != ZERO)
                        .filter_map(|x| {
                            row_of(c, x).map(|r| self.engine.mul(frame[k][x], block[r][col]))
                        })
                        .collect();
                    self.engine.sum(&terms)
                })
                .collect();
            out.push(row);
        }
        Some(out)
    }

    /// R_z(−ψ) for the heading ψ every rotating body's orientation starts
    /// with (`rot_z(ψ) * ..`), if they agree. Kane's sums and the contact
    /// rows are the same in any frame turned by a rotation R(q) applied to
    /// every world vector (VᵀV, Vᵀa, and the rows' combinations); in the
    /// heading's frame the bodies' and contacts' vectors are free of ψ.
    pub(crate) fn heading_frame(&mut self) -> Option<[[ExprId; 3]; 3]> {
        let back = self.heading()?;
        let back = self.engine.neg(back);
        Some(crate::lower::values::elementary(self.engine, 2, back))
    }

    /// ψ̇ of [`Model::heading_frame`]'s heading, if there is one.
    pub(crate) fn heading_rate(&mut self) -> Option<ExprId> {
        let psi = self.heading()?;
        Some(self.along_motion(psi))
    }

    /// The heading ψ every rotating body's orientation starts with.
    pub(crate) fn heading(&self) -> Option<ExprId> {
        let split = self.model.kinetic.as_ref()?;
        let mut headings = split
            .bodies
            .iter()
            .filter(|b| b.rotation.is_some())
            .map(|b| b.heading);
        let first = headings.next()??;
        headings.all(|h| h == Some(first)).then_some(first)
    }

    /// The columns of a 3 × n Jacobian turned into `frame`.
    pub(crate) fn in_frame(
        &mut self,
        frame: &Option<[[ExprId; 3]; 3]>,
        jacobian: [Vec<ExprId>; 3],
    ) -> [Vec<ExprId>; 3] {
        let Some(r) = frame else {
            return jacobian;
        };
        let e = &mut *self.engine;
        let mut turned: [Vec<ExprId>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        for i in 0..jacobian[0].len() {
            let column = [jacobian[0][i], jacobian[1][i], jacobian[2][i]];
            let column = crate::lower::values::mat_vec(e, r, column);
            for (x, t) in turned.iter_mut().enumerate() {
                t.push(column[x]);
            }
        }
        turned
    }
}

#[cfg(test)]
mod tests {
    use super::super::scene::Scene;
    use crate::testing::{DISC, SLED, lowered};

    /// The disc's rolling contact gets its chain from the centre, and the
    /// heading's frame (its orientation starts with rot_z(φ)); the sled has
    /// no contact and no block.
    #[test]
    fn the_discs_contact_has_a_chain_and_the_sled_has_none() {
        let (model, mut engine) = lowered(DISC);
        let mut scene = Scene::new(&model, &mut engine);
        assert_eq!(scene.contact_chains.len(), 1);
        assert!(scene.heading().is_some());
        assert!(scene.heading_frame().is_some());
        let (model, mut engine) = lowered(SLED);
        let scene = Scene::new(&model, &mut engine);
        assert!(scene.contact_chains.is_empty() && scene.block.is_none());
    }
}
