"""Independent reference for the stiff disc (lab/src/systems.rs StiffDisc,
lab/examples/work_precision.rs stiff_disc, lab/tests/tight_tolerances.rs):
the state at t = 1 to 16 digits.

The equations are derived here with SymPy from the Lagrangian and the rolling
constraints, with Lagrange multipliers (nothing is taken from the Rust model):
    M(q) q'' + (d/dq (dL/dq')) q' - dL/dq = Q + A^T lam,   A q'' + A' q' = 0,
A the rows of x' - R cos(phi) theta' = 0 and y' - R sin(phi) theta' = 0, Q the
spring-damper -k (psi - psi0) - c psi' on the lean. The multipliers are
eliminated by the null space of A (a 3x3 system in the independent
accelerations, solved in mpmath at 24 digits at every evaluation); the state is
(theta, phi, psi, x, y, theta', phi', psi') as in the Rust system.

Integration: Gragg-Bulirsch-Stoer extrapolation (the modified midpoint rule
with Gragg's smoothing, substeps n = 2, 4, ..., 2K, Aitken-Neville in h^2,
order 2K) on a fixed grid: macro steps H = 2^-15 over the lean's
transient t in [0, 1/32] (|H lambda| < 0.07 for the double eigenvalue near
-1960), H = 2^-11 after it; run with K = 5 (order 10, argument 5) and
K = 4 (order 8, argument 4): their difference bounds the error. The
parameters are the f64
values the Rust code uses (m = 1.7, R = 0.35, g = 9.81, k = 1e6,
c = 2 sqrt(k * 1.25 m R^2) evaluated in f64, psi0 = 0.2), converted exactly.

Result (K = 5; K = 4 differs by at most 3e-17; Dop853 at rtol 1e-14 by 5e-14):
  3.539656682379224097, 21.21130548621677073, 0.2000040918980611001,
  0.04201015202033279075, 0.09987198298802978988, 3.537073385109361771,
  21.21248507474876105, 3e-23

usage: python3 tests/data/stiff_disc_reference.py [5|4|rhs]   (5-10 CPU minutes)"""
import math
import sys
import mpmath as mp
import sympy as sp

mp.mp.dps = 24

t = sp.symbols('t')
m, R, g, k, c, psi0 = sp.symbols('m R g k c psi0')
th, ph, ps, x, y = [sp.Function(n)(t) for n in ('theta', 'phi', 'psi', 'x', 'y')]
q = sp.Matrix([th, ph, ps, x, y])
qd = q.diff(t)
X = x - R * sp.sin(ph) * sp.sin(ps)
Y = y + R * sp.cos(ph) * sp.sin(ps)
Z = R * sp.cos(ps)
L = (m / 2 * (X.diff(t)**2 + Y.diff(t)**2 + Z.diff(t)**2)
     + m * R**2 / 2 * (th.diff(t)**2 / 2 + ph.diff(t)**2 / 4 + ps.diff(t)**2 / 4)
     - m * g * Z)
Q = sp.Matrix([0, 0, -k * (ps - psi0) - c * ps.diff(t), 0, 0])
A = sp.Matrix([[-R * sp.cos(ph), 0, 0, 1, 0], [-R * sp.sin(ph), 0, 0, 0, 1]])

# Plain symbols for positions and velocities.
qs = sp.symbols('q0:5')
vs = sp.symbols('v0:5')
subs = {}
for i in range(5):
    subs[qd[i]] = vs[i]
for i in range(5):
    subs[q[i]] = qs[i]


def plain(e):
    return e.subs(subs)


Lp = plain(L)
M = sp.Matrix(5, 5, lambda i, j: sp.diff(Lp, vs[i], vs[j]))
dLdv = sp.Matrix([sp.diff(Lp, vs[i]) for i in range(5)])
# d/dt dL/dq' without the q'' terms, minus dL/dq.
h = sp.Matrix([sum(sp.diff(dLdv[i], qs[j]) * vs[j] for j in range(5)) - sp.diff(Lp, qs[i])
               for i in range(5)])
