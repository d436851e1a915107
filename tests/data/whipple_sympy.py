#!/usr/bin/env python3
"""Independent reference for the nonlinear accelerations of the Whipple
bicycle written in examples/whipple_bicycle/model.rs.

Method: Lagrange multipliers.  The Lagrangian L(q, qdot) is built in SymPy
from the bodies of model.rs, differentiated exactly (M = d2L/dqdot2,
h = (d/dq dL/dqdot) qdot - dL/dq), the five velocity-level constraint rows
g = A(q) qdot come from the material velocity of each wheel's contact point,
and d = (dg/dq) qdot.  Everything is evaluated in mpmath (40 digits) and the
KKT system

    [ M  A^T ] [ qddot ]   [ -h ]
    [ A   0  ] [ lam   ] = [ -d ]

is solved for qddot.  Nothing from the Rust engine is used.

World axes x forward, y left, z up.  q = (roll, steer, rear, yaw, pitch,
front, x, y); independent velocities (roll, steer, rear).

Writes whipple_nonlinear.json next to this file.
"""
import json
import math
import os
import random
import sys
import time

import mpmath as mp
import sympy as sp

T0 = time.time()
mp.mp.dps = 40
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "whipple_nonlinear.json")


def log(*a):
    print(f"[{time.time() - T0:7.1f}s]", *a, flush=True)


# --------------------------------------------------------------------------
# symbols, in model.rs's order
PNAMES = ["w", "c", "lambda", "g", "rR", "mR", "IRxx", "IRyy",
          "xB", "zB", "mB", "IBxx", "IByy", "IBzz", "IBxz",
          "xH", "zH", "mH", "IHxx", "IHyy", "IHzz", "IHxz",
          "rF", "mF", "IFxx", "IFyy"]
P = sp.symbols(" ".join(n if n != "lambda" else "lam" for n in PNAMES), real=True)
(w, c, lam, g, rR, mR, IRxx, IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz,
 xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy) = P

QNAMES = ["roll", "steer", "rear", "yaw", "pitch", "front", "x", "y"]
q = sp.symbols(" ".join(QNAMES), real=True)
qd = sp.symbols(" ".join("d" + n for n in QNAMES), real=True)
roll, steer, rear, yaw, pitch, front, x, y = q
droll, dsteer, drear, dyaw, dpitch, dfront, dx, dy = qd
INDEP = [0, 1, 2]
DEP = [3, 4, 5, 6, 7]


def rot_x(a):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])


def rot_y(a):
    return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])


def rot_z(a):
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def vec(*a):
    return sp.Matrix(a)


ex, ey, ez = vec(1, 0, 0), vec(0, 1, 0), vec(0, 0, 1)

# --------------------------------------------------------------------------
# kinematics, exactly as model.rs
Y = rot_z(yaw) * rot_x(roll)
B = Y * rot_y(pitch)
Cst = rot_y(-lam) * rot_z(-steer) * rot_y(lam)      # steering about the head tube
H = B * Cst
CR = vec(x, y, 0) + rR * (Y * ez)
S = CR + B * vec(w + c, 0, -rR)
GB = CR + B * vec(xB, 0, zB - rR)
GH = S + H * vec(xH - w - c, 0, zH)
CF = S + H * vec(-c, 0, rF)
R_rear = B * rot_y(rear)
R_front = H * rot_y(front)


def tdiff(expr):
    """time derivative of an expression in q along qdot"""
    return sum((sp.diff(expr, qi) * qdi for qi, qdi in zip(q, qd)), sp.S(0))


def tdiff_m(m):
    return m.applyfunc(tdiff)


