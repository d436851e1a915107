//! The kinds of values (DESIGN §10): scalars, 3-vectors, rotations and 3×3
//! matrices, their arithmetic component by component in the engine, and the
//! kind errors of the operators, each at its token.

use super::Lowerer;
use crate::ctxt::SpanRange;
use crate::parse::{BinOp, Expr};
use crate::sym::{Engine, ExprId, Fun, ONE, ZERO};
use std::rc::Rc;

pub(crate) use crate::algebra::{
    add3, cross as cross3, dot3, mat_mat, mat_t_vec, mat_vec, scale3, sub3, transpose,
};

/// A vector's world (or body) components.
pub(crate) type Vec3 = crate::algebra::Vec3<ExprId>;
/// A matrix by rows.
pub(crate) type Mat3 = crate::algebra::Mat3<ExprId>;

/// The value of an expression or a `let`, with its kind.
#[derive(Clone)]
pub(crate) enum Value {
    /// A scalar.
    Scalar(ExprId),
    /// A 3-vector.
    Vector(Vec3),
    /// A rotation, built from elementary rotations.
    Rotation(Rc<Rotation>),
    /// A 3×3 matrix that is not known to be a rotation.
    Matrix(Mat3),
}

/// A rotation (body → world) as the product of the elementary rotations
/// it was built from, and its matrix.
pub(crate) struct Rotation {
    /// The matrix, by rows.
    pub(crate) matrix: Mat3,
    /// The elementary factors, left to right: (axis 0, 1, 2 for x, y, z; angle).
    pub(crate) factors: Vec<(usize, ExprId)>,
}

impl Value {
    /// The kind, for messages.
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            Value::Scalar(_) => "a scalar",
            Value::Vector(_) => "a vector",
            Value::Rotation(_) => "a rotation",
            Value::Matrix(_) => "a 3×3 matrix",
        }
    }

    /// The matrix of a rotation or matrix.
    fn matrix(&self) -> Option<Mat3> {
        match self {
            Value::Rotation(r) => Some(r.matrix),
            Value::Matrix(m) => Some(*m),
            _ => None,
        }
    }

    /// Every scalar the value is made of.
    pub(crate) fn entries(&self) -> Vec<ExprId> {
        match self {
            Value::Scalar(s) => vec![*s],
            Value::Vector(v) => v.to_vec(),
            Value::Rotation(r) => r.matrix.iter().flatten().copied().collect(),
            Value::Matrix(m) => m.iter().flatten().copied().collect(),
        }
    }
}

/// The unit vector along axis `k`.
pub(crate) fn unit(k: usize) -> Vec3 {
    [0, 1, 2].map(|i| if i == k { ONE } else { ZERO })
}

/// The elementary rotation by `angle` about axis `k`.
pub(crate) fn elementary(e: &mut Engine, k: usize, angle: ExprId) -> Mat3 {
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let c = e.func(Fun::Cos, angle);
    let s = e.func(Fun::Sin, angle);
    let mut m = [[ZERO; 3]; 3];
    m[k][k] = ONE;
    m[i][i] = c;
    m[j][j] = c;
    m[i][j] = e.neg(s);
    m[j][i] = s;
    m
}

/// ω of a chain of elementary rotations R = R₁(a₁)⋯R_m(a_m) from each
/// factor's own ω_i (ȧ_i e_k): in the world's axes Σ R₁⋯R_{i−1} ω_i, in the
/// body's (`world` false) Σ (R_{i+1}⋯R_m)ᵀ ω_i, added up factor by factor.
pub(crate) fn chain_omega(
    e: &mut Engine,
    factors: &[(usize, ExprId)],
    own: &[Vec3],
    world: bool,
) -> Vec3 {
    let mut acc = [ZERO; 3];
    let steps: Vec<usize> = match world {
        true => (0..factors.len()).rev().collect(),
        false => (0..factors.len()).collect(),
    };
    for i in steps {
        let (k, a) = factors[i];
        let f = elementary(e, k, a);
        let turned = match world {
            true => mat_vec(e, &f, acc),
            false => mat_t_vec(e, &f, acc),
        };
        acc = add3(e, turned, own[i]);
    }
    acc
}

/// R₁R₂ of two rotations: their factors chained.
pub(crate) fn compose(e: &mut Engine, a: &Rotation, b: &Rotation) -> Rotation {
    Rotation {
        matrix: mat_mat(e, &a.matrix, &b.matrix),
        factors: a.factors.iter().chain(&b.factors).copied().collect(),
    }
}

