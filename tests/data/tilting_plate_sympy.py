"""Independent reference for a homogeneous ball rolling without slipping on a
plate that a joint tilts (tests/supports.rs, `TiltingPlate`), derived here from
scratch with SymPy; nothing is typed in from the Rust model.

Model (world z up, gravity -g e_z; Rx, Ry, Rz the elementary rotations):
  q = (beta, x, y, z, a, b, c).
  plate: orientation Rp = Rx(beta) about the fixed origin O, kinetic energy
         Jx/2 beta'^2; the generalized force u acts on beta (input torque).
  ball:  radius r, mass m, inertia 2/5 m r^2 about any axis through its centre
         G = (x, y, z), orientation R = Rz(a) Ry(b) Rx(c); world angular
         velocity w from [w]x = R' R^T.
  L = m/2 |G'|^2 + 1/2 (2/5 m r^2) |w|^2 + Jx/2 beta'^2 - m g z.
  plate plane z' = 0: N = Rp e_z, T1 = Rp e_x, T2 = Rp e_y; contact P = G - r N.
  constraint rows (all linear in q', A(q) q' = 0):
    row 0: d/dt [ (G - O).N - r ]                   (holonomic, differentiated once)
    row 1: T1 . (v_ball(P) - v_plate(P))             (no slip)
    row 2: T2 . (v_ball(P) - v_plate(P))             (no slip)
    with v_ball(P) = G' + w x (P - G), v_plate(P) = (beta' e_x) x (P - O).
  Lagrange-d'Alembert:  d/dt dL/dq' - dL/dq = Q + A^T lambda,  Q = (u, 0, ..., 0),
    A q'' + A' q' = 0, solved as [M -A^T; A 0] [q''; lambda] = [Q - h; -A' q'].
  Sign convention: lambda_k multiplies row k of A with a PLUS sign on the right
  hand side, i.e. A^T lambda is the generalized constraint force on the system.
  lambda_0 is then the normal force of the plate on the ball along +N,
  lambda_1 and lambda_2 the friction force of the plate on the ball along +T1
  and +T2 (the plate feels the opposite forces at P).

Cross-checks done by this script (all asserted):
 (K) the full q'' again from sympy.physics.mechanics KanesMethod (x', y', z'
     dependent speeds, the three rows as velocity constraints), to 1e-40;
 (E) energy balance dE/dt = u beta' along q'' (E = T + V);
 (F) a separate derivation with the plate fixed (beta a parameter, six
     coordinates x, y, z, a, b, c): a ball released from rest accelerates
     down the slope at 5/7 g sin(beta); the full model agrees with it when u
     holds the plate (beta'' = 0) and tends to it as Jx -> infinity.

Parameters r = 0.1, m = 0.5, Jx = 0.3, g = 9.81 (exact rationals); states drawn
from random.Random(20250611) as exact decimals; evaluated with mpmath at
DPS = 50 digits (more than the 30 asked for, so that the 30 digits written are
all correct); numbers written as strings with 30 significant digits.

usage (from the repository root): python3 tests/data/tilting_plate_sympy.py
writes tests/data/tilting_plate.json (about 10-20 s)."""
import json
import os
import random
import time

import mpmath
import sympy as sp
import sympy.physics.mechanics as me

DPS = 50
DIG = 30
mpmath.mp.dps = DPS
t0 = time.time()

PNAMES = ['r', 'm', 'Jx', 'g']
PVALS = ['0.1', '0.5', '0.3', '9.81']
QNAMES = ['beta', 'x', 'y', 'z', 'a', 'b', 'c']
P = sp.symbols(PNAMES)
r, m, Jx, g = P
u = sp.Symbol('u')


def Rx(s): return sp.Matrix([[1, 0, 0], [0, sp.cos(s), -sp.sin(s)], [0, sp.sin(s), sp.cos(s)]])
def Ry(s): return sp.Matrix([[sp.cos(s), 0, sp.sin(s)], [0, 1, 0], [-sp.sin(s), 0, sp.cos(s)]])
def Rz(s): return sp.Matrix([[sp.cos(s), -sp.sin(s), 0], [sp.sin(s), sp.cos(s), 0], [0, 0, 1]])


