"""Spatial (dimension = 3) mechanisms: compile to a plan and solve it, by the vector method of paper 003.

A spatial plan is a chain of steps, each with a closed form on second-order jets (exact
velocities and accelerations, as for planar plans):

- ``frame``: the frame's points (parameters ``P.x``, ``P.y``, ``P.z``);
- ``crank``: a link turning about a frame revolute with axis e (parameters ``P.axis.gamma1``,
  ``P.axis.gamma2``: e = e_Z2(γ1, γ2), paper 003 eq. (8)). Its arm is at
  ``ρ·(cos θ e_X2 + sin θ e_Y2) + h·e``, θ = zero + sense·q measured in the axis frame
  (e_X2, e_Y2, e_Z2) = T_Y(γ1)·T_X(γ2), right-handed about e; ``crank.length`` = |arm − pivot|,
  ``crank.axial`` = h.
- ``RSS``: an R–S–S dyad (paper 003 eqs. (7), (22)–(25)): a rocker hinged on a frame revolute at D
  (axis e) and a coupler from a known point A; the rocker point B solves
  |B − A| = coupler length, |B − D| = rocker length, (B − D)·e = rocker axial offset, by the
  robust unit-vector solver (:func:`assur.kernels.spatial.unit_vector`) on the branch
  s = sign det[A − D, e, B − D], fixed once from the sketch (never by continuity).

Every link has a frame: a hinged link (u_r, u_t, e) with u_r the unit normal part of its arm;
a coupler (e_x2, e_y2, e_z2) of eqs. (27)–(30), where e_x2 = Ort(U − other end) and
e_z2 = Ort(e_p × e_x2) for a universal joint at its end U whose pin axis e_p is fixed in the link
on the other side (β1 = β2 = 90°; erratum F3: the pin turns with its link). Further points of a
link have local coordinates (u, v, w) in its frame (parameters ``link.P.u``, ``.v``, ``.w``).
A coupler between two spherical joints spins idly; its frame is then undefined (NaN) and it may
carry no further point.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from .errors import SpecError, StructureError, UnbuildableError, UnbuildableWarning
from .kernels import spatial as V
from .kernels.jet import Jet
from .model.mechanism import Mechanism
from .plan import PlanLookups
from .structure.assur import Structure, analyse
from .tolerances import DEFAULT


@dataclass(frozen=True, slots=True)
class SpatialStep:
    kind: str                      # 'frame' | 'crank' | 'RSS'
    body: int                      # the body placed (for RSS: the rocker)
    key_point: str | None = None   # the point the branch refers to (RSS: B)
    branch: int = 1                # s = sign det[A − D, e, B − D]
    data: tuple = ()


@dataclass(frozen=True)
class SpatialPlan(PlanLookups):
    """The compiled plan of a spatial mechanism (the attributes a planar :class:`SolvePlan` has,
    with ``dimension = 3``)."""
    mechanism: Mechanism
    structure: Structure
    steps: tuple[SpatialStep, ...]
    param_names: tuple[str, ...]
    defaults: np.ndarray
    point_names: tuple[str, ...]
    body_names: tuple[str, ...]
    input_names: tuple[str, ...]
    input_kinds: tuple[str, ...]
    sketch_inputs: np.ndarray
    speeds: np.ndarray
    point_body: tuple[int, ...]
    length_scale: float = 1.0
    #: per body: ('frame',) | ('hinged', pivot, axis point) | ('coupler', U, other, pin body, pin local) |
    #: ('idle', A, B): how its frame is defined
    body_frames: tuple = field(repr=False, default=())
    dimension: int = 3

    def rss_steps(self) -> list[SpatialStep]:
        return [s for s in self.steps if s.kind == "RSS"]

    def with_branch(self, point: str, s: int | None = None, *, w: int | None = None) -> "SpatialPlan":
        """A copy with the branch of the dyad solving ``point`` set explicitly: ``s`` = ±1
        (sign det[A − D, e, B − D]), or the paper's ``w`` of eq. (21), converted by
        s = W·sign(V3_X) with V3 = (A − D) × e at the sketch input (SpecError where V3_X = 0)."""
        steps = list(self.steps)
        for i, st in enumerate(steps):
            if st.kind == "RSS" and st.key_point == point:
                if (s is None) == (w is None):
                    raise SpecError([("branch", "give exactly one of s or w (±1)")])
                if w is not None:
                    if w not in (1, -1):
                        raise SpecError([("branch.w", f"must be +1 or −1: {w!r}")])
                    A, D, e = _sketch_rss_vectors(self, st)
                    v3x = float(np.cross(A - D, e)[0])
                    if abs(v3x) <= 1e-12 * np.linalg.norm(A - D):
                        raise SpecError([("branch.w", f"the paper's W is undefined for '{point}': V3_X = 0 at the "
                                                      "sketch (the rocker axis lies in a plane containing X); give s")])
                    s = int(w * np.sign(v3x))
                if s not in (1, -1):
                    raise SpecError([("branch.s", f"must be +1 or −1: {s!r}")])
                steps[i] = replace(st, branch=int(s))
                return replace(self, steps=tuple(steps))
        raise SpecError([("branch", f"'{point}' is not solved by an R–S–S dyad "
                                    f"(dyad points: {', '.join(s.key_point for s in self.rss_steps())})")])


def _sketch_rss_vectors(plan, st):
    ctx = _run(plan, plan.defaults, [Jet(np.asarray(q)) for q in plan.sketch_inputs], 0, DEFAULT,
               steps=plan.steps[: plan.steps.index(st)])
    A = np.asarray(V.value(ctx.pos[st.data[1]]), dtype=float)
    D = np.asarray(V.value(ctx.pos[st.data[0]]), dtype=float)
    e = np.asarray(ctx.frame_of(st.data[0])[..., :, 2], dtype=float)
    return A, D, e


# -- compile -------------------------------------------------------------------------------------------
def _vec(t):
    return np.asarray(t, dtype=float)


def _unit(v):
    return v / np.linalg.norm(v)


class _Builder:
    def __init__(self, m: Mechanism):
        self.m = m
        self.names: list[str] = []
        self.values: list[float] = []
        self.problems: list[tuple[str, str]] = []

    def param(self, name, value):
        self.names.append(name)
        self.values.append(float(value))
        return len(self.names) - 1

    def sk(self, p):
        return _vec(self.m.sketch(p))


def _hinge_frame(axis_frame, arm):
    """(u_r, u_t, e) of a link hinged about the axis frame's e_Z2, with its arm vector ``arm``."""
    e = axis_frame[:, 2]
    n = arm - np.dot(arm, e) * e
    u_r = n / np.linalg.norm(n)
    return np.stack([u_r, np.cross(e, u_r), e], axis=-1)


