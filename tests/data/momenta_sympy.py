"""Reference values for tests/momenta.rs: the momenta of the rolling
disc's cyclic coordinates (the physically correct disc: a thin disc of
inertia diag(mR²/4, mR²/2, mR²/4) rolling on z = 0) and their rates,
derived here from scratch with SymPy, independently of the library and of
the thesis's (5.36):

* the rolling constraint as the vanishing horizontal velocity of the
  material point of the rim at (x, y, 0), solved for ẋ, ẏ;
* the momenta p = ∂Lc/∂ṙ of the constrained Lagrangian;
* their rates by the chain rule along the motion, ṗ = ∂p/∂q q̇ + ∂p/∂ṙ r̈,
  with r̈ from the Lagrange–d'Alembert equations M q̈ + h = Cᵀλ,
  C q̈ + Ċ q̇ = 0 (the multipliers eliminated numerically, 40 digits).

Run: python3 tests/data/momenta_sympy.py > tests/data/momenta.json
"""
import json
import sympy as sp
import mpmath

mpmath.mp.dps = 40
th, ph, ps, x, y = sp.symbols("theta phi psi x y")
thd, phd, psd, xd, yd = sp.symbols("thetad phid psid xd yd")
m, R, g = sp.Rational(13, 10), sp.Rational(2, 5), sp.Rational(981, 100)
q = [th, ph, ps, x, y]
qd = [thd, phd, psd, xd, yd]


def rot(axis, a):
    c, s = sp.cos(a), sp.sin(a)
    if axis == 0:
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def dt(expr):
    return sum(sp.diff(expr, a) * b for a, b in zip(q, qd))


F = rot(2, ph) * rot(0, -ps)
Rb = F * rot(1, th)
ez = sp.Matrix([0, 0, 1])
C = sp.Matrix([x, y, 0]) + R * F * ez
Cd = C.applyfunc(dt)
W = Rb.applyfunc(dt) * Rb.T  # [ω]× in world axes
w = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
wb = sp.simplify(Rb.T * w)
I = sp.diag(m * R**2 / 4, m * R**2 / 2, m * R**2 / 4)
T = m / 2 * (Cd.T * Cd)[0] + (wb.T * I * wb)[0] / 2
L = T - m * g * C[2]
# the rim's material point at (x, y, 0): C + ω × (−R F e_z)
vp = Cd + w.cross(-R * F * ez)
rows = [sp.expand(vp[0]), sp.expand(vp[1])]
sol = sp.solve(rows, [xd, yd], dict=True)[0]
Lc = L.subs(sol)
p = [sp.diff(Lc, thd), sp.diff(Lc, phd)]
# Lagrange–d'Alembert: constraint rows C q̇ = 0
Cm = sp.Matrix([[sp.diff(r, v) for v in qd] for r in rows])
M = sp.Matrix([[sp.diff(L, a, b) for b in qd] for a in qd])
pL = [sp.diff(L, v) for v in qd]
h = sp.Matrix([dt(pL[i]) - sp.diff(L, q[i]) for i in range(5)])  # velocity part
Cdot_qd = (Cm.applyfunc(dt) * sp.Matrix(qd))
fM = sp.lambdify(q + qd, M, "mpmath")
fh = sp.lambdify(q + qd, h, "mpmath")
fC = sp.lambdify(q + qd, Cm, "mpmath")
fCd = sp.lambdify(q + qd, Cdot_qd, "mpmath")
fsol = sp.lambdify(q + [thd, phd, psd], [sol[xd], sol[yd]], "mpmath")
fp = sp.lambdify(q + [thd, phd, psd], p, "mpmath")
dp = [
    sp.lambdify(q + [thd, phd, psd], [sp.diff(pi, a) for a in q + [thd, phd, psd]], "mpmath")
    for pi in p
]

states = [
    [0.3, -0.7, 0.4, 0.2, -0.1, 2.1, 0.5, -0.8],
    [1.1, 0.2, -0.6, -0.3, 0.4, -1.4, 1.2, 0.3],
    [-0.5, 2.3, 0.9, 0.7, 0.1, 0.6, -0.9, 1.5],
    [2.0, -1.6, -0.2, 0.0, 0.5, 3.0, 0.1, -0.4],
]
out = []
for s in states:
    qv = [mpmath.mpf(v) for v in s[:5]]
    rv = [mpmath.mpf(v) for v in s[5:]]
    xdv, ydv = fsol(*qv, *rv)
    qdv = rv + [xdv, ydv]
    args = qv + qdv
    Mm, hh, Cc, cd = fM(*args), fh(*args), fC(*args), fCd(*args)
    # [M −Cᵀ; C 0] [q̈; λ] = [−h; −Ċ q̇]
    A = mpmath.zeros(7, 7)
    b = mpmath.zeros(7, 1)
    for i in range(5):
        for j in range(5):
            A[i, j] = Mm[i, j]
        for a in range(2):
            A[i, 5 + a] = -Cc[a, i]
        b[i] = -hh[i]
    for a in range(2):
        for j in range(5):
            A[5 + a, j] = Cc[a, j]
        b[5 + a] = -cd[a]
    z = mpmath.lu_solve(A, b)
    qdd = [z[i] for i in range(5)]
    pv = fp(*qv, *rv)
    rates = []
    for k in range(2):
        grad = dp[k](*qv, *rv)
        rate = sum(grad[i] * qdv[i] for i in range(5)) + sum(grad[5 + j] * qdd[j] for j in range(3))
        rates.append(rate)
    out.append({
        "state": s,
        "momenta": [mpmath.nstr(v, 25) for v in pv],
        "rates": [mpmath.nstr(v, 25) for v in rates],
    })
print(json.dumps({"parameters": {"m": 1.3, "R": 0.4, "g": 9.81}, "points": out}, indent=1))