ex, ey, ez = sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0]), sp.Matrix([0, 0, 1])

# ============================================================ (A) full model, multipliers
Qs = sp.Matrix(sp.symbols('beta x y z a b c'))
Vs = sp.Matrix(sp.symbols('beta_d x_d y_d z_d a_d b_d c_d'))
As = sp.Matrix(sp.symbols('beta_dd x_dd y_dd z_dd a_dd b_dd c_dd'))
beta, x, y, z, a, b, c = Qs
n = 7


def ddt(e, Q=Qs, V=Vs):  # partial time derivative through q only (q' held): sum d e/dq_i q'_i
    return sum((e.diff(Q[i]) * V[i] for i in range(len(Q))), sp.zeros(*e.shape))


Rb = Rz(a) * Ry(b) * Rx(c)
W = (ddt(Rb) * Rb.T).applyfunc(sp.simplify)            # [w]x, world components
assert (W + W.T).applyfunc(sp.simplify) == sp.zeros(3, 3)
w = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
Rp = Rx(beta)
Nn, T1, T2 = Rp * ez, Rp * ex, Rp * ey
Gv = sp.Matrix([x, y, z])
Gd = ddt(Gv)
Ib = sp.Rational(2, 5) * m * r**2
T = m / 2 * (Gd.T * Gd)[0] + Ib / 2 * (w.T * w)[0] + Jx / 2 * Vs[0]**2
V = m * g * z
L = T - V
E = T + V

hol = (Gv.T * Nn)[0] - r                                # (G - O).N - r, O = 0
Pc = Gv - r * Nn
v_ball = Gd + w.cross(Pc - Gv)
w_p = Vs[0] * ex
v_plate = w_p.cross(Pc)
v_rel = v_ball - v_plate
rows = sp.Matrix([ddt(sp.Matrix([hol]))[0], (T1.T * v_rel)[0], (T2.T * v_rel)[0]])
A = rows.jacobian(Vs)
assert not (A.free_symbols & set(Vs))
assert (A * Vs - rows).applyfunc(sp.expand) == sp.zeros(3, 1)   # rows are linear, homogeneous in q'
Ad_qd = ddt(A * Vs)                                     # A' q'
rows_dot = A * As + Ad_qd                               # d/dt of the rows

pL = sp.Matrix([L]).jacobian(Vs).T
M = pL.jacobian(Vs)
assert not (M.free_symbols & set(Vs))
h = pL.jacobian(Qs) * Vs - sp.Matrix([L]).jacobian(Qs).T   # EL = M q'' + h
Qgen = sp.Matrix([u, 0, 0, 0, 0, 0, 0])
Edot = ddt(sp.Matrix([E]))[0] + (sp.Matrix([E]).jacobian(Vs) * As)[0]

args = list(P) + list(Qs) + list(Vs)
lam = lambda e, extra=(): sp.lambdify(args + list(extra), e, 'mpmath', cse=True)
f_M, f_h, f_A, f_Ad = lam(M), lam(h), lam(A), lam(Ad_qd)
f_rows, f_rowsdot = lam(rows), lam(rows_dot, As)
f_E, f_Edot = lam(E), lam(Edot, As)
f_hol = lam(hol)
f_geom = lam(sp.Matrix.hstack(Nn, T1, T2))
t_A = time.time() - t0

# ============================================================ (K) Kane, full model
t_ = me.dynamicsymbols._t
qk = me.dynamicsymbols('beta x y z a b c')
uk = me.dynamicsymbols('u1:8')
NF = me.ReferenceFrame('NF')
PF = me.ReferenceFrame('PF')
PF.orient_axis(NF, NF.x, qk[0])
BF = me.ReferenceFrame('BF')
BF.orient_body_fixed(NF, (qk[4], qk[5], qk[6]), 'ZYX')
Op = me.Point('O')
Op.set_vel(NF, 0)
Gp = Op.locatenew('G', qk[1] * NF.x + qk[2] * NF.y + qk[3] * NF.z)
Gp.set_vel(NF, Gp.pos_from(Op).dt(NF))
Pb = Gp.locatenew('Pb', -r * PF.z)                      # contact, material point of the ball
Pb.v2pt_theory(Gp, NF, BF)
Pp = Op.locatenew('Pp', Pb.pos_from(Op))                # contact, material point of the plate
Pp.v2pt_theory(Op, NF, PF)
kd = [qk[i].diff(t_) - uk[i] for i in range(n)]
kd_map = {qk[i].diff(t_): uk[i] for i in range(n)}
vrel_k = Pb.vel(NF) - Pp.vel(NF)
vc = [(Gp.pos_from(Op).dot(PF.z) - r).diff(t_).subs(kd_map),
      vrel_k.dot(PF.x).subs(kd_map), vrel_k.dot(PF.y).subs(kd_map)]