def compile_spatial(m: Mechanism, *, tolerances=DEFAULT) -> SpatialPlan:
    """Compile a dimension-3 mechanism. Raises StructureError (what cannot be solved) or SpecError
    (bad geometry, located: a missing or degenerate axis, a sketch that cannot assemble)."""
    s = analyse(m)
    free = s.mobility - s.idle
    n_drivers = len(m.drivers)
    kinds = {j.point: j.kind for j in m.joints}
    if not any(j.axis is not None for j in m.joints):
        frame_revolutes = [p for p in m.frame.points if kinds.get(p, "revolute") == "revolute"]
        raise StructureError("this spatial description has no joint axes: it is structural only ('assur info' gives "
                             "its mobility); to solve it give each frame revolute its axis: "
                             + ", ".join(f'joints.{p} = {{ kind = "revolute", axis = [x, y, z] }}'
                                         for p in frame_revolutes))
    if free != n_drivers:
        idle = f" − {s.idle} idle spin(s)" if s.idle else ""
        spinning = [lk for lk in m.links if len(lk.points) > 2
                    and sum(kinds.get(p) == "spherical" for p in lk.points) == 2]
        hint = "".join(f"; link {lk.name} spins about the line of its two spherical joints and carries "
                       f"{', '.join(p for p in lk.points if kinds.get(p) != 'spherical')}: make one of those joints "
                       "universal (with the pin's axis)" for lk in spinning)
        raise StructureError(f"mobility W = {s.mobility}{idle} (Somov–Malyshev) = {free} but {n_drivers} driver(s) "
                             f"are given; each degree of freedom needs one driver{hint}")
    axes = {j.point: j.axis for j in m.joints if j.axis is not None}
    B = _Builder(m)
    P = B.problems
    links = [lk for lk in m.links]
    body_names = tuple(lk.name for lk in links)
    body_of = {n: i for i, n in enumerate(body_names)}
    for lk in links:
        if lk.place:
            P.append((f"links.{lk.name}.place", "polar placement is planar; give the point's 3D sketch coordinates"))
    for j in m.joints:
        if j.kind not in ("revolute", "spherical", "universal"):
            P.append((f"joints.{j.point}", f"{j.kind} joints are not solved by the spatial engine "
                                           "(revolute, spherical and universal are)"))
        if j.kind == "spherical" and j.axis is not None:
            P.append((f"joints.{j.point}.axis", "a spherical joint has no axis"))
    for pr in m.prismatic:
        P.append((f"prismatic.{pr.name}", "prismatic pairs are not solved by the spatial engine"))
    for ac in m.actuators:
        P.append((f"actuators.{ac.name}", "actuators are not solved by the spatial engine"))
    if P:
        raise SpecError(P)
    frame = m.frame
    known: set[str] = set()
    steps: list[SpatialStep] = []
    rec = []
    for p in frame.points:
        x, y, z = B.sk(p)
        rec.append((p, B.param(f"{p}.x", x), B.param(f"{p}.y", y), B.param(f"{p}.z", z)))
        known.add(p)
    steps.append(SpatialStep("frame", 0, data=tuple(rec)))
    axis_params: dict[str, tuple[int, int]] = {}

    def axis_of(point, path):
        """Parameter indices (γ1, γ2) of the revolute axis at a frame point; None with a problem logged."""
        if point in axis_params:
            return axis_params[point]
        if kinds.get(point, "revolute") != "revolute":
            P.append((path, f"'{point}' must be a revolute joint with an axis (it is {kinds[point]})"))
            return None
        if point not in axes:
            P.append((f"joints.{point}", "a revolute of a spatial mechanism needs an axis: "
                                         f"{point} = {{ kind = \"revolute\", axis = [x, y, z] }}"))
            return None
        g1, g2 = V.axis_angles(_vec(axes[point]))
        axis_params[point] = (B.param(f"{point}.axis.gamma1", float(g1)), B.param(f"{point}.axis.gamma2", float(g2)))
        return axis_params[point]

    def axis_matrix(point):
        i1, i2 = axis_params[point]
        return V.axis_frame(B.values[i1], B.values[i2])

    def further_points(lk, skip, frame_mat, origin):
        out = []
        for p in lk.points:
            if p in skip:
                continue
            u, v, w = frame_mat.T @ (B.sk(p) - origin)
            out.append((p, B.param(f"{lk.name}.{p}.u", u), B.param(f"{lk.name}.{p}.v", v),
                        B.param(f"{lk.name}.{p}.w", w)))
        return tuple(out)

    def first_two_length(lk, a, b):
        if lk.length is not None and set(lk.points[:2]) == {a, b}:
            return lk.length
        return float(np.linalg.norm(B.sk(b) - B.sk(a)))

    placed: set[int] = {0}
    hinge_local: dict[int, np.ndarray] = {}     # sketch hinge frame of every hinged body
    body_frames: list = [None] * len(links)
    body_frames[0] = ("frame",)
    input_names, input_kinds, sketch_inputs, speeds = [], [], [], []
    point_body: dict[str, int] = {p: 0 for p in frame.points}
    for k, d in enumerate(m.drivers):
        path = f"drivers[{k}]"
        if d.kind != "rotary":
            P.append((path, "the spatial engine is driven by cranks (rotary drivers)"))
            continue
        bi = body_of[d.link]
        lk = links[bi]
        if axis_of(d.pivot, f"{path}.pivot") is None:
            continue
        E = axis_matrix(d.pivot)
        arm = B.sk(d.arm) - B.sk(d.pivot)
        length = first_two_length(lk, d.pivot, d.arm)
        h = float(np.dot(arm, E[:, 2]))
        rho2 = length * length - h * h
        if not rho2 > (1e-9 * length) ** 2:
            P.append((f"links.{lk.name}", f"the arm {d.arm} lies on the axis of {d.pivot}: the crank would not move it"))
            continue
        il = B.param(f"{lk.name}.length", length)
        ih = B.param(f"{lk.name}.axial", h)
        iz = B.param(f"{d.name}.zero", d.zero)
        theta_sk = math.atan2(float(arm @ E[:, 1]), float(arm @ E[:, 0]))
        sketch_inputs.append((d.sense * (theta_sk - d.zero)) % (2 * math.pi))
        input_names.append(d.name)
        input_kinds.append("rotary")
        speeds.append(d.speed)
        F = _hinge_frame(E, arm)
        hinge_local[bi] = F
        extra = further_points(lk, {d.pivot, d.arm}, F, B.sk(d.pivot))
        steps.append(SpatialStep("crank", bi, data=(d.pivot, d.arm, k, il, ih, iz, d.sense, extra)))
        body_frames[bi] = ("hinged", d.pivot, d.arm)
        placed.add(bi)
        known |= set(lk.points)
        for p in lk.points:
            point_body.setdefault(p, bi)
    if P:
        raise SpecError(P)
    # R–S–S dyads: a rocker hinged on the frame + a coupler from a known point
    progress = True
    while progress:
        progress = False
        for ri, rocker in enumerate(links):
            if ri in placed:
                continue
            hinges = [p for p in rocker.points if p in frame.points]
            if len(hinges) != 1:
                continue
            D = hinges[0]
            for ci, coupler in enumerate(links):
                if ci in placed or ci == ri:
                    continue
                common = [p for p in rocker.points if p in coupler.points and p != D]
                starts = [p for p in coupler.points if p in known and p not in rocker.points]
                if len(common) != 1 or len(starts) != 1:
                    continue
                Bp, Ap = common[0], starts[0]
                path = f"links.{coupler.name}"
                for p in (Ap, Bp):
                    if kinds.get(p, "revolute") not in ("spherical", "universal"):
                        P.append((f"joints.{p}", f"the coupler {coupler.name}'s end {p} must be a spherical or "
                                                 f"universal joint in an R–S–S dyad (it is {kinds.get(p, 'revolute')})"))
                if axis_of(D, f"links.{rocker.name}") is None or P:
                    raise SpecError(P)
                E = axis_matrix(D)
                arm = B.sk(Bp) - B.sk(D)
                lr = first_two_length(rocker, D, Bp)
                h = float(np.dot(arm, E[:, 2]))
                if not lr * lr - h * h > (1e-9 * lr) ** 2:
                    raise SpecError([(f"links.{rocker.name}", f"the point {Bp} lies on the axis of {D}: "
                                                              "the rocker arm is parallel to its axis")])
                lc = first_two_length(coupler, Ap, Bp)
                ilr = B.param(f"{rocker.name}.length", lr)
                ihr = B.param(f"{rocker.name}.axial", h)
                ilc = B.param(f"{coupler.name}.length", lc)
                F = _hinge_frame(E, arm)
                hinge_local[ri] = F
                r_extra = further_points(rocker, {D, Bp}, F, B.sk(D))
                # the coupler's frame: a universal joint at one end, pin fixed in the other side's link
                uj = [p for p in (Ap, Bp) if kinds.get(p) == "universal"]
                c_extra = ()
                if uj:
                    U = uj[0]
                    other = Bp if U == Ap else Ap
                    pin_body = point_body.get(U) if U == Ap else ri
                    pin = axes.get(U)
                    if pin is None:
                        raise SpecError([(f"joints.{U}", "a universal joint needs the axis of its pin on the crank "
                                                         "side: { kind = \"universal\", axis = [x, y, z] }")])
                    ex = _unit(B.sk(U) - B.sk(other))
                    n = np.cross(_vec(pin), ex)
                    if np.linalg.norm(n) <= 1e-9:
                        raise SpecError([(f"joints.{U}.axis", f"the pin axis is parallel to the coupler {coupler.name} "
                                                              "in the sketch: its frame (29) is undetermined")])
                    ez = _unit(n)
                    Cm = np.stack([ex, np.cross(ez, ex), ez], axis=-1)
                    if pin_body not in hinge_local:
                        raise SpecError([(f"joints.{U}", "the pin of a universal joint must be on a hinged link "
                                                         "(a crank or a rocker)")])
                    pin_local = hinge_local[pin_body].T @ _vec(pin)
                    c_extra = further_points(coupler, {Ap, Bp}, Cm, B.sk(U))
                    body_frames[ci] = ("coupler", U, other, pin_body, tuple(float(c) for c in pin_local))
                else:
                    if len(coupler.points) > 2:
                        raise SpecError([(path, f"the points {', '.join(p for p in coupler.points if p not in (Ap, Bp))}"
                                                f" of a coupler between two spherical joints are undetermined (it "
                                                f"spins idly about {Ap}–{Bp}); make {Ap} a universal joint "
                                                f"with the crank pin's axis")])
                    body_frames[ci] = ("idle", Ap, Bp)
                body_frames[ri] = ("hinged", D, Bp)
                steps.append(SpatialStep("RSS", ri, key_point=Bp, data=(D, Ap, Bp, ci, ilr, ihr, ilc, r_extra,
                                                                        c_extra)))
                placed |= {ri, ci}
                known |= set(rocker.points) | set(coupler.points)
                for p in rocker.points:
                    point_body.setdefault(p, ri)
                for p in coupler.points:
                    point_body.setdefault(p, ci)
                progress = True
                break
            if progress:
                break
    if P:
        raise SpecError(P)
    left = [links[i].name for i in range(len(links)) if i not in placed]
    if left:
        raise StructureError(f"the spatial engine cannot solve the links {', '.join(left)}: it solves a crank "
                             "turning about a frame revolute followed by R–S–S dyads (a rocker hinged on the frame "
                             "and a coupler with spherical or universal ends)")
    plan = SpatialPlan(
        mechanism=m, structure=s, steps=tuple(steps), param_names=tuple(B.names),
        defaults=np.array(B.values, dtype=float), point_names=m.point_names, body_names=body_names,
        input_names=tuple(input_names), input_kinds=tuple(input_kinds),
        sketch_inputs=np.array(sketch_inputs, dtype=float), speeds=np.array(speeds, dtype=float),
        point_body=tuple(point_body[p] for p in m.point_names), length_scale=m.length_scale,
        body_frames=tuple(body_frames))
    plan.defaults.setflags(write=False)
    return _fix_branches(plan, tolerances)


