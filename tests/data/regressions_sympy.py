"""Reference values for tests/regressions.rs: systems the differential
verification (verify/) found wrong, derived here with SymPy from their
Lagrangians (a body's kinetic energy 1/2 m |dC/dt|^2 + 1/2 w.I.w, w the axial
vector of R^T dR/dt) and the multiplier method (E = c^T mu, c qdd + dc/dt qd
+ db/dt = 0), evaluated at 30 digits.

    python3 tests/data/regressions_sympy.py > tests/data/regressions.json
"""
import json
from sympy import (Matrix, Rational, cos, diff, eye, sin, symbols, zeros, Symbol, N)

t = Symbol("t")


def rot(k, a):
    c, s = cos(a), sin(a)
    m = eye(3)
    i, j = (k + 1) % 3, (k + 2) % 3
    m[i, i], m[j, j], m[i, j], m[j, i] = c, c, -s, s
    return m


def rate(x, q, qd):
    return x.applyfunc(lambda e: sum(diff(e, q[i]) * qd[i] for i in range(len(q))))


def kinetic(m, centre, r, inertia, q, qd):
    cd = rate(centre, q, qd)
    t_ = Rational(1, 2) * m * (cd.T * cd)[0, 0]
    if r is not None:
        wm = r.T * rate(r, q, qd)
        w = Matrix([wm[2, 1], wm[0, 2], wm[1, 0]])
        t_ += Rational(1, 2) * (w.T * inertia * w)[0, 0]
    return t_


def accelerations(lag, rows, q, qd, dep, values, state_q, state_v):
    n = len(q)
    indep = [i for i in range(n) if i not in dep]
    sub = dict(values)
    sub.update({q[i]: state_q[i] for i in range(n)})
    c = Matrix([[diff(g, qd[i]) for i in range(n)] for g in rows])
    b = Matrix([g.subs({v: 0 for v in qd}) for g in rows])
    qdv = {qd[r]: state_v[j] for j, r in enumerate(indep)}
    cs = c.extract(list(range(len(rows))), dep).subs(sub)
    known = (c.extract(list(range(len(rows))), indep).subs(sub) * Matrix(state_v) + b.subs(sub))
    sd = cs.LUsolve(-known)
    for a, s in enumerate(dep):
        qdv[qd[s]] = sd[a]
    sub.update(qdv)
    mass = Matrix(n, n, lambda i, j: diff(lag, qd[i], qd[j])).subs(sub)
    h = Matrix([sum(diff(lag, qd[j], q[i]) * qd[i] for i in range(n)) - diff(lag, q[j])
                for j in range(n)]).subs(sub)
    d = Matrix([sum(diff(g, q[i]) * qd[i] for i in range(n)) for g in rows]).subs(sub)
    p = len(rows)
    kkt = zeros(n + p, n + p)
    kkt[:n, :n] = mass
    kkt[:n, n:] = -c.subs(sub).T
    kkt[n:, :n] = c.subs(sub)
    rhs = Matrix.vstack(-h, -d)
    x = kkt.LUsolve(rhs)
    return [str(N(x[r], 30)) for r in indep]


def held_velocity():
    """rot_z(z1 + z0) rot_x(z0) rot_y(1), general inertia, dot(z0) = -z1."""
    z = symbols("z0 z1")
    zd = symbols("zd0 zd1")
    k0, k1 = symbols("k0 k1")
    r = rot(2, z[1] + z[0]) * rot(0, z[0]) * rot(1, 1)
    inertia = Matrix([[1, k1 / 10, 0], [k1 / 10, 2, 0], [0, 0, k0]])
    lag = kinetic(1, Matrix([0, 0, 0]), r, inertia, z, zd)
    rows = [zd[0] + z[1]]
    out = []
    for qv, vv in [((0.3, -0.7), (0.9,)), ((-1.1, 0.4), (-0.5,)), ((0.8, 1.2), (0.2,))]:
        values = {k0: Rational(3, 2), k1: Rational(4, 5)}
        out.append({"q": qv, "v": vv,
                    "rdd": accelerations(lag, rows, z, zd, [0], values, qv, vv)})
    return out


def anchored_point():
    """A point at C + R [0, -1/2, k0], R = rot_x(z2) rot_x(z1), C = [0, 0, z2],
    with dot(z2) = -(z1 dot(z0))."""
    z = symbols("z0 z1 z2")
    zd = symbols("zd0 zd1 zd2")
    k0 = symbols("k0")
    r = rot(0, z[2]) * rot(0, z[1])
    c = Matrix([0, 0, z[2]]) + r * Matrix([0, Rational(-1, 2), k0])
    lag = kinetic(1, c, None, None, z, zd) + Rational(1, 2) * zd[0] ** 2
    rows = [zd[2] + z[1] * zd[0]]
    out = []
    for qv, vv in [((0.3, -0.7, 0.5), (0.9, -0.4)), ((-1.1, 0.4, 0.2), (-0.5, 0.3))]:
        values = {k0: Rational(6, 5)}
        out.append({"q": qv, "v": vv,
                    "rdd": accelerations(lag, rows, z, zd, [2], values, qv, vv)})
    return out


print(json.dumps({"held_velocity": held_velocity(), "anchored_point": anchored_point()}, indent=1))
