"""Independent check of the differential-drive robot (examples/diff_drive.rs,
tests/diff_drive.rs): the wheel accelerations from the Euler-Lagrange
equations with Lagrange multipliers, derived here with SymPy from the bodies'
positions and angular velocities and from the no-slip condition at each
wheel's contact point (nothing is taken from the Rust model: there the
constraints are written as the textbook's unicycle kinematics, here they are
the velocity of the material point of each wheel touching the ground).

The robot: chassis of mass m, inertia Ic about its centre of mass (vertical
axis), centre of mass a distance d ahead of the axle midpoint (x, y), heading
theta; two wheels of radius r, mass mw, spin inertia Iw and diametral inertia
Id, at +-b along the axle (left at +b), turned by phi_l, phi_r about the axle
(positive forward). Inputs: torques tau_l, tau_r from the chassis on the
wheels, and viscous friction -c phi' at each wheel.

At 24 random states (exact rationals, solved at 50 digits) it writes the
wheel accelerations (phi_l'', phi_r'') and the reaction forces C^T lambda = E - Q
(one per coordinate: the ground's force on x, y, its moment on theta, phi_l, phi_r) to
tests/data/diff_drive.json, together with the closed form of the reduced
equations in the forward speed v and the turn rate w, checked symbolically:
  (m + 2 mw + 2 Iw/r^2) v' - m d w^2     = (tau_l + tau_r - c (phi_l' + phi_r'))/r
  (It + 2 b^2 Iw/r^2)   w' + m d w v     = b (tau_r - tau_l - c (phi_r' - phi_l'))/r
with It = Ic + m d^2 + 2 mw b^2 + 2 Id.

usage: python3 tests/data/diff_drive_sympy.py   (a few seconds)"""
import json
import os
import random
import sympy as sp

t = sp.symbols('t')
m, Ic, d, mw, Iw, Id, r, b, c = sp.symbols('m Ic d mw Iw Id r b c', positive=True)
tau_l, tau_r = sp.symbols('tau_l tau_r')
x, y, th, pl, pr = [sp.Function(n)(t) for n in ('x', 'y', 'theta', 'phi_l', 'phi_r')]
q = sp.Matrix([x, y, th, pl, pr])
qd = q.diff(t)
qdd = qd.diff(t)

ez = sp.Matrix([0, 0, 1])
heading = sp.Matrix([sp.cos(th), sp.sin(th), 0])     # forward
axle = sp.Matrix([-sp.sin(th), sp.cos(th), 0])        # to the left
O = sp.Matrix([x, y, 0])                              # axle midpoint (height dropped: constant)
G = O + d * heading                                   # chassis centre of mass
wheels = [(O + b * axle, pl), (O - b * axle, pr)]     # (centre, spin angle): left, right

def vel(p):
    return p.diff(t)

# kinetic energy: chassis translation and yaw, each wheel's translation and rotation
T = m * vel(G).dot(vel(G)) / 2 + Ic * qd[2]**2 / 2
for centre, spin in wheels:
    omega = qd[2] * ez + spin.diff(t) * axle          # yaw plus spin about the axle
    # inertia about the centre: Iw along the axle, Id across it (axle and ez are orthonormal)
    T += mw * vel(centre).dot(vel(centre)) / 2
    T += (Iw * omega.dot(axle)**2 + Id * omega.dot(ez)**2) / 2
L = T
Q = sp.Matrix([0, 0, 0, tau_l - c * qd[3], tau_r - c * qd[4]])

# no slip: the wheel's material point at the contact, centre - r ez, is at rest
rows = []
for centre, spin in wheels:
    omega = qd[2] * ez + spin.diff(t) * axle
    vc = vel(centre) + omega.cross(-r * ez)
    rows.append((sp.expand(vc.dot(heading)), sp.expand(vc.dot(axle))))
(long_l, lat_l), (long_r, lat_r) = rows
# the two wheels' lateral rows are one row: the axle is rigid
assert sp.simplify(lat_l - lat_r) == 0
cons = sp.Matrix([lat_l, long_l, long_r])
C = cons.jacobian(qd)
assert sp.simplify(cons - C * qd) == sp.zeros(3, 1)   # homogeneous

EL = (sp.Matrix([L]).jacobian(qd).T).diff(t) - sp.Matrix([L]).jacobian(q).T
M = EL.jacobian(qdd)
h = sp.expand(EL - M * qdd)                            # E = M q'' + h; E - Q = C^T lambda
cdot_rest = ((C * qd).diff(t)).subs({e: 0 for e in qdd})

# plain symbols
Qs = sp.symbols('q0:5')
Vs = sp.symbols('v0:5')
def plain(e):
    e = e.subs({qdd[i]: 0 for i in range(5)}).subs({qd[i]: Vs[i] for i in range(5)})
    return e.subs({q[i]: Qs[i] for i in range(5)})
