"""A planar Assur group without a closed form (a triad or higher), by batched Newton iterations.

Used for groups without a closed form and, with ``method="newton"``, as the test oracle of the
closed forms. Unknowns are the poses (x, y, θ) of the group's bodies; equations: each revolute
joins two bodies at one point (2 equations), each prismatic pair keeps the slider aligned with and
on its guide line (2 equations), a driven actuator's slide also fixes its length (1 more).

Newton iterates on fewer unknowns (:func:`reduction`): a binary link of two revolutes whose ends are held by known
points or by the group's other bodies is one equation, the distance of its ends, and not three unknowns; its pose
follows from its ends after the iterations (:func:`expand`). The triad's four bodies iterate as its ternary's three
unknowns. The acceptance, the branch certificate and the derivatives are those of the full equations at the full
poses.

The assembly branch is the one connected to the sketch: the solver (:func:`steps.execute`) walks
each sample's inputs from the sketch inputs to the requested ones in small stages, and each
stage's Newton iterations start from the previous stage (the first from the sketch poses). Samples
are independent: no sample borrows another sample's solution, so the result does not depend on the
batch's order. Velocities and accelerations follow by implicit differentiation:
F_x·x' = −F', F_x·x'' = −(F'' at x'' = 0), evaluated on jets.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import StructureError
from ...kernels.jet import Jet, expi
from ...kernels.newton import ACCEPT_FACTOR, newton


@dataclass(frozen=True)
class Reduction:
    """The unknowns Newton iterates on for a group (:func:`reduction`): ``kept`` the bodies whose poses remain,
    ``index`` their unknowns' places among the group's (x, y, θ per body of ``st.bodies``), ``rods`` the binary links
    left out, each (body, its first point, its second point, the body holding the first, the one holding the
    second)."""
    kept: tuple
    index: tuple
    rods: tuple


def reduction(g, lines, st) -> Reduction:
    """The group's reduced unknowns: a body of two points, both revolutes joining it to exactly one other body, that
    slides on nothing (``lines``: the plan's slide records) and whose two partners are known bodies or kept bodies of
    the group (not both the same one), is a rod: one equation |P₂ − P₁| = l between the points that hold its ends.
    The group's bodies are taken in order; a rod's partners in the group stay kept. The system stays square: a rod
    takes three unknowns and its four joint equations away and adds one equation."""
    sliding = {b for rec in lines for b in rec[2:4]}
    at = dict(g.joints)
    group = set(st.bodies)
    rods, out, pinned = [], set(), set()
    for b in st.bodies:
        pts = tuple(g.bodies[b].points)
        if b in sliding or b in pinned or len(pts) != 2 or pts[0] == pts[1]:
            continue
        partners = []
        for p in pts:
            bodies = tuple(at.get(p, ()))
            others = [o for o in bodies if o != b]
            if len(bodies) != 2 or len(others) != 1 or others[0] in out:
                break
            partners.append(others[0])
        else:
            if partners[0] == partners[1] and partners[0] in group:
                continue
            rods.append((b, pts[0], pts[1], partners[0], partners[1]))
            out.add(b)
            pinned.update(o for o in partners if o in group)
    kept = tuple(b for b in st.bodies if b not in out)
    index = tuple(3 * i + k for i, b in enumerate(st.bodies) if b not in out for k in range(3))
    return Reduction(kept, index, tuple(rods))


def expand(c, st, red: Reduction, y: list, ref: list) -> list:
    """The group's full poses (a list of 3k values: x, y, θ per body of ``st.bodies``) from the reduced unknowns ``y``
    (the kept bodies' poses, a list) of :func:`reduction`: a rod's angle from the points at its ends, within half a
    turn of its angle in ``ref`` (the full poses the iterations started from), its origin from its first end.
    Element-wise (numpy arrays or traced values)."""
    out = list(ref)
    pose = {}
    for j, b in enumerate(red.kept):
        i = st.bodies.index(b)
        out[3 * i:3 * i + 3] = y[3 * j:3 * j + 3]
        pose[b] = (y[3 * j] + y[3 * j + 1] * 1j, np.cos(y[3 * j + 2]) + np.sin(y[3 * j + 2]) * 1j)

    def end(p, holder):
        if holder in pose:
            o, e = pose[holder]
            return o + e * c.w[(holder, p)]
        return c.pos[p].v
    for b, p1, p2, h1, h2 in red.rods:
        i = st.bodies.index(b)
        w1 = c.w[(b, p1)]
        first = end(p1, h1)
        d = (end(p2, h2) - first) * np.conj(c.w[(b, p2)] - w1)
        ref_theta = ref[3 * i + 2]
        cr, sr = np.cos(ref_theta), np.sin(ref_theta)
        dr, di = np.real(d), np.imag(d)
        theta = ref_theta + np.arctan2(di * cr - dr * sr, dr * cr + di * sr)
        e = d / np.abs(d)
        o = first - e * w1
        out[3 * i:3 * i + 3] = [np.real(o), np.imag(o), theta]
    return out


def _residual(c, st, X, derivs: bool, labels: list | None = None, lift: bool = False, red: Reduction | None = None):
    """Residual components (list of real jets) for unknown jets X (3k of them); with ``labels``, the
    joint point or slide name of each component is appended to it. ``lift``: the unknowns' values carry one more
    trailing axis (of length 1, their derivatives one of length 3k: every direction at once), so every known value
    of the context gets it too. ``red``: X holds the kept bodies' poses only (:func:`reduction`); each rod adds
    (|P₂ − P₁|² − l²)/(2l) (m: to first order the distance's error) after the other equations."""
    g = c.g

    def up(a):
        a = np.asarray(a)
        return a[..., None] if lift and a.ndim else a
    group = list(st.bodies if red is None else red.kept)
    gi = {b: i for i, b in enumerate(group)}

    def const(j):
        v = up(j.v)
        return j if derivs else Jet(v, np.zeros_like(v) if X[0].d is not None else None,
                                    np.zeros_like(v) if X[0].dd is not None else None)

    pose = {}
    for b, i in gi.items():
        pose[b] = (X[3 * i] + X[3 * i + 1] * 1j, expi(X[3 * i + 2]))
    for b, (o, e) in c.pose.items():
        pose[b] = (const(o), const(e))

    def world(b, p):
        o, e = pose[b]
        return o + e * up(c.w[(b, p)])

    res = []
    for point, at in g.joints:
        gb = [b for b in at if b in gi]
        if not gb:
            continue
        kb = [b for b in at if b in c.pose]
        if kb:
            target = const(c.pos[point])
            for b in gb:
                z = world(b, point) - target
                res += [z.real, z.imag]
                if labels is not None:
                    labels += [point, point]
        else:
            for b in gb[1:]:
                z = world(gb[0], point) - world(b, point)
                res += [z.real, z.imag]
                if labels is not None:
                    labels += [point, point]
    driven = {d.actuator: k for k, d in enumerate(c.plan.mechanism.drivers) if d.kind == "linear"}
    for idx, rec in enumerate(c.plan.lines):
        kind, name, guide, slider = rec[:4]
        if not (guide in gi or slider in gi) or guide not in pose or slider not in pose:
            continue
        q, u, ref, us = (up(a) for a in c.lines[idx])
        og, eg = pose[guide]
        os_, es = pose[slider]
        U = eg * u
        # the alignment of the slider with its guide (a sine) times the length scale: every residual in metres
        res.append((U.conj() * (es * us)).imag * c.plan.length_scale)
        d = os_ + es * ref - og - eg * q
        res.append((U.conj() * d).imag)
        if kind == "actuator" and name in driven:
            res.append((U.conj() * d).real - const(c.q[driven[name]]))
        if labels is not None:
            labels += [name] * (len(res) - len(labels))
    if red is not None:
        for b, p1, p2, h1, h2 in red.rods:
            ends = [world(h, p) if h in gi else const(c.pos[p]) for p, h in ((p1, h1), (p2, h2))]
            d = ends[1] - ends[0]
            length = np.abs(c.w[(b, p2)] - c.w[(b, p1)])
            length = up(length) if lift else length
            res.append((d.real * d.real + d.imag * d.imag - length * length) / (2.0 * length))
    return res


def _equilibrated_det(J):
    """(...) det of J (..., n, n) with every row scaled to unit length: |det| ≤ 1 (Hadamard)."""
    with np.errstate(all="ignore"):
        norms = np.linalg.norm(J, axis=-1, keepdims=True)
        return np.linalg.det(J / np.where(norms > 0, norms, 1.0))


def body_scales(c, st):
    """Per body of the group, its own length scale (m): the largest distance between two of its points in its
    local frame, (...) arrays of the design's batch shape; a body with one point (a slider block) takes the
    group's largest."""
    sizes = []
    for b in st.bodies:
        ws = [np.asarray(c.w[(b, p)]) for p in c.g.bodies[b].points]
        size = np.zeros(np.shape(ws[0]))
        for w in ws[1:]:
            size = np.maximum(size, np.abs(w - ws[0]))
        sizes.append(size)
    largest = np.maximum.reduce(sizes) if sizes else np.float64(c.plan.length_scale)
    largest = np.where(largest > 0, largest, c.plan.length_scale)
    return [np.where(s > 0, s, largest) for s in sizes]


def certificate_det(c, st, J):
    """The dimensionless branch certificate of a Newton-solved group: (...) the determinant of its loop equations'
    Jacobian J (..., n, n) (rows in metres, columns x, y (m) and θ (rad) per body) with each body's θ column
    divided by the body's own length scale (:func:`body_scales`) and then every row scaled to unit length. The
    matrix is then a pure number: the same for the mechanism drawn at any size (|det| ≤ 1, and 0 exactly where two
    assemblies meet)."""
    cols = np.ones(np.shape(J)[:-2] + (np.shape(J)[-1],))
    for i, s in enumerate(body_scales(c, st)):
        cols[..., 3 * i + 2] = 1.0 / s
    return _equilibrated_det(J * cols[..., None, :])


def ball_constants(c, st, m: int):
    """The constants of :func:`alone_within`'s uniqueness ball for the group ``st`` at ``m`` samples of the context
    ``c`` (a group of revolutes): ``(gamma (m,), cols (m, 3k), reach (m,), smallest (m,))``. In the unknowns
    u = x·cols (x, y and s·θ per body; s: :func:`body_scales`), ‖J(u) − J(v)‖₂·cols ≤ gamma·‖u − v‖₂ everywhere;
    any poses whose points of the group's bodies are all within d ≤ ``smallest`` (the least body scale) of another
    poses' lie within ``reach``·d of them (each body's angle turned the short way)."""
    g = c.g
    gi = {b: i for i, b in enumerate(st.bodies)}
    scales = [np.broadcast_to(s, (m,)) for s in body_scales(c, st)]

    def offset(b, p):
        return np.broadcast_to(np.abs(np.asarray(c.w[(b, p)])), (m,))

    lipschitz = [np.zeros(m) for _ in st.bodies]
    for point, at in g.joints:
        gb = [b for b in at if b in gi]
        if not gb:
            continue
        pairs = [[b] for b in gb] if any(b in c.pose and b not in gi for b in at) else [[gb[0], b] for b in gb[1:]]
        for pair in pairs:              # a residual pair: the joint's two components
            for b in pair:
                lipschitz[gi[b]] = lipschitz[gi[b]] + len(pair) * (offset(b, point) / scales[gi[b]] ** 2) ** 2
    cols = np.ones((m, 3 * len(st.bodies)))
    spread = np.zeros(m)
    for i, b in enumerate(st.bodies):
        cols[:, 3 * i + 2] = scales[i]
        nearest = np.min([offset(b, p) for p in g.bodies[b].points], axis=0)
        spread += (1.0 + math.pi * nearest / scales[i]) ** 2 + math.pi ** 2
    return np.sqrt(np.max(lipschitz, axis=0)), cols, np.sqrt(spread), np.min(scales, axis=0)


def alone_within(c, st, x, F, J, distance):
    """(m,) True where the group's poses ``x (m, 3k)`` are proven to be the only assembly of the group within
    ``distance`` (m; the largest displacement of a point of its bodies, as :func:`.group_assemblies.assembly_distances`
    measures assemblies apart), from the loop equations' residual ``F (m, 3k)`` and Jacobian ``J (m, 3k, 3k)`` there.

    A uniqueness ball (docs/assemblies.md), in the unknowns u of :func:`ball_constants`, whose Jacobian changes by at
    most γ‖u − v‖ (only a body's angle column turns, with the body): two roots y ≠ z within R of x̂ would give
    0 = F(y) − F(z) = (J̃(x̂) + E)(y − z) with ‖E‖ ≤ γR, impossible while γR < σ (σ: the smallest singular value of
    J̃(x̂)). The sample's own root lies within 2η of x̂ (η = ‖F‖/σ; Kantorovich, where γη ≤ σ/4), another assembly
    whose points are all within d of x̂'s within reach·d: both inside R = max(2η, reach·d) with γR ≤ σ/2 cannot be.
    Groups with a prismatic pair (other second derivatives) are never proven here."""
    x = np.asarray(x, dtype=float)
    m = x.shape[0]
    if any(guide in st.bodies or slider in st.bodies for _, _, guide, slider, *_ in c.plan.lines):
        return np.zeros(m, dtype=bool)
    gamma, cols, reach, smallest = ball_constants(c, st, m)
    with np.errstate(all="ignore"):
        sigma = np.linalg.svd(np.asarray(J) / cols[:, None, :], compute_uv=False)[:, -1]
        eta = np.linalg.norm(F, axis=-1) / sigma
        radius = np.maximum(2.0 * eta, reach * distance)
        return ((distance <= smallest) & (gamma * eta <= 0.25 * sigma) & (gamma * radius <= 0.5 * sigma)
                & np.isfinite(radius))


def sketch_misfit(c, st, poses):
    """How far the drawn sketch is from closing the group's loop equations.

    ``c``: a context with the group's known bodies placed (at the file's design and sketch inputs);
    ``poses``: (x, y, θ) of every body as drawn. Returns (largest residual (m), the joint or slide
    where it is)."""
    X = [Jet(np.asarray(v, dtype=float)) for b in st.bodies for v in poses[b]]
    labels: list = []
    r = _residual(c, st, X, derivs=False, labels=labels)
    # a joint's two components (x, y) make one distance
    off: dict[str, float] = {}
    for ri, label in zip(r, labels):
        off[label] = off.get(label, 0.0) + float(np.max(np.abs(ri.v))) ** 2
    where = max(off, key=off.get)
    return math.sqrt(off[where]), where


def _residual_and_jacobian(c, st, x, shape, red: Reduction | None = None):
    """(F (shape + (n,)), J (shape + (n, n))) of the group's loop equations at the body poses ``x``: one pass of the
    residual on jets whose derivative holds all n directions at once. ``red``: the reduced equations, ``x`` the kept
    bodies' poses (:func:`reduction`)."""
    n = 3 * len(st.bodies if red is None else red.kept)
    x = _shaped(x, shape + (n,))
    eye = np.eye(n)
    X = [Jet(x[..., i:i + 1], _shaped(eye[i], shape + (n,)), None) for i in range(n)]
    r = _residual(c, st, X, derivs=False, lift=True, red=red)
    if len(r) != n:
        raise StructureError(f"group of {len(st.bodies)} bodies gave {len(r)} equations, expected {n}")
    F = np.stack([_shaped(ri.v, shape + (1,))[..., 0] for ri in r], axis=-1)
    J = np.stack([_shaped(ri.d, shape + (n,)) for ri in r], axis=-2)
    return F, J


def _shaped(a, shape: tuple):
    """``a`` broadcast to ``shape``: itself where it has that shape already (one sample, as a compile's sketch solve
    has: a broadcast costs more than the rest of some of these lines)."""
    return a if np.shape(a) == shape else np.broadcast_to(a, shape)


def sketch_branch_sign(c, st, poses) -> int:
    """The branch invariant of a Newton-solved group as the sketch draws it: the sign of the equilibrated
    Jacobian determinant of its loop equations at the drawn body poses (x, y, θ) ``poses`` (``c``: a context with
    the group's known bodies placed, as for :func:`sketch_misfit`). The solver keeps every sample on this sign."""
    x = np.array([v for b in st.bodies for v in poses[b]], dtype=float)
    return int(np.sign(certificate_det(c, st, _residual_and_jacobian(c, st, x, ())[1])))


def solve_group(c, st):
    """Solve one group for every sample of the context by Newton's method, warm-started from
    ``c.warm[step]`` (the previous continuation stage) or from the plan's sketch poses."""
    tol = c.tol
    shape = np.broadcast_shapes(*(np.shape(j.v) for j in c.pos.values()), np.shape(c.valid),
                                *(np.shape(q.v) for q in c.q))
    k = len(st.bodies)
    n = 3 * k
    key = id(st)
    x = c.warm.get(key)
    if x is None or x.shape != shape + (n,):
        x = np.empty(shape + (n,))
        for i, (px, py, th) in enumerate(c.plan.sketch_poses[b] for b in st.bodies):
            x[..., 3 * i], x[..., 3 * i + 1], x[..., 3 * i + 2] = px, py, th
    else:
        x = x.copy()

    def F_and_J(x):
        return _residual_and_jacobian(c, st, x, shape)

    scale = c.plan.length_scale
    red = reduction(c.g, c.plan.lines, st)

    def full(y, ref):
        """The full poses from the kept bodies' ``y`` (:func:`expand`), ``ref`` the poses started from."""
        out = expand(c, st, red, [y[..., i] for i in range(y.shape[-1])], [ref[..., i] for i in range(n)])
        return np.stack([_shaped(v, shape) for v in out], axis=-1)
    start = x
    if red.rods:
        with np.errstate(all="ignore"):
            x = full(x[..., list(red.index)], start)
    sign_key = (key, "det_sign")
    if sign_key not in c.warm:
        # the branch invariant: the sign of the equilibrated Jacobian determinant at the seed (the sketch
        # assembly, on the plan's branches); it changes only through a singular position
        c.warm[sign_key] = np.sign(certificate_det(c, st, F_and_J(x)[1]))
    accept = ACCEPT_FACTOR * tol.newton_residual * scale
    if red.rods:
        # the iterations on the kept bodies' poses; the rods follow, and the full equations are checked there
        y, ok, _ = newton(lambda y: _residual_and_jacobian(c, st, y, shape, red), x[..., list(red.index)],
                          tol.newton_residual * scale, tol.newton_iterations, accept_tol=accept)
        with np.errstate(all="ignore"):
            x = full(y, start)
            F, J = F_and_J(x)
            ok = ok & np.all(np.abs(F) < accept, axis=-1) & np.all(np.isfinite(x), axis=-1)
        x = np.where(ok[..., None], x, np.nan)
    else:
        x, ok, J = newton(F_and_J, x, tol.newton_residual * scale, tol.newton_iterations, accept_tol=accept)
    # a converged sample counts only where its branch is certified: the same determinant sign as the seed,
    # clear of the singular positions where two assemblies meet
    det = certificate_det(c, st, J)
    certified = (np.sign(det) == c.warm[sign_key]) & (np.abs(det) > tol.newton_certify)
    ok = ok & certified
    x = np.where(ok[..., None], x, np.nan)
    c.warm[key] = x
    c.flag(ok)
    order = c.order
    with np.errstate(all="ignore"):
        Jinv = np.linalg.inv(np.where(ok[..., None, None], J, np.eye(n)))
    X = [Jet(x[..., i], np.zeros(shape) if order >= 1 else None, np.zeros(shape) if order >= 2 else None)
         for i in range(n)]
    if order >= 1:
        r = _residual(c, st, X, derivs=True)
        r1 = np.stack([np.broadcast_to(ri.d, shape) for ri in r], axis=-1)
        xd = -np.einsum("...ij,...j->...i", Jinv, r1)
        X = [Jet(x[..., i], xd[..., i], np.zeros(shape) if order >= 2 else None) for i in range(n)]
        if order >= 2:
            r = _residual(c, st, X, derivs=True)
            r2 = np.stack([np.broadcast_to(ri.dd, shape) for ri in r], axis=-1)
            xdd = -np.einsum("...ij,...j->...i", Jinv, r2)
            X = [Jet(x[..., i], xd[..., i], xdd[..., i]) for i in range(n)]
    for i, b in enumerate(st.bodies):
        o = X[3 * i] + X[3 * i + 1] * 1j
        c.place(b, o, expi(X[3 * i + 2]))
