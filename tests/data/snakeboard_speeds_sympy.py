"""Independent check of the snakeboard in generalized speeds (tests/speeds.rs):
Maggi's equations of the generated code against the Euler-Lagrange equations
with Lagrange multipliers, derived here with SymPy from the Lagrangian and the
wheels' no-slip constraints (nothing typed in from the generated model: the
kinematics are only used to turn a state (q, u) into q', and are checked to
satisfy the constraints exactly).

The snakeboard (Ostrowski; Bloch, sec. 1.x) rides on a belt moving along x at
velocity V(t) = b t: body at (x, y) with heading theta, rotor angle psi, wheel
axles at +-l along the body turned by +-phi; the wheels roll without slipping
relative to the belt. Inputs: torques tau_psi on the rotor and tau_phi on the
wheels; a viscous drag -c x' on x. Speeds: xi (the body's forward speed
relative to the belt), w_psi = psi', w_phi = phi'; kinematics
  x' = xi cos(theta) + b t, y' = xi sin(theta), theta' = xi tan(phi)/l.

At 24 random states (exact rationals, evaluated at 40 digits) it writes u' and
the reaction forces E - Q = C^T lambda to tests/data/snakeboard_speeds.json.

usage: python3 tests/data/snakeboard_speeds_sympy.py   (a few seconds)"""
import json
import os
import random
import sympy as sp

t = sp.symbols('t')
m, J, Jr, Jw, l, c, b = sp.symbols('m J Jr Jw l c b', positive=True)
tau_psi, tau_phi = sp.symbols('tau_psi tau_phi')
x, y, th, psi, phi = [sp.Function(n)(t) for n in ('x', 'y', 'theta', 'psi', 'phi')]
q = sp.Matrix([x, y, th, psi, phi])
qd = q.diff(t)
qdd = qd.diff(t)

# kinetic energy: body, rotor (on the body's rotation), two wheels turned +-phi
L = (m * (qd[0]**2 + qd[1]**2) / 2 + J * qd[2]**2 / 2 + Jr * (qd[2] + qd[3])**2 / 2
     + Jw * (qd[2] + qd[4])**2 / 2 + Jw * (qd[2] - qd[4])**2 / 2)
Q = sp.Matrix([-c * qd[0], 0, 0, tau_psi, tau_phi])

# no slip of each wheel relative to the belt: the wheel point's velocity
# relative to the belt has no component along the axle's normal
V = b * t
def wheel_constraint(offset, angle):
    # wheel point: (x, y) + offset (cos theta, sin theta); direction theta + angle
    px = qd[0] - offset * sp.sin(th) * qd[2] - V
    py = qd[1] + offset * sp.cos(th) * qd[2]
    return -sp.sin(th + angle) * px + sp.cos(th + angle) * py
cons = sp.Matrix([wheel_constraint(l, phi), wheel_constraint(-l, -phi)])
C = cons.jacobian(qd)
c0 = sp.simplify(cons - C * qd)            # the affine part (the belt)

EL = (sp.Matrix([L]).jacobian(qd).T).diff(t) - sp.Matrix([L]).jacobian(q).T
M = EL.jacobian(qdd)
h = EL - M * qdd                           # E = M q'' + h; E - Q = C^T lambda
cdot_rest = ((C * qd + c0).diff(t)).subs({e: 0 for e in qdd})   # d/dt cons = C q'' + this

# plain symbols
Qs = sp.symbols('q0:5'); Vs = sp.symbols('v0:5')
def plain(e):
    e = e.subs({qdd[i]: 0 for i in range(5)}).subs({qd[i]: Vs[i] for i in range(5)})
    return e.subs({q[i]: Qs[i] for i in range(5)})
Mp, Cp, hp, rest = plain(M), plain(C), plain(h), plain(cdot_rest)
Qp = plain(Q)
consp = plain(cons)

# the kinematics of the Rust model, q' = S u + sigma
xi, wpsi, wphi = sp.symbols('xi w_psi w_phi')
qdot_of_u = sp.Matrix([xi * sp.cos(Qs[2]) + b * t, xi * sp.sin(Qs[2]),
                       xi * sp.tan(Qs[4]) / l, wpsi, wphi])
assert sp.simplify(consp.subs(dict(zip(Vs, qdot_of_u)))) == sp.zeros(2, 1), \
    "the kinematics violate the constraints"
S = qdot_of_u.jacobian([xi, wpsi, wphi])

params = {m: sp.Rational(3, 2), J: sp.Rational(1, 5), Jr: sp.Rational(3, 20),
          Jw: sp.Rational(1, 25), l: sp.Rational(2, 5), c: sp.Rational(1, 10),
          b: sp.Rational(3, 10)}
random.seed(12)
def rnd(lo, hi):
    return sp.Rational(random.randint(int(lo * 1000), int(hi * 1000)), 1000)

cases = []
for _ in range(24):
    tv = rnd(0, 3)
    qv = [rnd(-2, 2), rnd(-2, 2), rnd(-3.1, 3.1), rnd(-3, 3), rnd(-1.2, 1.2)]
    uv = [rnd(-2, 2), rnd(-3, 3), rnd(-2, 2)]
    inv = [rnd(-1, 1), rnd(-1, 1)]
    sub = dict(params)
    sub[t] = tv
    sub.update(dict(zip(Qs, qv)))
    sub.update({xi: uv[0], wpsi: uv[1], wphi: uv[2], tau_psi: inv[0], tau_phi: inv[1]})
    qdv = qdot_of_u.subs(sub)
    sub.update(dict(zip(Vs, qdv)))
    Mn = Mp.subs(sub).evalf(50)
    Cn = Cp.subs(sub).evalf(50)
    # [M  -C^T] [q'' ]   [Q - h ]
    # [C   0  ] [lam ] = [-rest ]
    A = sp.zeros(7, 7)
    A[:5, :5] = Mn
    A[:5, 5:] = -Cn.T
    A[5:, :5] = Cn
    rhs = sp.zeros(7, 1)
    rhs[:5, 0] = (Qp - hp).subs(sub).evalf(50)
    rhs[5:, 0] = -rest.subs(sub).evalf(50)
    sol = A.LUsolve(rhs)
    qddv, lam = sol[:5, 0], sol[5:, 0]
    # u' from q'' = S u' + (S' u + sigma'): least squares is exact here, as
    # q'' - (S' u + sigma') lies in the range of S; solve S^T S u' = S^T (..)
    Sn = S.subs(sub).evalf(50)
    Sdot_u_sigmadot = (qdot_of_u.jacobian(Qs) * qdv + qdot_of_u.diff(t)).subs(sub).evalf(50)
    r = qddv - Sdot_u_sigmadot
    udot = (Sn.T * Sn).LUsolve(Sn.T * r)
    assert max(abs(v) for v in (Sn * udot - r)) < 1e-35
    reaction = Cn.T * lam
    f = lambda v: float(sp.Float(v, 40))
    cases.append({
        't': f(tv), 'q': [f(v) for v in qv], 'u': [f(v) for v in uv],
        'inputs': [f(v) for v in inv], 'udot': [f(v) for v in udot],
        'reaction_forces': [f(v) for v in reaction],
    })

out = {
    'system': 'snakeboard on a belt, in generalized speeds (tests/speeds.rs)',
    'generated_by': 'tests/data/snakeboard_speeds_sympy.py',
    'parameters': {str(k): float(v) for k, v in params.items()},
    'cases': cases,
}
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'snakeboard_speeds.json')
with open(path, 'w') as fh:
    json.dump(out, fh, indent=1)
print(f'wrote {len(cases)} cases to {path}')