# Body angular velocities (body axes).  For R = A Rk(t) C the contribution of
# t to the body angular velocity vee(R^T Rdot) is tdot C^T e_k; this keeps the
# expressions small.  It is checked numerically below against vee(R^T Rdot)
# with Rdot from exact differentiation of the rotation matrices.
wb_B = dyaw * (rot_x(roll) * rot_y(pitch)).T * ez + droll * rot_y(pitch).T * ex + dpitch * ey
wb_rear = rot_y(rear).T * wb_B + drear * ey
wb_H = Cst.T * wb_B + (-dsteer) * rot_y(lam).T * ez
wb_front = rot_y(front).T * wb_H + dfront * ey
# world angular velocities of the wheels (for the contacts)
ww_rear = R_rear * wb_rear
ww_front = R_front * wb_front


def inertia(xx, yy, zz, xz):
    return sp.Matrix([[xx, 0, xz], [0, yy, 0], [xz, 0, zz]])


bodies = [
    ("rear_wheel", mR, CR, R_rear, wb_rear, inertia(IRxx, IRyy, IRxx, 0)),
    ("frame", mB, GB, B, wb_B, inertia(IBxx, IByy, IBzz, IBxz)),
    ("fork", mH, GH, H, wb_H, inertia(IHxx, IHyy, IHzz, IHxz)),
    ("front_wheel", mF, CF, R_front, wb_front, inertia(IFxx, IFyy, IFxx, 0)),
]

Tkin = sp.S(0)
for name, m, G, R, wb, I in bodies:
    vG = tdiff_m(G)
    Tkin += sp.Rational(1, 2) * m * (vG.T * vG)[0] + sp.Rational(1, 2) * (wb.T * I * wb)[0]
V = g * (mR * CR[2] + mB * GB[2] + mH * GH[2] + mF * CF[2])
L = Tkin - V
log("Lagrangian built, ops", sp.count_ops(L, visual=False))

# --------------------------------------------------------------------------
# constraints: contact point P = G - r * wv, wv = (e_z - n_z n)/sqrt(1 - n_z^2)


def contact(G, R, ww, r):
    n = R * ey
    nz = n[2]
    wv = (ez - nz * n) / sp.sqrt(1 - nz ** 2)
    Pc = G - r * wv
    vmat = tdiff_m(G) + ww.cross(Pc - G)       # material velocity of P
    return Pc, vmat


P_rear, v_rear = contact(CR, R_rear, ww_rear, rR)
P_front, v_front = contact(CF, R_front, ww_front, rF)
grows = [v_rear[0], v_rear[1], v_front[0], v_front[1], v_front[2]]
Pz_front = P_front[2]
Pz_rear = P_rear[2]
A_sym = sp.Matrix([[sp.diff(gr, qdj) for qdj in qd] for gr in grows])
# g is linear in qdot: the rate at qddot = 0
d_sym = sp.Matrix([tdiff(gr) for gr in grows])
log("constraints built")

# --------------------------------------------------------------------------
# equations of motion pieces
pL = [sp.diff(L, qdi) for qdi in qd]
M_sym = sp.Matrix(8, 8, lambda i, j: sp.diff(pL[i], qd[j]) if j >= i else 0)
for i in range(8):
    for j in range(i):
        M_sym[i, j] = M_sym[j, i]
h_sym = sp.Matrix([tdiff(pL[i]) - sp.diff(L, q[i]) for i in range(8)])
log("M, h differentiated")

ARGS = list(P) + list(q) + list(qd)


def lam_(expr, cse=True):
    return sp.lambdify(ARGS, expr, modules="mpmath", cse=cse)


f_M = lam_(M_sym)
f_h = lam_(h_sym)
f_A = lam_(A_sym)
f_d = lam_(d_sym)
f_g = lam_(sp.Matrix(grows))
f_Pz = lam_(Pz_front)
f_Pzr = lam_(Pz_rear)
f_L = lam_(L)
f_E = lam_(Tkin + V)
f_p = lam_(sp.Matrix(pL))
# for the angular velocity check: rotation matrices and their exact rates
rot_checks = []
for name, m, G, R, wb, I in bodies:
    rot_checks.append((name, lam_(R), lam_(tdiff_m(R)), lam_(wb)))
log("lambdified")

