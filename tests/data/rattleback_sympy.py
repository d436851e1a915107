"""Independent reference for a rattleback: a rigid body whose surface is the
ellipsoid x^2/a1^2 + y^2/a2^2 + z^2/a3^2 = 1 (body axes, centred at the
geometric centre C), rolling without slipping on the plane z = 0 (world z up,
gravity -g e_z).  Derived from scratch with SymPy; nothing is typed in from the
Rust model.

Model (SI units throughout):
  q = (psi, theta, phi, x, y); R = Rz(psi) Ry(theta) Rx(phi) (body -> world);
  gamma = R^T e_z; D = diag(a1, a2, a3); C = (x, y, sqrt(gamma^T D^2 gamma));
  contact point P = C - R D^2 gamma / sqrt(gamma^T D^2 gamma)  (support point of
  the ellipsoid in direction -e_z; checked: P_z = 0, P on the ellipsoid, outward
  normal there = -e_z); centre of mass G = C + R (0, 0, -h);
  inertia about G in body axes I = [[Ixx, Ixy, 0], [Ixy, Iyy, 0], [0, 0, Izz]]
  (tensor entries), for the 'delta' sets I = Rz(delta) diag(A, B, Cz) Rz(delta)^T;
  w_body from R^T R', w_world from R' R^T;
  L = m/2 |G'|^2 + 1/2 w_body.I w_body - m g G_z.
  Rolling: v_P = C' + w_world x (P - C) = 0; rows x, y are the two constraints
  (coefficient rows c_a = d v_P,a / d q'); the z row vanishes identically
  (proved with sympy.simplify, and checked numerically at 40 digits).
  Lagrange-d'Alembert: d/dt dL/dq' - dL/dq = sum_a lambda_a c_a, solved with
  c_a q'' + c_a' q' = 0 as the 7x7 system [M -C^T; C 0][q''; lambda] = [F; -C' q'].
  Because c_a has coefficient 1 on x' (resp. y'), lambda = (F_x, F_y) is the
  horizontal contact force exerted by the plane on the body (checked against
  m G''_x, m G''_y and against the Newton-Euler angular momentum balance about G).

Output 1 (states): 12 seeded random states, each evaluated at 40 digits for the
'main' parameter set (delta = 0.1) and for the 'check' set (delta = 0).
Output 2 (spin reversal): own Bulirsch-Stoer (Gragg midpoint + Richardson
extrapolation) and own Dormand-Prince 5(4) integrators on the reduced equations
(independent speeds psi', theta', phi'), lambdified with the math module; tol
1e-11 and 1e-13 (100x tighter), plus Dormand-Prince at 1e-12 and a 30-digit
mpmath Bulirsch-Stoer run up to just past the first reversal.  Two cases: the
brief's delta = 0.1 set (spin -5 rad/s, theta = phi = 0.01), and the Kane &
Levinson (1982) parameter set with the initial conditions of the
Autolev/MotionGenesis sample problem.
Parameters enter the 40-digit evaluation as mpf of their decimal strings
(relative error < 1e-40), so the 30 digits written are exact for the decimals.

usage (from the repository root): python3 tests/data/rattleback_sympy.py
        writes tests/data/rattleback.json (a few minutes)."""
import bisect
import json
import math
import os
import random
import sys
import time

import mpmath
import sympy as sp

DPS = 40
mpmath.mp.dps = DPS
T_START = time.time()
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, 'rattleback.json')
NSIG = 30          # significant digits written for the 40-digit state values


def log(*a):
    print('[%7.1fs]' % (time.time() - T_START), *a, flush=True)


# =============================================================== symbolic model
PNAMES = ['a1', 'a2', 'a3', 'h', 'm', 'g', 'Ixx', 'Iyy', 'Izz', 'Ixy']
PAR = sp.symbols(PNAMES)
a1, a2, a3, h, m, g, Ixx, Iyy, Izz, Ixy = PAR
QN = ['psi', 'theta', 'phi', 'x', 'y']
Q = sp.Matrix(sp.symbols(QN))
V = sp.Matrix(sp.symbols([n + '_d' for n in QN]))
Acc = sp.Matrix(sp.symbols([n + '_dd' for n in QN]))
psi, th, ph, x, y = Q


def Rz(u): return sp.Matrix([[sp.cos(u), -sp.sin(u), 0], [sp.sin(u), sp.cos(u), 0], [0, 0, 1]])
def Ry(u): return sp.Matrix([[sp.cos(u), 0, sp.sin(u)], [0, 1, 0], [-sp.sin(u), 0, sp.cos(u)]])
def Rx(u): return sp.Matrix([[1, 0, 0], [0, sp.cos(u), -sp.sin(u)], [0, sp.sin(u), sp.cos(u)]])


def ddt(e):
    """d/dt of an expression in (q, q') along q(t) (q'' enters through q')."""
    return sum((e.diff(Q[i]) * V[i] + e.diff(V[i]) * Acc[i] for i in range(5)), sp.zeros(*e.shape))


R = Rz(psi) * Ry(th) * Rx(ph)
ez = sp.Matrix([0, 0, 1])
gam = (R.T * ez).applyfunc(sp.simplify)
assert gam == sp.Matrix([-sp.sin(th), sp.sin(ph) * sp.cos(th), sp.cos(ph) * sp.cos(th)])
D2 = sp.diag(a1**2, a2**2, a3**2)
Sig = sp.sqrt((gam.T * D2 * gam)[0])        # support function h(-e_z) = height of C
Cpos = sp.Matrix([x, y, Sig])
rP = -R * D2 * gam / Sig                     # P - C (world)
Ppos = Cpos + rP
G = Cpos + R * sp.Matrix([0, 0, -h])

# --- support point: maximise -e_z . (R p) over the ellipsoid p^T D^-2 p = 1:
#     stationarity -gamma = mu D^-2 p  ->  p = -D^2 gamma / sqrt(gamma^T D^2 gamma)
pb = -D2 * gam / Sig
assert sp.simplify((pb.T * D2.inv() * pb)[0] - 1) == 0           # on the surface
assert sp.simplify(Ppos[2]) == 0                                  # touches z = 0
nb = D2.inv() * pb                                                # outward normal (body), unnormalised
n_world = (R * nb).applyfunc(sp.simplify)
assert sp.simplify(n_world + ez / Sig) == sp.zeros(3, 1)          # normal = -e_z

W = (R.T * ddt(R)).applyfunc(sp.simplify)
assert (W + W.T).applyfunc(sp.simplify) == sp.zeros(3, 3)
w_body = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
Ww = (ddt(R) * R.T).applyfunc(sp.simplify)
w_world = sp.Matrix([Ww[2, 1], Ww[0, 2], Ww[1, 0]])
assert (w_world - R * w_body).applyfunc(sp.simplify) == sp.zeros(3, 1)
assert sp.simplify(w_world[2] - (V[0] - V[2] * sp.sin(th))) == 0   # omega_z = psi' - phi' sin(theta)

Itens = sp.Matrix([[Ixx, Ixy, 0], [Ixy, Iyy, 0], [0, 0, Izz]])
Gd = ddt(G)
T = m / 2 * (Gd.T * Gd)[0] + (w_body.T * Itens * w_body)[0] / 2
Vpot = m * g * G[2]
L = T - Vpot
Etot = T + Vpot

dLdv = sp.Matrix([L.diff(v) for v in V])
dLdq = sp.Matrix([L.diff(qq) for qq in Q])
EL = ddt(dLdv) - dLdq                          # d/dt dL/dq' - dL/dq (linear in q'')
Mmat = EL.jacobian(Acc)
Fvec = -EL.subs({a: 0 for a in Acc})           # EL = M q'' - F
log('Lagrangian equations derived')

