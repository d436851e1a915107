"""The plain derivation of a sample of random systems, in SymPy.

Independent check of nh-verify's plain derivation (verify/src/plain.rs),
which the differential test compares the generated code with. This script
reads the sample that `cargo run -p nh-verify --example sympy_sample` writes
(verify/data/sympy_sample.json: each system's Lagrangian, bodies, constraints
and kinematics as SymPy expressions, its dependent coordinates and states),
derives each system symbolically and evaluates at each state with mpmath at
40 digits:

  L as written; a body's kinetic energy 1/2 m |dC/dt|^2 + 1/2 w.I.w with w the
  axial vector of R^T dR/dt; dot(X) of a `let` its total time derivative;
  M = d2L/dqd2, h_j = sum_i d2L/dqd_j dq_i qd_i + d2L/dqd_j dt - dL/dq_j - Q_j;
  velocity rows g(q, qd, t): dot(s) - rhs, lhs - rhs, df/dt of a holonomic f,
  and per rolling contact the rate of the contact point's height and the x, y
  components of dG/dt + w x (P - G), P - G = -r (e_z - n_z n)/|e_z x n| - rho e_z
  (n = R a/|a|; e_z for a sphere);
  the rows reduced to independent ones, the dependent velocities solved from
  them, and [M -c^T; c 0][qdd; mu] = [-h; -(dc/dt qd + db/dt)] solved;
  lambda = E_s = (M qdd + h)_s, energy = qd.dL/dqd - L.
  In generalized speeds: qd = W(q, w, t), (S^T M S) wd = -S^T (h + M a),
  S = dW/dw, a = sum_j dW/dq_j W_j + dW/dt.

Writes verify/data/sympy_reference.json: per system and state the values as
[hi, lo] pairs of doubles (hi + lo to about 32 digits).

    python3 verify/data/sympy_reference.py
"""
import json
import os
import sys

import mpmath
from sympy import (Abs, Matrix, Rational, Symbol, acos, asin, atan, atan2, cos, cosh, diff, exp,
                   lambdify, log, pi, sin, sinh, sqrt, symbols, tan, tanh, zeros)

mpmath.mp.dps = 40
HERE = os.path.dirname(os.path.abspath(__file__))


def rot_x(a):
    c, s = cos(a), sin(a)
    return Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a):
    c, s = cos(a), sin(a)
    return Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a):
    c, s = cos(a), sin(a)
    return Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