# --------------------------------------------------------------------------
# parameters
BENCH = [1.02, 0.08, 3.141592653589793 / 10.0, 9.81,
         0.3, 2.0, 0.0603, 0.12,
         0.3, 0.9, 85.0, 9.2, 11.0, 2.8, -2.4,
         0.9, 0.7, 4.0, 0.05892, 0.06, 0.00708, 0.00756,
         0.35, 3.0, 0.1405, 0.28]
assert len(BENCH) == 26
rng = random.Random(20070101)
PERT = [float(v * rng.uniform(0.9, 1.1)) for v in BENCH]


def mpv(xs):
    return [mp.mpf(v) for v in xs]


def call(f, par, qq, qqd):
    return f(*(par + qq + qqd))


def mat(v):
    return mp.matrix(v) if not isinstance(v, mp.matrix) else v


ZERO8 = [mp.mpf(0)] * 8


def solve_pitch(par, qq):
    def fz(p):
        qq2 = list(qq)
        qq2[4] = p
        return call(f_Pz, par, qq2, ZERO8)
    return mp.findroot(fz, mp.mpf(0), solver="newton", tol=mp.mpf(10) ** -36)


def dependent_velocities(par, qq, rdot):
    A = mat(call(f_A, par, qq, ZERO8))
    Ad = mp.matrix(5, 5)
    rhs = mp.matrix(5, 1)
    for a in range(5):
        for k, j in enumerate(DEP):
            Ad[a, k] = A[a, j]
        rhs[a] = -sum(A[a, j] * rdot[k] for k, j in enumerate(INDEP))
    s = mp.lu_solve(Ad, rhs)
    qqd = [mp.mpf(0)] * 8
    for k, j in enumerate(INDEP):
        qqd[j] = rdot[k]
    for k, j in enumerate(DEP):
        qqd[j] = s[k]
    return qqd, A


def accelerations(par, qq, qqd):
    M = mat(call(f_M, par, qq, qqd))
    h = mat(call(f_h, par, qq, qqd))
    A = mat(call(f_A, par, qq, qqd))
    d = mat(call(f_d, par, qq, qqd))
    K = mp.matrix(13, 13)
    rhs = mp.matrix(13, 1)
    for i in range(8):
        for j in range(8):
            K[i, j] = M[i, j]
        rhs[i] = -h[i]
    for a in range(5):
        for j in range(8):
            K[8 + a, j] = A[a, j]
            K[j, 8 + a] = A[a, j]
        rhs[8 + a] = -d[a]
    sol = mp.lu_solve(K, rhs)
    qdd = [sol[i] for i in range(8)]
    lam_m = [sol[8 + a] for a in range(5)]
    return qdd, lam_m, M, h, A, d


def vee(Wm):
    return [Wm[2, 1], Wm[0, 2], Wm[1, 0]]


def maxabs(xs):
    return max(abs(v) for v in xs)


# --------------------------------------------------------------------------
cases = []
worst = {}


def note(key, val):
    worst[key] = max(worst.get(key, mp.mpf(0)), val)