def _fix_branches(plan: SpatialPlan, tol) -> SpatialPlan:
    """Each dyad's branch s = sign det[A − D, e, B − D] from the sketch, once."""
    steps = list(plan.steps)
    q0 = [Jet(np.asarray(q)) for q in plan.sketch_inputs]
    for i, st in enumerate(steps):
        if st.kind != "RSS":
            continue
        D, Ap, Bp = st.data[:3]
        ctx = _run(plan, plan.defaults, q0, 0, tol, steps=steps[:i])
        A = np.asarray(V.value(ctx.pos[Ap]), dtype=float)
        Dv = np.asarray(V.value(ctx.pos[D]), dtype=float)
        e = np.asarray(ctx.frame_of(D)[..., :, 2], dtype=float)
        Bs = _vec(plan.mechanism.sketch(Bp))
        v1 = A - Dv
        if np.linalg.norm(np.cross(v1, e)) <= tol.parallel * np.linalg.norm(v1):
            raise SpecError([(f"points.{Ap}", f"{Ap} lies on the axis line of {D} in the sketch: the dyad solving "
                                              f"{Bp} is undetermined there (V1 ∥ V2); move the sketch")])
        trial = []
        for sgn in (1, -1):
            steps[i] = replace(st, branch=sgn)
            c2 = _run(plan, plan.defaults, q0, 0, tol, steps=steps[: i + 1])
            trial.append((sgn, np.asarray(V.value(c2.pos[Bp])), bool(np.all(c2.valid))))
        ok = [t for t in trial if t[2]]
        if not ok:
            raise SpecError([(f"points.{Bp}", f"the dyad solving '{Bp}' cannot be assembled in the sketch position "
                                              "(check the link lengths, the axes and the sketch)")])
        dev = [np.linalg.norm(t[1] - Bs) for t in ok]
        if len(ok) == 2 and abs(dev[0] - dev[1]) <= tol.branch_separation * plan.length_scale:
            raise SpecError([(f"points.{Bp}", f"the sketch does not tell the assembly branch of '{Bp}' (both branches "
                                              "are equally near: it lies in the plane of the rocker axis and the "
                                              "coupler's other end); move it off that plane")])
        steps[i] = replace(st, branch=ok[int(np.argmin(dev))][0])
    return replace(plan, steps=tuple(steps))