/// Rᵀ of a rotation: the factors reversed, each angle negated.
pub(crate) fn inverse(e: &mut Engine, r: &Rotation) -> Rotation {
    Rotation {
        matrix: transpose(&r.matrix),
        factors: r
            .factors
            .iter()
            .rev()
            .map(|&(k, a)| (k, e.neg(a)))
            .collect(),
    }
}

impl Lowerer<'_> {
    /// `a op b` for values of any kinds, or an error at `at` naming the kinds.
    pub(super) fn combine(
        &mut self,
        op: BinOp,
        a: Value,
        b: Value,
        at: SpanRange,
        operand: &Expr,
    ) -> Option<Value> {
        use Value::{Matrix as M, Rotation as R, Scalar as S, Vector as V};
        let e = &mut self.e;
        let out = match (op, &a, &b) {
            (BinOp::Add, S(x), S(y)) => S(e.add(*x, *y)),
            (BinOp::Sub, S(x), S(y)) => S(e.sub(*x, *y)),
            (BinOp::Mul, S(x), S(y)) => S(e.mul(*x, *y)),
            (BinOp::Div, S(x), S(y)) => S(e.div(*x, *y)),
            (BinOp::Add, V(x), V(y)) => V(add3(e, *x, *y)),
            (BinOp::Sub, V(x), V(y)) => V(sub3(e, *x, *y)),
            (BinOp::Mul, S(s), V(v)) | (BinOp::Mul, V(v), S(s)) => V(scale3(e, *s, *v)),
            (BinOp::Div, V(v), S(s)) => {
                let r = e.pow(*s, crate::sym::Rational::MINUS_ONE);
                V(scale3(e, r, *v))
            }
            (BinOp::Mul, R(x), R(y)) => R(Rc::new(compose(e, x, y))),
            (BinOp::Mul, R(_) | M(_), V(v)) => V(mat_vec(e, &a.matrix()?, *v)),
            (BinOp::Mul, R(_) | M(_), R(_) | M(_)) => M(mat_mat(e, &a.matrix()?, &b.matrix()?)),
            (BinOp::Add | BinOp::Sub, R(_) | M(_), R(_) | M(_)) => {
                let (x, y) = (a.matrix()?, b.matrix()?);
                let sub = op == BinOp::Sub;
                M([0, 1, 2].map(|i| {
                    [0, 1, 2].map(|j| {
                        if sub {
                            e.sub(x[i][j], y[i][j])
                        } else {
                            e.add(x[i][j], y[i][j])
                        }
                    })
                }))
            }
            (BinOp::Mul, S(s), R(_) | M(_)) | (BinOp::Mul, R(_) | M(_), S(s)) => {
                let m = if let S(_) = a {
                    b.matrix()?
                } else {
                    a.matrix()?
                };
                M(m.map(|row| row.map(|x| e.mul(*s, x))))
            }
            (BinOp::Div, R(_) | M(_), S(s)) => {
                let r = e.pow(*s, crate::sym::Rational::MINUS_ONE);
                M(a.matrix()?.map(|row| row.map(|x| e.mul(r, x))))
            }
            _ => {
                let msg = kind_mismatch(op, &a, &b, operand);
                let at = if matches!(op, BinOp::Add | BinOp::Sub) {
                    operand.range()
                } else {
                    at
                };
                self.cx.error(at, msg);
                return None;
            }
        };
        Some(out)
    }

    /// The scalar of `v`, or an error at `x` saying what was found.
    pub(super) fn scalar_of(&mut self, v: Value, x: &Expr) -> Option<ExprId> {
        match v {
            Value::Scalar(s) => Some(s),
            other => {
                let src = super::short(x.to_source());
                let hint = match other {
                    Value::Vector(_) => format!(
                        "take a component (`{src}.z`), its length `norm({src})` or a dot product `dot({src}, v)`"
                    ),
                    Value::Rotation(_) => {
                        format!("a rotation turns vectors: write `{src} * v`")
                    }
                    _ => format!("a matrix multiplies vectors: write `{src} * v`"),
                };
                self.cx.error(
                    x.range(),
                    format!(
                        "`{src}` is {}, but a scalar is needed here: {hint}",
                        other.kind()
                    ),
                );
                None
            }
        }
    }

    /// The vector of `v`, or an error at `x`: `what` says where a vector
    /// is needed ("the centre of mass must be a vector").
    pub(super) fn vector_of(&mut self, v: Value, x: &Expr, what: &str) -> Option<Vec3> {
        match v {
            Value::Vector(v) => Some(v),
            other => {
                let src = super::short(x.to_source());
                self.cx.error(
                    x.range(),
                    format!(
                        "`{src}` is {}, but {what}: a vector is written `[a, b, c]`",
                        other.kind()
                    ),
                );
                None
            }
        }
    }

    /// The rotation of `v`, or an error at `x` saying how rotations are built.
    pub(super) fn rotation_of(&mut self, v: Value, x: &Expr, what: &str) -> Option<Rc<Rotation>> {
        match v {
            Value::Rotation(r) => Some(r),
            other => {
                let src = super::short(x.to_source());
                let why = match other {
                    Value::Matrix(_) => " that is not known to be a rotation",
                    _ => "",
                };
                self.cx.error(
                    x.range(),
                    format!(
                        "{what} must be a rotation, but `{src}` is {}{why}: build rotations from `rot_x(a)`, `rot_y(a)`, `rot_z(a)`, their products and `transpose(..)`",
                        other.kind()
                    ),
                );
                None
            }
        }
    }

    /// `[a, b, c]` (a vector) or `[[..], [..], [..]]` (a matrix by rows).
    pub(super) fn lower_brackets(
        &mut self,
        items: &[Expr],
        range: SpanRange,
        depth: usize,
    ) -> Option<Value> {
        let values: Vec<Option<Value>> = items
            .iter()
            .map(|x| self.lower_value(x, depth + 1))
            .collect();
        if items.len() != 3 {
            self.cx.error(
                range,
                format!(
                    "a vector has 3 components, but `[{}]` has {}: write `[a, b, c]`",
                    super::short(
                        items
                            .iter()
                            .map(Expr::to_source)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                    items.len()
                ),
            );
            return None;
        }
        let values: Vec<Value> = values.into_iter().collect::<Option<_>>()?;
        if values.iter().all(|v| matches!(v, Value::Vector(_))) {
            let rows: Vec<crate::lower::values::Vec3> = values
                .into_iter()
                .map(|v| match v {
                    Value::Vector(v) => v,
                    _ => [ZERO; 3],
                })
                .collect();
            return Some(Value::Matrix([rows[0], rows[1], rows[2]]));
        }
        let mut comps = [ZERO; 3];
        for (i, (v, x)) in values.into_iter().zip(items).enumerate() {
            comps[i] = self.scalar_of(v, x)?;
        }
        Some(Value::Vector(comps))
    }

    /// `v.x`, `v.y`, `v.z`.
    pub(super) fn lower_component(
        &mut self,
        base: &Expr,
        field: &proc_macro2::Ident,
        depth: usize,
    ) -> Option<Value> {
        let v = self.lower_value(base, depth + 1)?;
        let f = field.to_string();
        let Some(i) = crate::words::Component::parse(&f).map(crate::words::Component::index) else {
            self.cx.error_at(
                field.span(),
                format!(
                    "unknown component `.{f}`: the components of a vector are `.x`, `.y` and `.z`"
                ),
            );
            return None;
        };
        let v = match v {
            Value::Vector(v) => v,
            other => {
                let src = super::short(base.to_source());
                self.cx.error(
                    base.range(),
                    format!(
                        "`{src}` is {}: `.{f}` is a component of a vector",
                        other.kind()
                    ),
                );
                return None;
            }
        };
        Some(Value::Scalar(v[i]))
    }
}