Mp, Cp, hp, rest, Qp = plain(M), plain(C), plain(h), plain(cdot_rest), plain(Q)

# the velocities of a state (phi_l', phi_r'), from the contact rows
wl, wr = sp.symbols('w_l w_r')
vf = r * (wl + wr) / 2
yaw = r * (wr - wl) / (2 * b)
qdot_of_w = sp.Matrix([vf * sp.cos(Qs[2]), vf * sp.sin(Qs[2]), yaw, wl, wr])
assert sp.simplify(Cp.subs(dict(zip(Vs, qdot_of_w))) * qdot_of_w) == sp.zeros(3, 1)

# the closed form in (v, w), checked symbolically: project the Euler-Lagrange
# equations on the admissible velocities q' = S w (w = (phi_l', phi_r')),
# S^T (M q'' + h - Q) = 0 with q'' = S w' + S' w, and solve for w'
S = qdot_of_w.jacobian([wl, wr])
sub_v = dict(zip(Vs, qdot_of_w))
# S' w = d/dt (S w) at fixed w: S w is q' itself
Sdot_w = qdot_of_w.jacobian(Qs) * qdot_of_w
Mw = sp.simplify(S.T * Mp * S)
fw = sp.simplify(S.T * ((Qp - hp).subs(sub_v) - Mp * Sdot_w))
wdd = Mw.LUsolve(fw)
vdot = sp.simplify(r * (wdd[0] + wdd[1]) / 2)
wdot = sp.simplify(r * (wdd[1] - wdd[0]) / (2 * b))
It = Ic + m * d**2 + 2 * mw * b**2 + 2 * Id
v_closed = ((tau_l + tau_r - c * (wl + wr)) / r + m * d * yaw**2) / (m + 2 * mw + 2 * Iw / r**2)
w_closed = (b * (tau_r - tau_l - c * (wr - wl)) / r - m * d * yaw * vf) / (It + 2 * b**2 * Iw / r**2)
assert sp.simplify(vdot - v_closed) == 0, sp.simplify(vdot - v_closed)
assert sp.simplify(wdot - w_closed) == 0, sp.simplify(wdot - w_closed)

# the Euler-Lagrange equations with multipliers, solved at each state below:
# [M  -C^T] [q''] = [Q - h]
# [C   0  ] [lam]   [-C' q']
A = sp.zeros(8, 8)
A[:5, :5] = Mp
A[:5, 5:] = -Cp.T
A[5:, :5] = Cp
rhs = sp.zeros(8, 1)
rhs[:5, 0] = Qp - hp
rhs[5:, 0] = -rest

params = {m: sp.Rational(12), Ic: sp.Rational(3, 10), d: sp.Rational(1, 10),
          mw: sp.Rational(1, 2), Iw: sp.Rational(5, 8000), Id: sp.Rational(5, 16000),
          r: sp.Rational(1, 20), b: sp.Rational(3, 20), c: sp.Rational(1, 100)}
random.seed(15)
def rnd(lo, hi):
    return sp.Rational(random.randint(int(lo * 1000), int(hi * 1000)), 1000)

cases = []
for _ in range(24):
    qv = [rnd(-3, 3), rnd(-3, 3), rnd(-3.1, 3.1), rnd(-6, 6), rnd(-6, 6)]
    wv = [rnd(-30, 30), rnd(-30, 30)]
    inv = [rnd(-2, 2), rnd(-2, 2)]
    sub = dict(params)
    sub.update(dict(zip(Qs, qv)))
    sub.update({wl: wv[0], wr: wv[1], tau_l: inv[0], tau_r: inv[1]})
    sub.update(dict(zip(Vs, qdot_of_w.subs(sub))))
    An = A.subs(sub).evalf(50)
    bn = rhs.subs(sub).evalf(50)
    s = An.LUsolve(bn)
    lam = s[5:, 0]
    # the closed form at the same state, as a second check of the solve
    cv = v_closed.subs(sub).evalf(50)
    assert abs(r.subs(params) * (s[3] + s[4]) / 2 - cv) < 1e-40
    f = lambda v: float(sp.Float(v, 40))
    cases.append({
        'q': [f(v) for v in qv], 'rdot': [f(v) for v in wv], 'inputs': [f(v) for v in inv],
        'accelerations': [f(s[3]), f(s[4])],
        'reaction_forces': [f(v) for v in (Cp.subs(sub).evalf(50).T * lam)],
    })

out = {
    'system': 'differential-drive robot, centre of mass ahead of the axle (tests/diff_drive.rs)',
    'generated_by': 'tests/data/diff_drive_sympy.py',
    'coordinates': ['x', 'y', 'theta', 'phi_l', 'phi_r'],
    'parameters': {str(k): float(v) for k, v in params.items()},
    'cases': cases,
}
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'diff_drive.json')
with open(path, 'w') as fh:
    json.dump(out, fh, indent=1)
print(f'wrote {len(cases)} cases to {path}')