# -- solve ---------------------------------------------------------------------------------------------
class _Context:
    def __init__(self, plan, params, q, order, tol):
        self.plan, self.params, self.q, self.order, self.tol = plan, params, q, order, tol
        self.pos: dict[str, object] = {}
        self.axis: dict[str, np.ndarray] = {}
        self.axis_frame: dict[str, np.ndarray] = {}
        self.frames: dict[int, tuple] = {}
        self.valid = np.True_
        self.status: list[tuple[str, np.ndarray]] = []

    def p(self, i):
        return self.params[..., i]

    def frame_of(self, point):
        if point not in self.axis_frame:
            i1 = self.plan.param_index(f"{point}.axis.gamma1")
            i2 = self.plan.param_index(f"{point}.axis.gamma2")
            E = V.axis_frame(self.p(i1), self.p(i2))
            self.axis_frame[point] = E
            self.axis[point] = E[..., :, 2]
        return self.axis_frame[point]

    def place_extra(self, origin, frame, extra):
        ex, ey, ez = frame
        for name, iu, iv, iw in extra:
            self.pos[name] = origin + V.scale(self.p(iu), ex) + V.scale(self.p(iv), ey) + V.scale(self.p(iw), ez)


def _frame(c: _Context, st):
    for name, ix, iy, iz in st.data:
        c.pos[name] = np.stack([c.p(ix), c.p(iy), c.p(iz)], axis=-1)
    eye = np.eye(3)
    c.frames[0] = (eye[:, 0], eye[:, 1], eye[:, 2])


