"""An independent oracle for the sensitivity tests: a planar mechanism's kinematics and kinetostatics in real body
coordinates (x_b, y_b, θ_b), written here from the file format's definitions (docs/format.md: what every parameter
means), symbolic (sympy: the constraint Jacobian and the acceleration terms), and differentiated by the *complex
step*: every parameter is perturbed by i·h (h = 1e-30) in turn and every output's imaginary part over h is its
derivative (Squire & Trapp, SIAM Review 40 (1998) 110–112: no subtractive cancellation, exact to round-off).

Nothing here reads the engine's plan beyond names (the parameter names, the body list and the force analysis's pair
list): positions come from Newton's method on this closure (seeded by the engine's solution), velocities and
accelerations from its own linear solves, reactions and efforts from its Lagrange multipliers with the loads
rebuilt from the file's mass properties, gear and cam drives realised by their contact forces written in real
components.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

H = 1e-30


def _rot(th, v):
    c, s = sp.cos(th), sp.sin(th)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


class Oracle:
    """The closure of ``plan.mechanism`` in real coordinates (see the module docstring)."""

    def __init__(self, plan):
        self.plan = plan
        m = plan.mechanism
        self.m = m
        self.P = {name: sp.Symbol(f"p{k}") for k, name in enumerate(plan.param_names)}
        self.psyms = [self.P[n] for n in plan.param_names]
        self.bodies = list(plan.body_names)
        self.moving = self.bodies[1:]
        self.X = {b: sp.symbols(f"x{i} y{i} t{i}") for i, b in enumerate(self.moving)}
        self.xsyms = [s for b in self.moving for s in self.X[b]]
        self.U = list(sp.symbols(f"u0:{plan.n_inputs + len(m.gears) + len(m.cams)}"))   # inputs, then drive angles
        self.local = self._local()
        self.eqs, self.eq_kinds = self._equations()
        assert len(self.eqs) == len(self.xsyms), (len(self.eqs), len(self.xsyms))

    # -- geometry from the parameters, as docs/format.md defines them -----------------------------------
    def _sketch(self, p):
        return self.m.sketch(p)[:2]

    def _local(self):
        m, P = self.m, self.P
        loc = {}
        for lk in m.links:
            if lk.name == "frame":
                loc["frame"] = {p: (P[f"{p}.x"], P[f"{p}.y"]) for p in lk.points}
                continue
            pts = lk.points
            w = {pts[0]: (sp.Integer(0), sp.Integer(0))}
            if len(pts) > 1:
                w[pts[1]] = (P[f"{lk.name}.length"], sp.Integer(0))
            for p in pts[2:]:
                pl = lk.placement(p)
                org, tow = (pl.origin, pl.toward) if pl else (pts[0], pts[1])
                a, b = w[org], w[tow]
                d = (b[0] - a[0], b[1] - a[1])
                n = sp.sqrt(d[0] ** 2 + d[1] ** 2)
                r = _rot(P[f"{lk.name}.{p}.angle"], (d[0] / n, d[1] / n))
                dist = P[f"{lk.name}.{p}.distance"]
                w[p] = (a[0] + dist * r[0], a[1] + dist * r[1])
            loc[lk.name] = w
        for pr in m.prismatic:
            if pr.point is not None:
                loc[f"{pr.name}.block"] = {pr.point: (sp.Integer(0), sp.Integer(0))}
        for ac in m.actuators:
            loc[f"{ac.name}.cylinder"] = {ac.between[0]: (sp.Integer(0), sp.Integer(0))}
            loc[f"{ac.name}.rod"] = {ac.between[1]: (sp.Integer(0), sp.Integer(0))}
        return loc

    def world(self, body, point):
        w = self.local[body][point]
        if body == "frame":
            return w
        x, y, t = self.X[body]
        r = _rot(t, w)
        return (x + r[0], y + r[1])

    def angle(self, body):
        return sp.Integer(0) if body == "frame" else self.X[body][2]

    def _line(self, pr):
        """(U, Q): the slide line's direction and point in the frame."""
        a = self.P[f"{pr.name}.angle"]
        U = _rot(self.angle(pr.guide) + a, (1, 0))
        T = self.world(pr.guide, pr.through)
        off = self.P[f"{pr.name}.offset"]
        return U, (T[0] - U[1] * off, T[1] + U[0] * off)

    def _sketch_angle(self, body):
        pts = self.m.link(body).points
        a, b = self._sketch(pts[0]), self._sketch(pts[1])
        return math.atan2(b[1] - a[1], b[0] - a[0])

    # -- the constraints ---------------------------------------------------------------------------------
    def _equations(self):
        m, plan = self.m, self.plan
        eqs, kinds = [], []
        # joints: the force analysis's pairs (earlier body → later body at a point)
        from assur.kinetostatics.tables import force_tables
        for k, fp in enumerate(force_tables(plan).pairs):
            if fp.kind != "R":
                continue
            point = plan.point_names[fp.point]
            a, b = self.world(self.bodies[fp.earlier], point), self.world(self.bodies[fp.later], point)
            eqs += [a[0] - b[0], a[1] - b[1]]
            kinds += [("R", k, 0), ("R", k, 1)]
        driven = {d.actuator: i for i, d in enumerate(m.drivers) if d.kind == "linear"}
        for pr in m.prismatic:
            U, Q = self._line(pr)
            if pr.point is not None:
                body, ref, c0 = f"{pr.name}.block", pr.point, 0.0
            else:
                body, ref = pr.link, m.link(pr.link).points[0]
                gsk = 0.0 if pr.guide == "frame" else self._sketch_angle(pr.guide)
                c0 = self._sketch_angle(pr.link) - (gsk + pr.angle)
            rel = self.angle(body) - self.angle(pr.guide) - self.P[f"{pr.name}.angle"] - c0
            r = self.world(body, ref)
            eqs += [sp.sin(rel), _cross(U, (r[0] - Q[0], r[1] - Q[1]))]
            kinds += [("Pa", pr.name, body), ("Pn", pr.name, body)]
        for ac in m.actuators:
            cyl, rod = f"{ac.name}.cylinder", f"{ac.name}.rod"
            A, B = self.world(cyl, ac.between[0]), self.world(rod, ac.between[1])
            e = _rot(self.angle(cyl), (1, 0))
            d = (B[0] - A[0], B[1] - A[1])
            eqs += [sp.sin(self.angle(rod) - self.angle(cyl)), _cross(e, d)]
            kinds += [("Aa", ac.name, rod), ("An", ac.name, rod)]
            if ac.name in driven:
                eqs.append(_dot(e, d) - self.U[driven[ac.name]])
                kinds.append(("Al", ac.name, driven[ac.name]))
        for k, d in enumerate(m.drivers):
            if d.kind == "rotary":
                eqs.append(self._turn(d.link, d.pivot, d.arm, self.P[f"{d.name}.zero"] + d.sense * self.U[k]))
                kinds.append(("T", d.link, None))
        n_in = len(m.drivers)
        for j, gp in enumerate(m.gears):
            pivot, arm = self._pivot_arm(gp.b)
            eqs.append(self._turn(gp.b, pivot, arm, self.P[f"{gp.name}.zero"] + self.U[n_in + j]))
            kinds.append(("G", gp.b, j))
        for j, cp in enumerate(m.cams):
            slot = self.U[n_in + len(m.gears) + j]
            frame = set(m.frame.points)
            if cp.motion == "oscillating":
                pivot = next(p for p in m.link(cp.follower).points if p in frame)
                arm = cp.point if cp.point != pivot else next(p for p in m.link(cp.follower).points if p != pivot)
                eqs.append(self._turn(cp.follower, pivot, arm, self.P[f"{cp.name}.zero"] + slot))
                kinds.append(("C", cp.follower, j))
            else:
                pr = next(p for p in m.prismatic if p.link == cp.follower)
                U, Q = self._line(pr)
                r = self.world(cp.follower, m.link(cp.follower).points[0])
                eqs.append(_dot(U, (r[0] - Q[0], r[1] - Q[1])) - self.P[f"{cp.name}.start"] - slot)
                kinds.append(("S", cp.follower, j))
        return eqs, kinds

    def _pivot_arm(self, link):
        frame = set(self.m.frame.points)
        pts = self.m.link(link).points
        pivot = next(p for p in pts if p in frame)
        return pivot, next(p for p in pts if p != pivot)

    def _turn(self, link, pivot, arm, target):
        """sin of (the link's pivot → arm direction − target), times |arm − pivot| (zero on the drive)."""
        a, b = self.local[link][pivot], self.local[link][arm]
        d = _rot(self.angle(link), (b[0] - a[0], b[1] - a[1]))
        return _cross((sp.cos(target), sp.sin(target)), d)

    # -- the drive angles: inputs and the gear and cam slots (the laws at real inputs) ------------------------
    def drives(self, q):
        """(u, du/dq, d²u/dq²) (n, n_u) of the inputs and the gear and cam drive angles at inputs q (n, n_in)."""
        m, plan = self.m, self.plan
        n = q.shape[0]
        u, u1, u2 = [q[:, k] for k in range(plan.n_inputs)], [], []
        eye = np.eye(plan.n_inputs)
        u1 = [np.broadcast_to(eye[k], (n, plan.n_inputs)) for k in range(plan.n_inputs)]
        u2 = [np.zeros((n, plan.n_inputs, plan.n_inputs)) for _ in range(plan.n_inputs)]

        def rotation_of(link):
            """(x, dx/dq, d²x/dq²) of a turning link's rotation from the sketch."""
            for k, d in enumerate(m.drivers):
                if d.kind == "rotary" and d.link == link:
                    sk = math.atan2(*(np.subtract(self._sketch(d.arm), self._sketch(d.pivot))[::-1]))
                    q0 = (d.sense * (sk - d.zero)) % (2 * math.pi)
                    return d.sense * (u[k] - q0), d.sense * u1[k], d.sense * u2[k]
            for j, gp in enumerate(m.gears):
                if gp.b == link:
                    i = plan.n_inputs + j
                    return u[i], u1[i], u2[i]
            for j, cp in enumerate(m.cams):
                if cp.follower == link and cp.motion == "oscillating":
                    i = plan.n_inputs + len(m.gears) + j
                    return u[i], u1[i], u2[i]
            raise AssertionError(link)

        self.rates = {}
        for gp in m.gears:
            x, x1, x2 = rotation_of(gp.a)
            y, y1, y2 = gp.relative(x)
            self.rates[gp.name] = (y1, y2)
            u.append(y)
            u1.append(y1[:, None] * x1)
            u2.append(y2[:, None, None] * x1[:, :, None] * x1[:, None, :] + y1[:, None, None] * x2)
        for cp in m.cams:
            x, x1, x2 = rotation_of(cp.cam)
            sign = self.lift_sign(cp)
            self.rates[cp.name] = (cp.relative(x)[1], x)
            y, y1, y2 = (sign * c for c in cp.relative(x))
            u.append(y)
            u1.append(y1[:, None] * x1)
            u2.append(y2[:, None, None] * x1[:, :, None] * x1[:, None, :] + y1[:, None, None] * x2)
        return np.stack(u, -1), np.stack(u1, 1), np.stack(u2, 1)

    def lift_sign(self, cp):
        """+1 when the follower's positive move (along its slide, or ccw about its pivot) carries the trace point
        away from the cam's pivot in the sketch."""
        m = self.m
        frame = set(m.frame.points)
        O = np.array(self._sketch(next(p for p in m.link(cp.cam).points if p in frame)))
        R = np.array(self._sketch(cp.point))
        if cp.motion == "oscillating":
            F = np.array(self._sketch(next(p for p in m.link(cp.follower).points if p in frame)))
            move = np.array([-(R - F)[1], (R - F)[0]])
        else:
            pr = next(p for p in m.prismatic if p.link == cp.follower)
            move = np.array([math.cos(pr.angle), math.sin(pr.angle)])
        return float(np.sign(np.dot(move, R - O)))