ball = me.RigidBody('ball', Gp, BF, m, (me.inertia(BF, Ib, Ib, Ib), Gp))
plate = me.RigidBody('plate', Op, PF, 0, (me.inertia(PF, Jx, 0, 0), Op))
kane = me.KanesMethod(NF, q_ind=qk, u_ind=[uk[0], uk[4], uk[5], uk[6]],
                      u_dependent=[uk[1], uk[2], uk[3]], kd_eqs=kd, velocity_constraints=vc)
kane.kanes_equations([ball, plate], [(Gp, -m * g * NF.z), (PF, u * NF.x)])
plain = {**{qk[i]: Qs[i] for i in range(n)}, **{uk[i]: Vs[i] for i in range(n)}}
MK = kane.mass_matrix.xreplace(plain)
FK = kane.forcing.xreplace(plain)
assert MK.shape == (7, 7) and not (MK.atoms(sp.Derivative) | FK.atoms(sp.Derivative))
assert (MK.free_symbols | FK.free_symbols) <= set(args) | {u}
f_MK, f_FK = lam(MK, [u]), lam(FK, [u])
KPERM = [list(uk).index(s_) for s_ in kane.u]           # Kane's speeds: independent first, then dependent
assert sorted(KPERM) == list(range(n)) and KPERM != list(range(n))
Rk = sp.Matrix([[bx.dot(nx) for bx in (BF.x, BF.y, BF.z)] for nx in (NF.x, NF.y, NF.z)]).xreplace(plain)
chk = {a: sp.Rational('0.7'), b: sp.Rational('-0.4'), c: sp.Rational('1.1')}
assert max(abs(v) for v in sp.N((Rk - Rb).subs(chk), 60)) < 1e-50
t_K = time.time() - t0 - t_A

# ============================================================ (F) plate fixed, beta a parameter
Q6 = sp.Matrix([x, y, z, a, b, c])
V6 = sp.Matrix(Vs[1:])
d6 = lambda e: ddt(e, Q6, V6)
Gd6 = d6(Gv)
W6 = (d6(Rb) * Rb.T).applyfunc(sp.simplify)
w6 = sp.Matrix([W6[2, 1], W6[0, 2], W6[1, 0]])
L6 = m / 2 * (Gd6.T * Gd6)[0] + Ib / 2 * (w6.T * w6)[0] - m * g * z
# fixed plate: the contact point of the ball has zero velocity; its normal
# component is the derivative of the height constraint (the plate does not move)
v6 = Gd6 + w6.cross(-r * Nn)
rows6 = sp.Matrix([(Nn.T * Gd6)[0], (T1.T * v6)[0], (T2.T * v6)[0]])
A6 = rows6.jacobian(V6)
Ad6 = d6(A6 * V6)
p6 = sp.Matrix([L6]).jacobian(V6).T
M6 = p6.jacobian(V6)
h6 = p6.jacobian(Q6) * V6 - sp.Matrix([L6]).jacobian(Q6).T
args6 = list(P) + list(Qs) + list(V6)                    # beta enters as a parameter
f6 = [sp.lambdify(args6, e, 'mpmath', cse=True) for e in (M6, h6, A6, Ad6)]
t_F = time.time() - t0 - t_A - t_K


# ============================================================ numerics
def mpf(s):
    q_ = sp.Rational(s)
    return mpmath.mpf(q_.p) / q_.q


def S(v):
    return mpmath.nstr(mpmath.mpf(v), DIG, strip_zeros=False, min_fixed=-4, max_fixed=6)