state_rng = random.Random(12345)
# headings where a static pivot on the rows' x and y columns would fail
# (cos or sin of the yaw zero), for the benchmark's parameters
HEADINGS = [math.pi / 2, -math.pi / 2, math.pi, math.pi / 2 + 1e-9]
for pset_name, pflt in (("benchmark", BENCH), ("perturbed", PERT)):
    par = mpv(pflt)
    for k in range(6 + (len(HEADINGS) if pset_name == "benchmark" else 0)):
        if k < 6:
            qf = [state_rng.uniform(-0.5, 0.5),           # roll
                  state_rng.uniform(-0.5, 0.5),           # steer
                  state_rng.uniform(-3.14, 3.14),         # rear
                  state_rng.uniform(-3.14, 3.14),         # yaw
                  0.0,                                    # pitch (solved)
                  state_rng.uniform(-3.14, 3.14),         # front
                  state_rng.uniform(-5.0, 5.0),           # x
                  state_rng.uniform(-5.0, 5.0)]           # y
            rdf = [state_rng.uniform(-2.0, 2.0), state_rng.uniform(-2.0, 2.0),
                   state_rng.uniform(-20.0, 20.0)]
        else:
            qf = [0.3, -0.4, 1.0, HEADINGS[k - 6], 0.0, 0.5, 2.0, -1.0]
            rdf = [0.5, -0.8, 12.0]
        qq = mpv(qf)
        ptc = solve_pitch(par, qq)
        qf[4] = float(ptc)          # the reference uses the double the JSON carries
        qq = mpv(qf)
        rdot = mpv(rdf)
        qqd, A0 = dependent_velocities(par, qq, rdot)
        qdd, lm, M, h, A, d = accelerations(par, qq, qqd)

        pz = abs(call(f_Pz, par, qq, ZERO8))
        pzr = abs(call(f_Pzr, par, qq, ZERO8))
        gres = maxabs(mat(call(f_g, par, qq, qqd)))
        acc = A * mp.matrix(qdd) + d
        ares = maxabs(acc)
        # KKT residual of the dynamics rows
        dyn = M * mp.matrix(qdd) + h + A.T * mp.matrix(lm)
        dres = maxabs(dyn)
        # power of the constraint forces and dE/dt along the motion
        # (E = T + V is conserved: the constraints are ideal and scleronomic)
        Egrad_q = [mp.diff(lambda t, i=i: call(f_E, par, [qq[j] + (t if j == i else 0) for j in range(8)], qqd), 0)
                   for i in range(8)]
        pvec = mat(call(f_p, par, qq, qqd))   # dE/dqdot = dT/dqdot = p (V indep. of qdot)
        dEdt = sum(Egrad_q[i] * qqd[i] for i in range(8)) + sum(pvec[i] * qdd[i] for i in range(8))
        Escale = abs(call(f_E, par, qq, qqd)) + 1
        # row 5 of A equals the gradient of the front contact height
        gradPz = [mp.diff(lambda t, i=i: call(f_Pz, par, [qq[j] + (t if j == i else 0) for j in range(8)], ZERO8), 0)
                  for i in range(8)]
        row5 = maxabs([A[4, i] - gradPz[i] for i in range(8)])
        note("P_z front", pz)
        note("P_z rear", pzr)
        note("|g(q,qdot)|", gres)
        note("|A qddot + d|", ares)
        note("|M qddot + h + A^T lam|", dres)
        note("|dE/dt|/(|E|+1)", abs(dEdt) / Escale)
        note("|A[4,:] - grad P_z|", row5)
        log(f"{pset_name} case {k}: pitch={mp.nstr(ptc, 8)} Pz={mp.nstr(pz, 3)} "
            f"|g|={mp.nstr(gres, 3)} |Aqdd+d|={mp.nstr(ares, 3)} |dyn|={mp.nstr(dres, 3)} "
            f"dE/dt={mp.nstr(dEdt, 3)} |row5-gradPz|={mp.nstr(row5, 3)}")
        cases.append({"set": pset_name, "params": pflt, "q": qf, "rdot": rdf,
                      "qdot": qqd, "qddot": qdd})

        if k == 0:
            # (a) angular velocity shortcut vs vee(R^T Rdot) with exact Rdot
            for name, fR, fRd, fwb in rot_checks:
                Rn = mat(call(fR, par, qq, qqd))
                Rdn = mat(call(fRd, par, qq, qqd))
                W = Rn.T * Rdn
                wv1 = vee(W)
                wv2 = mat(call(fwb, par, qq, qqd))
                skew_sym = maxabs([W[i, j] + W[j, i] for i in range(3) for j in range(3)])
                note("angular velocity shortcut", maxabs([wv1[i] - wv2[i] for i in range(3)]))
                note("R^T Rdot skew-symmetry", skew_sym)
            log("angular velocity check",
                mp.nstr(worst["angular velocity shortcut"], 3),
                "skew", mp.nstr(worst["R^T Rdot skew-symmetry"], 3))
            # (b) finite difference of the velocity rows along the motion:
            # d/dt g(q(t), qdot(t)) at t=0 with q(t) = q + t qdot + t^2/2 qddot
            # must vanish (it is A qddot + d); and the numerical derivative of
            # g(q + t qdot, qdot) must equal d.
            def gat(t, withacc):
                q2 = [qq[i] + t * qqd[i] + (t * t / 2 * qdd[i] if withacc else 0) for i in range(8)]
                qd2 = [qqd[i] + (t * qdd[i] if withacc else 0) for i in range(8)]
                return mat(call(f_g, par, q2, qd2))
            hstep = mp.mpf(10) ** -12
            fd_full = (gat(hstep, True) - gat(-hstep, True)) / (2 * hstep)
            fd_d = (gat(hstep, False) - gat(-hstep, False)) / (2 * hstep)
            note("FD d/dt g along motion", maxabs(fd_full))
            note("FD (dg/dq)qdot - d", maxabs(fd_d - d))
            log("FD along motion:", mp.nstr(maxabs(fd_full), 3), " FD rate vs d:", mp.nstr(maxabs(fd_d - d), 3))
            # (c) h against a numerical differentiation of the momentum:
            # h = (dp/dq) qdot - dL/dq
            h_num = []
            for i in range(8):
                dpdt = mp.diff(lambda t: call(f_p, par, [qq[j] + t * qqd[j] for j in range(8)], qqd)[i], 0)
                dLdq = mp.diff(lambda t: call(f_L, par, [qq[j] + (t if j == i else 0) for j in range(8)], qqd), 0)
                h_num.append(dpdt - dLdq)
            note("h vs numerical", maxabs([h[i] - h_num[i] for i in range(8)]))
            log("h vs numerical differentiation:", mp.nstr(worst["h vs numerical"], 3))
            # (d) symmetric positive definite M on the constraint null space
            ev = mp.eigsy(M)[0]
            log("eigenvalues of M:", [mp.nstr(e, 5) for e in ev])

