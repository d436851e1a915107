"""Independent references for the forward sensitivities (tests/sensitivities.rs):
derivatives of whole motions with respect to the parameters and the initial
state, computed here without the macro.

1. The damped oscillator m x'' + c x' + k x = 0 (underdamped), x(0) = x0,
   x'(0) = v0: its closed form
       x(t) = exp(-gamma t) (x0 cos(w t) + (v0 + gamma x0)/w sin(w t)),
       gamma = c/(2m), w = sqrt(k/m - gamma^2),
   differentiated symbolically by m, c, k, x0 and v0 and evaluated at 40 digits.

2. The rolling disc of the thesis, section 6, from its closed form
   (6.60)-(6.62) (C. Flygare 2012) and the rolling constraints (6.27)-(6.28):
       theta'' = 4 cos(psi) phi' psi' / (4 sin^2 psi + 3)
       phi''   = -4 sin(2 psi) phi' psi' / (4 sin^2 psi + 3)
       psi''   = 4 (R (sin(psi) phi' - theta') cos(psi) phi' + g sin(psi)) / (5 R)
       x' = R cos(phi) theta',  y' = R sin(phi) theta'
   with state X = (theta, phi, psi, x, y, theta', phi', psi'). The variational
   equations S' = (df/dX) S + [df/dp | 0], S(0) = [0 | I], p = (m, R, g), are
   derived here with SymPy and integrated with the classical Runge-Kutta
   method at 4000 and 8000 fixed steps in double precision, extrapolated
   (Richardson): a method and code that share nothing with the crate's.

Writes tests/data/sensitivities.json (numbers as strings, 17 significant digits).

usage: python3 tests/data/sensitivities_sympy.py   (a few seconds on a quiet machine)"""
import json
import os

import mpmath
import sympy as sp

mpmath.mp.dps = 30


def s17(v):
    return mpmath.nstr(mpmath.mpf(v), 17, strip_zeros=False)


def oscillator():
    m, c, k, x0, v0, t = sp.symbols('m c k x0 v0 t', positive=True)
    gamma = c / (2 * m)
    w = sp.sqrt(k / m - gamma**2)
    x = sp.exp(-gamma * t) * (x0 * sp.cos(w * t) + (v0 + gamma * x0) / w * sp.sin(w * t))
    v = sp.diff(x, t)
    assert sp.simplify(sp.diff(x, t, 2) * m + c * v + k * x) == 0
    assert sp.simplify(x.subs(t, 0) - x0) == 0 and sp.simplify(v.subs(t, 0) - v0) == 0
    values = {m: sp.Rational(13, 10), c: sp.Rational(4, 10), k: sp.Rational(7, 2),
              x0: sp.Rational(3, 10), v0: sp.Rational(-2, 10), t: sp.Integer(2)}
    state = [x, v]
    by = [m, c, k, x0, v0]
    return {
        'parameters': {'m': '1.3', 'c': '0.4', 'k': '3.5'},
        'x0': ['0.3', '-0.2'],
        't1': '2',
        'x': [s17(sp.N(e.subs(values), 40)) for e in state],
        # rows: the state; columns: m, c, k, then x0, v0
        'dx_dp': [[s17(sp.N(sp.diff(e, z).subs(values), 40)) for z in by[:3]] for e in state],
        'dx_dx0': [[s17(sp.N(sp.diff(e, z).subs(values), 40)) for z in by[3:]] for e in state],
    }


def disc():
    m, R, g = sp.symbols('m R g', positive=True)
    X = sp.symbols('theta phi psi x y dtheta dphi dpsi')
    th, ph, ps, x, y, td, pd, sd = X
    den = 4 * sp.sin(ps)**2 + 3
    f = sp.Matrix([
        td, pd, sd,
        R * sp.cos(ph) * td,
        R * sp.sin(ph) * td,
        4 * sp.cos(ps) * pd * sd / den,
        -4 * sp.sin(2 * ps) * pd * sd / den,
        4 * (R * (sp.sin(ps) * pd - td) * sp.cos(ps) * pd + g * sp.sin(ps)) / (5 * R),
    ])
    params = [m, R, g]
    D, P = 8, 3
    J = f.jacobian(X)
    Fp = f.jacobian(params)
    S = sp.Matrix(D, P + D, lambda i, j: sp.Symbol(f's_{i}_{j}'))
    dS = J * S + Fp.row_join(sp.zeros(D, D))
    values = {m: sp.Rational(17, 10), R: sp.Rational(35, 100), g: sp.Rational(981, 100)}
    args = list(X) + list(S)
    rhs = sp.lambdify(args, list(f.subs(values)) + list(dS.subs(values)), 'math', cse=True)
    x0 = ['0', '0', '0.3', '0', '0', '6', '20', '0.5']
    s0 = [1.0 if j == P + i else 0.0 for i in range(D) for j in range(P + D)]
    y0 = [float(v) for v in x0] + s0
    t1 = 1

    def rk4(steps):
        h = t1 / steps
        y = list(y0)
        for _ in range(steps):
            k1 = rhs(*y)
            k2 = rhs(*[a + h / 2 * b for a, b in zip(y, k1)])
            k3 = rhs(*[a + h / 2 * b for a, b in zip(y, k2)])
            k4 = rhs(*[a + h * b for a, b in zip(y, k3)])
            y = [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(y, k1, k2, k3, k4)]
        return y

    # classical RK4 at two step sizes; Richardson's extrapolation removes the
    # h^4 term, and the two agree to the rounding of double precision
    coarse, fine = rk4(4000), rk4(8000)
    z = [b + (b - a) / 15 for a, b in zip(coarse, fine)]
    spread = max(abs(b - a) / max(1.0, abs(b)) for a, b in zip(coarse, fine))
    print(f'disc: RK4 with 4000 and 8000 steps differ by {spread:.1e} (relative); extrapolated')
    assert spread < 1e-10
    xs, ss = z[:D], z[D:]
    ss = [[ss[i * (P + D) + j] for j in range(P + D)] for i in range(D)]
    return {
        'parameters': {'m': '1.7', 'R': '0.35', 'g': '9.81'},
        'x0': x0,
        't1': str(t1),
        'x': [repr(v) for v in xs],
        'dx_dp': [[repr(ss[i][j]) for j in range(P)] for i in range(D)],
        'dx_dx0': [[repr(ss[i][P + j]) for j in range(D)] for i in range(D)],
    }


if __name__ == '__main__':
    out = {'oscillator': oscillator(), 'thesis_disc': disc()}
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'sensitivities.json')
    with open(path, 'w') as fh:
        json.dump(out, fh, indent=1)
        fh.write('\n')
    print('wrote', path)
