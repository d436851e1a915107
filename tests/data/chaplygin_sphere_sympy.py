"""Independent reference for the Chaplygin sphere: a ball of radius r rolling
without slipping on the plane z = 0 (gravity -g e_z), its centre of mass offset
by b = (b1, b2, b3) from the geometric centre (body axes) and a full inertia
tensor I about the centre of mass (body axes, products of inertia included as
the tensor entries: I = [[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]]).
Coordinates (yaw, pitch, roll, x, y), rotation body -> world
Rot = Rz(yaw) Ry(pitch) Rx(roll), geometric centre C = (x, y, r), centre of mass
G = C + Rot b. Nothing is typed in from the Rust model.

The accelerations q'' (all five coordinates) are derived twice, and the two
must agree to 1e-30 relative at every state:
 (a) Euler-Lagrange with multipliers from L = m/2 |G'|^2 + 1/2 w_b.I w_b - m g G_z
     (w_b from Rot^T Rot'), the constraints v_C + w x (-r e_z) = 0 (x, y
     components; the z component is checked to vanish), solving
     [M -C^T; C 0] [q''; lambda] = [-h; -C' q'];
 (b) sympy.physics.mechanics: orient_body_fixed 'ZYX' (checked against Rot),
     point velocities, a RigidBody with inertia(...) including the products,
     KanesMethod with x', y' as dependent speeds.
At 24 random states (each with its own random parameters; exact rationals drawn
from random.Random(2026), evaluated at 40 digits) it writes q, (yaw', pitch',
roll'), the full q' (x', y' from the constraints), q'' and the energy
E = T + V to tests/data/chaplygin_sphere.json; it also checks that
dE/dt = 0 along (a)'s q'' (the contact force does no work).

usage: python3 tests/data/chaplygin_sphere_sympy.py   (about 10 s)"""
import json
import math
import os
import random
import time
import mpmath
import sympy as sp
import sympy.physics.mechanics as me

DPS = 40
mpmath.mp.dps = DPS
t0 = time.time()

PNAMES = ['m', 'r', 'g', 'b1', 'b2', 'b3', 'I11', 'I22', 'I33', 'I12', 'I13', 'I23']
QNAMES = ['yaw', 'pitch', 'roll', 'x', 'y']
P = sp.symbols(PNAMES)
m, r, g, b1, b2, b3, I11, I22, I33, I12, I13, I23 = P
Itens = sp.Matrix([[I11, I12, I13], [I12, I22, I23], [I13, I23, I33]])
bvec = sp.Matrix([b1, b2, b3])


def Rz(u): return sp.Matrix([[sp.cos(u), -sp.sin(u), 0], [sp.sin(u), sp.cos(u), 0], [0, 0, 1]])
def Ry(u): return sp.Matrix([[sp.cos(u), 0, sp.sin(u)], [0, 1, 0], [-sp.sin(u), 0, sp.cos(u)]])
def Rx(u): return sp.Matrix([[1, 0, 0], [0, sp.cos(u), -sp.sin(u)], [0, sp.sin(u), sp.cos(u)]])


# ---------------------------------------------------------------- (a) multipliers
Qs = sp.Matrix(sp.symbols('yaw pitch roll x y'))      # q
Vs = sp.Matrix(sp.symbols('yaw_d pitch_d roll_d x_d y_d'))  # q'
yaw, pitch, roll, x, y = Qs
Rot = Rz(yaw) * Ry(pitch) * Rx(roll)


def ddt(e):  # time derivative of an expression in q, q' only through q (chain rule)
    return sum((e.diff(Qs[i]) * Vs[i] for i in range(5)), sp.zeros(*e.shape))


W = (Rot.T * ddt(Rot)).applyfunc(sp.simplify)        # skew: body angular velocity
assert (W + W.T).applyfunc(sp.simplify) == sp.zeros(3, 3)
w_body = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
w_world = (Rot * w_body).applyfunc(sp.simplify)
Cpos = sp.Matrix([x, y, r])
G = Cpos + Rot * bvec
Gd = ddt(G)
T = m / 2 * (Gd.T * Gd)[0] + (w_body.T * Itens * w_body)[0] / 2
V = m * g * G[2]
L = T - V
E = T + V

vP = ddt(Cpos) + w_world.cross(sp.Matrix([0, 0, -r]))  # velocity of the contact material point
assert sp.simplify(vP[2]) == 0
cons = sp.Matrix([vP[0], vP[1]])
Cm = cons.jacobian(Vs)
assert Cm[:, 3:] == sp.eye(2) and not Cm.free_symbols & set(Vs)
Cd_qd = ddt(Cm * Vs)                                  # C' q'

p = sp.Matrix([L]).jacobian(Vs).T                     # dL/dq'
M = p.jacobian(Vs)                                    # EL = M q'' + h
h = p.jacobian(Qs) * Vs - sp.Matrix([L]).jacobian(Qs).T