def _crank(c: _Context, st):
    pivot, arm, k, il, ih, iz, sense, extra = st.data
    E = c.frame_of(pivot)
    ex2, ey2, e = E[..., :, 0], E[..., :, 1], E[..., :, 2]
    theta = c.q[k] * float(sense) + c.p(iz)
    cs, sn = V.cos(theta), V.sin(theta)
    u_r = V.scale(cs, ex2) + V.scale(sn, ey2)
    u_t = V.scale(-1.0 * sn, ex2) + V.scale(cs, ey2)
    length, h = c.p(il), c.p(ih)
    rho = np.sqrt(np.maximum(length * length - h * h, 0.0))
    O = c.pos[pivot]
    c.pos[arm] = O + V.scale(rho, u_r) + V.scale(h, e)
    c.frames[st.body] = (u_r, u_t, e)
    c.place_extra(O, c.frames[st.body], extra)


def _rss(c: _Context, st):
    D, Ap, Bp, ci, ilr, ihr, ilc, r_extra, c_extra = st.data
    E = c.frame_of(D)
    e = E[..., :, 2]
    Dv, A = c.pos[D], c.pos[Ap]
    lr, h, lc = c.p(ilr), c.p(ihr), c.p(ilc)
    v1 = A - Dv                                             # (7) P4_2 = P2 − P4
    d2 = V.dot(v1, v1)
    d = V.sqrt(d2)
    cos_a1 = (d2 + (lr * lr - lc * lc)) * V.reciprocal(d * (2.0 * lr))   # (23) cos α1
    cos_a2 = h / lr                                          # cos α2
    e43, status = V.unit_vector(v1, e, cos_a1, cos_a2, st.branch, parallel_tol=c.tol.parallel,
                                disc_tol=c.tol.radicand)    # (22)
    c.valid = c.valid & V.assembled(status)
    c.status.append((Bp, status))
    Bv = Dv + V.scale(lr, e43)                               # (24), (25)
    c.pos[Bp] = Bv
    u_r = V.ort(e43 - V.scale(V.dot(e43, e), e))
    c.frames[st.body] = (u_r, V.cross(e, u_r), e)
    c.place_extra(Dv, c.frames[st.body], r_extra)
    kind = c.plan.body_frames[ci]
    if kind[0] == "coupler":
        _, U, other, pin_body, pin_local = kind
        fr = c.frames[pin_body]
        pin = V.scale(pin_local[0], fr[0]) + V.scale(pin_local[1], fr[1]) + V.scale(pin_local[2], fr[2])
        ex = V.ort(c.pos[U] - c.pos[other])                  # (27)
        ez = V.ort(V.cross(pin, ex))                         # (29), β1 = β2 = 90°, Wp = +1
        ey = V.cross(ez, ex)                                 # (30)
        c.frames[ci] = (ex, ey, ez)
        c.place_extra(c.pos[U], c.frames[ci], c_extra)
    else:
        nan = np.full(3, np.nan)
        c.frames[ci] = (nan, nan, nan)


_EXEC = {"frame": _frame, "crank": _crank, "RSS": _rss}


def _run(plan, params, q, order, tol, steps=None, method="closed", seeds=None):
    c = _Context(plan, params, q, order, tol)
    with np.errstate(all="ignore"):
        for st in (plan.steps if steps is None else steps):
            if method == "newton" and st.kind == "RSS":
                _rss_newton(c, st, seeds)
            else:
                _EXEC[st.kind](c, st)
    return c


