//! A block of velocity rows solved numerically in the generated code
//! (DESIGN §9): the coefficients c_s, c_r of its rows, an LU factorisation
//! of c_s with the pivots chosen at expansion, the dependent velocities
//! ṡ = −c_s⁻¹ c_r ṙ and accelerations at r̈ = 0, −c_s⁻¹ ġ. Rows of a rolling
//! contact are assembled from the contact's kinematics (DESIGN §10), whose
//! expanded forms would carry 1/|e_z × n| into every term.

use super::chains::chain_rate;
use super::motion::Motion;
use super::nodes::planar_columns;
use super::nodes::{exprs, matrix};
use crate::algebra::cross_component;
use crate::algebra::lu::{self, Lu, Order};
use crate::emit::{Dag, Node, ONE_NODE, ZERO_NODE};
use crate::mechanics::Scene;
use crate::mechanics::{BlockTerms, ContactTerms, RowTerms};

/// A contact's offset o = P − G and, for a disc or torus, (n, s, w).
struct Offset {
    o: [Node; 3],
    rim: Option<([Node; 3], Node, [Node; 3])>,
}

/// The coefficients ∂g_a/∂q̇_i of the block's rows, p × n.
fn coefficients(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> Vec<Vec<Node>> {
    let offsets: Vec<Offset> = bt.contacts.iter().map(|c| offset(d, m, c)).collect();
    bt.rows
        .iter()
        .map(|row| match row {
            RowTerms::Written { coefficients, .. } => exprs(d, m, coefficients),
            RowTerms::Contact { contact, component } => {
                let c = &bt.contacts[*contact];
                let o = offsets[*contact].o;
                if let Some(columns) = screw_columns(d, m, c, o) {
                    return columns.iter().map(|col| col[*component]).collect();
                }
                let jg = matrix(d, m, &c.centre_jacobian);
                let w = matrix(d, m, &c.omega_jacobian);
                (0..m.n())
                    .map(|i| {
                        let wi = [w[0][i], w[1][i], w[2][i]];
                        let spin = cross_component(d, wi, o, *component);
                        d.add(jg[*component][i], spin)
                    })
                    .collect()
            }
        })
        .collect()
}

/// A contact point's ∂v/∂q̇_i (columns i) as screws: its centre's chain
/// and the offset o = P − G in the body's own frame; `None` without frames.
fn screw_columns(
    d: &mut Dag,
    m: &Scene<'_>,
    c: &ContactTerms,
    o: [Node; 3],
) -> Option<Vec<[Node; 3]>> {
    let own = c.frame.as_ref()?;
    let (root, links) = match &c.chain {
        Some(chain) => (&chain.root, chain.links.as_slice()),
        None => (&c.centre_jacobian, &[][..]),
    };
    let mut pieces = super::screws::link_pieces(d, m, links)?;
    pieces.push((own, o));
    Some(super::screws::Screws::of(d, m, root, &pieces, None).columns(d))
}

/// The rows' rates at q̈ = 0, Σ ∂g/∂q_i q̇_i.
fn rates(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> Vec<Node> {
    let offsets: Vec<Offset> = bt.contacts.iter().map(|c| offset(d, m, c)).collect();
    let motion = Motion::of(d, m, bt.heading_rate);
    let turned = bt.heading_rate.is_some();
    bt.rows
        .iter()
        .map(|row| match row {
            RowTerms::Written { along, .. } => d.expr(m.engine, *along),
            RowTerms::Contact { contact, component } => {
                let c = &bt.contacts[*contact];
                let off = &offsets[*contact];
                let (omega, alpha0) = match &c.frame {
                    Some(frame) => super::frames::world_motion(d, m, &motion, frame),
                    None => {
                        let omega = exprs(d, m, &c.omega);
                        let omega = [omega[0], omega[1], omega[2]];
                        (omega, motion.rate(d, omega, turned))
                    }
                };
                let planar = bt
                    .planar
                    .map(|p| p.columns.map(|a| m.constraints[a].dependent));
                let a0 = match &c.chain {
                    Some(chain) => chain_rate(d, m, &motion, chain, planar)[*component],
                    None => {
                        let mut jg = matrix(d, m, &c.centre_jacobian);
                        planar_columns(&mut jg, planar, false);
                        motion.rate_of_jacobian(d, &jg, turned)[*component]
                    }
                };
                let turn = cross_component(d, [alpha0[0], alpha0[1], alpha0[2]], off.o, *component);
                let acc = d.add(a0, turn);
                match &off.rim {
                    None => acc,
                    Some(rim) => {
                        let radius = d.expr(m.engine, c.radius);
                        let wdot = match c.rim {
                            Some(_) => motion.rate(d, rim.2, turned),
                            None => rim_rate(d, omega, rim),
                        };
                        let odot = wdot.map(|x| {
                            let t = d.mul(radius, x);
                            d.neg(t)
                        });
                        let roll = cross_component(d, omega, odot, *component);
                        d.add(acc, roll)
                    }
                }
            }
        })
        .collect()
}

/// o = −r w − ρ e_z with w = (e_z − n_z n)/s (w = e_z for a sphere).
fn offset(d: &mut Dag, m: &Scene<'_>, c: &ContactTerms) -> Offset {
    let radius = d.expr(m.engine, c.radius);
    let tube = d.expr(m.engine, c.tube);
    let (w, rim) = match &c.axle {
        None => ([ZERO_NODE, ZERO_NODE, ONE_NODE], None),
        Some((n, s)) => {
            let n = exprs(d, m, n);
            let n = [n[0], n[1], n[2]];
            let s = d.expr(m.engine, *s);
            // w_z = (1 − n_z²)/s = s
            let w = match &c.rim {
                Some(w) => {
                    let w = exprs(d, m, w);
                    [w[0], w[1], w[2]]
                }
                None => {
                    // −n_z n_x / s = −n_x (n_z/s)
                    let inv = d.div(ONE_NODE, s);
                    let k = d.mul(n[2], inv);
                    [0, 1, 2].map(|x| match x {
                        2 => s,
                        _ => {
                            let t = d.mul(n[x], k);
                            d.neg(t)
                        }
                    })
                }
            };
            (w, Some((n, s, w)))
        }
    };
    let o = [0, 1, 2].map(|x| {
        let rw = d.mul(radius, w[x]);
        let rw = d.neg(rw);
        if x == 2 { d.sub(rw, tube) } else { rw }
    });
    Offset { o, rim }
}

/// ẇ for w = (e_z − n_z n)/s, with ṅ = ω × n (the axle turns with the
/// body) and ṡ = −n_z ṅ_z / s (s² = 1 − n_z²); ẇ_z = ṡ since w_z = s.
fn rim_rate(d: &mut Dag, omega: [Node; 3], rim: &([Node; 3], Node, [Node; 3])) -> [Node; 3] {
    let (n, s, w) = *rim;
    // one reciprocal 1/s for every quotient (as in `offset`)
    let inv = d.div(ONE_NODE, s);
    let ndot = [0, 1, 2].map(|x| cross_component(d, omega, n, x));
    let k = d.mul(n[2], inv);
    let t = d.mul(ndot[2], k);
    let sdot = d.neg(t);
    [0, 1, 2].map(|x| {
        if x == 2 {
            return sdot;
        }
        let a = d.mul(ndot[2], n[x]);
        let b = d.mul(n[2], ndot[x]);
        let c = d.mul(w[x], sdot);
        let num = d.add(a, b);
        let num = d.add(num, c);
        let num = d.mul(num, inv);
        d.neg(num)
    })
}

/// The dependent velocities (or accelerations) x with c_s x = b: the
/// factored block solved, a [`Planar`](crate::mechanics::Planar) pair turned
/// back from u to (ẋ, ẏ).
fn solve_block(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &BlockTerms,
    lu: &Lu<Node>,
    b: Vec<Node>,
) -> Vec<Node> {
    let x = lu::solve(d, lu, b, Order::Pivots);
    turn_back(d, m, bt, x)
}

/// x with a [`Planar`](crate::mechanics::Planar) pair turned from u to (ẋ, ẏ).
fn turn_back(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms, mut x: Vec<Node>) -> Vec<Node> {
    if let Some(p) = &bt.planar {
        let u = p.columns.map(|a| x[a]);
        for (row, &a) in p.turn.iter().zip(&p.columns) {
            let r = [d.expr(m.engine, row[0]), d.expr(m.engine, row[1])];
            x[a] = crate::algebra::dot(d, [(r[0], u[0]), (r[1], u[1])]);
        }
    }
    x
}

/// The block's coefficients split into c_s (columns: the constraints'
/// dependent velocities) factored, and c_r (columns: the independent ones).
fn factored(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> (Lu<Node>, Vec<Vec<Node>>) {
    let coef = coefficients(d, m, bt);
    let cs: Vec<Vec<Node>> = coef
        .iter()
        .zip(&bt.rows)
        .map(|(row, source)| {
            let component = match source {
                RowTerms::Contact { component, .. } => Some(*component),
                RowTerms::Written { .. } => None,
            };
            (m.constraints.iter().enumerate())
                .map(|(a, c)| match (&bt.planar, component) {
                    (Some(p), Some(k)) if p.columns.contains(&a) => {
                        if k < 2 && p.columns[k] == a {
                            ONE_NODE
                        } else {
                            ZERO_NODE
                        }
                    }
                    _ => row[c.dependent],
                })
                .collect()
        })
        .collect();
    let cr = coef
        .iter()
        .map(|row| m.independent().iter().map(|&i| row[i]).collect())
        .collect();
    (lu::factor_at(d, cs, &bt.pivots), cr)
}

/// −c_s⁻¹ c_r: column b gives the dependent velocities (in the order of
/// the constraints) per unit of the independent velocity b.
pub(crate) fn velocity_columns(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> Vec<Vec<Node>> {
    let columns = velocity_columns_in_heading(d, m, bt);
    columns
        .into_iter()
        .map(|x| turn_back(d, m, bt, x))
        .collect()
}

/// [`velocity_columns`] with a [`Planar`](crate::mechanics::Planar) pair's
/// rows those of u = R_z(−ψ)(ẋ, ẏ).
pub(crate) fn velocity_columns_in_heading(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &BlockTerms,
) -> Vec<Vec<Node>> {
    let (lu, cr) = factored(d, m, bt);
    (0..m.k())
        .map(|b| {
            let rhs = cr.iter().map(|row: &Vec<Node>| d.neg(row[b])).collect();
            lu::solve(d, &lu, rhs, Order::Pivots)
        })
        .collect()
}

/// The dependent velocities −c_s⁻¹ c_r ṙ, in the order of the constraints.
pub(crate) fn dependent_velocities(
    d: &mut Dag,
    m: &Scene<'_>,
    bt: &BlockTerms,
    rdot: &[Node],
) -> Vec<Node> {
    let (lu, cr) = factored(d, m, bt);
    let rhs = cr
        .iter()
        .map(|row| {
            let mut acc = ZERO_NODE;
            for (&c, &v) in row.iter().zip(rdot) {
                let t = d.mul(c, v);
                acc = d.sub(acc, t);
            }
            acc
        })
        .collect();
    solve_block(d, m, bt, &lu, rhs)
}

/// The dependent accelerations at r̈ = 0, −c_s⁻¹ ġ, in the order of the
/// constraints (the dependent velocities bound in `d`).
pub(crate) fn dependent_bias(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> Vec<Node> {
    let x = dependent_bias_in_heading(d, m, bt);
    turn_back(d, m, bt, x)
}

/// [`dependent_bias`] with a [`Planar`](crate::mechanics::Planar) pair's
/// entries those of u̇ (heading frame, at r̈ = 0).
pub(crate) fn dependent_bias_in_heading(d: &mut Dag, m: &Scene<'_>, bt: &BlockTerms) -> Vec<Node> {
    let (lu, _) = factored(d, m, bt);
    let rates = rates(d, m, bt);
    let rhs = rates.into_iter().map(|x| d.neg(x)).collect();
    lu::solve(d, &lu, rhs, Order::Pivots)
}

#[cfg(test)]
mod tests {
    use crate::generate::graph::{Args, bound_dag};
    use crate::mechanics::Scene;
    use crate::testing::{CART, lowered, node_value};

    /// The cart's rolling rows are one block solved by LU on the graph:
    /// the dependent velocities it gives satisfy every velocity row.
    #[test]
    fn the_carts_block_gives_velocities_that_satisfy_its_rows() {
        let (model, mut engine) = lowered(CART);
        let scene = Scene::new(&model, &mut engine);
        assert!(
            scene.block.is_some(),
            "the cart's rows are solved as a block"
        );
        let d = bound_dag(&scene, &Args::vectors(&scene));
        let mut at: Vec<(String, f64)> = vec![("k".into(), 0.3)];
        for (i, c) in model.coordinates.iter().enumerate() {
            at.push((c.name.to_string(), 0.1 + 0.37 * i as f64));
        }
        for (j, &i) in model.independent().iter().enumerate() {
            at.push((
                format!("dot({})", model.coordinates[i].name),
                0.5 - 0.3 * j as f64,
            ));
        }
        let named: Vec<(&str, f64)> = at.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let mut all = named.clone();
        let dependent: Vec<(String, f64)> = model
            .dependent()
            .iter()
            .map(|&s| {
                let c = &model.coordinates[s];
                let v = node_value(&model, &d, d.bound(c.velocity).expect("bound"), &named);
                (format!("dot({})", c.name), v)
            })
            .collect();
        all.extend(dependent.iter().map(|(k, v)| (k.as_str(), *v)));
        assert!(!model.velocity_rows.is_empty());
        for &row in &model.velocity_rows {
            let r = crate::testing::value(&model, scene.engine, row, &all);
            assert!(r.abs() < 1e-12, "row residual {r}");
        }
    }
}