args_a = list(P) + list(Qs) + list(Vs)
f_M = sp.lambdify(args_a, M, 'mpmath', cse=True)
f_h = sp.lambdify(args_a, h, 'mpmath', cse=True)
f_C = sp.lambdify(args_a, Cm, 'mpmath', cse=True)
f_Cd = sp.lambdify(args_a, Cd_qd, 'mpmath', cse=True)
f_E = sp.lambdify(args_a, E, 'mpmath', cse=True)
As = sp.Matrix(sp.symbols('yaw_dd pitch_dd roll_dd x_dd y_dd'))
Ed = ddt(sp.Matrix([E]))[0] + (sp.Matrix([E]).jacobian(Vs) * As)[0]   # dE/dt
f_Ed = sp.lambdify(args_a + list(As), Ed, 'mpmath', cse=True)
t_a = time.time() - t0

# ---------------------------------------------------------------- (b) Kane
qk = me.dynamicsymbols('yaw pitch roll x y')
uk = me.dynamicsymbols('u1:6')
N = me.ReferenceFrame('N')
B = me.ReferenceFrame('B')
B.orient_body_fixed(N, (qk[0], qk[1], qk[2]), 'ZYX')
O = me.Point('O')
O.set_vel(N, 0)
Cp = O.locatenew('C', qk[3] * N.x + qk[4] * N.y + r * N.z)
Cp.set_vel(N, Cp.pos_from(O).dt(N))
Gp = Cp.locatenew('G', b1 * B.x + b2 * B.y + b3 * B.z)
Gp.v2pt_theory(Cp, N, B)
Pc = Cp.locatenew('P', -r * N.z)                      # contact material point of the ball
Pc.v2pt_theory(Cp, N, B)
kd = [qk[i].diff(me.dynamicsymbols._t) - uk[i] for i in range(5)]
kd_map = {qk[i].diff(me.dynamicsymbols._t): uk[i] for i in range(5)}
vc = [Pc.vel(N).dot(N.x).subs(kd_map), Pc.vel(N).dot(N.y).subs(kd_map)]
assert sp.simplify(Pc.vel(N).dot(N.z)) == 0
ball = me.RigidBody('ball', Gp, B, m, (me.inertia(B, I11, I22, I33, ixy=I12, iyz=I23, izx=I13), Gp))
kane = me.KanesMethod(N, q_ind=qk, u_ind=uk[:3], u_dependent=uk[3:], kd_eqs=kd,
                      velocity_constraints=vc)
kane.kanes_equations([ball], [(Gp, -m * g * N.z)])
plain = {**{qk[i]: Qs[i] for i in range(5)}, **{uk[i]: Vs[i] for i in range(5)}}
MK = kane.mass_matrix.xreplace(plain)                 # 5x5 in u' (incl. d/dt of the constraints)
FK = kane.forcing.xreplace(plain)
assert MK.shape == (5, 5) and not (MK.atoms(sp.Derivative) | FK.atoms(sp.Derivative))
assert (MK.free_symbols | FK.free_symbols) <= set(args_a)
f_MK = sp.lambdify(args_a, MK, 'mpmath', cse=True)
f_FK = sp.lambdify(args_a, FK, 'mpmath', cse=True)

# the frame's orientation must be exactly Rot (columns = body axes in world components)
Rot_k = sp.Matrix([[B_ax.dot(n_ax) for B_ax in (B.x, B.y, B.z)] for n_ax in (N.x, N.y, N.z)]).xreplace(plain)
chk = {yaw: sp.Rational('0.7'), pitch: sp.Rational('-0.4'), roll: sp.Rational('1.1')}
assert max(abs(v) for v in sp.N((Rot_k - Rot).subs(chk), 50)) < 1e-45
t_b = time.time() - t0 - t_a


# ---------------------------------------------------------------- random states
rng = random.Random(2026)


def dec(lo, hi, nd):  # a decimal string with nd decimals in [lo, hi]
    return f"{rng.uniform(lo, hi):.{nd}f}"