vP = ddt(Cpos) + w_world.cross(rP)             # material velocity of the body at P
vPz_simpl = sp.simplify(vP[2])
assert vPz_simpl == 0, vPz_simpl               # z row implied by the height relation
cons = sp.Matrix([vP[0], vP[1]])
Cm = cons.jacobian(V)
assert Cm[:, 3:] == sp.eye(2) and not (Cm.free_symbols & set(V))
CdQd = sum((Cm.diff(Q[i]) * V[i] for i in range(5)), sp.zeros(2, 5)) * V   # C' q'
assert not (CdQd.free_symbols & set(Acc))

Gdd = ddt(Gd)
wbd = ddt(w_body)
Edot = ddt(sp.Matrix([Etot]))[0]
log('constraints derived; v_P,z == 0 symbolically')

ARGS_QV = list(Q) + list(V) + list(PAR)
ARGS_QVA = list(Q) + list(V) + list(Acc) + list(PAR)
ARGS_Q = list(Q) + list(PAR)


def lamb(args, exprs, mod):
    return sp.lambdify(args, list(exprs), modules=mod, cse=True)


F_CM = {md: lamb(ARGS_Q, Cm, md) for md in ('math', 'mpmath')}
F_DYN = {md: lamb(ARGS_QV, list(Mmat) + list(Fvec) + list(CdQd), md) for md in ('math', 'mpmath')}
F_E = {md: lamb(ARGS_QV, [Etot], md) for md in ('math', 'mpmath')}
F_AUX = lamb(ARGS_QV, list(vP) + list(Ppos) + list(G) + list(w_world) + list(w_body)
             + list(n_world) + [Sig], 'mpmath')
F_NE = lamb(ARGS_QVA, list(Gdd) + list(wbd) + [Edot], 'mpmath')
log('lambdified')


# =============================================================== numerics
def solve_lin(a, r):
    """Gaussian elimination with partial pivoting (works for float and mpf)."""
    n = len(r)
    a = [list(a[i]) + [r[i]] for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda i: abs(a[i][c]))
        a[c], a[p] = a[p], a[c]
        for i in range(c + 1, n):
            f = a[i][c] / a[c][c]
            for j in range(c, n + 1):
                a[i][j] -= f * a[c][j]
    xs = [0] * n
    for i in range(n - 1, -1, -1):
        xs[i] = (a[i][n] - sum(a[i][j] * xs[j] for j in range(i + 1, n))) / a[i][i]
    return xs


def dep_speeds(c, u):
    """x', y' from the rolling constraints (C[:, 3:] = identity)."""
    return (-(c[0] * u[0] + c[1] * u[1] + c[2] * u[2]),
            -(c[5] * u[0] + c[6] * u[1] + c[7] * u[2]))


def make_rhs(par, md):
    """Reduced equations for s = (psi, theta, phi, x, y, psi', theta', phi'):
    q' = S u, q'' = S u' + b (b from C' q'), S^T (M q'' - F) = 0."""
    fcm, fdyn = F_CM[md], F_DYN[md]
    sin = math.sin if md == 'math' else mpmath.sin

    def rhs(t, s):
        q = s[:5]
        u = s[5:8]
        c = fcm(*q, *par)
        xd, yd = dep_speeds(c, u)
        out = fdyn(*q, u[0], u[1], u[2], xd, yd, *par)
        Mm, Fv, cd = out[:25], out[25:30], out[30:32]
        Sm = ((1, 0, 0), (0, 1, 0), (0, 0, 1), (-c[0], -c[1], -c[2]), (-c[5], -c[6], -c[7]))
        b3, b4 = -cd[0], -cd[1]
        rv = [Fv[i] - Mm[5 * i + 3] * b3 - Mm[5 * i + 4] * b4 for i in range(5)]
        MS = [[sum(Mm[5 * i + k] * Sm[k][j] for k in range(5)) for j in range(3)] for i in range(5)]
        A3 = [[sum(Sm[k][i] * MS[k][j] for k in range(5)) for j in range(3)] for i in range(3)]
        r3 = [sum(Sm[k][i] * rv[k] for k in range(5)) for i in range(3)]
        ud = solve_lin(A3, r3)
        out = [u[0], u[1], u[2], xd, yd, ud[0], ud[1], ud[2]]
        if len(s) > 8:                 # Omega' = omega_z (integral of the vertical spin)
            out.append(u[0] - u[2] * sin(q[1]))
        return out
    return rhs


def full_solve_mp(par, q, u):
    """40-digit evaluation with the full multiplier system (Lagrange-d'Alembert)."""
    c = F_CM['mpmath'](*q, *par)
    xd, yd = dep_speeds(c, u)
    qd = list(u) + [xd, yd]
    out = F_DYN['mpmath'](*q, *qd, *par)
    Mm, Fv, cd = out[:25], out[25:30], out[30:32]
    K = mpmath.zeros(7, 7)
    rhs = mpmath.zeros(7, 1)
    for i in range(5):
        for j in range(5):
            K[i, j] = Mm[5 * i + j]
        for a in range(2):
            K[i, 5 + a] = -c[5 * a + i]
            K[5 + a, i] = c[5 * a + i]
        rhs[i] = Fv[i]
    rhs[5], rhs[6] = -cd[0], -cd[1]
    sol = mpmath.lu_solve(K, rhs)
    qdd = [sol[i] for i in range(5)]
    lam = [sol[5], sol[6]]
    return qd, qdd, lam


def params_delta(ps):
    """Inertia entries of Rz(delta) diag(A, B, Cz) Rz(delta)^T at DPS digits."""
    dl = mpmath.mpf(ps['delta'])
    A, B, Cz = (mpmath.mpf(ps[k]) for k in ('A', 'B', 'Cz'))
    cd, sd = mpmath.cos(dl), mpmath.sin(dl)
    return {'Ixx': A * cd**2 + B * sd**2, 'Iyy': A * sd**2 + B * cd**2, 'Izz': Cz,
            'Ixy': (A - B) * sd * cd}


def par_list(ps):
    base = [mpmath.mpf(ps[k]) for k in ('a1', 'a2', 'a3', 'h', 'm', 'g')]
    if 'delta' in ps:
        it = params_delta(ps)
    else:
        it = {k: mpmath.mpf(ps[k]) for k in ('Ixx', 'Iyy', 'Izz', 'Ixy')}
    return base + [it['Ixx'], it['Iyy'], it['Izz'], it['Ixy']]


def S(v, n=NSIG):
    return mpmath.nstr(mpmath.mpf(v), n, min_fixed=-4, max_fixed=6, strip_zeros=False)


def relerr(a, b):
    return abs(a - b) / max(abs(a), abs(b), mpmath.mpf(1))


# --------------------------------------------------------------- parameter sets
BASE = {'a1': '0.20', 'a2': '0.03', 'a3': '0.02', 'h': '0.01', 'm': '1.0', 'g': '9.81',
        'A': '2.0e-4', 'B': '1.6e-3', 'Cz': '1.7e-3'}
PSETS = {
    'main': dict(BASE, delta='0.1'),
    'check': dict(BASE, delta='0.0'),
    # Kane & Levinson (1982) as given by the Autolev / MotionGenesis sample problem,
    # mapped to these axes (b1 -> z up, b2 -> x long, b3 -> y):  I23 -> Ixy.
    'kane_levinson_1982': {'a1': '0.20', 'a2': '0.03', 'a3': '0.02', 'h': '0.01', 'm': '1.0',
                           'g': '9.81', 'Ixx': '2.0e-4', 'Iyy': '1.6e-3', 'Izz': '1.7e-3',
                           'Ixy': '2.0e-5'},
}
PARS_MP = {k: par_list(v) for k, v in PSETS.items()}
PARS_F = {k: [float(a) for a in v] for k, v in PARS_MP.items()}


# =============================================================== output 1: states
def gen_states(seed, n):
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        def d(lo, hi):
            return '%.6f' % round(rng.uniform(lo, hi), 6)
        q = [d(-3, 3), d(-0.4, 0.4), d(-0.4, 0.4), d(-1, 1), d(-1, 1)]
        u = [d(-2, 2), d(-2, 2), d(-2, 2)]
        out.append((q, u))
    return out


