"""Independent check of tests/pass/offset_ball.rs: the offset-centre ball
(Chaplygin top) rolling without slipping, derived with SymPy from the rotation
matrix (the angular velocity from Q^T Q', the rolling constraint from
v_C + w x (-R e_z) = 0, nothing typed in from the Rust model) by the multiplier
method, evaluated at 50 digits. Prints r'' = (psi'', theta'', phi'') at the
three states whose values tests/pass/offset_ball.rs asserts (about 30 s).

usage: python3 tests/data/offset_ball_sympy.py [FILE]
FILE (optional): generated values to compare, three numbers a line, one line a state."""
import sys
import sympy as sp

t = sp.symbols('t')
m, R, a, I1, I2, I3, g = sp.symbols('m R a I1 I2 I3 g', positive=True)
psi, th, ph, x, y = [sp.Function(n)(t) for n in ('psi', 'theta', 'phi', 'x', 'y')]
q = sp.Matrix([psi, th, ph, x, y])
qd = q.diff(t)

def Rz(u): return sp.Matrix([[sp.cos(u), -sp.sin(u), 0], [sp.sin(u), sp.cos(u), 0], [0, 0, 1]])
def Ry(u): return sp.Matrix([[sp.cos(u), 0, sp.sin(u)], [0, 1, 0], [-sp.sin(u), 0, sp.cos(u)]])
def Rx(u): return sp.Matrix([[1, 0, 0], [0, sp.cos(u), -sp.sin(u)], [0, sp.sin(u), sp.cos(u)]])

Q = Rz(psi) * Ry(th) * Rx(ph)                      # body -> world, Z-Y-X
W = sp.simplify(Q.T * Q.diff(t))                   # skew: body angular velocity
w_body = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
w_world = sp.simplify(Q * w_body)
C = sp.Matrix([x, y, R])
G = C - a * Q[:, 2]                                # centre of mass
Gd = G.diff(t)
T = m / 2 * (Gd.T * Gd)[0] + (I1 * w_body[0]**2 + I2 * w_body[1]**2 + I3 * w_body[2]**2) / 2
L = T - m * g * G[2]

# rolling: v_C + w x (-R e_z) = 0
vP = C.diff(t) + w_world.cross(sp.Matrix([0, 0, -R]))
cons = sp.Matrix([vP[0], vP[1]])                   # linear in qd
Cm = cons.jacobian(qd)
assert sp.simplify(vP[2]) == 0

qdd = qd.diff(t)
EL = (sp.Matrix([L]).jacobian(qd).T).diff(t) - sp.Matrix([L]).jacobian(q).T
M = EL.jacobian(qdd)
cdd = (Cm * qd).diff(t)
Cd_qd = cdd.subs({e: 0 for e in qdd})  # cdd = C qdd + C' qd
# plain symbols for evaluation
Qs = sp.symbols('q0:5'); Vs = sp.symbols('v0:5'); As = sp.symbols('a0:5')
def plain(e):
    e = e.subs({qdd[i]: As[i] for i in range(5)}).subs({qd[i]: Vs[i] for i in range(5)})
    return e.subs({q[i]: Qs[i] for i in range(5)})
M, Cm, Cd_qd = plain(M), plain(Cm), plain(Cd_qd)
h = plain(EL).subs({A: 0 for A in As})  # EL = M qdd + h

params = {m: sp.Rational('1.5'), R: sp.Rational('0.2'), a: sp.Rational('0.05'), I1: sp.Rational('0.012'),
          I2: sp.Rational('0.016'), I3: sp.Rational('0.02'), g: sp.Rational('9.81')}
states = [
    ['0.1', '0.3', '-0.2', '0.0', '0.0', '5.0', '0.4', '-0.7'],
    ['1.3', '-0.6', '0.9', '0.25', '-1.5', '-2.0', '1.7', '0.3'],
    ['-2.2', '0.8', '0.45', '3.0', '2.0', '0.6', '-3.1', '2.4'],
]
rust = [list(map(float, l.split())) for l in open(sys.argv[1])] if len(sys.argv) > 1 else None
worst = 0
for i, s in enumerate(states):
    s = [sp.Rational(v) for v in s]
    sub = dict(params)
    sub.update({Qs[j]: s[j] for j in range(5)})
    # dependent velocities from the constraints: Cm[:, 3:] = I
    rd = sp.Matrix(s[5:8])
    Cq = Cm.subs(sub)
    assert Cq[:, 3:] == sp.eye(2)
    sd = -Cq[:, :3] * rd
    sub.update({Vs[j]: rd[j] for j in range(3)}); sub.update({Vs[3]: sd[0], Vs[4]: sd[1]})
    Mn, hn, Cn, cn = [sp.N(e.subs(sub), 50) for e in (M, h, Cm, Cd_qd)]
    K = sp.zeros(7, 7); K[:5, :5] = Mn; K[:5, 5:] = -Cn.T; K[5:, :5] = Cn
    rhs = sp.Matrix.vstack(-hn, -cn)
    sol = K.LUsolve(rhs)
    rdd = [sp.N(sol[j], 20) for j in range(3)]
    print(f"state {i}: r'' = " + ", ".join(f"{v:.17e}" for v in map(float, rdd)))
    if rust:
        err = max(abs(float(rdd[j]) - rust[i][j]) / max(1.0, abs(float(rdd[j]))) for j in range(3))
        worst = max(worst, err)
        print(f"  generated: " + ", ".join(f"{v:.17e}" for v in rust[i]) + f"; max rel. difference {err:.2e}")
if rust:
    print(f"worst relative difference {worst:.2e}")