def rot3(a, b_, c):  # float rotation, for drawing the inertia tensor only
    ca, sa, cb, sb, cc, sc = math.cos(a), math.sin(a), math.cos(b_), math.sin(b_), math.cos(c), math.sin(c)
    Rzf = [[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]]
    Ryf = [[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]]
    Rxf = [[1, 0, 0], [0, cc, -sc], [0, sc, cc]]
    mul = lambda A, Bm: [[sum(A[i][k] * Bm[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return mul(mul(Rzf, Ryf), Rxf)


def draw_params():
    ms = dec(0.5, 3, 4)
    rs = dec(0.1, 0.5, 4)
    mr, rr = sp.Rational(ms), sp.Rational(rs)
    bs = [f"{rng.uniform(-0.3, 0.3) * float(rr):.5f}" for _ in range(3)]
    while True:
        # principal moments in [0.3, 0.5] m r^2 (triangle inequality holds), randomly rotated
        d = [rng.uniform(0.3, 0.5) * float(mr * rr**2) for _ in range(3)]
        Rf = rot3(rng.uniform(-math.pi, math.pi), rng.uniform(-1.5, 1.5), rng.uniform(-math.pi, math.pi))
        If = [[sum(Rf[i][k] * d[k] * Rf[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
        Is = [f"{v:.6g}" for v in (If[0][0], If[1][1], If[2][2], If[0][1], If[0][2], If[1][2])]
        Iq = [sp.Rational(s) for s in Is]
        Im = sp.Matrix([[Iq[0], Iq[3], Iq[4]], [Iq[3], Iq[1], Iq[5]], [Iq[4], Iq[5], Iq[2]]])
        pd = all(Im[:k, :k].det() > 0 for k in (1, 2, 3))
        if pd and all(v != 0 for v in Iq[3:]):
            break
    return [ms, rs, '9.81'] + bs + Is


def mpf(s):  # exact decimal string -> mpf at working precision
    return mpmath.mpf(sp.Rational(s).p) / sp.Rational(s).q


cases = []
worst = 0
for k in range(24):
    ps = draw_params()
    qs = [dec(-3, 3, 5), dec(-1.2, 1.2, 5), dec(-1.2, 1.2, 5), dec(-2, 2, 5), dec(-2, 2, 5)]
    rds = [dec(-5, 5, 5) for _ in range(3)]
    pv, qv, rdv = [mpf(s) for s in ps], [mpf(s) for s in qs], [mpf(s) for s in rds]
    # x', y' from the constraints (C[:, 3:] = I; C does not depend on q')
    Cn = mpmath.matrix(f_C(*pv, *qv, 0, 0, 0, 0, 0))
    sd = -(Cn[:, :3] * mpmath.matrix(rdv))
    vv = rdv + [sd[0], sd[1]]
    a = pv + qv + vv
    assert mpmath.mnorm(Cn * mpmath.matrix(vv), 1) < mpmath.mpf(10)**(-DPS + 5)
    # (a)
    Mn, hn, Cdn = mpmath.matrix(f_M(*a)), mpmath.matrix(f_h(*a)), mpmath.matrix(f_Cd(*a))
    K = mpmath.zeros(7, 7)
    rhs = mpmath.zeros(7, 1)
    for i in range(5):
        for j in range(5):
            K[i, j] = Mn[i, j]
        for j in range(2):
            K[i, 5 + j] = -Cn[j, i]
            K[5 + j, i] = Cn[j, i]
        rhs[i] = -hn[i]
    for j in range(2):
        rhs[5 + j] = -Cdn[j]
    qdd_a = mpmath.lu_solve(K, rhs)[:5]
    # (b)
    qdd_b = mpmath.lu_solve(mpmath.matrix(f_MK(*a)), mpmath.matrix(f_FK(*a)))
    rel = max(abs(qdd_a[i] - qdd_b[i]) / max(abs(qdd_a[i]), abs(qdd_b[i])) for i in range(5))
    assert rel < mpmath.mpf('1e-30'), (k, rel)
    worst = max(worst, rel)
    en = f_E(*a)
    assert abs(f_Ed(*a, *qdd_a)) < mpmath.mpf(10)**(-DPS + 8) * (1 + abs(en))
    cases.append({"params": [float(s) for s in ps], "q": [float(s) for s in qs],
                  "rdot": [float(s) for s in rds], "qdot": [float(s) for s in rds] + [float(sd[0]), float(sd[1])],
                  "qddot": [float(qdd_a[i]) for i in range(5)], "energy": float(en)})
    print(f"case {k:2d}: q'' = " + ", ".join(f"{float(qdd_a[i]): .6e}" for i in range(5))
          + f"; (a)-(b) rel {float(rel):.1e}")

out = {
    "description": "Chaplygin sphere (ball of radius r rolling without slipping on z = 0, gravity -g e_z, centre "
                   "of mass at C + Rot b, full inertia tensor I about the centre of mass in body axes, "
                   "I = [[I11,I12,I13],[I12,I22,I23],[I13,I23,I33]]). Rot = Rz(yaw) Ry(pitch) Rx(roll) body -> "
                   "world, C = (x, y, r). rdot = (yaw', pitch', roll'), qdot = all five q' (x', y' from the "
                   "rolling constraints), qddot = all five q''; energy = T + V with V = m g G_z. Derived by "
                   "tests/data/chaplygin_sphere_sympy.py twice (Euler-Lagrange with multipliers; "
                   "sympy.physics.mechanics KanesMethod), agreeing to %.1e relative, evaluated at %d digits."
                   % (float(worst), DPS),
    "parameters": PNAMES,
    "coordinates": QNAMES,
    "cases": cases,
}
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'chaplygin_sphere.json')
with open(path, 'w') as f:
    json.dump(out, f, indent=1)
    f.write('\n')
print(f"derivation (a) {t_a:.1f} s, (b) {t_b:.1f} s, total {time.time() - t0:.1f} s; "
      f"max (a)-(b) relative difference {float(worst):.2e}; wrote {path}")
