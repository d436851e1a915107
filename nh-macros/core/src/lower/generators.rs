//! Generators (DESIGN §4.1): a declared symmetry's ξ_Q and a declared
//! momentum's direction X, the rate of each coordinate along the group or
//! the motion. A coordinate's rate is written by its name (`x: -y`); the
//! angles a rotation `let R = rot_z(a)*rot_y(b)*..` is built from are
//! written together as the fixed axis the rotation turns about at unit
//! rate (`R: [1, 0, 0]`): the macro solves ω(R)(q̇) = axis for their rates,
//! so that a user names a body's turn, not its chart's formula.

use super::values::{Rotation, Value, Vec3};
use super::{Binding, Lowerer, Place, list_names};
use crate::algebra::lu;
use crate::parse::{Expr, Symmetry};
use crate::sym::random_points::vanish_at_random_points;
use crate::sym::{ExprId, Rational, ZERO};
use proc_macro2::Ident;
use std::rc::Rc;

/// What a list of generators declares, for its messages.
#[derive(Clone, Copy)]
pub(super) enum Declared {
    /// `symmetries { .. }`: one-parameter groups.
    Symmetries,
    /// `momenta { .. }`: the directions of momenta.
    Momenta,
}

impl Declared {
    /// How one entry is written.
    fn form(self) -> &'static str {
        match self {
            Declared::Symmetries => {
                "a symmetry gives the rate of each coordinate it moves, `NAME(q: rate, ..)`"
            }
            Declared::Momenta => {
                "a momentum's direction gives the rate of each coordinate the motion moves, `NAME(q: rate, ..)`, or the fixed axis a rotation turns about, `NAME(R: [a, b, c], ..)`"
            }
        }
    }

    /// Why a rate is a function of the configuration.
    fn why_configuration(self) -> &'static str {
        match self {
            Declared::Symmetries => {
                "a symmetry group acts on the configuration, so its generator is a function of the coordinates and parameters"
            }
            Declared::Momenta => {
                "a momentum's direction is a motion of the configuration, a function of the coordinates and parameters"
            }
        }
    }
}

/// One entry's target: a coordinate, or the angles of a rotation.
enum Target {
    Coordinate(usize),
    Rotation(Rc<Rotation>),
}

