"""Independent reference for the functions of the language (tests/functions.rs):
the accelerations of systems whose Lagrangians use atan2, abs, cot, sec, csc,
sinh, cosh, tanh, asin, acos and atan, from the Euler-Lagrange equations
derived here with SymPy (exact symbolic derivatives; SymPy's derivative of
Abs(u) for real u is sign(u) u'), evaluated to 30 digits (SymPy's N, on mpmath).

Systems (the same Lagrangians as in tests/functions.rs):
- gauntlet: a particle in the plane, q = (x, y), with a position-dependent
  inertia cosh(y)^2 on y and a potential using every function;
- polar_spring: a particle in the plane held by a torsion spring on its polar
  angle atan2(y, x) and a radial spring on sqrt(x^2 + y^2).

usage: python3 tests/data/functions_sympy.py > tests/data/functions.json"""
import json
import sympy as sp

t = sp.symbols('t')
m, k = sp.Rational(3, 2), sp.Rational(7, 10)


def accelerations(L, q, qd, points):
    """q'' from d/dt dL/dq' - dL/dq = 0 at each (q, q') point."""
    n = len(q)
    acc = sp.symbols('a0:%d' % n)
    p = sp.symbols('p0:%d' % n, real=True)
    v = sp.symbols('v0:%d' % n, real=True)
    # replace the functions of time by plain symbols before differentiating
    Lp = L.subs({qd[i]: v[i] for i in range(n)}).subs({q[i]: p[i] for i in range(n)})
    eqs = []
    for i in range(n):
        dv = sp.diff(Lp, v[i])
        # total time derivative: sum d/dp_j p'_j + d/dv_j v'_j
        ddt = sum(sp.diff(dv, p[j]) * v[j] + sp.diff(dv, v[j]) * acc[j] for j in range(n))
        eqs.append(ddt - sp.diff(Lp, p[i]))
    out = []
    for (qv, vv) in points:
        vals = {p[i]: sp.Rational(qv[i]) for i in range(n)}
        vals.update({v[i]: sp.Rational(vv[i]) for i in range(n)})
        sol = sp.solve([e.subs(vals) for e in eqs], acc, dict=True)[0]
        out.append({
            'q': qv, 'qdot': vv,
            'qddot': [sp.N(sol[acc[i]], 30).__str__() for i in range(n)],
        })
    return out


x, y = [sp.Function(n)(t) for n in ('x', 'y')]
xd, yd = x.diff(t), y.diff(t)

gauntlet_V = k * (sp.atan2(y, x + 2) + sp.Abs(x * y - sp.Rational(1, 5)) + sp.cot(x + 1)
                  + sp.sec(y / 2) + sp.csc(x + 2) + sp.sinh(x * y) + sp.tanh(x - y)
                  + sp.asin(x / 3) + sp.acos(y / 4) + sp.atan(x * y))
gauntlet_L = m / 2 * (xd**2 + sp.cosh(y)**2 * yd**2) - gauntlet_V
gauntlet_points = [
    (['3/10', '1/2'], ['7/10', '-2/5']),
    (['-3/5', '11/10'], ['-1/5', '9/10']),
    (['9/10', '-4/5'], ['1/2', '3/10']),
]

polar_L = m / 2 * (xd**2 + yd**2) - k * sp.atan2(y, x)**2 / 2 - sp.sqrt(x**2 + y**2)
polar_points = [
    (['1', '1/2'], ['0', '1']),
    (['-1', '1/2'], ['1/3', '-1/4']),
    (['-7/10', '-3/2'], ['2', '1/2']),
]

print(json.dumps({
    'm': str(m), 'k': str(k),
    'gauntlet': accelerations(gauntlet_L, [x, y], [xd, yd], gauntlet_points),
    'polar_spring': accelerations(polar_L, [x, y], [xd, yd], polar_points),
}, indent=1))