class System:
    def __init__(self, entry):
        np_, n, ni = entry["sizes"]
        self.entry = entry
        self.n = n
        self.P = symbols("P0:%d" % np_) if np_ else ()
        self.q = symbols("q0:%d" % n)
        self.qd = symbols("qd0:%d" % n)
        self.U = symbols("U0:%d" % ni) if ni else ()
        self.t = Symbol("t")
        k = len(entry["states"][0]["v"])
        self.w = symbols("w0:%d" % k) if entry["kinematics"] is not None else ()
        self.lets = {name: code for name, _, code in entry["lets"]}
        self.bodies = {b[0]: b for b in entry["bodies"]}
        self.cache = {}
        self.env = dict(P=self.P, q=self.q, qd=self.qd, U=self.U, t=self.t, w=self.w,
                        L=self.let, D=self.dot_let, KE=self.kinetic, Matrix=Matrix,
                        Rational=Rational, sin=sin, cos=cos, tan=tan, exp=exp, log=log,
                        sqrt=sqrt, atan=atan, asin=asin, acos=acos, sinh=sinh, cosh=cosh,
                        tanh=tanh, Abs=Abs, atan2=atan2, pi=pi, rot_x=rot_x, rot_y=rot_y,
                        rot_z=rot_z)

    def ev(self, code):
        return eval(code, self.env)

    def let(self, name):
        if name not in self.cache:
            self.cache[name] = self.ev(self.lets[name])
        return self.cache[name]

    def rate(self, x):
        """Total time derivative of a velocity-free expression or matrix."""
        if hasattr(x, "applyfunc"):
            return x.applyfunc(self.rate)
        return sum(diff(x, self.q[i]) * self.qd[i] for i in range(self.n)) + diff(x, self.t)

    def dot_let(self, name):
        return self.rate(self.let(name))

    def kinetic(self, name):
        _, mass, centre, rotation = self.bodies[name]
        cdot = self.rate(self.ev(centre))
        t = Rational(1, 2) * self.ev(mass) * (cdot.T * cdot)[0, 0]
        if rotation is not None:
            r = self.ev(rotation[0])
            wm = r.T * self.rate(r)
            om = Matrix([wm[2, 1], wm[0, 2], wm[1, 0]])
            inertia = Matrix([[self.ev(x) for x in row] for row in rotation[1]])
            t += Rational(1, 2) * (om.T * inertia * om)[0, 0]
        return t

    def rows(self):
        out = []
        for c in self.entry["constraints"]:
            kind = c[0]
            if kind == "explicit":
                out.append(self.qd[c[1]] - self.ev(c[2]))
            elif kind == "implicit":
                out.append(self.ev(c[1]) - self.ev(c[2]))
            elif kind == "holonomic":
                out.append(self.rate(self.ev(c[1]) - self.ev(c[2])))
            else:
                out.extend(self.contact(c))
        return out

    def contact(self, c):
        _, b, radius, axle, tube, centre = c
        _, _, body_centre, rotation = self.bodies[self.entry["bodies"][b][0]]
        g = self.ev(centre if centre is not None else body_centre)
        r = self.ev(rotation[0])
        ez = Matrix([0, 0, 1])
        if axle is None:
            wv = ez
        else:
            a = Matrix(axle)
            nv = r * a / sqrt((a.T * a)[0, 0])
            s = sqrt(1 - nv[2] ** 2)
            wv = (ez - nv[2] * nv) / s
        rho = self.ev(tube) if tube is not None else 0
        arm = -self.ev(radius) * wv - rho * ez
        height = g[2] + arm[2]
        wm = self.rate(r) * r.T
        om = Matrix([wm[2, 1], wm[0, 2], wm[1, 0]])
        vel = self.rate(g) + om.cross(arm)
        return [self.rate(height), vel[0], vel[1]]


def mp(x):
    return mpmath.mpf(x)


def pair(x):
    hi = float(x)
    lo = float(mpmath.mpf(x) - mpmath.mpf(hi))
    return [hi, lo]


def independent_rows(c, b, tol=mpmath.mpf("1e-20")):
    basis, kept = [], []
    for a in range(c.rows):
        row = [c[a, i] for i in range(c.cols)] + [b[a]]
        res = list(row)
        n = c.cols
        for e in basis:
            d = sum(res[i] * e[i] for i in range(n))
            res = [x - d * y for x, y in zip(res, e)]
        size = mpmath.sqrt(sum(x ** 2 for x in row[:n]))
        left = mpmath.sqrt(sum(x ** 2 for x in res[:n]))
        if size > 0 and left > tol * size:
            basis.append([x / left for x in res])
            kept.append(a)
        elif abs(res[n]) > tol * max(size + abs(row[n]), 1):
            raise ValueError("contradicting rows")
    return kept


def numeric(expr, syms, vals):
    f = lambdify(syms, expr, modules="mpmath")
    return f(*vals)


