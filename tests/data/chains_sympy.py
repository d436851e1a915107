"""Reference accelerations for tests/chains.rs: the planar chain of rigid
links of the scaling benchmark (nh-macros/core/tests/synthetic/mod.rs,
`planar`) with N = 2, 3 and 10, derived here with SymPy from scratch,
independently of the library:

* positions in the links' absolute angles phi_i = th_1 + ... + th_i (the
  benchmark's coordinates are the relative angles th_i), no rotation
  matrices: C_i = sum_{j<i} l e(phi_j) + l/2 e(phi_i), e(a) = (cos a, sin a);
* T = sum_i m |C_i'|^2/2 + J phi_i'^2/2 (a planar link turns about z only),
  V = m g sum_i C_i.y, and the Euler-Lagrange equations M q'' = Q - h by
  differentiation;
* for N = 2, that M and that right side are checked symbolically against
  the closed form of the compound double pendulum written out below (in the
  absolute angles, then taken to the relative ones).

At 8 fixed random states per N (seed 34; the states and parameters taken
exactly as the doubles the test reads), it solves M q'' = Q - h at 50 digits and writes the parameters, the states and the
accelerations to tests/data/chains.json.

For N = 10 it also writes the energy T + V at each state (the links'
velocities from the absolute angles' rates, not by differentiation).

usage: python3 tests/data/chains_sympy.py   (about eight minutes: N = 10)"""
import json
import os
import random

import mpmath
import sympy as sp

mpmath.mp.dps = 50
PARAMETERS = {"m": sp.Rational(13, 10), "l": sp.Rational(7, 10),
              "J": sp.Rational(1, 20), "g": sp.Rational(981, 100)}
m, l, J, g = sp.symbols("m l J g", positive=True)


def equations(n):
    """M(th) and the right side Q - h(th, th') of the n-link chain, in the
    relative angles th_i, and the symbols of th and th'."""
    th = sp.symbols(f"th1:{n + 1}")
    thd = sp.symbols(f"thd1:{n + 1}")
    phi = [sum(th[: i + 1]) for i in range(n)]
    e = [sp.Matrix([sp.cos(a), sp.sin(a)]) for a in phi]
    centres = [sum((l * e[j] for j in range(i)), sp.zeros(2, 1)) + l / 2 * e[i] for i in range(n)]

    def rate(expr):
        return sum(sp.diff(expr, a) * b for a, b in zip(th, thd))

    T = 0
    for i, c in enumerate(centres):
        v = c.applyfunc(rate)
        T += m * (v.T * v)[0] / 2 + J * rate(phi[i]) ** 2 / 2
    V = m * g * sum(c[1] for c in centres)
    L = T - V
    M = sp.Matrix(n, n, lambda i, j: sp.diff(L, thd[i], thd[j]))
    # d/dt dL/dth' = M th'' + (d/dth dL/dth') th'; the rest moves right
    p = [sp.diff(L, v) for v in thd]
    rhs = sp.Matrix([sp.diff(L, th[i]) - sum(sp.diff(p[i], a) * b for a, b in zip(th, thd))
                     for i in range(n)])
    return M, rhs, th, thd