def col(x_):
    return [x_[i] for i in range(x_.rows)]


PV = [mpf(s) for s in PVALS]
TOL = mpmath.mpf(10) ** (-DPS + 8)


def solve_full(pv, qv, vv, uv):
    aa = pv + qv + vv
    Mn, hn = mpmath.matrix(f_M(*aa)), mpmath.matrix(f_h(*aa))
    An, Adn = mpmath.matrix(f_A(*aa)), mpmath.matrix(f_Ad(*aa))
    K = mpmath.zeros(n + 3, n + 3)
    rhs = mpmath.zeros(n + 3, 1)
    for i in range(n):
        for j in range(n):
            K[i, j] = Mn[i, j]
        for k in range(3):
            K[i, n + k] = -An[k, i]
            K[n + k, i] = An[k, i]
        rhs[i] = -hn[i]
    rhs[0] += uv
    for k in range(3):
        rhs[n + k] = -Adn[k]
    sol = mpmath.lu_solve(K, rhs)
    return [sol[i] for i in range(n)], [sol[n + k] for k in range(3)]


def solve_fixed(pv, qv, v6):  # plate fixed at qv[0]; returns (x, y, z, a, b, c)'' and lambda
    aa = pv + qv + v6
    Mn, hn, An, Adn = [mpmath.matrix(f(*aa)) for f in f6]
    K = mpmath.zeros(9, 9)
    rhs = mpmath.zeros(9, 1)
    for i in range(6):
        for j in range(6):
            K[i, j] = Mn[i, j]
        for k in range(3):
            K[i, 6 + k] = -An[k, i]
            K[6 + k, i] = An[k, i]
        rhs[i] = -hn[i]
    for k in range(3):
        rhs[6 + k] = -Adn[k]
    sol = mpmath.lu_solve(K, rhs)
    return [sol[i] for i in range(6)], [sol[6 + k] for k in range(3)]


def consistent(pv, qs, rates):
    """qs = (beta, x, y, a, b, c), rates = (beta', a', b', c') as exact strings:
    z from the height constraint, (x', y', z') from the three velocity rows."""
    be, xx, yy, aa_, bb, cc = [mpf(s) for s in qs]
    zz = (pv[0] + yy * mpmath.sin(be)) / mpmath.cos(be)   # -y sin(beta) + z cos(beta) = r
    qv = [be, xx, yy, zz, aa_, bb, cc]
    assert abs(f_hol(*pv, *qv, *[0] * n)) < TOL
    bd, ad, bdd, cd = [mpf(s) for s in rates]
    An = mpmath.matrix(f_A(*pv, *qv, *[0] * n))
    known = {0: bd, 4: ad, 5: bdd, 6: cd}
    Ak = mpmath.matrix([[An[k, j] for j in (1, 2, 3)] for k in range(3)])
    rk = mpmath.matrix([-sum(An[k, j] * v for j, v in known.items()) for k in range(3)])
    xd = mpmath.lu_solve(Ak, rk)
    vv = [bd, xd[0], xd[1], xd[2], ad, bdd, cd]
    return qv, vv


def record(pv, qv, vv, uv, label=None):
    qdd, lm = solve_full(pv, qv, vv, uv)
    aa = pv + qv + vv
    # (K) Kane
    qdd_k = mpmath.lu_solve(mpmath.matrix(f_MK(*aa, uv)), mpmath.matrix(f_FK(*aa, uv)))
    dk = max(abs(qdd[KPERM[i]] - qdd_k[i]) for i in range(n)) / (1 + max(abs(v) for v in qdd))
    assert dk < mpmath.mpf('1e-40'), (label, dk)
    res_v = col(mpmath.matrix(f_rows(*aa)))
    res_a = col(mpmath.matrix(f_rowsdot(*aa, *qdd)))
    en = f_E(*aa)
    ebal = f_Edot(*aa, *qdd) - uv * vv[0]
    hres = f_hol(*aa)
    for v in res_v + res_a + [ebal, hres]:
        assert abs(v) < TOL, (label, v)
    rec = {}
    if label:
        rec["label"] = label
    rec.update({
        "q": [S(v) for v in qv], "qdot": [S(v) for v in vv], "u": S(uv),
        "qddot": [S(v) for v in qdd], "lambda": [S(v) for v in lm],
        "height_residual": S(hres),
        "velocity_residuals": [S(v) for v in res_v],
        "acceleration_residuals": [S(v) for v in res_a],
        "energy": S(en), "energy_balance_residual": S(ebal),
    })
    return rec, qdd, lm, dk