STATE_SEED = 1988
STATES = gen_states(STATE_SEED, 12)
checks = {'max_rel_full_vs_reduced_qdd': 0, 'max_rel_lambda_vs_m_Gdd_xy': 0,
          'max_abs_newton_euler_torque_residual': 0, 'max_abs_dEdt': 0,
          'max_abs_vP': 0, 'max_abs_Pz': 0, 'max_abs_normal_plus_ez': 0,
          'max_abs_contact_on_ellipsoid_residual': 0}
state_out = {}
for setname in ('main', 'check'):
    par = PARS_MP[setname]
    p = dict(zip(PNAMES, par))
    Imat = mpmath.matrix([[p['Ixx'], p['Ixy'], 0], [p['Ixy'], p['Iyy'], 0], [0, 0, p['Izz']]])
    rhs_mp = make_rhs(par, 'mpmath')
    lst = []
    for qs, us in STATES:
        q = [mpmath.mpf(v) for v in qs]
        u = [mpmath.mpf(v) for v in us]
        qd, qdd, lam = full_solve_mp(par, q, u)
        red = rhs_mp(0, q + u)
        checks['max_rel_full_vs_reduced_qdd'] = max(checks['max_rel_full_vs_reduced_qdd'],
                                                    max(relerr(qdd[i], red[5 + i]) for i in range(3)),
                                                    relerr(qd[3], red[3]), relerr(qd[4], red[4]))
        aux = F_AUX(*q, *qd, *par)
        vPn, Pw, Gw, ww, wb, nw, zc = aux[0:3], aux[3:6], aux[6:9], aux[9:12], aux[12:15], aux[15:18], aux[18]
        ne = F_NE(*q, *qd, *qdd, *par)
        Gddn, wbdn, dEdt = ne[0:3], ne[3:6], ne[6]
        Fc = [p['m'] * Gddn[0], p['m'] * Gddn[1], p['m'] * (Gddn[2] + p['g'])]   # plane -> body
        checks['max_rel_lambda_vs_m_Gdd_xy'] = max(checks['max_rel_lambda_vs_m_Gdd_xy'],
                                                   relerr(lam[0], Fc[0]), relerr(lam[1], Fc[1]))
        # Newton-Euler about G in body axes: I wb' + wb x I wb = R^T ((P - G) x Fc)
        c1, s1 = mpmath.cos(q[0]), mpmath.sin(q[0])
        c2, s2 = mpmath.cos(q[1]), mpmath.sin(q[1])
        c3, s3 = mpmath.cos(q[2]), mpmath.sin(q[2])
        Rn = (mpmath.matrix([[c1, -s1, 0], [s1, c1, 0], [0, 0, 1]])
              * mpmath.matrix([[c2, 0, s2], [0, 1, 0], [-s2, 0, c2]])
              * mpmath.matrix([[1, 0, 0], [0, c3, -s3], [0, s3, c3]]))
        rGP = mpmath.matrix([Pw[i] - Gw[i] for i in range(3)])
        Fm = mpmath.matrix(Fc)
        tq = mpmath.matrix([rGP[1] * Fm[2] - rGP[2] * Fm[1], rGP[2] * Fm[0] - rGP[0] * Fm[2],
                            rGP[0] * Fm[1] - rGP[1] * Fm[0]])
        wbm, wbdm = mpmath.matrix(wb), mpmath.matrix(wbdn)
        Iw = Imat * wbm
        lhs = Imat * wbdm + mpmath.matrix([wbm[1] * Iw[2] - wbm[2] * Iw[1], wbm[2] * Iw[0] - wbm[0] * Iw[2],
                                           wbm[0] * Iw[1] - wbm[1] * Iw[0]])
        res = lhs - Rn.T * tq
        checks['max_abs_newton_euler_torque_residual'] = max(
            checks['max_abs_newton_euler_torque_residual'], max(abs(res[i]) for i in range(3)))
        checks['max_abs_dEdt'] = max(checks['max_abs_dEdt'], abs(dEdt))
        checks['max_abs_vP'] = max(checks['max_abs_vP'], max(abs(v) for v in vPn))
        checks['max_abs_Pz'] = max(checks['max_abs_Pz'], abs(Pw[2]))
        checks['max_abs_normal_plus_ez'] = max(checks['max_abs_normal_plus_ez'],
                                               abs(nw[0] * zc), abs(nw[1] * zc), abs(nw[2] * zc + 1))
        pbody = Rn.T * mpmath.matrix([Pw[i] - [q[3], q[4], zc][i] for i in range(3)])
        on = (pbody[0] / p['a1'])**2 + (pbody[1] / p['a2'])**2 + (pbody[2] / p['a3'])**2 - 1
        checks['max_abs_contact_on_ellipsoid_residual'] = max(
            checks['max_abs_contact_on_ellipsoid_residual'], abs(on))
        E = F_E['mpmath'](*q, *qd, *par)[0]
        lst.append({
            'q': qs, 'u': us,
            'qdot_dep': [S(qd[3]), S(qd[4])],
            'u_dot': [S(v) for v in qdd[:3]],
            'qddot_dep': [S(qdd[3]), S(qdd[4])],
            'lambda': [S(lam[0]), S(lam[1])],
            'normal_force': S(Fc[2]),
            'energy': S(E),
            'contact_point': [S(Pw[0]), S(Pw[1]), S(Pw[2])],
            'centre_height': S(zc),
            'com': [S(v) for v in Gw],
            'omega_world': [S(v) for v in ww],
            'omega_body': [S(v) for v in wb],
        })
    state_out[setname] = lst
for k in checks:
    assert checks[k] < mpmath.mpf(10) ** (-(DPS - 8)), (k, checks[k])
log('states done', {k: mpmath.nstr(v, 3) for k, v in checks.items()})


# =============================================================== integrators
NSEQ = [2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28]


class BS:
    """Bulirsch-Stoer: Gragg's modified midpoint rule with the smoothing end step,
    polynomial (Neville) extrapolation in h^2 over n = 2, 4, 6, ...; a step is
    accepted at the first column j >= 2 whose last two diagonal entries agree
    within tol (mixed abs/rel, RMS norm)."""
    name = 'Bulirsch-Stoer (Gragg midpoint + Richardson extrapolation)'

    def __init__(self, f, tol, kmax=8, jtarget=5):
        self.f, self.tol, self.kmax, self.jt = f, tol, kmax, jtarget
        self.nfev = 0

    def attempt(self, t, y, f0, H):
        f, tol, n = self.f, self.tol, len(y)
        if not isinstance(y[0], float):
            H = mpmath.mpf(H)          # H / n_j must not be rounded to a double
        Tab = []
        err = float('inf')
        for j in range(self.kmax):
            nj = NSEQ[j]
            hh = H / nj
            z0 = list(y)
            z1 = [y[i] + hh * f0[i] for i in range(n)]
            for k in range(1, nj):
                fk = f(t + k * hh, z1)
                z0, z1 = z1, [z0[i] + 2 * hh * fk[i] for i in range(n)]
            fe = f(t + H, z1)
            self.nfev += nj
            row = [[(z1[i] + z0[i] + hh * fe[i]) / 2 for i in range(n)]]
            for k in range(1, j + 1):
                # (cur - prev) / ((n_j / n_{j-k})^2 - 1) with exact integer factors (no float
                # rounding of the ratio: matters for the mpmath run)
                num, den = NSEQ[j - k] ** 2, NSEQ[j] ** 2 - NSEQ[j - k] ** 2
                prev, cur = Tab[j - 1][k - 1], row[k - 1]
                row.append([cur[i] + (cur[i] - prev[i]) * num / den for i in range(n)])
            Tab.append(row)
            if j >= 2:
                a, b = row[j], row[j - 1]
                err = math.sqrt(sum(float((a[i] - b[i]) / (tol + tol * max(abs(a[i]), abs(y[i])))) ** 2
                                    for i in range(n)) / n)
                if err <= 1.0:
                    return True, a, err, j
        return False, None, err, self.kmax - 1

    def next_h(self, H, err, j, ok):
        if not ok:
            return H * 0.5
        if j < self.jt - 1:
            return H * 1.6
        if j > self.jt:
            return H * 0.6
        return H * min(1.5, max(0.7, 0.94 * (0.65 / max(err, 1e-10)) ** (1.0 / (2 * j + 1))))