def motion(sysm, lag, forces, state):
    n = sysm.n
    P, q, qd, U, t, w = sysm.P, sysm.q, sysm.qd, sysm.U, sysm.t, sysm.w
    pv = [mp(x) for x in state["params"]]
    uv = [mp(x) for x in state["inputs"]]
    tv = mp(state["t"])
    qv = [mp(x) for x in state["q"]]
    vv = [mp(x) for x in state["v"]]
    syms = list(P) + list(U) + [t] + list(q) + list(qd) + list(w)
    dep = sysm.entry["dependent"]
    kin = sysm.entry["kinematics"]
    h_sym = [sum(diff(diff(lag, qd[j]), q[i]) * qd[i] for i in range(n)) + diff(diff(lag, qd[j]), t)
             - diff(lag, q[j]) - forces[j] for j in range(n)]
    m_sym = [[diff(diff(lag, qd[i]), qd[j]) for j in range(n)] for i in range(n)]
    energy_sym = sum(qd[i] * diff(lag, qd[i]) for i in range(n)) - lag
    if kin is not None:
        wexpr = [sysm.ev(x) for x in kin]
        k = len(w)
        base = pv + uv + [tv] + qv + [0] * n + vv
        wv = [numeric(x, syms, base) for x in wexpr]
        s = mpmath.matrix([[numeric(diff(x, w[a]), syms, base) for a in range(k)] for x in wexpr])
        acc_sym = [sum(diff(x, q[j]) * wexpr[j] for j in range(n)) + diff(x, t) for x in wexpr]
        av = mpmath.matrix([numeric(x, syms, base) for x in acc_sym])
        full = pv + uv + [tv] + qv + wv + vv
        m = mpmath.matrix([[numeric(x, syms, full) for x in row] for row in m_sym])
        h = mpmath.matrix([numeric(x, syms, full) for x in h_sym])
        red = s.T * m * s
        rhs = -(s.T * (h + m * av))
        wd = mpmath.lu_solve(red, rhs)
        return {"accelerations": [wd[a] for a in range(k)], "qdot": wv,
                "energy": numeric(energy_sym, syms, full)}
    rows = sysm.rows()
    indep = [i for i in range(n) if i not in dep]
    zero = pv + uv + [tv] + qv + [0] * n
    cmat = mpmath.matrix(len(rows), n)
    bvec = []
    for a, g in enumerate(rows):
        for i in range(n):
            cmat[a, i] = numeric(diff(g, qd[i]), syms, zero)
        bvec.append(numeric(g, syms, zero))
    kept = independent_rows(cmat, bvec)
    if len(kept) != len(dep):
        raise ValueError("rows %d, dependent %d" % (len(kept), len(dep)))
    cs = mpmath.matrix([[cmat[a, s] for s in dep] for a in kept]) if dep else None
    qdv = [mpmath.mpf(0)] * n
    for j, r in enumerate(indep):
        qdv[r] = vv[j]
    if dep:
        known = mpmath.matrix([bvec[a] + sum(cmat[a, r] * qdv[r] for r in indep) for a in kept])
        sd = mpmath.lu_solve(cs, -known)
        for a, s in enumerate(dep):
            qdv[s] = sd[a]
    full = pv + uv + [tv] + qv + qdv
    m = mpmath.matrix([[numeric(x, syms, full) for x in row] for row in m_sym])
    h = [numeric(x, syms, full) for x in h_sym]
    rates = [numeric(sum(diff(rows[a], q[i]) * qd[i] for i in range(n)) + diff(rows[a], t), syms, full)
             for a in kept]
    size = n + len(kept)
    kkt = mpmath.matrix(size, size)
    f = mpmath.matrix(size, 1)
    for i in range(n):
        for j in range(n):
            kkt[i, j] = m[i, j]
        for r, a in enumerate(kept):
            kkt[i, n + r] = -cmat[a, i]
            kkt[n + r, i] = cmat[a, i]
        f[i] = -h[i]
    for r in range(len(kept)):
        f[n + r] = -rates[r]
    x = mpmath.lu_solve(kkt, f)
    qdd = [x[i] for i in range(n)]
    e = [h[j] + sum(m[j, i] * qdd[i] for i in range(n)) for j in range(n)]
    return {"accelerations": [qdd[r] for r in indep], "multipliers": [e[s] for s in dep],
            "sdot": [qdv[s] for s in dep], "energy": numeric(energy_sym, syms, full)}


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "sympy_sample.json")
    dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "sympy_reference.json")
    sample = json.load(open(src))
    out = []
    for entry in sample:
        sysm = System(entry)
        lag = sysm.ev(entry["lagrangian"])
        forces = [0] * sysm.n
        for i, f in entry["forces"]:
            forces[i] += sysm.ev(f)
        values = []
        for state in entry["states"]:
            try:
                res = motion(sysm, lag, forces, state)
                values.append({k: ([pair(x) for x in v] if isinstance(v, list) else pair(v))
                               for k, v in res.items()})
            except (ValueError, ZeroDivisionError) as err:
                values.append({"error": str(err)})
        out.append({"seed": entry["seed"], "text": entry["text"], "values": values})
        print("seed", entry["seed"], "done", file=sys.stderr)
    with open(dst, "w") as fh:
        json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