# -- the Newton loop-closure oracle ---------------------------------------------------------------------
def _rss_newton(c: _Context, st, seeds):
    """B from the loop-closure equations (B − D)·e = h, |B − D|² = l_r², |B − A|² = l_c² by Newton,
    warm-started from ``seeds[B]`` (the previous continuation stage); its derivatives by implicit
    differentiation (spec 003 §6): J·B' = (0, 0, (B − A)·A'), J·B'' = (0, −|B'|², (B − A)·A'' − |B' − A'|²),
    J = [eᵀ; (B − D)ᵀ; (B − A)ᵀ]."""
    D, Ap, Bp, ci, ilr, ihr, ilc, r_extra, c_extra = st.data
    E = c.frame_of(D)
    e = E[..., :, 2]
    Dv = np.asarray(c.pos[D])
    Aj = c.pos[Ap]
    A = V.value(Aj)
    lr, h, lc = c.p(ilr), c.p(ihr), c.p(ilc)
    shape = np.broadcast_shapes(A.shape, Dv.shape, e.shape)
    x = np.array(np.broadcast_to(seeds[Bp], shape), dtype=float)
    x, ok = V.newton_rss(A, Dv, e, lr, h, lc, x, tol=c.tol.newton_residual * c.plan.length_scale,
                         iterations=c.tol.newton_iterations)
    seeds[Bp] = x
    c.valid = c.valid & ok
    Bv = np.where(ok[..., None], x, np.nan)
    J = np.stack([np.broadcast_to(e, shape), Bv - Dv, Bv - A], axis=-2)
    if isinstance(Aj, Jet) and Aj.d is not None:
        Ad = Aj.d
        rhs = np.stack([np.zeros(shape[:-1]), np.zeros(shape[:-1]), np.sum((Bv - A) * Ad, -1)], -1)
        with np.errstate(all="ignore"):
            Bd = np.linalg.solve(J, rhs[..., None])[..., 0]
            Bdd = None
            if Aj.dd is not None:
                rhs2 = np.stack([np.zeros(shape[:-1]), -np.sum(Bd * Bd, -1),
                                 np.sum((Bv - A) * Aj.dd, -1) - np.sum((Bd - Ad) ** 2, -1)], -1)
                Bdd = np.linalg.solve(J, rhs2[..., None])[..., 0]
        Bj = Jet(Bv, Bd, Bdd)
    else:
        Bj = Bv
    c.pos[Bp] = Bj
    e43 = V.scale(1.0 / lr, Bj - Dv)
    u_r = V.ort(e43 - V.scale(V.dot(e43, e), e))
    c.frames[st.body] = (u_r, V.cross(e, u_r), e)
    c.place_extra(Dv, c.frames[st.body], r_extra)
    kind = c.plan.body_frames[ci]
    if kind[0] == "coupler":
        _, U, other, pin_body, pin_local = kind
        fr = c.frames[pin_body]
        pin = V.scale(pin_local[0], fr[0]) + V.scale(pin_local[1], fr[1]) + V.scale(pin_local[2], fr[2])
        ex = V.ort(c.pos[U] - c.pos[other])
        ez = V.ort(V.cross(pin, ex))
        c.frames[ci] = (ex, V.cross(ez, ex), ez)
        c.place_extra(c.pos[U], c.frames[ci], c_extra)
    else:
        nan = np.full(3, np.nan)
        c.frames[ci] = (nan, nan, nan)


def _execute_newton(plan, params, q, order, tol):
    """Continue every sample from the sketch input to its own in stages of at most 10° of crank,
    Newton warm-started from the previous stage (the first from the sketch)."""
    seeds = {st.key_point: _vec(plan.mechanism.sketch(st.key_point)) for st in plan.steps if st.kind == "RSS"}
    q_s = plan.sketch_inputs
    deltas = [(np.asarray(qj.v, dtype=float) - q_s[k] + np.pi) % (2 * np.pi) - np.pi for k, qj in enumerate(q)]
    finite = [np.abs(d[np.isfinite(d)]) for d in deltas]
    m = max([int(np.ceil(f.max() / tol.stage_angle)) if f.size else 1 for f in finite] + [1])
    dp = params - plan.defaults
    moved = bool(np.any(dp != 0))
    if moved:
        m = max(m, tol.stages_for_new_design)
    for i in range(1, m):
        t = i / m
        q_stage = [Jet(q_s[k] + t * deltas[k]) for k in range(len(q))]
        _run(plan, plan.defaults + t * dp if moved else params, q_stage, 0, tol, method="newton", seeds=seeds)
    q_final = [Jet(q_s[k] + deltas[k], qj.d, qj.dd) for k, qj in enumerate(q)]
    return _run(plan, params, q_final, order, tol, method="newton", seeds=seeds)