impl Lowerer<'_> {
    /// Each declared generator's rates in coordinate order, functions of
    /// the coordinates and parameters only.
    pub(super) fn lower_generators(
        &mut self,
        list: &[Symmetry],
        declared: Declared,
    ) -> Vec<crate::model::Symmetry> {
        let mut out = Vec::new();
        for sym in list {
            let mut generator = vec![ZERO; self.coords.len()];
            let mut given_by: Vec<Option<String>> = vec![None; self.coords.len()];
            for (q, expr) in &sym.generator {
                self.place = Place::Force;
                let Some(target) = self.target(q, declared) else {
                    continue;
                };
                let task = format!("expanding the rate of `{q}` along `{}`", sym.name);
                let rates = match target {
                    Target::Coordinate(i) => {
                        let v = self.at(expr.range(), task, |lw| lw.lower(expr, 0));
                        v.map(|v| vec![(i, v)])
                    }
                    Target::Rotation(r) => self.at(expr.range(), task, |lw| {
                        lw.turn_about(q, &r, expr, &sym.name)
                    }),
                };
                for (i, v) in rates.into_iter().flatten() {
                    if self.moving(v) {
                        self.cx.error(expr.range(), format!("the rate of `{q}` along `{}` depends on a velocity, an input or `t`: {}", sym.name, declared.why_configuration()));
                    }
                    if let Some(first) = given_by[i].replace(q.to_string()) {
                        let c = &self.coords[i].name;
                        self.cx.error_at(q.span(), format!("the rate of `{c}` along `{}` is given twice, by `{first}` and by `{q}`: give it once", sym.name));
                    }
                    generator[i] = v;
                }
            }
            out.push(crate::model::Symmetry {
                name: sym.name.clone(),
                generator,
            });
        }
        out
    }

    /// Whether `v` depends on a velocity, an input or `t`.
    fn moving(&self, v: ExprId) -> bool {
        (self.coords.iter().map(|c| c.velocity))
            .chain(self.inputs.iter().map(|u| u.sym))
            .chain([self.t_sym])
            .any(|s| self.e.depends_on(v, s))
    }

    /// What the name of an entry is: a coordinate or a rotation, else an
    /// error at it.
    fn target(&mut self, q: &Ident, declared: Declared) -> Option<Target> {
        match self.scope.get(&q.to_string()).cloned() {
            Some(Binding::Coord(i)) => return Some(Target::Coordinate(i)),
            Some(Binding::Let(_)) => match self.lower_name(q) {
                Some(Value::Rotation(r)) => return Some(Target::Rotation(r)),
                None => return None,
                Some(_) => {}
            },
            _ => {}
        }
        let hint = self.coordinate_hint(q);
        let all = list_names(self.coords.iter().map(|c| &c.name));
        let form = declared.form();
        self.cx.error_at(
            q.span(),
            format!("`{q}` is not a coordinate{hint}: {form}, for some of {all}"),
        );
        None
    }

    /// The rates of the angles `r` is built from along the turn about the
    /// fixed axis `axis` at unit rate: ω(r)(q̇) = axis, solved by Cramer's
    /// rule on the rows of ω's coefficients with the largest minor at a
    /// random point; the other rows must then hold too. `None` after an
    /// error at `axis`.
    fn turn_about(
        &mut self,
        name: &Ident,
        r: &Rotation,
        axis: &Expr,
        along: &Ident,
    ) -> Option<Vec<(usize, ExprId)>> {
        let value = self.lower_value(axis, 0)?;
        let Value::Vector(e) = value else {
            let kind = value.kind();
            self.cx.error(axis.range(), format!("`{name}` is a rotation and `{}` is {kind}: the entry of a rotation is the fixed axis it turns about along `{along}`, `{name}: [a, b, c]` (world components)", super::short(axis.to_source())));
            return None;
        };
        let omega = self.angular_velocity(r, true);
        let cols: Vec<(usize, Vec3)> = (0..self.coords.len())
            .filter_map(|i| {
                let v = self.coords[i].velocity;
                let col = omega.map(|w| self.e.diff(w, v));
                col.iter().any(|&c| c != ZERO).then_some((i, col))
            })
            .collect();
        let src = super::short(axis.to_source());
        if cols.is_empty() || cols.len() > 3 {
            let n = cols.len();
            self.cx.error_at(name.span(), format!("`{name}` turns with the rates of {n} coordinates, so its turn about `{src}` does not fix them: give each coordinate's rate along `{along}` instead"));
            return None;
        }
        let Some(rows) = self.largest_minor(&cols) else {
            let n = cols.len();
            self.cx.error_at(name.span(), format!("`{name}` turns with the rates of {n} coordinates that turn it about fewer than {n} independent axes, so its turn about `{src}` does not fix them: give each coordinate's rate along `{along}` instead"));
            return None;
        };
        let block: Vec<Vec<ExprId>> = (rows.iter())
            .map(|&row| cols.iter().map(|c| c.1[row]).collect())
            .collect();
        let det = lu::laplace(&mut self.e, &block);
        let inv = self.e.pow(det, Rational::int(-1));
        let rhs: Vec<ExprId> = rows.iter().map(|&row| e[row]).collect();
        let rates = lu::cramer(&mut self.e, &block, &rhs, inv);
        for row in (0..3).filter(|row| !rows.contains(row)) {
            let mut parts: Vec<ExprId> = (cols.iter().zip(&rates))
                .map(|(c, &x)| self.e.mul(c.1[row], x))
                .collect();
            parts.push(self.e.neg(e[row]));
            let residual = self.e.sum(&parts);
            if residual != ZERO && !vanish_at_random_points(&self.e, self.pi_sym, &[residual]) {
                self.cx.error(axis.range(), format!("`{name}` cannot turn about `{src}`: the rates of its angles turn it about other axes only; give an axis it can turn about, or each coordinate's rate along `{along}`"));
                return None;
            }
        }
        Some(cols.iter().map(|c| c.0).zip(rates).collect())
    }

    /// The rows of ω's coefficient columns `cols` (as many as columns)
    /// whose minor is largest at a random point; `None` if every minor
    /// vanishes there (the angles' rates turn the rotation about no axis).
    fn largest_minor(&mut self, cols: &[(usize, Vec3)]) -> Option<Vec<usize>> {
        let subsets: &[&[usize]] = match cols.len() {
            1 => &[&[0], &[1], &[2]],
            2 => &[&[0, 1], &[0, 2], &[1, 2]],
            _ => &[&[0, 1, 2]],
        };
        let mut rng = crate::sym::Rng::new(0x452821E6_38D01377);
        let vals = rng.point(self.e.num_symbols(), self.pi_sym);
        let mut best: Option<(f64, &[usize])> = None;
        for &rows in subsets {
            let block: Vec<Vec<ExprId>> = (rows.iter())
                .map(|&row| cols.iter().map(|c| c.1[row]).collect())
                .collect();
            let det = lu::laplace(&mut self.e, &block);
            let size = self.e.eval_with_scale(det, &vals).0.to_f64().abs();
            if size > 1e-12 && best.is_none_or(|(b, _)| size > b) {
                best = Some((size, rows));
            }
        }
        best.map(|(_, rows)| rows.to_vec())
    }
}