class DP54:
    """Dormand-Prince 5(4) with local extrapolation (5th-order solution), FSAL."""
    name = 'Dormand-Prince 5(4)'
    c = (0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1)
    a = ((), (1 / 5,), (3 / 40, 9 / 40), (44 / 45, -56 / 15, 32 / 9),
         (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729),
         (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656))
    b = (35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0)
    bs = (5179 / 57600, 0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40)

    def __init__(self, f, tol):
        self.f, self.tol, self.nfev = f, tol, 0
        self.e = [self.b[i] - self.bs[i] for i in range(7)]

    def attempt(self, t, y, f0, H):
        f, n = self.f, len(y)
        ks = [f0]
        for s in range(1, 6):
            ys = [y[i] + H * sum(self.a[s][j] * ks[j][i] for j in range(s)) for i in range(n)]
            ks.append(f(t + self.c[s] * H, ys))
        yn = [y[i] + H * sum(self.b[j] * ks[j][i] for j in range(6)) for i in range(n)]
        ks.append(f(t + H, yn))
        self.nfev += 6
        e = [H * sum(self.e[j] * ks[j][i] for j in range(7)) for i in range(n)]
        err = math.sqrt(sum(float(e[i] / (self.tol + self.tol * max(abs(y[i]), abs(yn[i])))) ** 2
                            for i in range(n)) / n)
        self._last_f = ks[6]
        return err <= 1.0, yn, err, 5

    def next_h(self, H, err, j, ok):
        if not ok:
            return H * max(0.2, 0.9 * err ** -0.2)
        return H * min(5.0, 0.9 * max(err, 1e-12) ** -0.2)


def advance(integ, t0, y0, f0, t1, h0):
    """Adaptive integration from t0 to t1 (used for refinement)."""
    t, y, fv, hcur = t0, y0, f0, h0
    while t < t1:
        H = min(hcur, t1 - t)
        if t + H >= t1 - 1e-14 * max(1.0, abs(float(t1))):
            H = t1 - t
        ok, yn, err, j = integ.attempt(t, y, fv, H)
        hcur = integ.next_h(H, err, j, ok)
        if ok:
            t = t1 if H == t1 - t else t + H
            y = yn
            fv = integ.f(t, y)
    return y


def hermite(y0, f0, y1, f1, H, th_):
    h00 = 2 * th_**3 - 3 * th_**2 + 1
    h10 = th_**3 - 2 * th_**2 + th_
    h01 = -2 * th_**3 + 3 * th_**2
    h11 = th_**3 - th_**2
    return [h00 * y0[i] + h10 * H * f0[i] + h01 * y1[i] + h11 * H * f1[i] for i in range(len(y0))]


def run_reversal(par, s0, t_end, integ, hmax, grid_dt=0.05, mean_window=0.2, band=0.2, full=True):
    """Integrate s = (q, u, Omega) with Omega' = omega_z; afterwards locate
      * every sign change of omega_z in [0, t_end]: omega_z is sampled 8 times per step (cubic
        Hermite), samples with |omega_z| < `band` are replaced by exact values (re-integration
        from the step start); sign changes between samples, and dips towards zero between
        samples (local minima of |omega_z|, golden-section refined), are then solved by
        Illinois regula falsi on exact re-integration;
      * (full) sign changes of the centred moving average
        wbar(t) = (Omega(t + w/2) - Omega(t - w/2)) / w, w = mean_window;
      * (full) the extreme of omega_z with sign opposite to the initial spin between the
        first and second sign change of wbar (or the end of the run)."""
    md = 'math' if isinstance(s0[0], float) else 'mpmath'
    sin = math.sin if md == 'math' else mpmath.sin
    fE, fcm, f = F_E[md], F_CM[md], integ.f
    gsteps = int(round(1 / grid_dt))

    def wz(s):
        return s[5] - s[7] * sin(s[1])

    def energy(s):
        xd, yd = dep_speeds(fcm(*s[:5], *par), s[5:8])
        return fE(*s[:5], s[5], s[6], s[7], xd, yd, *par)[0]

    t_cpu = time.time()
    zero = 0.0 if md == 'math' else mpmath.mpf(0)
    t, yv = zero, list(s0) + [zero]
    fv = f(t, yv)
    sign0 = 1 if wz(yv) > 0 else -1
    E0 = energy(yv)
    dEmax = 0
    hcur = hmax / 10
    steps_t, steps_y, steps_f = [t], [yv], [fv]
    amp = []                                  # per step end: (t, |theta|, |phi|)
    smp_t, smp_w = [t], [wz(yv)]              # omega_z samples
    grid = [(0.0, float(wz(yv)), float(yv[1]), float(yv[2]))]
    targets = [ig / gsteps if md == 'math' else mpmath.mpf(ig) / gsteps
               for ig in range(1, int(math.floor(float(t_end) * gsteps + 1e-9)) + 1)]
    if not targets or targets[-1] < t_end - 1e-12:
        targets.append(t_end)
    nsteps = nrej = 0
    for tg in targets:
        while t < tg:
            H = min(hcur, hmax, tg - t)
            if t + H >= tg - 1e-12:
                H = tg - t
            ok, yn, err, j = integ.attempt(t, yv, fv, H)
            hcur = integ.next_h(H, err, j, ok)
            if not ok:
                nrej += 1
                continue
            nsteps += 1
            tn = tg if H == tg - t else t + H
            fn = f(tn, yn)
            for i in range(1, 8):
                smp_t.append(t + H * i / 8)
                smp_w.append(wz(hermite(yv, fv, yn, fn, H, i / 8)))
            smp_t.append(tn)
            smp_w.append(wz(yn))
            steps_t.append(tn)
            steps_y.append(yn)
            steps_f.append(fn)
            amp.append((float(tn), abs(float(yn[1])), abs(float(yn[2]))))
            dEmax = max(dEmax, abs(energy(yn) - E0))
            t, yv, fv = tn, yn, fn
        if abs(float(tg) * gsteps - round(float(tg) * gsteps)) < 1e-9:
            grid.append((float(tg), float(wz(yv)), float(yv[1]), float(yv[2])))
    t_int = time.time() - t_cpu

    def state_at(tau):
        k = min(bisect.bisect_right(steps_t, tau) - 1, len(steps_t) - 2)
        if tau == steps_t[k]:
            return steps_y[k]
        return advance(integ, steps_t[k], steps_y[k], steps_f[k], tau, steps_t[k + 1] - steps_t[k])

    def wz_t(tau):
        return wz(state_at(tau))

    eps_t = 1e-13 if md == 'math' else mpmath.mpf(10) ** -22

    def root(fun, ta, tb, fa, fb):
        side = 0                              # Illinois (modified regula falsi)
        for _ in range(200):
            tc = (ta * fb - tb * fa) / (fb - fa)
            fc = fun(tc)
            if fc == 0:
                return tc
            if (fc > 0) == (fb > 0):
                tb, fb = tc, fc
                if side == -1:
                    fa /= 2
                side = -1
            else:
                ta, fa = tc, fc
                if side == 1:
                    fb /= 2
                side = 1
            if abs(tb - ta) < eps_t:
                break
        return (ta + tb) / 2

    def golden_min(fun, lo, hi, tolx):
        gr = (math.sqrt(5) - 1) / 2
        x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
        f1, f2 = fun(x1), fun(x2)
        while hi - lo > tolx:
            if f1 > f2:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + gr * (hi - lo)
                f2 = fun(x2)
            else:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - gr * (hi - lo)
                f1 = fun(x1)
        tm = (lo + hi) / 2
        return tm, fun(tm)

    tol_min = 1e-10 if md == 'math' else mpmath.mpf(10) ** -16
    # ---- sign changes of omega_z
    # samples close to zero are replaced by exact values, so that every sign decision is exact
    N = len(smp_t)
    herr = 0.0
    for i in range(N):
        if abs(smp_w[i]) < band:
            we = wz_t(smp_t[i])
            herr = max(herr, abs(float(we - smp_w[i])))
            smp_w[i] = we
    assert herr < band / 4, ('Hermite sampling error too large for the exact band', herr)
    roots, dips = [], []
    for i in range(1, N):
        if (smp_w[i - 1] > 0) != (smp_w[i] > 0):
            roots.append(root(wz_t, smp_t[i - 1], smp_t[i], smp_w[i - 1], smp_w[i]))
    for i in range(1, N - 1):                 # dips towards zero that no sample reaches
        a_, b_, c_ = smp_w[i - 1], smp_w[i], smp_w[i + 1]
        if ((a_ > 0) == (b_ > 0) == (c_ > 0) and abs(b_) < band
                and abs(b_) <= abs(a_) and abs(b_) <= abs(c_)):
            dips.append((i - 1, i + 1, 1 if b_ > 0 else -1))
    for i0, i1, sg in dips:
        tm, vm = golden_min(lambda tau: sg * wz_t(tau), smp_t[i0], smp_t[i1], tol_min)
        if vm < 0:                            # the dip crosses zero between the samples
            for ta, tb in ((smp_t[i0], tm), (tm, smp_t[i1])):
                fa, fb = wz_t(ta), wz_t(tb)
                roots.append(root(wz_t, ta, tb, fa, fb))
    roots.sort()
    crossings = []
    for r_ in roots:
        if not crossings or abs(r_ - crossings[-1]) > 1e-9:
            crossings.append(r_)
    res = {'t_end': float(t), 'sign0': sign0, 'crossings': crossings, 'E0': E0, 'dEmax': dEmax,
           'grid': grid, 'steps': nsteps, 'rejected': nrej, 'nfev': integ.nfev,
           'cpu_integration': t_int, 'hermite_max_err_in_band': herr}
    if len(crossings) >= 2 and crossings[1] - crossings[0] < 0.01:
        sg = -sign0
        tm, vm = golden_min(lambda tau: -sg * wz_t(tau), crossings[0], crossings[1], tol_min)
        res['first_excursion'] = {'duration': crossings[1] - crossings[0], 'extreme_time': tm, 'extreme': vm}
    if not full:
        return res
    # ---- centred moving average of omega_z
    w2 = mean_window / 2

    def omega_h(tau):                         # Hermite interpolation of Omega (for bracketing)
        k = min(bisect.bisect_right(steps_t, tau) - 1, len(steps_t) - 2)
        Hk = steps_t[k + 1] - steps_t[k]
        th_ = (tau - steps_t[k]) / Hk
        h00, h10 = 2 * th_**3 - 3 * th_**2 + 1, th_**3 - 2 * th_**2 + th_
        h01, h11 = -2 * th_**3 + 3 * th_**2, th_**3 - th_**2
        return (h00 * steps_y[k][8] + h10 * Hk * steps_f[k][8]
                + h01 * steps_y[k + 1][8] + h11 * Hk * steps_f[k + 1][8])

    def wbar(tau):
        return (state_at(tau + w2)[8] - state_at(tau - w2)[8]) / mean_window

    mt = [tk for tk in steps_t if w2 <= tk <= t - w2]
    mv = [(omega_h(tk + w2) - omega_h(tk - w2)) / mean_window for tk in mt]
    mean_cross = []
    for i in range(1, len(mt)):
        if (mv[i - 1] > 0) != (mv[i] > 0):
            fa, fb = wbar(mt[i - 1]), wbar(mt[i])
            if (fa > 0) != (fb > 0):
                mean_cross.append(root(wbar, mt[i - 1], mt[i], fa, fb))
    res['mean_crossings'] = mean_cross
    # ---- extreme of omega_z in the first reversed phase
    if mean_cross:
        lo_t = mean_cross[0] - w2
        hi_t = mean_cross[1] + w2 if len(mean_cross) > 1 else t
        cand = [i for i in range(1, N - 1) if lo_t <= smp_t[i] <= hi_t]
        ib = max(cand, key=lambda i: -sign0 * smp_w[i])
        tm, vm = golden_min(lambda tau: sign0 * wz_t(tau), smp_t[ib - 1], smp_t[ib + 1], tol_min)
        res['extreme'] = (tm, sign0 * vm)
        res['extreme_window'] = (lo_t, hi_t)
    # ---- rocking amplitudes per phase of the mean spin
    edges = [0.0] + [float(c) for c in mean_cross] + [float(t)]
    res['phase_amplitudes'] = [
        [edges[k], edges[k + 1],
         max([a[1] for a in amp if edges[k] < a[0] <= edges[k + 1]] or [0.0]),
         max([a[2] for a in amp if edges[k] < a[0] <= edges[k + 1]] or [0.0])]
        for k in range(len(edges) - 1)]
    return res