rng = random.Random(20250611)


def dec(lo, hi, nd=6):
    return f"{rng.uniform(lo, hi):.{nd}f}"


cases = []
worst_k = mpmath.mpf(0)
worst_res = mpmath.mpf(0)
for k in range(12):
    qs = [dec(-0.5, 0.5)] + [dec(-1, 1) for _ in range(2)] + [dec(-1, 1) for _ in range(3)]
    rates = [dec(-1, 1) for _ in range(4)]
    us = dec(-1, 1)
    qv, vv = consistent(PV, qs, rates)
    rec, qdd, lm, dk = record(PV, qv, vv, mpf(us))
    worst_k = max(worst_k, dk)
    worst_res = max([worst_res] + [abs(mpmath.mpf(s)) for s in rec["velocity_residuals"]
                                   + rec["acceleration_residuals"] + [rec["energy_balance_residual"]]])
    cases.append(rec)
    print(f"case {k:2d}: q'' = " + ", ".join(f"{float(v): .5e}" for v in qdd)
          + f"; lambda = " + ", ".join(f"{float(v): .4e}" for v in lm)
          + f"; Kane diff {float(dk):.1e}; dE/dt - u beta' = {float(mpmath.mpf(rec['energy_balance_residual'])):.1e}")

# ------------------------------------------------------------ check (1): incline, plate held
BETA = '0.3'
sb = mpmath.sin(mpf(BETA))
want = mpmath.mpf(5) / 7 * PV[3] * sb
want_fric = mpmath.mpf(2) / 7 * PV[1] * PV[3] * sb
want_norm = PV[1] * PV[3] * mpmath.cos(mpf(BETA))


def slope_parts(pv, qv, gdd):
    """G'' split along -T2 (down the slope), T1 and N of the plate at qv."""
    Gm = mpmath.matrix(f_geom(*pv, *qv, *[0] * n))
    comp = lambda j: sum(Gm[i, j] * gdd[i] for i in range(3))   # columns N, T1, T2
    return -comp(2), comp(1), comp(0)


def beta_dd_of_u(pv, qv, vv):  # beta'' is affine in u: the u that makes it zero holds the plate
    b0 = solve_full(pv, qv, vv, 0)[0][0]
    b1 = solve_full(pv, qv, vv, 1)[0][0]
    return -b0 / (b1 - b0)