# -- the state -------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SpatialState:
    """The solved state of a spatial batch. Shapes: ``pos``, ``vel``, ``acc`` (..., n_points, 3);
    ``dpos_dq`` (..., n_points, 3, n_inputs); ``d2pos_dq2`` (..., n_points, 3, n_inputs, n_inputs);
    ``valid`` (...); ``body_frame`` (..., n_bodies, 3, 3) with columns the body's unit axes (NaN for
    a coupler that spins idly); ``body_omega``, ``body_alpha`` (..., n_bodies, 3) angular velocity
    and acceleration vectors; ``status`` maps each dyad point to its solver status (...)."""
    plan: SpatialPlan
    inputs: np.ndarray
    valid: np.ndarray
    n_unbuildable: int
    qdot: np.ndarray
    qddot: np.ndarray
    pos: np.ndarray
    dpos_dq: np.ndarray | None
    d2pos_dq2: np.ndarray | None
    body_frame: np.ndarray
    dframe_dq: np.ndarray | None = field(repr=False, default=None)
    d2frame_dq2: np.ndarray | None = field(repr=False, default=None)
    status: dict = field(repr=False, default_factory=dict)
    dimension: int = 3

    @property
    def shape(self):
        return self.valid.shape

    @property
    def vel(self):
        if self.dpos_dq is None:
            return None
        return np.einsum("...k,...k->...", self.dpos_dq, self.qdot)

    @property
    def acc(self):
        if self.d2pos_dq2 is None:
            return None
        return (np.einsum("...k,...k->...", self.dpos_dq, self.qddot)
                + np.einsum("...kl,...k,...l->...", self.d2pos_dq2, self.qdot, self.qdot))

    def _frame_rate(self, d1, d2=None):
        R = self.body_frame
        # ω× = R'Rᵀ; α× = the skew part of R''Rᵀ (R'R'ᵀ is symmetric)
        W = (d1 if d2 is None else d2) @ np.swapaxes(R, -1, -2)
        return np.stack([W[..., 2, 1] - W[..., 1, 2], W[..., 0, 2] - W[..., 2, 0], W[..., 1, 0] - W[..., 0, 1]],
                        axis=-1) * 0.5

    @property
    def body_omega(self):
        """(..., n_bodies, 3) angular velocity vectors (rad/s): ω× = R'Rᵀ."""
        if self.dframe_dq is None:
            return None
        d1 = np.einsum("...ijk,...k->...ij", self.dframe_dq, self.qdot)
        return self._frame_rate(d1)

    @property
    def body_alpha(self):
        """(..., n_bodies, 3) angular acceleration vectors (rad/s²): the skew part of R''Rᵀ."""
        if self.d2frame_dq2 is None:
            return None
        d1 = np.einsum("...ijk,...k->...ij", self.dframe_dq, self.qddot)
        d2 = np.einsum("...ijkl,...k,...l->...ij", self.d2frame_dq2, self.qdot, self.qdot) + d1
        return self._frame_rate(None, d2)

    def point(self, name: str) -> "SpatialPointView":
        return SpatialPointView(self, self.plan.point_index(name))

    def body(self, name: str) -> int:
        return self.plan.body_names.index(name)


@dataclass(frozen=True)
class SpatialPointView:
    state: SpatialState
    index: int

    pos = property(lambda self: self.state.pos[..., self.index, :])
    vel = property(lambda self: None if self.state.vel is None else self.state.vel[..., self.index, :])
    acc = property(lambda self: None if self.state.acc is None else self.state.acc[..., self.index, :])
    dpos_dq = property(lambda self: None if self.state.dpos_dq is None else self.state.dpos_dq[..., self.index, :, :])
    d2pos_dq2 = property(lambda self: None if self.state.d2pos_dq2 is None
                         else self.state.d2pos_dq2[..., self.index, :, :, :])


def _prepare(plan, params, inputs):
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    if params.ndim == 0 or params.shape[-1] != plan.n_params:
        raise SpecError([("params", f"must have a trailing axis of {plan.n_params} parameters "
                                    f"({', '.join(plan.param_names)}): shape {params.shape}")])
    inputs = plan.sketch_inputs if inputs is None else np.asarray(inputs, dtype=float)
    if plan.n_inputs == 1 and (inputs.ndim <= 1 or inputs.shape[-1] != 1):
        inputs = inputs[..., None]
    if inputs.shape[-1] != plan.n_inputs:
        raise SpecError([("inputs", f"must have a trailing axis of {plan.n_inputs} inputs "
                                    f"({', '.join(plan.input_names)}): shape {inputs.shape}")])
    return params, inputs