# =============================================================== output 2: spin reversal
def ic_main(spin):
    return [0.0, 0.01, 0.01, 0.0, 0.0, float(spin), 0.0, 0.0]


def ic_autolev_mp(w1=5):
    """Autolev/MotionGenesis sample: BodyXYZ q1 = 0 (about b1 = z), q2 = +0.5 deg
    (about b2 = x), q3 = -0.5 deg (about b3 = y); w = 5 rad/s about b1 (body z),
    w2 = w3 = 0.  Converted exactly to (psi, theta, phi, psi', theta', phi')."""
    d = mpmath.pi / 180
    q2, q3 = mpmath.mpf('0.5') * d, mpmath.mpf('-0.5') * d
    Rxm = mpmath.matrix([[1, 0, 0], [0, mpmath.cos(q2), -mpmath.sin(q2)], [0, mpmath.sin(q2), mpmath.cos(q2)]])
    Rym = mpmath.matrix([[mpmath.cos(q3), 0, mpmath.sin(q3)], [0, 1, 0], [-mpmath.sin(q3), 0, mpmath.cos(q3)]])
    Rm = Rxm * Rym
    th_ = -mpmath.asin(Rm[2, 0])
    ps_ = mpmath.atan2(Rm[1, 0], Rm[0, 0])
    ph_ = mpmath.atan2(Rm[2, 1], Rm[2, 2])
    st, ct, sp_, cp_ = mpmath.sin(th_), mpmath.cos(th_), mpmath.sin(ph_), mpmath.cos(ph_)
    # w_body = (phi' - psi' st, psi' sp ct + theta' cp, psi' cp ct - theta' sp)
    Amat = mpmath.matrix([[-st, 0, 1], [sp_ * ct, cp_, 0], [cp_ * ct, -sp_, 0]])
    ud = mpmath.lu_solve(Amat, mpmath.matrix([0, 0, w1]))
    return [ps_, th_, ph_, mpmath.mpf(0), mpmath.mpf(0), ud[0], ud[1], ud[2]]


def fl(v):
    return repr(float(v))


def summarize(r):
    out = {'t_end': r['t_end'], 'steps': r['steps'], 'rejected_steps': r['rejected'], 'rhs_evaluations': r['nfev'],
           'energy_initial': fl(r['E0']), 'energy_max_abs_drift': float(r['dEmax']),
           'energy_max_rel_drift': float(r['dEmax'] / abs(r['E0'])),
           't_first_sign_change': fl(r['crossings'][0]) if r['crossings'] else None,
           'omega_z_sign_changes': [fl(c) for c in r['crossings']],
           'hermite_sample_max_error_near_zero': float(r['hermite_max_err_in_band'])}
    if 'first_excursion' in r:
        fe = r['first_excursion']
        out['first_excursion'] = {'duration': fl(fe['duration']), 'extreme_omega_z': fl(fe['extreme']),
                                  'extreme_time': fl(fe['extreme_time'])}
    if 'mean_crossings' in r:
        out['mean_spin_sign_changes'] = [fl(c) for c in r['mean_crossings']]
        out['t_first_mean_spin_sign_change'] = fl(r['mean_crossings'][0]) if r['mean_crossings'] else None
    if 'extreme' in r:
        out['reversed_extreme_omega_z'] = fl(r['extreme'][1])
        out['reversed_extreme_time'] = fl(r['extreme'][0])
        out['reversed_extreme_search_window'] = [fl(v) for v in r['extreme_window']]
    if 'phase_amplitudes' in r:
        out['rocking_amplitude_per_mean_spin_phase'] = [
            {'from': round(a, 6), 'to': round(b, 6), 'max_abs_theta': round(c, 6), 'max_abs_phi': round(d, 6)}
            for a, b, c, d in r['phase_amplitudes']]
    out['cpu_seconds'] = round(r['cpu_total'], 1)
    return out