special = []
incline = []
# (i) ball at rest at the plate's centre (G = r N, as `plate_at_rest` in tests/supports.rs)
# (ii) ball at rest off-centre; (iii) off-centre with the ball rolling and spinning (plate still)
setups = [
    ("centre_rest", [BETA, '0', '-0.1'], ['0', '0', '0'], ['0', '0', '0', '0']),
    ("offcentre_rest", [BETA, '0.35', '0.4'], ['0.2', '-0.6', '0.45'], ['0', '0', '0', '0']),
    ("offcentre_moving", [BETA, '0.35', '0.4'], ['0.2', '-0.6', '0.45'], ['0', '0.8', '-0.5', '0.7']),
]
for name, (bs, xs, ys), angs, rates in setups:
    be = mpf(bs)
    if name == "centre_rest":  # G = r N exactly: y = -r sin(beta); z follows from the constraint
        qv, vv = consistent(PV, [bs, xs, '0'] + angs, rates)
        qv[2] = -PV[0] * mpmath.sin(be)
        qv[3] = PV[0] * mpmath.cos(be)
    else:
        qv, vv = consistent(PV, [bs, xs, ys] + angs, rates)
    u_hold = beta_dd_of_u(PV, qv, vv)
    entry = {"label": name}
    # free plate, u = 0
    rec_free, qdd_free, lm_free, _ = record(PV, qv, vv, mpmath.mpf(0), name + "_free_u0")
    # plate held by u_hold (beta'' = 0)
    rec_hold, qdd_hold, lm_hold, _ = record(PV, qv, vv, u_hold, name + "_held")
    assert abs(qdd_hold[0]) < TOL
    special += [rec_free, rec_hold]
    # separate fixed-plate derivation
    qdd6, lm6 = solve_fixed(PV, qv, vv[1:])
    d6max = max(abs(qdd6[i] - qdd_hold[1 + i]) for i in range(6))
    dl6 = max(abs(lm6[k] - lm_hold[k]) for k in range(3))
    assert d6max < TOL and dl6 < TOL, (name, d6max, dl6)
    entry.update({
        "q": [S(v) for v in qv], "qdot": [S(v) for v in vv],
        "u_hold": S(u_hold),
        "free_u0": {"beta_ddot": S(qdd_free[0]), "xyz_ddot": [S(v) for v in qdd_free[1:4]],
                    "along_slope_T1_N": [S(v) for v in slope_parts(PV, qv, qdd_free[1:4])],
                    "lambda": [S(v) for v in lm_free]},
        "held": {"beta_ddot": S(qdd_hold[0]), "xyz_ddot": [S(v) for v in qdd_hold[1:4]],
                 "along_slope_T1_N": [S(v) for v in slope_parts(PV, qv, qdd_hold[1:4])],
                 "lambda": [S(v) for v in lm_hold]},
        "fixed_plate_derivation": {"xyz_ddot": [S(v) for v in qdd6[:3]], "abc_ddot": [S(v) for v in qdd6[3:]],
                                   "along_slope_T1_N": [S(v) for v in slope_parts(PV, qv, qdd6[:3])],
                                   "lambda": [S(v) for v in lm6],
                                   "max_diff_from_held": S(max(d6max, dl6))},
    })
    # held: the fixed incline's closed form, G'' = 5/7 g sin(beta) down the slope (spin or not)
    dn = slope_parts(PV, qv, qdd_hold[1:4])
    assert abs(dn[0] - want) < TOL and abs(dn[1]) < TOL and abs(dn[2]) < TOL
    # free (u = 0, beta' = 0): the plate's material point at P accelerates along N only
    # (beta'' e_x x P with P in the plane), so the down-slope part is still 5/7 g sin(beta);
    # G''.N = beta'' (G.T2) from d^2/dt^2 [(G-O).N - r] = 0; the torque that holds the
    # plate is the normal force's moment, u_hold = lambda_0 (G.T2)
    Gm = mpmath.matrix(f_geom(*PV, *qv, *[0] * n))
    gT2 = sum(Gm[i, 2] * qv[1 + i] for i in range(3))
    df = slope_parts(PV, qv, qdd_free[1:4])
    assert abs(df[0] - want) < TOL and abs(df[1]) < TOL and abs(df[2] - qdd_free[0] * gT2) < TOL
    assert abs(u_hold - lm_hold[0] * gT2) < TOL
    entry["G_dot_T2"] = S(gT2)
    if name.endswith("_rest"):
        assert abs(lm_hold[0] - want_norm) < TOL and abs(lm_hold[1]) < TOL and abs(lm_hold[2] - want_fric) < TOL
        # Jx -> infinity with u = 0
        heavy = []
        for jx in ['1e3', '1e6', '1e12']:
            pv_h = PV[:2] + [mpmath.mpf(jx)] + PV[3:]
            qdd_h, _ = solve_full(pv_h, qv, vv, 0)
            heavy.append({"Jx": jx, "beta_ddot": S(qdd_h[0]),
                          "along_slope": S(slope_parts(pv_h, qv, qdd_h[1:4])[0])})
        entry["heavy_plate_u0"] = heavy
    incline.append(entry)
    fs, hs = slope_parts(PV, qv, qdd_free[1:4])[0], slope_parts(PV, qv, qdd_hold[1:4])[0]
    print(f"{name}: u_hold = {float(u_hold):.6e}; free (u=0): beta'' = {float(qdd_free[0]):.6e}, "
          f"down-slope {float(fs):.12f}; held: down-slope {float(hs):.12f}; "
          f"5/7 g sin(beta) = {float(want):.12f}; fixed-plate derivation differs by {float(max(d6max, dl6)):.1e}")