Ap = plain(A)
Adot_v = sp.Matrix([sum(sp.diff(Ap[a, j], qs[l]) * vs[l] * vs[j] for j in range(5) for l in range(5))
                    for a in range(2)])
Qp = plain(Q)

m_, R_, g_, k_ = 1.7, 0.35, 9.81, 1e6
c_ = 2.0 * math.sqrt(k_ * (1.25 * m_ * R_ * R_))
params = {m: mp.mpf(m_), R: mp.mpf(R_), g: mp.mpf(g_), k: mp.mpf(k_), c: mp.mpf(c_),
          psi0: mp.mpf(0.2)}
# The multipliers eliminated: with q' = S(q) u, u = (theta', phi', psi') (the
# null space of A), S^T (M (S u' + S' u) + h - Q) = 0, a 3x3 system in u'.
us = sp.symbols('u0:3')
S = sp.Matrix([[1, 0, 0], [0, 1, 0], [0, 0, 1], [R * sp.cos(qs[1]), 0, 0], [R * sp.sin(qs[1]), 0, 0]])
assert sp.simplify(Ap * S) == sp.zeros(2, 3)
v_of_u = dict(zip(vs, S * sp.Matrix(us)))
qdot = S * sp.Matrix(us)
Sdot_u = sp.Matrix(5, 1, lambda i, _: sum(sp.diff((S * sp.Matrix(us))[i], qs[l]) * qdot[l]
                                          for l in range(5)))
Mr = (S.T * M * S).subs(v_of_u)
rr = (S.T * (Qp - h - M * Sdot_u)).subs(v_of_u)
args = list(qs) + list(us)
fMr = sp.lambdify(args, Mr.subs(params), 'mpmath', cse=True)
frr = sp.lambdify(args, rr.subs(params), 'mpmath', cse=True)
Rm = params[R]


def rhs(s):
    """(theta, phi, psi, x, y, theta', phi', psi') -> derivative."""
    a = list(s)
    sol = mp.lu_solve(mp.matrix(fMr(*a)), mp.matrix(frr(*a)))
    return [s[5], s[6], s[7], Rm * mp.cos(s[1]) * s[5], Rm * mp.sin(s[1]) * s[5],
            sol[0], sol[1], sol[2]]


def axpy(a, xv, yv):
    return [a * xi + yi for xi, yi in zip(xv, yv)]


def midpoint(s, H, n):
    hh = H / n
    z0 = s
    z1 = axpy(hh, rhs(z0), z0)
    for _ in range(n - 1):
        z0, z1 = z1, axpy(2 * hh, rhs(z1), z0)
    # Gragg's smoothing.
    f = rhs(z1)
    return [(a + b + hh * fi) / 2 for a, b, fi in zip(z0, z1, f)]


def gbs_step(s, H, K):
    ns = [2 * (j + 1) for j in range(K)]
    T = []
    for j, n in enumerate(ns):
        row = [midpoint(s, H, n)]
        for l in range(1, j + 1):
            r = (mp.mpf(ns[j]) / ns[j - l])**2 - 1
            row.append([a + (a - b) / r for a, b in zip(row[l - 1], T[j - 1][l - 1])])
        T.append(row)
    return T[-1][-1]


def integrate(refine, K):
    """Macro steps 2^-15/refine over the lean's transient t in [0, 1/32]
    (|H lambda| < 0.07), then 2^-11/refine up to t = 1."""
    s = [mp.mpf(v) for v in (0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5)]
    for steps, H in ((1024 * refine, mp.mpf(2)**-15 / refine),
                     (1984 * refine, mp.mpf(2)**-11 / refine)):
        for _ in range(steps):
            s = gbs_step(s, H, K)
    return s


if __name__ == '__main__':
    s0 = [mp.mpf(v) for v in (0.0, 0.0, 0.3, 0.0, 0.0, 6.0, 20.0, 0.5)]
    print('f(x0) =', [mp.nstr(v, 20) for v in rhs(s0)])
    if len(sys.argv) > 1 and sys.argv[1] == 'rhs':
        sys.exit()
    K = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    x1 = integrate(1, K)
    print('K = %d:' % K, [mp.nstr(v, 22) for v in x1])