def reversal_case(setname, s0, t_end, label):
    log('spin reversal', label)
    runs = {}
    hmax = 0.005
    for key, mk in (('BS_tol1e-11', lambda f: BS(f, 1e-11)),
                    ('BS_tol1e-13', lambda f: BS(f, 1e-13)),
                    ('DP54_tol1e-12', lambda f: DP54(f, 1e-12))):
        integ = mk(make_rhs(PARS_F[setname], 'math'))
        t1 = time.time()
        r = run_reversal(PARS_F[setname], s0, t_end, integ, hmax)
        r['cpu_total'] = time.time() - t1
        runs[key] = r
        log('  ', key, 'crossings', [round(c, 9) for c in r['crossings'][:4]], 'mean', [round(c, 7) for c in r['mean_crossings'][:3]],
            'extreme', r.get('extreme'), 'dE %.2e' % float(r['dEmax']), 'steps', r['steps'],
            'nfev', r['nfev'], '%.1fs (int %.1fs)' % (r['cpu_total'], r['cpu_integration']))
    ref, lo, dp = runs['BS_tol1e-13'], runs['BS_tol1e-11'], runs['DP54_tol1e-12']

    def pairdiff(a, b):
        n = min(len(a), len(b))
        return {'count_equal': len(a) == len(b), 'max_abs_diff': max([abs(float(a[i] - b[i])) for i in range(n)] or [0.0])}

    conv = {}
    for nm, other in (('BS11', lo), ('DP12', dp)):
        conv['first_sign_change_BS13_minus_' + nm] = float(ref['crossings'][0] - other['crossings'][0])
        conv['first_mean_sign_change_BS13_minus_' + nm] = float(ref['mean_crossings'][0] - other['mean_crossings'][0])
        conv['extreme_omega_z_BS13_minus_' + nm] = float(ref['extreme'][1] - other['extreme'][1])
        conv['extreme_time_BS13_minus_' + nm] = float(ref['extreme'][0] - other['extreme'][0])
        conv['all_sign_changes_BS13_vs_' + nm] = pairdiff(ref['crossings'], other['crossings'])
        conv['all_mean_sign_changes_BS13_vs_' + nm] = pairdiff(ref['mean_crossings'], other['mean_crossings'])
        conv['grid_omega_z_max_abs_diff_BS13_vs_' + nm] = max(abs(a[1] - b[1]) for a, b in zip(ref['grid'], other['grid']))
        conv['grid_omega_z_max_abs_diff_BS13_vs_%s_up_to' % nm] = {
            '%g' % tw: max(abs(a[1] - b[1]) for a, b in zip(ref['grid'], other['grid']) if a[0] <= tw + 1e-9)
            for tw in (0.5, 1, 2, 5, 10, 20) if tw <= t_end}
    out = {
        'reference_run': 'BS_tol1e-13',
        't_end': t_end,
        't_first_sign_change': fl(ref['crossings'][0]),
        't_first_mean_spin_sign_change': fl(ref['mean_crossings'][0]),
        'reversed_extreme_omega_z': fl(ref['extreme'][1]),
        'reversed_extreme_time': fl(ref['extreme'][0]),
        'energy_max_abs_drift': float(ref['dEmax']),
        'runs': {k: dict(summarize(v), integrator=('Bulirsch-Stoer' if k.startswith('BS') else 'Dormand-Prince 5(4)'),
                         rtol=float(k.split('tol')[1]), atol=float(k.split('tol')[1]), hmax=hmax)
                 for k, v in runs.items()},
        'convergence': conv,
        'trajectory': {
            'dt': 0.05,
            't': [round(gr[0], 10) for gr in ref['grid']],
            'omega_z': [float('%.12g' % gr[1]) for gr in ref['grid']],
            'theta': [float('%.12g' % gr[2]) for gr in ref['grid']],
            'phi': [float('%.12g' % gr[3]) for gr in ref['grid']],
            'omega_z_abs_diff_BS13_vs_DP12': [float('%.3g' % abs(a[1] - b[1])) for a, b in zip(ref['grid'], dp['grid'])],
            'omega_z_abs_diff_BS13_vs_BS11': [float('%.3g' % abs(a[1] - b[1])) for a, b in zip(ref['grid'], lo['grid'])],
            'note': 'grid values are the states reached exactly at t = k dt (steps end on the grid); '
                    'the two difference arrays indicate the attainable accuracy as a function of time',
        },
    }
    return out, runs


def mp_first_reversal(setname, s0, t_end, dps=30, tol=1e-18):
    """30-digit Bulirsch-Stoer run (same code, mpmath arithmetic) over [0, t_end]."""
    save = mpmath.mp.dps
    mpmath.mp.dps = dps
    try:
        par = par_list(PSETS[setname])
        integ = BS(make_rhs(par, 'mpmath'), tol, kmax=12, jtarget=8)
        s0m = [mpmath.mpf(v) for v in s0]
        t1 = time.time()
        r = run_reversal(par, s0m, mpmath.mpf(t_end), integ, hmax=0.004, full=False)
        r['cpu_total'] = time.time() - t1
        return r
    finally:
        mpmath.mp.dps = save


def mp_check(setname, s0, float_runs, label):
    t_stop = math.ceil((float_runs['BS_tol1e-13']['crossings'][0] + 0.01) * 100) / 100
    log('mpmath run', label, 'to', t_stop)
    mpr = mp_first_reversal(setname, s0, t_stop)
    c0 = mpr['crossings'][0]
    out = {'dps': 30, 'integrator': 'Bulirsch-Stoer (same code, mpmath arithmetic)', 'tol': 1e-18,
           'kmax': 12, 'hmax': 0.004, 'integrated_until': mpr['t_end'], 'rhs_evaluations': mpr['nfev'],
           'cpu_seconds': round(mpr['cpu_total'], 1),
           't_first_sign_change': mpmath.nstr(c0, 20),
           'sign_changes_until_end': [mpmath.nstr(c, 20) for c in mpr['crossings']],
           'energy_max_abs_drift': mpmath.nstr(mpr['dEmax'], 5)}
    for k, nm in (('BS_tol1e-13', 'BS13'), ('BS_tol1e-11', 'BS11'), ('DP54_tol1e-12', 'DP12')):
        out[nm + '_minus_mpmath'] = float(float_runs[k]['crossings'][0] - c0)
    if 'first_excursion' in mpr:
        out['first_excursion_extreme_omega_z'] = mpmath.nstr(mpr['first_excursion']['extreme'], 15)
    log('   ', out)
    return out


reversal = {}
# --- which direction reverses for delta = 0.1?  (both do, in this conservative model;
#     the one that reverses first/fast is the 'non-preferred' one)
dircheck = {}
for spin in (-5, 5):
    integ = BS(make_rhs(PARS_F['main'], 'math'), 1e-10)
    r = run_reversal(PARS_F['main'], ic_main(spin), 2.5, integ, 0.005, full=False)
    dircheck['psi_d0=%+d' % spin] = {'t_first_sign_change': fl(r['crossings'][0]) if r['crossings'] else None,
                                     'tol': 1e-10, 'integrated_until': 2.5}
log('direction check', dircheck)
reversal['direction_check_main'] = dict(dircheck, note=(
    'initial state of the main run with psi_d0 = -5 and +5, BS tol 1e-10: both directions reverse in this '
    'conservative model; -5 reverses first, so -5 is taken as the non-preferred (reversing) direction'))