def solve_spatial(plan: SpatialPlan, params=None, inputs=None, *, speeds=None, accels=None, order: int = 2,
                  on_unbuildable: str = "nan", method: str = "closed", tolerances=DEFAULT) -> SpatialState:
    """Solve a spatial plan: see :func:`assur.solve` (same arguments; ``method='newton'`` is the
    loop-closure oracle). Unassemblable samples are NaN with ``valid`` False."""
    from .solve import check_options
    check_options(on_unbuildable, method, order)
    params, inputs = _prepare(plan, params, inputs)
    shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    n = plan.n_inputs
    names = plan.point_names
    nb = len(plan.body_names)

    def run(direction):
        q = [Jet(inputs[..., k], np.full(inputs.shape[:-1], float(direction[k])) if order >= 1 else None,
                 np.zeros(inputs.shape[:-1]) if order >= 2 else None) for k in range(n)]
        if method == "newton":
            return _execute_newton(plan, params, q, order, tolerances)
        return _run(plan, params, q, order, tolerances)

    def part(x, attr):
        if isinstance(x, Jet):
            y = getattr(x, attr)
            return y if y is not None else np.zeros_like(x.v)
        return np.asarray(x, dtype=float) if attr == "v" else np.zeros_like(np.asarray(x, dtype=float))

    def stack(ctx, attr):
        pts = np.stack([np.broadcast_to(part(ctx.pos[p], attr), shape + (3,)) for p in names], axis=-2)
        frames = np.stack([np.stack([np.broadcast_to(part(a, attr), shape + (3,)) for a in ctx.frames[b]], axis=-1)
                           for b in range(nb)], axis=-3)
        return pts, frames

    eye = np.eye(n)
    passes = [run(eye[k]) for k in range(n)] if order >= 1 and n > 0 else [run(np.zeros(n))]
    base = passes[0]
    pos, frames = stack(base, "v")
    valid = np.broadcast_to(base.valid, shape) & np.all(np.isfinite(pos), axis=(-1, -2))
    d1 = d2 = f1 = f2 = None
    if order >= 1:
        s1 = [stack(p, "d") for p in passes]
        d1 = np.stack([s[0] for s in s1], axis=-1)
        f1 = np.stack([s[1] for s in s1], axis=-1)
    if order >= 2:
        d2 = np.empty(pos.shape + (n, n))
        f2 = np.empty(frames.shape + (n, n))
        for i in range(n):
            d2[..., i, i], f2[..., i, i] = stack(passes[i], "dd")
        for i in range(n):
            for j in range(i + 1, n):
                mp, mf = stack(run(eye[i] + eye[j]), "dd")
                d2[..., i, j] = d2[..., j, i] = 0.5 * (mp - d2[..., i, i] - d2[..., j, j])
                f2[..., i, j] = f2[..., j, i] = 0.5 * (mf - f2[..., i, i] - f2[..., j, j])
    inv = ~valid
    if inv.any():
        for a in (pos, frames, d1, d2, f1, f2):
            if a is not None:
                a[inv] = np.nan
    status = {p: np.broadcast_to(s, shape) for p, s in base.status}
    n_bad = int(np.count_nonzero(inv))
    full_inputs = np.broadcast_to(inputs, shape + (n,))
    if n_bad and on_unbuildable != "nan":
        msg = unbuildable_message(plan, full_inputs, valid, status)
        if on_unbuildable == "raise":
            raise UnbuildableError(msg, n_bad, int(np.prod(shape)) if shape else 1)
        warnings.warn(msg, UnbuildableWarning, stacklevel=2)
    at_branch = [p for p, s_ in status.items() if np.any((s_ == V.BRANCH_POINT) & valid)]
    if at_branch and on_unbuildable == "warn":
        warnings.warn(f"{', '.join(at_branch)}: some samples are at a branch point (the two assemblies meet, "
                      "μ_T = 0; velocities there are infinite)", UnbuildableWarning, stacklevel=2)
    qdot = plan.speeds if speeds is None else np.asarray(speeds, dtype=float)
    qddot = np.zeros(n) if accels is None else np.asarray(accels, dtype=float)
    if qdot.shape[-1:] != (n,) or qddot.shape[-1:] != (n,):
        raise SpecError([("speeds", f"speeds and accels need a trailing axis of {n} inputs")])
    return SpatialState(plan=plan, inputs=full_inputs, valid=valid, n_unbuildable=n_bad, qdot=qdot, qddot=qddot,
                        pos=pos, dpos_dq=d1, d2pos_dq2=d2, body_frame=frames, dframe_dq=f1, d2frame_dq2=f2,
                        status=status)


def invalid_ranges(q: np.ndarray, valid: np.ndarray) -> list[tuple[float, float]]:
    """Contiguous runs of invalid samples of a sorted 1-D sweep ``q`` (n,): [(first q, last q), ...]."""
    out, start = [], None
    for i, ok in enumerate(valid):
        if not ok and start is None:
            start = i
        if ok and start is not None:
            out.append((float(q[start]), float(q[i - 1])))
            start = None
    if start is not None:
        out.append((float(q[start]), float(q[-1])))
    return out


def unbuildable_message(plan, inputs, valid, status) -> str:
    """'k of n samples cannot be assembled (…): the dyad solving B: crank 100°…140°; …'."""
    n_bad = int(np.count_nonzero(~valid))
    total = valid.size
    head = f"{n_bad} of {total} samples cannot be assembled"
    parts = []
    if valid.ndim == 1 and plan.n_inputs == 1:
        q = inputs[..., 0]
        order = np.argsort(q, kind="stable")
        for point, st in status.items():
            failed = ~V.assembled(st)
            bad = failed[order]
            if not bad.any():
                continue
            why = sorted({V.STATUS_TEXT[int(k)] for k in np.unique(st[failed])})
            rng = ", ".join(f"{math.degrees(a):.4g}°…{math.degrees(b):.4g}°"
                            for a, b in invalid_ranges(q[order], ~bad))
            parts.append(f"the dyad solving {point} ({'; '.join(why)}) at {plan.input_names[0]} {rng}")
    else:
        flat = inputs.reshape(-1, plan.n_inputs)[~valid.reshape(-1)]
        parts.append("first at " + ", ".join(f"{plan.input_names[k]}={math.degrees(flat[0, k]):.6g}°"
                                              for k in range(plan.n_inputs)))
    return head + (": " + "; ".join(parts) if parts else "") + "; they are NaN with valid=False"