# --------------------------------------------------------------------------
# (e) the linearisation of these nonlinear accelerations about upright,
# straight-ahead running must reproduce the published benchmark matrices
# (Meijaard et al. 2007, eqs. (A 1)-(A 5)): M qdd + v C1 qd + (g K0 + v^2 K2) q = 0
PUB = {
    "M": [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]],
    "C1": [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]],
    "K0": [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]],
    "K2": [[0.0, 76.59734589573222], [0.0, 2.65431523794604]],
}
par = mpv(BENCH)


def rs_acc(v, rl, st, drl, dst):
    qq = [rl, st, mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.mpf(0)]
    qq[4] = solve_pitch(par, qq)
    qqd, _ = dependent_velocities(par, qq, [drl, dst, v / par[4]])
    return accelerations(par, qq, qqd)[0][:2]


def lin(v):
    z = mp.mpf(0)
    eps = mp.mpf(10) ** -15
    Jq = mp.matrix(2, 2)
    Jv = mp.matrix(2, 2)
    for j in range(2):
        e = [z, z]
        e[j] = eps
        ap = rs_acc(v, e[0], e[1], z, z)
        am = rs_acc(v, -e[0], -e[1], z, z)
        bp = rs_acc(v, z, z, e[0], e[1])
        bm = rs_acc(v, z, z, -e[0], -e[1])
        for i in range(2):
            Jq[i, j] = (ap[i] - am[i]) / (2 * eps)
            Jv[i, j] = (bp[i] - bm[i]) / (2 * eps)
    return Jq, Jv


q0 = [mp.mpf(0)] * 8
_, A00 = dependent_velocities(par, q0, [mp.mpf(0)] * 3)
Tm = mp.matrix(8, 3)
for k, j in enumerate(INDEP):
    Tm[j, k] = 1