dircheck_kl = {}
for w1 in (5, -5):
    integ = BS(make_rhs(PARS_F['kane_levinson_1982'], 'math'), 1e-10)
    r = run_reversal(PARS_F['kane_levinson_1982'], [float(v) for v in ic_autolev_mp(w1)], 20.0, integ, 0.005,
                     full=False)
    dircheck_kl['w1=%+d' % w1] = {'t_first_sign_change': fl(r['crossings'][0]) if r['crossings'] else None,
                                  'tol': 1e-10, 'integrated_until': 20.0}
log('direction check KL', dircheck_kl)
reversal['direction_check_kane_levinson_1982'] = dict(dircheck_kl, note=(
    'Autolev initial state with the body spin w1 = +5 (as published) and w1 = -5 about the upward body axis'))

S0_MAIN = ic_main(-5)
main_out, main_runs = reversal_case('main', S0_MAIN, 10.0, 'main')
S0_KL_MP = ic_autolev_mp()
S0_KL = [float(v) for v in S0_KL_MP]
kl_out, kl_runs = reversal_case('kane_levinson_1982', S0_KL, 20.0, 'kane_levinson_1982')
main_out['mpmath_check'] = mp_check('main', S0_MAIN, main_runs, 'main')
kl_out['mpmath_check'] = mp_check('kane_levinson_1982', S0_KL, kl_runs, 'kane_levinson_1982')

main_out['initial_state'] = {'psi': '0', 'theta': '0.01', 'phi': '0.01', 'x': '0', 'y': '0',
                             'psi_d': '-5', 'theta_d': '0', 'phi_d': '0',
                             'omega_z0': '-5 (psi_d - phi_d sin(theta))',
                             'source': 'fallback of the brief (no published initial conditions found for '
                                       'Garcia & Hubbard 1988 or Lindberg & Longman 1983)'}
main_out['parameter_set'] = 'main'
kl_out['initial_state'] = {
    'psi': S(S0_KL_MP[0], 25), 'theta': S(S0_KL_MP[1], 25), 'phi': S(S0_KL_MP[2], 25), 'x': '0', 'y': '0',
    'psi_d': S(S0_KL_MP[5], 25), 'theta_d': S(S0_KL_MP[6], 25), 'phi_d': S(S0_KL_MP[7], 25),
    'as_integrated_f64': {'order': ['psi', 'theta', 'phi', 'x', 'y', 'psi_d', 'theta_d', 'phi_d'],
                          'values': [fl(v) for v in S0_KL],
                          'note': 'the exact values above rounded to IEEE doubles; all runs (float and '
                                  'mpmath) start from these doubles'},
    'source': 'Autolev/MotionGenesis rattleback sample problem (Kane & Levinson 1982 parameters): '
              'BodyXYZ angles q1 = 0, q2 = 0.5 deg, q3 = -0.5 deg, body angular velocity '
              'w1 = 5 rad/s about the (upward) body axis b1, w2 = w3 = 0; converted exactly to these '
              'coordinates: R0 = Rx(0.5 deg) Ry(-0.5 deg), omega_body = (0, 0, 5)'}
kl_out['parameter_set'] = 'kane_levinson_1982'
reversal['main'] = main_out
reversal['kane_levinson_1982'] = kl_out

# =============================================================== published values
published = {
    'searched': ['Garcia & Hubbard 1988, Proc. R. Soc. Lond. A 418, 165-197',
                 'Lindberg & Longman 1983, Acta Mechanica 49',
                 'Kane & Levinson 1982, Int. J. Non-Linear Mech. 17, 175-186'],
    'kane_levinson_1982': {
        'status': 'parameter set and initial conditions confirmed from secondary sources; '
                  'no numerical reversal time or reversed spin rate found in any accessible source',
        'parameters_as_found': 'ellipsoid semi-axes 20 cm (long), 3 cm, 2 cm (vertical); h = 1 cm from the '
                               'ellipsoid centre to the mass centre (mass centre below the centre); m = 1 kg; '
                               'g = 9.81 m/s^2; central moments 2 kg cm^2 (long axis), 16 kg cm^2 (transverse), '
                               '17 kg cm^2 (vertical); product of inertia 0.2 kg cm^2 in the horizontal plane',
        'sources': [
            'http://www.autolev.com/WebSite/SampleProblemRattleback/Rattleback.html (Autolev sample problem: '
            'a = 2 cm (b1, vertical), b = 20 cm, c = 3 cm, h = 1 cm, m = 1 kg, I11 = 17, I22 = 2, I33 = 16, '
            'I23 = 0.2 kg cm^2; q1 = 0, q2 = 0.5 deg, q3 = -0.5 deg, w1 = 5 rad/s, w2 = w3 = 0, t = 0..5 s)',
            'http://www.motiongenesis.com/MGWebSite/MGGetStarted/MGExampleRattleback/RattlebackKane.html '
            '(same numbers: SetMassInertia(m = 1 kg, Ixx = 17, Iyy = 2, Izz = 16, Ixy = 0, Iyz = 0.2, Izx = 0 kg cm^2), '
            'So = Bcm + h Bx, Bx up; a, b, c = 2, 20, 3 cm)',
            'https://pypi.org/project/RattleBack (cites Kane & Levinson 1982: abch = (20, 3, 2, 1) cm, '
            'ABCD = (2, 16, 17, -0.2) cm^2 per unit mass with a body frame whose third axis points down; '
            'example init 0.5 deg, 0.5 deg, spin -5 rad/s about that downward axis, with damping sigma = 1)',
            'pydy/pydy_examples rattleback/cpp/ellipsoid_eq.cc (a, b, c = 0.2, 0.03, 0.02 m, COM offset 0.01 m along '
            'the downward body z, m = 1 kg, Ixx = 2e-4, Iyy = 1.6e-3, Izz = 1.7e-3, Ixy = -2e-5 kg m^2, z down)',
            'supercomputingchallenge.org 99-00 final report 038 (high-school project, not peer reviewed; '
            'a = 0.2, b = 0.03, c = 0.02, h = 0.01 m, A = 2.0e-4, B = 1.6e-3, C = 1.7e-3, D = -2.0e-5 kg m^2, '
            'M = 1 kg, g = 9.81; 0.5 deg roll and pitch, spin -5 rad/s, 20 s; qualitative plots only)'],
        'mapping_to_these_axes': 'Autolev b1 (up) -> z, b2 (20 cm) -> x, b3 (3 cm) -> y (a cyclic, right-handed '
                                 'relabelling), so I23 -> Ixy = +2.0e-5 kg m^2 as an inertia-tensor entry (Kane/'
                                 'Autolev products of inertia are tensor entries). The z-down sources give '
                                 'Ixy = -2e-5 with spin -5 about their down axis, i.e. the same body and the same '
                                 'spin (+5 about up) in these axes. Simulation (direction_check_kane_levinson_1982): '
                                 'w1 = +5 first reverses at t = %s s, w1 = -5 %s.' % (
                                     dircheck_kl['w1=+5']['t_first_sign_change'],
                                     ('first reverses at t = %s s' % dircheck_kl['w1=-5']['t_first_sign_change'])
                                     if dircheck_kl['w1=-5']['t_first_sign_change'] else 'does not reverse within 20 s'),
        'equivalent_delta': 'Ixy = +2e-5 corresponds to principal axes turned by about -0.0143 rad about z '
                            '(0.5 atan(2 Ixy / (Ixx - Iyy))); the brief\'s delta = 0.1 has the opposite sign and '
                            'a 7x larger product of inertia (Ixy = (A - B) sin(delta) cos(delta) = -1.39e-4).',
        'published_reversal_time': None,
    },
    'garcia_hubbard_1988': {
        'status': 'could not confirm: no accessible source lists the parameter set or initial conditions used '
                  'by Garcia & Hubbard; the set a1 = 0.20, a2 = 0.03, a3 = 0.02, h = 0.01, m = 1, A = 2e-4, '
                  'B = 1.6e-3, Cz = 1.7e-3 is, in every source found, attributed to Kane & Levinson 1982 '
                  '(with a product of inertia 2e-5 instead of a misalignment angle).',
        'found': 'Kondo & Nakanishi, Phys. Rev. E 95, 062207 (2017), arXiv:1704.06717 (abstract): Garcia & '
                 'Hubbard derived a formula for the reversal time t_r valid for small spin and small '
                 'oscillations; no numbers taken from it here.',
    },
    'lindberg_longman_1983': {'status': 'could not find any accessible text with parameters or results'},
    'comparison': 'no published numerical reversal time / reversed spin rate was found, so no quantitative '
                  'comparison is possible; qualitatively the Kane & Levinson set with +5 rad/s about the '
                  'vertical reverses within a few seconds, consistent with the Autolev sample problem '
                  'simulating 0..5 s.',
}