def closed_form_double():
    """The compound double pendulum in its absolute angles p1, p2 (link 1
    hinged at the origin, gravity along -y):
      (5/4 m l^2 + J) p1'' + 1/2 m l^2 cos(p1-p2) p2'' = -1/2 m l^2 sin(p1-p2) p2'^2 - 3/2 m g l cos p1
      1/2 m l^2 cos(p1-p2) p1'' + (1/4 m l^2 + J) p2'' =  1/2 m l^2 sin(p1-p2) p1'^2 - 1/2 m g l cos p2
    returned with p1 = th1, p2 = th1 + th2 (so p1'' = th1'', p2'' = th1'' + th2''),
    as the mass matrix and right side of th''."""
    th1, th2, thd1, thd2 = sp.symbols("th1 th2 thd1 thd2")
    p1, p2, pd1, pd2 = th1, th1 + th2, thd1, thd1 + thd2
    c, s = sp.cos(p1 - p2), sp.sin(p1 - p2)
    A = sp.Matrix([[sp.Rational(5, 4) * m * l**2 + J, m * l**2 * c / 2],
                   [m * l**2 * c / 2, m * l**2 / 4 + J]])
    b = sp.Matrix([-m * l**2 * s * pd2**2 / 2 - sp.Rational(3, 2) * m * g * l * sp.cos(p1),
                   m * l**2 * s * pd1**2 / 2 - m * g * l * sp.cos(p2) / 2])
    # p'' = S th'' with S = [[1, 0], [1, 1]]: A S th'' = b
    S = sp.Matrix([[1, 0], [1, 1]])
    # the Euler-Lagrange equations of th are S^T of those of p
    return S.T * A * S, S.T * b


def check_double(M, rhs):
    Mc, bc = closed_form_double()
    zero = sp.simplify(sp.expand_trig((M - Mc).applyfunc(sp.expand)))
    assert zero == sp.zeros(2, 2), zero
    zero = sp.simplify(sp.expand_trig((rhs - bc).applyfunc(sp.expand)))
    assert zero == sp.zeros(2, 1), zero


def exact(x):
    """The rational whose value is the double nearest x: the test reads the
    states and parameters as doubles, the reference is computed at them."""
    return sp.Rational(float(x))


def energy(n, th, thd):
    """T + V of the n-link chain, in the relative angles."""
    phi = [sum(th[: i + 1]) for i in range(n)]
    phid = [sum(thd[: i + 1]) for i in range(n)]
    e = [sp.Matrix([sp.cos(a), sp.sin(a)]) for a in phi]
    de = [sp.Matrix([-sp.sin(a), sp.cos(a)]) * w for a, w in zip(phi, phid)]
    total = 0
    for i in range(n):
        c = sum((l * e[j] for j in range(i)), sp.zeros(2, 1)) + l / 2 * e[i]
        v = sum((l * de[j] for j in range(i)), sp.zeros(2, 1)) + l / 2 * de[i]
        total += m * (v.T * v)[0] / 2 + J * phid[i] ** 2 / 2 + m * g * c[1]
    return total


def cases(n, M, rhs, th, thd, rng):
    subs = {m: exact(PARAMETERS["m"]), l: exact(PARAMETERS["l"]),
            J: exact(PARAMETERS["J"]), g: exact(PARAMETERS["g"])}
    out = []
    for _ in range(8):
        q = [rng.randint(-3000, 3000) / 1000 for _ in range(n)]
        v = [rng.randint(-2000, 2000) / 1000 for _ in range(n)]
        at = dict(subs)
        at.update(zip(th, map(exact, q)))
        at.update(zip(thd, map(exact, v)))
        Mn = mpmath.matrix([[sp.N(M[i, j].subs(at), 60) for j in range(n)] for i in range(n)])
        bn = mpmath.matrix([sp.N(rhs[i].subs(at), 60) for i in range(n)])
        a = mpmath.lu_solve(Mn, bn)
        case = {"q": q, "rdot": v, "accelerations": [float(a[i]) for i in range(n)]}
        if n > 3:
            case["energy"] = float(sp.N(energy(n, th, thd).subs(at), 60))
        out.append(case)
    return out


def main():
    rng = random.Random(34)
    data = {"parameters": {k: float(v) for k, v in PARAMETERS.items()}}
    for n in (2, 3, 10):
        M, rhs, th, thd = equations(n)
        if n == 2:
            check_double(M, rhs)
        data[f"planar{n}"] = cases(n, M, rhs, th, thd, rng)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "chains.json")
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
        f.write("\n")
    print(f"wrote {path}: planar2 checked against the closed form")


main()