Ad = mp.matrix(5, 5)
Ai = mp.matrix(5, 3)
for a in range(5):
    for k, j in enumerate(DEP):
        Ad[a, k] = A00[a, j]
    for k, j in enumerate(INDEP):
        Ai[a, k] = A00[a, j]
Sdep = -(mp.inverse(Ad) * Ai)
for k, j in enumerate(DEP):
    for m_ in range(3):
        Tm[j, m_] = Sdep[k, m_]
Mred = Tm.T * mat(call(f_M, par, q0, ZERO8)) * Tm
M2 = mp.matrix([[Mred[0, 0], Mred[0, 1]], [Mred[1, 0], Mred[1, 1]]])
Jq0, _ = lin(mp.mpf(0))
Jq5, Jv5 = lin(mp.mpf(5))
gK0 = -(M2 * Jq0)
K0 = gK0 / par[3]
K2 = (-(M2 * Jq5) - gK0) / 25
C1 = -(M2 * Jv5) / 5
ours = {"M": M2, "C1": C1, "K0": K0, "K2": K2}
for key in ("M", "C1", "K0", "K2"):
    diff = max(abs(ours[key][i, j] - PUB[key][i][j]) for i in range(2) for j in range(2))
    note("benchmark " + key + " (published, ~1e-14 digits)", diff)
    log(f"linearised {key}: {[[mp.nstr(ours[key][i, j], 15) for j in range(2)] for i in range(2)]}  "
        f"max |diff| to published {mp.nstr(diff, 3)}")

# --------------------------------------------------------------------------


def repr_num(v):
    # 17 significant digits of the value (mpf: of the exact 40-digit result)
    if isinstance(v, mp.mpf):
        s = mp.nstr(v, 17, strip_zeros=False)
        # mpmath may print "1.0e-5" style; JSON accepts that. Ensure no "+" issues
        return s.replace("e+", "e")
    return format(float(v), ".17g")


def js_list(xs):
    return "[" + ", ".join(repr_num(v) for v in xs) + "]"


lines = ["{",
         '  "description": ' + json.dumps(
             "Independent SymPy/mpmath reference (Lagrange multipliers, KKT solve at 40 digits) for the "
             "nonlinear accelerations of the Whipple bicycle of examples/whipple_bicycle/model.rs. "
             "q = (roll, steer, rear, yaw, pitch, front, x, y); rdot = (droll, dsteer, drear); "
             "qdot has the dependent rates solved from the 5 velocity rows at (q, rdot); qddot from "
             "[M A^T; A 0][qddot; lam] = [-h; -d]. params in model.rs order (w, c, lambda, g, rR, mR, IRxx, "
             "IRyy, xB, zB, mB, IBxx, IByy, IBzz, IBxz, xH, zH, mH, IHxx, IHyy, IHzz, IHxz, rF, mF, IFxx, IFyy); "
             "cases 0-5 benchmark() values, 6-11 each parameter times a seeded factor in [0.9, 1.1]. "
             "pitch solves the front contact height = 0 (to ~1e-17 after rounding to the printed double). "
             "Generated by tests/data/whipple_sympy.py.") + ",",
         '  "cases": [']
for n, cs in enumerate(cases):
    body = ("    {" + f'"set": "{cs["set"]}", '
            + '"params": ' + js_list(cs["params"]) + ", "
            + '"q": ' + js_list(cs["q"]) + ", "
            + '"rdot": ' + js_list(cs["rdot"]) + ", "
            + '"qdot": ' + js_list(cs["qdot"]) + ", "
            + '"qddot": ' + js_list(cs["qddot"]) + "}")
    lines.append(body + ("," if n + 1 < len(cases) else ""))
lines.append("  ]")
lines.append("}")
with open(OUT, "w") as fh:
    fh.write("\n".join(lines) + "\n")
# validate it parses
with open(OUT) as fh:
    data = json.load(fh)
assert len(data["cases"]) == 16

log("worst residuals over all cases:")
for k, v in worst.items():
    print(f"    {k:32s} {mp.nstr(v, 3)}")
log("wrote", OUT)