layout = {
    "parameters": "r, m, Jx, g (exact decimal strings)",
    "coordinates": "q order: beta, x, y, z, a, b, c; ball orientation Rz(a) Ry(b) Rx(c), plate Rx(beta)",
    "cases": "12 random consistent states; each: q[7], qdot[7], u, qddot[7], lambda[3], height_residual "
             "((G-O).N - r), velocity_residuals[3] (rows 0..2 of A(q) q'), acceleration_residuals[3] "
             "(A q'' + A' q'), energy (T + V, V = m g z), energy_balance_residual (dE/dt - u beta')",
    "rows": "row 0: d/dt[(G-O).N - r]; row 1: T1.(v_ball(P) - v_plate(P)); row 2: T2.(v_ball(P) - v_plate(P)); "
            "N = Rx(beta) e_z, T1 = Rx(beta) e_x, T2 = Rx(beta) e_y, P = G - r N, v_ball(P) = G' + w x (P - G), "
            "v_plate(P) = beta' e_x x P",
    "lambda": "d/dt dL/dq' - dL/dq = Q + A^T lambda (Q = (u,0,...,0)); lambda[k] belongs to row k: lambda[0] = "
              "normal force of the plate on the ball along +N, lambda[1], lambda[2] = friction force of the "
              "plate on the ball along +T1, +T2",
    "special": "beta = 0.3, plate still (beta' = 0); records in the format of cases, labelled "
               "<setup>_free_u0 (u = 0: beta'' != 0 unless the ball sits at the plate centre, where the "
               "contact forces act at O and exert no torque, so beta'' = 0) and <setup>_held (u = u_hold, "
               "the torque that holds the plate: beta'' = 0)",
    "incline": "check (1) at beta = 0.3, beta' = 0, setups centre_rest (ball at rest at G = r N), offcentre_rest (ball at rest elsewhere), offcentre_moving (ball rolling and spinning); per setup: q, qdot, G_dot_T2 (= G.T2), u_hold (= lambda_0 of held times G.T2); free_u0 and held: beta_ddot, xyz_ddot, along_slope_T1_N = "
               "(G''.(-T2) down the slope, G''.T1, G''.N), lambda; fixed_plate_derivation: the separate "
               "6-coordinate derivation with beta a parameter (must equal held); heavy_plate_u0: u = 0 with "
               "Jx = 1e3, 1e6, 1e12 (beta'' -> -u_hold/Jx -> 0); expected_along_slope = 5/7 g sin(beta), "
               "expected_lambda = (m g cos beta, 0, 2/7 m g sin beta) for the rest setups. Found: the down-slope part is 5/7 g sin(beta) for held AND free plate (beta' = 0: the plate's point P accelerates along N only); the free plate changes G''.N (= beta'' G.T2) and lambda_0",
    "numbers": "strings, %d significant digits, computed at %d digits" % (DIG, DPS),
}
out = {
    "layout": layout,
    "description": "Homogeneous ball rolling without slipping on a plate tilted by a joint about the world x "
                   "axis (input torque u on beta). Derived by tests/data/tilting_plate_sympy.py "
                   "(Lagrange-d'Alembert with multipliers), q'' cross-checked with sympy.physics.mechanics "
                   "KanesMethod (max scaled difference %.1e); all residuals below %.1e."
                   % (float(worst_k), float(worst_res)),
    "parameters": dict(zip(PNAMES, PVALS)),
    "coordinates": QNAMES,
    "cases": cases,
    "special": special,
    "incline": {"beta": BETA, "expected_along_slope": S(want),
                "expected_lambda": [S(want_norm), S(0), S(want_fric)], "setups": incline},
}
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'tilting_plate.json')
with open(path, 'w') as f:
    json.dump(out, f, indent=1, ensure_ascii=False)
    f.write('\n')
print(f"derivation: multipliers {t_A:.1f} s, Kane {t_K:.1f} s, fixed plate {t_F:.1f} s; "
      f"total {time.time() - t0:.1f} s; max Kane difference {float(worst_k):.1e}; "
      f"max residual {float(worst_res):.1e}; wrote {path}")