# =============================================================== json
doc = {
    'description': 'Rattleback: rigid body with ellipsoidal surface (semi-axes a1, a2, a3 along the body '
                   'axes, centred at the geometric centre C) rolling without slipping on the plane z = 0. '
                   'Independent SymPy/mpmath reference (tests/data/rattleback_sympy.py).',
    'conventions': {
        'units': 'SI: m, kg, s, rad, N, J',
        'world_frame': 'z up, plane z = 0, gravity -g e_z',
        'coordinates_q': ['psi', 'theta', 'phi', 'x', 'y'],
        'rotation': 'R = Rz(psi) Ry(theta) Rx(phi), body -> world, usual right-handed elementary matrices',
        'independent_speeds_u': ['psi_d', 'theta_d', 'phi_d'],
        'dependent_speeds': ['x_d', 'y_d'],
        'centre': 'C = (x, y, z_C), z_C = sqrt(gamma^T D^2 gamma), gamma = R^T e_z, D = diag(a1, a2, a3)',
        'contact_point': 'P = C - R D^2 gamma / sqrt(gamma^T D^2 gamma) (world coordinates)',
        'centre_of_mass': 'G = C + R (0, 0, -h)',
        'inertia': 'about G in body axes, tensor entries [[Ixx, Ixy, 0], [Ixy, Iyy, 0], [0, 0, Izz]]; '
                   'delta sets: Rz(delta) diag(A, B, Cz) Rz(delta)^T, i.e. Ixx = A cos^2 + B sin^2, '
                   'Iyy = A sin^2 + B cos^2, Ixy = (A - B) sin(delta) cos(delta), Izz = Cz',
        'angular_velocity': 'omega_world from R_dot R^T, omega_body from R^T R_dot; '
                            'omega_z (world) = psi_d - phi_d sin(theta)',
        'lagrangian': 'L = m/2 |G_dot|^2 + 1/2 omega_body^T I omega_body - m g G_z',
        'energy': 'E = T + m g G_z (zero of potential at the plane)',
        'constraints': 'rows x, y of v_P = C_dot + omega_world x (P - C) = 0; the z row is identically zero',
        'lambda': 'multipliers in d/dt dL/dq_dot - dL/dq = sum_a lambda_a c_a with c_a = d(v_P,a)/d(q_dot), '
                  'a = x, y; since c_a has coefficient +1 on x_d (resp. y_d), lambda = (F_x, F_y) = '
                  'horizontal components of the contact force exerted BY the plane ON the body (N); '
                  'checked equal to m G_ddot_x, m G_ddot_y',
        'normal_force': 'F_z = m (G_ddot_z + g), plane on body (N)',
        'number_format': 'state values are strings with 30 significant digits from a 40-digit evaluation; '
                         'q and u inputs are exact decimal strings',
    },
    'generator': {'script': 'tests/data/rattleback_sympy.py', 'sympy': sp.__version__,
                  'mpmath': mpmath.__version__, 'python': sys.version.split()[0], 'dps': DPS},
    'parameters': {
        'order': PNAMES,
        'sets': {k: dict(PSETS[k], **{'derived': {n: S(v, 30) for n, v in zip(PNAMES, PARS_MP[k])}})
                 for k in PSETS},
    },
    'states': {
        'seed': STATE_SEED,
        'generator': 'random.Random(seed); per state: psi U[-3,3], theta U[-0.4,0.4], phi U[-0.4,0.4], '
                     'x U[-1,1], y U[-1,1], psi_d theta_d phi_d U[-2,2], each rounded to 6 decimals '
                     '(the rounded decimal strings are the exact inputs)',
        'keys': {'q': '[psi, theta, phi, x, y]', 'u': '[psi_d, theta_d, phi_d]', 'qdot_dep': '[x_d, y_d]',
                 'u_dot': '[psi_dd, theta_dd, phi_dd]', 'qddot_dep': '[x_dd, y_dd]',
                 'lambda': '[F_x, F_y] contact force on the body (see conventions.lambda)',
                 'normal_force': 'F_z', 'energy': 'E', 'contact_point': 'P world [x, y, z]',
                 'centre_height': 'z_C', 'com': 'G world', 'omega_world': 'omega in world axes',
                 'omega_body': 'omega in body axes'},
        'main': state_out['main'],
        'check': state_out['check'],
        'note': 'same 12 (q, u) inputs for both sets; main uses delta = 0.1, check uses delta = 0',
    },
    'checks': {k: mpmath.nstr(v, 3) for k, v in checks.items()},
    'checks_note': 'max over all 24 evaluations: reduced (S^T M S) solve vs 7x7 multiplier solve; lambda vs '
                   'm G_ddot; Newton-Euler angular momentum balance about G with the contact force; dE/dt along '
                   'the solution; |v_P| (all three components); P_z; world normal at P + e_z; P on the ellipsoid. '
                   'Symbolically (sympy.simplify): v_P,z == 0, P_z == 0, P on the ellipsoid, normal = -e_z.',
    'spin_reversal': dict(reversal, notes=(
        'omega_z is the world-z angular velocity psi_d - phi_d sin(theta) (rad/s); times in s. '
        't_first_sign_change: first zero of omega_z. Detection: omega_z sampled 8 times per accepted step '
        '(cubic Hermite), samples with |omega_z| < 0.2 rad/s replaced by exact values (re-integration from the '
        'step start), sign changes between samples and dips towards zero between samples (golden-section '
        'minimum of |omega_z|) solved by regula falsi on exact re-integration. Near a reversal omega_z '
        'oscillates at the rocking frequencies around a slowly moving mean, so the first zero can be a '
        'shallow, sub-millisecond excursion (first_excursion gives its duration and depth when < 10 ms). '
        't_first_mean_spin_sign_change: first zero of the centred 0.2 s moving average '
        '(Omega(t + 0.1) - Omega(t - 0.1)) / 0.2 with Omega = integral of omega_z from 0 (a robust indicator). '
        'reversed_extreme_omega_z / _time: extreme of omega_z with the sign opposite to the initial spin in '
        'the window [first mean sign change - 0.1, second mean sign change + 0.1] (golden-section refined). '
        'The model is conservative (no slip, no dissipation), so the spin keeps reversing back and forth; '
        'all sign changes in the window are listed, later ones are increasingly sensitive (see convergence). '
        'rocking_amplitude_per_mean_spin_phase: max |theta| (pitch, about body y ~ long-axis rocking) and '
        'max |phi| (roll about body x) at step ends between successive mean-spin sign changes. '
        'Trajectory and headline numbers from the BS tol 1e-13 run; BS tol 1e-11, Dormand-Prince 5(4) tol '
        '1e-12 and a 30-digit mpmath Bulirsch-Stoer run (to just past the first sign change) are the '
        'convergence evidence. Integrators: own code in the script (rtol = atol = tol, RMS error norm, '
        'max step 5 ms).')),
    'published': published,
    'runtime_seconds': None,
}
doc['runtime_seconds'] = round(time.time() - T_START, 1)
with open(OUT, 'w') as fh:
    json.dump(doc, fh, indent=1)
log('wrote', OUT)
