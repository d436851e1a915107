//! Products of vectors and matrices: dot and cross products, 3 × 3 matrices
//! times vectors and matrices, transposes. A matrix is read by rows, each
//! row anything that holds its entries (an array, a `Vec`).

use super::Carrier;

/// A 3-vector's components.
pub type Vec3<V> = [V; 3];
/// A 3 × 3 matrix by rows.
pub type Mat3<V> = [[V; 3]; 3];

/// Σ x·y over `pairs`: [`dot_from`] 0 (exactly: the engine's 0 has no
/// terms to add, and the graph's 0 + x is x).
pub fn dot<C: Carrier>(
    c: &mut C,
    pairs: impl IntoIterator<Item = (C::Value, C::Value)>,
) -> C::Value {
    dot_from(c, C::ZERO, pairs)
}

/// init + Σ x·y over `pairs`: a running sum ([`Carrier::plus`]) of `init`,
/// then of each product in turn as it is formed.
pub fn dot_from<C: Carrier>(
    c: &mut C,
    init: C::Value,
    pairs: impl IntoIterator<Item = (C::Value, C::Value)>,
) -> C::Value {
    let mut s = c.begin_sum();
    c.plus(&mut s, init);
    for (x, y) in pairs {
        let t = c.mul(x, y);
        c.plus(&mut s, t);
    }
    c.total(s)
}

/// a · b.
pub fn dot3<C: Carrier>(c: &mut C, a: Vec3<C::Value>, b: Vec3<C::Value>) -> C::Value {
    dot(c, a.into_iter().zip(b))
}

/// Component `x` of a × b: a_y b_z − a_z b_y (y, z the next axes after x).
pub fn cross_component<C: Carrier>(
    c: &mut C,
    a: impl AsRef<[C::Value]>,
    b: impl AsRef<[C::Value]>,
    x: usize,
) -> C::Value {
    let (a, b) = (a.as_ref(), b.as_ref());
    let (y, z) = ((x + 1) % 3, (x + 2) % 3);
    let l = c.mul(a[y], b[z]);
    let r = c.mul(a[z], b[y]);
    c.sub(l, r)
}

/// a × b, component by component.
pub fn cross<C: Carrier>(
    c: &mut C,
    a: impl AsRef<[C::Value]>,
    b: impl AsRef<[C::Value]>,
) -> Vec3<C::Value> {
    let (a, b) = (a.as_ref(), b.as_ref());
    [0, 1, 2].map(|x| cross_component(c, a, b, x))
}

/// a + b.
pub fn add3<C: Carrier>(c: &mut C, a: Vec3<C::Value>, b: Vec3<C::Value>) -> Vec3<C::Value> {
    [0, 1, 2].map(|i| c.add(a[i], b[i]))
}

/// a − b.
pub fn sub3<C: Carrier>(c: &mut C, a: Vec3<C::Value>, b: Vec3<C::Value>) -> Vec3<C::Value> {
    [0, 1, 2].map(|i| c.sub(a[i], b[i]))
}

/// s·v.
pub fn scale3<C: Carrier>(c: &mut C, s: C::Value, v: Vec3<C::Value>) -> Vec3<C::Value> {
    v.map(|x| c.mul(s, x))
}

/// M v for a 3 × 3 matrix M: row by row, the dot product of the row with v.
pub fn mat_vec<C: Carrier, R: AsRef<[C::Value]>>(
    c: &mut C,
    m: &[R],
    v: impl AsRef<[C::Value]>,
) -> Vec3<C::Value> {
    let v = v.as_ref();
    [0, 1, 2].map(|i| {
        let row = m[i].as_ref();
        dot(c, (0..3).map(|k| (row[k], v[k])))
    })
}

/// Mᵀ v for a 3 × 3 matrix M (column i of M dotted with v).
pub fn mat_t_vec<C: Carrier, R: AsRef<[C::Value]>>(
    c: &mut C,
    m: &[R],
    v: impl AsRef<[C::Value]>,
) -> Vec3<C::Value> {
    let v = v.as_ref();
    [0, 1, 2].map(|i| dot(c, (0..3).map(|k| (m[k].as_ref()[i], v[k]))))
}

/// A B for 3 × 3 matrices: entry by entry, rows first, each the dot product
/// of a row of A with a column of B.
pub fn mat_mat<C: Carrier, A: AsRef<[C::Value]>, B: AsRef<[C::Value]>>(
    c: &mut C,
    a: &[A],
    b: &[B],
) -> Mat3<C::Value> {
    [0, 1, 2].map(|i| {
        let row = a[i].as_ref();
        [0, 1, 2].map(|j| dot(c, (0..3).map(|k| (row[k], b[k].as_ref()[j]))))
    })
}

/// Mᵀ.
pub fn transpose<T: Copy>(m: &Mat3<T>) -> Mat3<T> {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[j][i]))
}
