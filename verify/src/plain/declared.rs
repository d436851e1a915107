//! A declared momentum plainly (`momenta { .. }`, DESIGN §4.1): J =
//! ⟨∂L/∂q̇, X(q)⟩ and its rate as the total derivative along the plain
//! motion, dJ/dt = Σ_i (d/dt ∂L/∂q̇_i) X_i + ∂L/∂q̇_i Ẋ_i, with d/dt taken
//! by moving (q, q̇, t) along (q̇, q̈, 1): the accelerations of the
//! Lagrange–d'Alembert solve, not the momentum equation the engine uses.
//! A direction is given by its rates, or as the turn of a rotation `let`
//! about a fixed axis: then X solves ω(R)(X) = axis here, numerically, on
//! the three coordinates whose rates turn R.

use super::{At, Motion, Plain, Point, Scalar, axial, mat_mat, transpose};
use crate::jet::{Eps, Jet};
use crate::model::{Ex, LetValue};

/// A declared momentum's direction.
#[derive(Clone, Debug)]
pub enum Direction {
    /// The rate of each coordinate.
    Rates(Vec<Ex>),
    /// The turn of the rotation `let` (its index) about a fixed world axis.
    Turn(usize, [i64; 3]),
}

impl<S: Scalar> Plain<'_, S> {
    /// (J, dJ/dt) along `dir` at the state `p` of the motion `m` (solved
    /// in coordinates); `None` where a turn does not fix the rates (its
    /// rotation is not turned by exactly three coordinates, or singular).
    pub fn declared_momentum(
        &self,
        p: &Point<S>,
        m: &Motion<S>,
        dir: &Direction,
    ) -> Option<(S, S)> {
        let along = |seed: Option<usize>| {
            let moving = |v: S, d: S| Jet::constant(v).plus_eps(Eps::Two, &Jet::constant(d));
            let mut qd: Vec<Jet<S>> = (0..self.n).map(|j| moving(m.qdot[j], m.qdd[j])).collect();
            if let Some(i) = seed {
                qd[i] = qd[i].plus_eps(Eps::One, &Jet::constant(S::one()));
            }
            At {
                q: (0..self.n).map(|j| moving(p.q[j], m.qdot[j])).collect(),
                qd,
                u: Vec::new(),
                t: moving(p.t, S::one()),
            }
        };
        let still = along(None);
        let x: Vec<Jet<S>> = match dir {
            Direction::Rates(x) => x.iter().map(|e| self.eval.ex(e, &still)).collect(),
            Direction::Turn(r, axis) => self.turn(*r, axis, &still)?,
        };
        let (mut j, mut rate) = (S::zero(), S::zero());
        for (i, xi) in x.iter().enumerate() {
            let l = self.lagrangian(&along(Some(i)));
            j = j + l.part(1) * xi.value();
            rate = rate + l.part(3) * xi.value() + l.part(1) * xi.part(2);
        }
        Some((j, rate))
    }

    /// The rates X with ω(R)(X) = `axis` at the positions of `at` (their
    /// motion carried along), by Cramer's rule on the coordinates whose
    /// unit rates turn R.
    fn turn(&self, r: usize, axis: &[i64; 3], at: &At<S>) -> Option<Vec<Jet<S>>> {
        let LetValue::Rotation(rx) = &self.eval.sys.lets[r].1 else {
            return None;
        };
        let mut cols = Vec::new();
        for k in 0..self.n {
            let mut unit = At {
                q: at.q.clone(),
                qd: vec![Jet::constant(S::zero()); self.n],
                u: Vec::new(),
                t: at.t,
            };
            unit.qd[k] = Jet::constant(S::one());
            let (rot, rate) = self.eval.rx_rate(rx, &unit);
            let w = axial(&mat_mat(&rate, &transpose(&rot)));
            if w.iter().any(|c| c.value().to_f64().abs() > 1e-12) {
                cols.push((k, w));
            }
        }
        let [a, b, c] = &cols[..] else { return None };
        let det3 = |u: &[Jet<S>; 3], v: &[Jet<S>; 3], w: &[Jet<S>; 3]| {
            u[0] * (v[1] * w[2] - v[2] * w[1]) - v[0] * (u[1] * w[2] - u[2] * w[1])
                + w[0] * (u[1] * v[2] - u[2] * v[1])
        };
        let e = axis.map(|v| Jet::constant(S::from_f64(v as f64)));
        let det = det3(&a.1, &b.1, &c.1);
        if det.value().to_f64().abs() < 1e-9 {
            return None;
        }
        let mut x = vec![Jet::constant(S::zero()); self.n];
        x[a.0] = det3(&e, &b.1, &c.1) / det;
        x[b.0] = det3(&a.1, &e, &c.1) / det;
        x[c.0] = det3(&a.1, &b.1, &e) / det;
        Some(x)
    }
}