/// The message for `a op b` with kinds that do not combine.
fn kind_mismatch(op: BinOp, a: &Value, b: &Value, operand: &Expr) -> String {
    let (ka, kb) = (a.kind(), b.kind());
    let src = super::short(operand.to_source());
    match (op, a, b) {
        (BinOp::Mul, Value::Vector(_), Value::Vector(_)) => "the product of two vectors is ambiguous: write the scalar product `dot(a, b)` or the cross product `cross(a, b)`".to_string(),
        (BinOp::Div, _, _) => format!("cannot divide {ka} by {kb} (`{src}`): only a scalar can divide"),
        (BinOp::Mul, Value::Vector(_), _) => format!("cannot multiply {ka} by {kb} (`{src}`) from the right: a rotation or matrix acts on a vector from the left, `R * v`"),
        (BinOp::Add | BinOp::Sub, Value::Scalar(_), Value::Vector(_)) => format!("`{src}` is a vector, but the terms before it are a scalar: the terms of a sum are of one kind (take a component, `({src}).z`, or a length, `norm({src})`)"),
        (BinOp::Add | BinOp::Sub, _, _) => format!("`{src}` is {kb}, but the terms before it are {ka}: the terms of a sum are of one kind"),
        _ => format!("cannot multiply {ka} by {kb} (`{src}`)"),
    }
}