def _lam(args, exprs):
    f = sp.lambdify(args, exprs, "numpy")

    def call(*values, shape):
        out = f(*values)
        return np.stack([np.broadcast_to(np.asarray(o, dtype=complex), shape) for o in out], axis=-1)
    return call


class Numeric:
    """The oracle's numbers over a batch of inputs, at (complex) parameters."""

    def __init__(self, oracle: Oracle):
        o = self.o = oracle
        X, U, Pp = o.xsyms, o.U, o.psyms
        n = len(X)
        F = sp.Matrix(o.eqs)
        J = F.jacobian(X)
        Fu = F.jacobian(U)
        Xd = sp.Matrix(sp.symbols(f"xd0:{n}"))
        Ud = sp.Matrix(sp.symbols(f"ud0:{len(U)}"))
        Fdot = J * Xd + Fu * Ud
        gamma = Fdot.jacobian(X) * Xd + Fdot.jacobian(U) * Ud
        self.args = list(X) + list(U) + list(Pp)
        self.dargs = self.args + list(Xd) + list(Ud)
        self.F = _lam(self.args, list(F))
        self.J = _lam(self.args, list(J))
        self.Fu = _lam(self.args, list(Fu))
        self.gamma = _lam(self.dargs, list(gamma))
        self.n, self.nu = n, len(U)
        self.Xdd = sp.Matrix(sp.symbols(f"xdd0:{n}"))
        self.Xd_syms, self.Ud_syms = Xd, Ud
        self._points = {}

    # -- kinematics ---------------------------------------------------------------------------------------
    def solve(self, X0, q, params, qdot):
        """(X, Ẋ, Ẍ, u, u̇, ü) at inputs q (N, n_in), complex parameters (n_params,), seeded by X0 (N, n)."""
        o = self.o
        N = q.shape[0]
        u, u1, u2 = o.drives(q)
        ud = np.einsum("nuk,k->nu", u1, qdot)
        udd = np.einsum("nukl,k,l->nu", u2, qdot, qdot)
        X = X0.astype(complex)
        P = [np.full(N, params[k], dtype=complex) for k in range(len(params))]
        for _ in range(60):
            args = [X[:, j] for j in range(self.n)] + [u[:, j] + 0j for j in range(self.nu)] + P
            r = self.F(*args, shape=(N,))
            Jv = self.J(*args, shape=(N,)).reshape(N, self.n, self.n)
            dx = np.linalg.solve(Jv, -r[..., None])[..., 0]
            X = X + dx
            if np.max(np.abs(dx.real)) < 1e-15 and np.max(np.abs(dx.imag)) < 1e-15 * H:
                break
        args = [X[:, j] for j in range(self.n)] + [u[:, j] + 0j for j in range(self.nu)] + P
        Jv = self.J(*args, shape=(N,)).reshape(N, self.n, self.n)
        Fu = self.Fu(*args, shape=(N,)).reshape(N, self.n, self.nu)
        Xd = np.linalg.solve(Jv, -np.einsum("nij,nj->ni", Fu, ud)[..., None])[..., 0]
        g = self.gamma(*(args + [Xd[:, j] for j in range(self.n)] + [ud[:, j] + 0j for j in range(self.nu)]),
                       shape=(N,))
        Xdd = np.linalg.solve(Jv, -(g + np.einsum("nij,nj->ni", Fu, udd))[..., None])[..., 0]
        self.state = dict(X=X, Xd=Xd, Xdd=Xdd, u=u, u1=u1, ud=ud, udd=udd, P=P, J=Jv, Fu=Fu, args=args, q=q,
                          qdot=qdot)
        return self.state

    def expression(self, key, expr):
        """A symbolic expression of the body coordinates, lambdified with its first two time derivatives."""
        if key not in self._points:
            X = self.o.xsyms
            ex = sp.Matrix(expr)
            d1 = ex.jacobian(X) * self.Xd_syms
            d2 = d1.jacobian(X) * self.Xd_syms + ex.jacobian(X) * self.Xdd
            args = self.args + list(self.Xd_syms) + list(self.Xdd)
            self._points[key] = (_lam(self.args, list(ex)), _lam(args, list(d1)), _lam(args, list(d2)),
                                 _lam(self.args, list(ex.jacobian(X))))
        return self._points[key]

    def motion_of(self, key, expr):
        """(value, first, second time derivative) of an expression of the coordinates at the solved state."""
        s = self.state
        f, f1, f2, _ = self.expression(key, expr)
        N = s["X"].shape[0]
        a2 = s["args"] + [s["Xd"][:, j] for j in range(self.n)] + [s["Xdd"][:, j] for j in range(self.n)]
        return f(*s["args"], shape=(N,)), f1(*a2, shape=(N,)), f2(*a2, shape=(N,))

    def point(self, name):
        o = self.o
        body = o.bodies[o.plan.point_body[o.plan.point_index(name)]]
        return self.motion_of(("pt", name), o.world(body, name))

    # -- kinetostatics ------------------------------------------------------------------------------------
    def _com(self, body, mp):
        """The centre of mass of ``body`` as a symbolic point (the file's com rules, docs/format.md)."""
        o, m = self.o, self.o.m
        if body.endswith(".block"):
            return o.world(body, next(iter(o.local[body])))
        if body.endswith(".cylinder") or body.endswith(".rod"):
            ac = next(a for a in m.actuators if body.startswith(a.name + "."))
            cyl = body.endswith(".cylinder")
            at = o.world(body, ac.between[0] if cyl else ac.between[1])
            e = _rot(o.angle(body), (1, 0))
            dist = float(mp.com or 0.0) * (1 if cyl else -1)
            return (at[0] + dist * e[0], at[1] + dist * e[1])
        pts = m.link(body).points
        com = mp.com
        if com is None:
            ws = [o.world(body, p) for p in pts]
            return (sum(w[0] for w in ws) / len(ws), sum(w[1] for w in ws) / len(ws))
        if com == "mid":
            a, b = o.world(body, pts[0]), o.world(body, pts[1])
            return ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        if isinstance(com, str):
            return o.world(body, com)
        sk0 = o._sketch(pts[0])
        th = o._sketch_angle(body)
        rel = (com[0] - sk0[0], com[1] - sk0[1])
        loc = (math.cos(th) * rel[0] + math.sin(th) * rel[1], -math.sin(th) * rel[0] + math.cos(th) * rel[1])
        x, y, t = o.X[body]
        r = _rot(t, loc)
        return (x + r[0], y + r[1])

    def _inertia(self, body, mp, com):
        o, m = self.o, self.o.m
        if mp.inertia is not None:
            return sp.Float(mp.inertia)
        if "." in body:
            return sp.Integer(0)
        pts = m.link(body).points
        if len(pts) == 2:
            L = o.P[f"{body}.length"]
            return mp.mass * L ** 2 / 12
        ws = [o.world(body, p) for p in pts]
        return sum((mp.mass / len(pts)) * ((w[0] - com[0]) ** 2 + (w[1] - com[1]) ** 2) for w in ws)

    def generalised_loads(self):
        """Q (N, n): the generalised forces of gravity, d'Alembert inertia and the file's loads on the coordinates."""
        o, m, s = self.o, self.o.m, self.state
        N = s["X"].shape[0]
        Q = np.zeros((N, self.n), dtype=complex)
        dyn = m.dynamics
        if dyn is None:
            return Q
        g = np.array(dyn.gravity[:2], dtype=float)
        X = o.xsyms
        idx = {b: o.moving.index(b) for b in o.moving}
        for body, mp in dyn.bodies:
            com = self._com(body, mp)
            (cx, cy), (vx, vy), (ax, ay) = (np.moveaxis(a, -1, 0) for a in self.motion_of(("com", body), com))
            J = self._jacobian(("com", body), com)                                   # (N, 2, n)
            f = np.stack([mp.mass * (g[0] - ax), mp.mass * (g[1] - ay)], -1)
            Q += np.einsum("nij,ni->nj", J, f)
            I = self._value(("I", body), [self._inertia(body, mp, com)])[:, 0]
            alpha = s["Xdd"][:, 3 * idx[body] + 2]
            Q[:, 3 * idx[body] + 2] += -I * alpha
        from assur.kinetostatics.loads import point_body
        from assur.kinetostatics.tables import force_tables
        t = force_tables(o.plan)
        q0 = s["q"][:, 0]
        for ld in dyn.loads:
            value = self._load_value(ld, q0)
            if ld.force is None and ld.point is None:
                Q[:, 3 * idx[ld.link] + 2] += value
                continue
            body = o.bodies[point_body(t, ld.point, ld.link)]
            r = o.world(body, ld.point)
            J = self._jacobian(("load", body, ld.point), r)
            f = np.stack([np.real(value) + 0j, np.imag(value) + 0j], -1) if np.iscomplexobj(value) and not \
                np.all(np.isreal(value)) else value
            if ld.opposes == "velocity":
                _, v, _ = self.motion_of(("pt", body, ld.point), r)
                sp_ = np.sqrt(v[:, 0] ** 2 + v[:, 1] ** 2)
                mag = abs(complex(*ld.force[:2])) if ld.law is None else np.abs(value)
                f = -mag[..., None] * v / sp_[:, None] if np.ndim(mag) else -mag * v / sp_[:, None]
            elif ld.law is None:
                f = np.broadcast_to(np.array(ld.force[:2], dtype=complex), (N, 2))
            Q += np.einsum("nij,ni->nj", J, f)
        return Q

    def _load_value(self, ld, q):
        if ld.law is None:
            return complex(*ld.force[:2]) if ld.force is not None else float(ld.torque)
        xs, ys = np.asarray(ld.law.inputs, float), np.asarray(ld.law.values, float)
        period = 2 * math.pi if self.o.plan.input_kinds[0] == "rotary" else None
        cols = [np.interp(q.real, xs, ys[:, j], period=period) for j in range(ys.shape[1])]
        return np.stack(cols[:2], -1) + 0j if ys.shape[1] == 2 else cols[0]

    def _value(self, key, exprs):
        s = self.state
        if key not in self._points:
            self._points[key] = _lam(self.args, list(exprs))
        return self._points[key](*s["args"], shape=(s["X"].shape[0],))

    def _jacobian(self, key, expr):
        s = self.state
        k = ("jac",) + tuple(key)
        if k not in self._points:
            self._points[k] = _lam(self.args, list(sp.Matrix(expr).jacobian(self.o.xsyms)))
        N = s["X"].shape[0]
        return self._points[k](*s["args"], shape=(N,)).reshape(N, len(expr), self.n)

    def multipliers(self):
        """(λ (N, n), efforts (N, n_in)): Jᵀλ = −Q, and each driver's effort −Σ λ·∂F/∂q."""
        s = self.state
        Q = self.generalised_loads()
        lam = np.linalg.solve(np.swapaxes(s["J"], -1, -2), -Q[..., None])[..., 0]
        dF_dq = np.einsum("nij,njk->nik", s["Fu"], s["u1"])
        return lam, -np.einsum("ni,nik->nk", lam, dF_dq)

    def reactions(self, lam):
        """(N, n_pairs, 2) complex: every pair's reaction (the earlier body's force on the later one), gear and cam
        drives realised by their tooth and contact forces (written again here in real components)."""
        o, m, s = self.o, self.o.m, self.state
        from assur.kinetostatics.tables import force_tables
        t = force_tables(o.plan)
        N = s["X"].shape[0]
        out = np.zeros((N, len(t.pairs), 2), dtype=complex)
        row = {kind: i for i, kind in enumerate(o.eq_kinds)}

        def val(expr, key):
            return self._value(("v",) + key, list(expr))

        for k, fp in enumerate(t.pairs):
            if fp.kind == "R":
                out[:, k] = -np.stack([lam[:, row[("R", k, 0)]], lam[:, row[("R", k, 1)]]], -1)
            elif fp.kind == "P":
                pr = next((p for p in m.prismatic if p.name == fp.name), None)
                if pr is not None:
                    U, _ = o._line(pr)
                    slider = f"{pr.name}.block" if pr.point is not None else pr.link
                    c = row[("Pn", pr.name, slider)]
                else:
                    ac = next(a for a in m.actuators if a.name == fp.name)
                    U = _rot(o.angle(f"{ac.name}.cylinder"), (1, 0))
                    slider = f"{ac.name}.rod"
                    c = row[("An", ac.name, slider)]
                Uv = val(U, ("U", fp.name))
                n = np.stack([-Uv[:, 1], Uv[:, 0]], -1)
                sign = 1.0 if o.bodies[fp.later] == slider else -1.0
                out[:, k] = sign * lam[:, c, None] * n
        self._realise(lam, out, t, row, val)
        return out

    def _pivot(self, t, body, point):
        plan = self.o.plan
        return next(k for k, fp in enumerate(t.pairs) if fp.kind == "R" and fp.later == plan.body_names.index(body)
                    and fp.earlier == 0 and plan.point_names[fp.point] == point)

    def _realise(self, lam, out, t, row, val):
        o, m = self.o, self.o.m
        frame = set(m.frame.points)

        def c2(v):                                   # (N, 2) components
            return v[:, 0], v[:, 1]

        def cross(a, b):
            return a[0] * b[1] - a[1] * b[0]

        def dot(a, b):
            return a[0] * b[0] + a[1] * b[1]

        def norm(a):
            return np.sqrt(a[0] ** 2 + a[1] ** 2)

        def torque_of(kind, link, j):
            """The drive constraint's torque on its link, λ·∂c/∂θ (= λ·(t·d))."""
            i = row[(kind, link, j)]
            expr = self.o.eqs[i]
            dth = sp.diff(expr, o.X[link][2])
            return lam[:, i] * self._value(("dth", kind, link, j), [dth])[:, 0]

        for j in reversed(range(len(m.cams))):
            cp = m.cams[j]
            y1, x = o.rates[cp.name]
            rate = y1
            pivot = next(p for p in m.link(cp.cam).points if p in frame)
            O = c2(val(o.world("frame", pivot), ("pt", "frame", pivot)))
            R = c2(val(o.world(cp.follower, cp.point), ("pt", cp.follower, cp.point)))
            sign = o.lift_sign(cp)
            fa = (math.cos(cp.face_angle), math.sin(cp.face_angle))
            if cp.motion == "translating":
                pr = next(p for p in m.prismatic if p.link == cp.follower)
                U = c2(val(o._line(pr)[0], ("U", pr.name)))
                along = (sign * U[0], sign * U[1])
                centre = (O[0] + rate * along[1], O[1] - rate * along[0])            # O − i·rate·along
                fx, fy = -along[1], along[0]                                        # i·along
                face = (fx * fa[0] - fy * fa[1], fx * fa[1] + fy * fa[0])
            else:
                fpv = next(p for p in m.link(cp.follower).points if p in frame)
                Of = c2(val(o.world("frame", fpv), ("pt", "frame", fpv)))
                w = sign * rate
                centre = ((O[0] - w * Of[0]) / (1 - w), (O[1] - w * Of[1]) / (1 - w))
                arm = (R[0] - Of[0], R[1] - Of[1])
                na = norm(arm)
                a = (arm[0] / na, arm[1] / na)
                face = (a[0] * fa[0] - a[1] * fa[1], a[0] * fa[1] + a[1] * fa[0])
            if cp.contact == "flat":
                nn = (-face[1], face[0])
                flip = np.where(np.real(dot(nn, (R[0] - O[0], R[1] - O[1]))) < 0, -1.0, 1.0)
                nn = (nn[0] * flip, nn[1] * flip)
                d = dot((R[0] - centre[0], R[1] - centre[1]), nn)
                C = (centre[0] + d * nn[0], centre[1] + d * nn[1])
            else:
                v = (R[0] - centre[0], R[1] - centre[1])
                nv = norm(v)
                nn = (v[0] / nv, v[1] / nv)
                flip = np.where(np.real(dot(nn, (R[0] - O[0], R[1] - O[1]))) < 0, -1.0, 1.0)
                nn = (nn[0] * flip, nn[1] * flip)
                C = (R[0] - cp.roller_radius * nn[0], R[1] - cp.roller_radius * nn[1])
            if cp.motion == "oscillating":
                T = torque_of("C", cp.follower, j)
                F = T / cross((C[0] - Of[0], C[1] - Of[1]), nn)
                kf = self._pivot(t, cp.follower, fpv)
                out[:, kf, 0] -= F * nn[0]
                out[:, kf, 1] -= F * nn[1]
            else:
                Fd = lam[:, row[("S", cp.follower, j)]]
                F = Fd / dot(nn, U)
                k = next(i for i, fp in enumerate(t.pairs) if fp.kind == "P" and fp.name == pr.name)
                n_line = (-U[1], U[0])
                Nold = out[:, k, 0] * n_line[0] + out[:, k, 1] * n_line[1]
                Nnew = Nold - F * dot(nn, n_line)
                out[:, k, 0], out[:, k, 1] = Nnew * n_line[0], Nnew * n_line[1]
            kc = self._pivot(t, cp.cam, pivot)
            out[:, kc, 0] += F * nn[0]
            out[:, kc, 1] += F * nn[1]
        for j in reversed(range(len(m.gears))):
            gp = m.gears[j]
            y1, y2 = o.rates[gp.name]
            pa = next(p for p in m.link(gp.a).points if p in frame)
            pb = next(p for p in m.link(gp.b).points if p in frame)
            Oa = c2(val(o.world("frame", pa), ("pt", "frame", pa)))
            Ob = c2(val(o.world("frame", pb), ("pt", "frame", pb)))
            dv = (Ob[0] - Oa[0], Ob[1] - Oa[1])
            d = norm(dv)
            e = (dv[0] / d, dv[1] / d)
            P = ((Oa[0] - y1 * Ob[0]) / (1 - y1), (Oa[1] - y1 * Ob[1]) / (1 - y1))
            ra = -y1 * d / (1 - y1)
            ra1 = -d * y2 / (1 - y1) ** 2
            tt = (ra1 * e[0] + ra * e[1], ra1 * e[1] - ra * e[0])                  # ra′·e − ra·i·e
            nt = norm(tt)
            tt = (tt[0] / nt, tt[1] / nt)
            n0 = (-tt[1], tt[0])
            flip = np.where(np.real(dot(n0, (Ob[0] - P[0], Ob[1] - P[1]))) < 0, -1.0, 1.0)
            n0 = (n0[0] * flip, n0[1] * flip)
            T = torque_of("G", gp.b, j)
            r = (P[0] - Ob[0], P[1] - Ob[1])
            s = np.where(np.real(T * cross(r, tt)) >= 0, 1.0, -1.0)
            ca, sa = math.cos(gp.pressure_angle), math.sin(gp.pressure_angle)
            dvec = (s * ca * tt[0] + sa * n0[0], s * ca * tt[1] + sa * n0[1])
            F = T / cross(r, dvec)
            kb, ka = self._pivot(t, gp.b, pb), self._pivot(t, gp.a, pa)
            out[:, kb, 0] -= F * dvec[0]
            out[:, kb, 1] -= F * dvec[1]
            out[:, ka, 0] += F * dvec[0]
            out[:, ka, 1] += F * dvec[1]
