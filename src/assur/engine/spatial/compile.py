"""Compile a spatial (dimension = 3) mechanism into a :class:`~assur.engine.plan.SpatialPlan`: a
crank turning about a frame revolute, then the R–S–S dyads that :mod:`assur.structure.spatial`
found, each with its branch s = sign det[A − D, e, B − D] fixed once from the sketch.

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
from dataclasses import replace

import numpy as np

from ...errors import SpecError, StructureError
from ...kernels import spatial as V
from ...kernels.jet import Jet
from ...model.mechanism import Mechanism
from ...structure.assur import analyse
from ...structure.spatial import spatial_dyads
from ...tolerances import DEFAULT
from ..plan import PARAM_KINDS, RSSStep, SpatialCrankStep, SpatialFrameStep, SpatialPlan
from .steps import run


# -- helpers -------------------------------------------------------------------------------------------
def _vec(t):
    return np.asarray(t, dtype=float)


def _unit(v):
    return v / np.linalg.norm(v)


class _Builder:
    """What the steps of a compile share: the parameters made so far (names, sketch values, kinds, in the order
    made: that order is the plan's parameter vector), the located problems, the revolute axes' parameters, and
    what each step learns of the bodies (hinge frames, body frames, the body of each point, the inputs)."""

    def __init__(self, m: Mechanism, tolerances):
        self.m = m
        self.tolerances = tolerances
        self.names: list[str] = []
        self.values: list[float] = []
        self.kinds: list[int] = []
        self.problems: list[tuple[str, str]] = []
        self.joint_kinds = {j.point: j.kind for j in m.joints}
        self.axes = {j.point: j.axis for j in m.joints if j.axis is not None}
        self.axis_params: dict[str, tuple[int, int]] = {}
        self.links = list(m.links)
        self.body_of = {lk.name: i for i, lk in enumerate(self.links)}
        self.hinge_local: dict[int, np.ndarray] = {}     # sketch hinge frame of every hinged body
        self.body_frames: list = [None] * len(self.links)
        self.body_frames[0] = ("frame",)
        self.point_body: dict[str, int] = {p: 0 for p in m.frame.points}
        self.input_names, self.input_kinds, self.sketch_inputs, self.speeds = [], [], [], []

    def param(self, name, value, kind: str = "length"):
        self.names.append(name)
        self.values.append(float(value))
        self.kinds.append(PARAM_KINDS.index(kind))
        return len(self.names) - 1

    def sk(self, p):
        return _vec(self.m.sketch(p))

    def axis_of(self, point, path):
        """Parameter indices (γ1, γ2) of the revolute axis at a frame point; None with a problem logged."""
        if point in self.axis_params:
            return self.axis_params[point]
        if self.joint_kinds.get(point, "revolute") != "revolute":
            self.problems.append((path, f"'{point}' must be a revolute joint with an axis (it is "
                                        f"{self.joint_kinds[point]})"))
            return None
        if point not in self.axes:
            self.problems.append((f"joints.{point}", "a revolute of a spatial mechanism needs an axis: "
                                                     f"{point} = {{ kind = \"revolute\", axis = [x, y, z] }}"))
            return None
        g1, g2 = V.axis_angles(_vec(self.axes[point]))
        self.axis_params[point] = (self.param(f"{point}.axis.gamma1", float(g1), "angle"),
                                   self.param(f"{point}.axis.gamma2", float(g2), "angle"))
        return self.axis_params[point]

    def axis_matrix(self, point):
        """The sketch axis frame (e_X2, e_Y2, e_Z2) (3, 3) of the revolute at ``point`` (its axis made)."""
        i1, i2 = self.axis_params[point]
        return V.axis_frame(self.values[i1], self.values[i2])

    def further_points(self, lk, skip, frame_mat, origin):
        """The points of ``lk`` other than ``skip`` as local-coordinate parameters (u, v, w) in ``frame_mat``."""
        out = []
        for p in lk.points:
            if p in skip:
                continue
            u, v, w = frame_mat.T @ (self.sk(p) - origin)
            out.append((p, self.param(f"{lk.name}.{p}.u", u), self.param(f"{lk.name}.{p}.v", v),
                        self.param(f"{lk.name}.{p}.w", w)))
        return tuple(out)

    def first_two_length(self, lk, a, b):
        """The link's ``length`` when it is the distance a–b of its first two points, else the sketch's."""
        if lk.length is not None and set(lk.points[:2]) == {a, b}:
            return lk.length
        return float(np.linalg.norm(self.sk(b) - self.sk(a)))

    def raise_if_any(self):
        if self.problems:
            raise SpecError(self.problems)


def _hinge_frame(axis_frame, arm):
    """(u_r, u_t, e) of a link hinged about the axis frame's e_Z2, with its arm vector ``arm``."""
    e = axis_frame[:, 2]
    n = arm - np.dot(arm, e) * e
    u_r = n / np.linalg.norm(n)
    return np.stack([u_r, np.cross(e, u_r), e], axis=-1)


def compile_spatial(m: Mechanism, *, tolerances=DEFAULT) -> SpatialPlan:
    """Compile a dimension-3 mechanism. Raises StructureError (what cannot be solved) or SpecError
    (bad geometry, located: a missing or degenerate axis, a sketch that cannot assemble).

    The steps, in turn: check the mobility against the drivers, refuse what the spatial engine does not solve,
    then the frame's points, the cranks and the R–S–S dyads (each adds its parameters and its plan step), the
    plan, and each dyad's branch from the sketch."""
    s = analyse(m)
    _check_drivers_match_mobility(m, s)
    _refuse_unsolved_parts(m)
    B = _Builder(m, tolerances)
    steps = [_frame_step(B)]
    steps += _crank_steps(B)
    steps += _dyad_steps(B, s)
    left = list(s.undetermined)
    if left:
        raise StructureError(f"the spatial engine cannot solve the links {', '.join(left)}: it solves a crank "
                             "turning about a frame revolute followed by R–S–S dyads (a rocker hinged on the frame "
                             "and a coupler with spherical or universal ends)")
    plan = SpatialPlan(
        mechanism=m, structure=s, steps=tuple(steps), param_names=tuple(B.names),
        defaults=np.array(B.values, dtype=float), point_names=m.point_names,
        body_names=tuple(lk.name for lk in B.links),
        input_names=tuple(B.input_names), input_kinds=tuple(B.input_kinds),
        sketch_inputs=np.array(B.sketch_inputs, dtype=float), speeds=np.array(B.speeds, dtype=float),
        point_body=tuple(B.point_body[p] for p in m.point_names), param_kind=np.array(B.kinds),
        length_scale=m.length_scale, body_frames=tuple(B.body_frames))
    return _fix_branches(plan, tolerances)


def _check_drivers_match_mobility(m: Mechanism, s) -> None:
    """StructureError unless the description gives its joint axes and one driver per degree of freedom."""
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


def _refuse_unsolved_parts(m: Mechanism) -> None:
    """One SpecError listing every part the spatial engine does not solve (polar placements, cylindrical
    joints, an axis on a spherical joint, prismatic pairs, actuators)."""
    P = []
    for lk in m.links:
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


def _frame_step(B: _Builder) -> SpatialFrameStep:
    """The frame's points, each with its parameters P.x, P.y, P.z."""
    rec = []
    for p in B.m.frame.points:
        x, y, z = B.sk(p)
        rec.append((p, B.param(f"{p}.x", x), B.param(f"{p}.y", y), B.param(f"{p}.z", z)))
    return SpatialFrameStep(tuple(rec))


def _crank_steps(B: _Builder) -> list[SpatialCrankStep]:
    """One step per rotary driver: its link turning about a frame revolute; SpecError listing every problem."""
    steps = []
    for k, d in enumerate(B.m.drivers):
        path = f"drivers[{k}]"
        if d.kind != "rotary":
            B.problems.append((path, "the spatial engine is driven by cranks (rotary drivers)"))
            continue
        bi = B.body_of[d.link]
        lk = B.links[bi]
        if B.axis_of(d.pivot, f"{path}.pivot") is None:
            continue
        E = B.axis_matrix(d.pivot)
        arm = B.sk(d.arm) - B.sk(d.pivot)
        length = B.first_two_length(lk, d.pivot, d.arm)
        h = float(np.dot(arm, E[:, 2]))
        rho2 = length * length - h * h
        if not rho2 > (B.tolerances.axis_offset * length) ** 2:
            B.problems.append((f"links.{lk.name}", f"the arm {d.arm} lies on the axis of {d.pivot}: the crank "
                                                   "would not move it"))
            continue
        il = B.param(f"{lk.name}.length", length)
        ih = B.param(f"{lk.name}.axial", h)
        iz = B.param(f"{d.name}.zero", d.zero, "angle")
        theta_sk = math.atan2(float(arm @ E[:, 1]), float(arm @ E[:, 0]))
        B.sketch_inputs.append((d.sense * (theta_sk - d.zero)) % (2 * math.pi))
        B.input_names.append(d.name)
        B.input_kinds.append("rotary")
        B.speeds.append(d.speed)
        F = _hinge_frame(E, arm)
        B.hinge_local[bi] = F
        extra = B.further_points(lk, {d.pivot, d.arm}, F, B.sk(d.pivot))
        steps.append(SpatialCrankStep(bi, d.pivot, d.arm, k, il, ih, iz, d.sense, extra))
        B.body_frames[bi] = ("hinged", d.pivot, d.arm)
        for p in lk.points:
            B.point_body.setdefault(p, bi)
    B.raise_if_any()
    return steps


def _dyad_steps(B: _Builder, s) -> list[RSSStep]:
    """One step per R–S–S dyad, in the order the structure found them."""
    dyads = {(dy.rocker, dy.coupler): (dy.pivot, dy.start, dy.joint) for dy in spatial_dyads(B.m, s.graph)[0]}
    steps = []
    for dy in s.groups:
        steps.append(_dyad_step(B, dy.bodies, *dyads[dy.bodies]))
    B.raise_if_any()
    return steps


def _dyad_step(B: _Builder, bodies, D, Ap, Bp) -> RSSStep:
    """The dyad of the rocker hinged at D (joint Bp) and the coupler Ap–Bp: its parameters, its links' frames."""
    ri, ci = bodies
    rocker, coupler = B.links[ri], B.links[ci]
    kinds, tolerances = B.joint_kinds, B.tolerances
    for p in (Ap, Bp):
        if kinds.get(p, "revolute") not in ("spherical", "universal"):
            B.problems.append((f"joints.{p}", f"the coupler {coupler.name}'s end {p} must be a spherical or universal "
                                              f"joint in an R–S–S dyad (it is {kinds.get(p, 'revolute')})"))
    if B.axis_of(D, f"links.{rocker.name}") is None or B.problems:
        raise SpecError(B.problems)
    E = B.axis_matrix(D)
    arm = B.sk(Bp) - B.sk(D)
    lr = B.first_two_length(rocker, D, Bp)
    h = float(np.dot(arm, E[:, 2]))
    if not lr * lr - h * h > (tolerances.axis_offset * lr) ** 2:
        raise SpecError([(f"links.{rocker.name}", f"the point {Bp} lies on the axis of {D}: "
                                                  "the rocker arm is parallel to its axis")])
    lc = B.first_two_length(coupler, Ap, Bp)
    ilr = B.param(f"{rocker.name}.length", lr)
    ihr = B.param(f"{rocker.name}.axial", h)
    ilc = B.param(f"{coupler.name}.length", lc)
    F = _hinge_frame(E, arm)
    B.hinge_local[ri] = F
    r_extra = B.further_points(rocker, {D, Bp}, F, B.sk(D))
    c_extra = _coupler_frame(B, ri, ci, coupler, Ap, Bp)
    B.body_frames[ri] = ("hinged", D, Bp)
    for p in rocker.points:
        B.point_body.setdefault(p, ri)
    for p in coupler.points:
        B.point_body.setdefault(p, ci)
    return RSSStep(ri, D, Ap, Bp, ci, ilr, ihr, ilc, r_extra, c_extra)


def _coupler_frame(B: _Builder, ri, ci, coupler, Ap, Bp) -> tuple:
    """The coupler's frame (a universal joint at one end, its pin fixed in the other side's link; idle between two
    spherical joints) recorded in ``B.body_frames``; its further points' parameters."""
    uj = [p for p in (Ap, Bp) if B.joint_kinds.get(p) == "universal"]
    if not uj:
        if len(coupler.points) > 2:
            raise SpecError([(f"links.{coupler.name}",
                              f"the points {', '.join(p for p in coupler.points if p not in (Ap, Bp))}"
                              f" of a coupler between two spherical joints are undetermined (it "
                              f"spins idly about {Ap}–{Bp}); make {Ap} a universal joint "
                              f"with the crank pin's axis")])
        B.body_frames[ci] = ("idle", Ap, Bp)
        return ()
    U = uj[0]
    other = Bp if U == Ap else Ap
    pin_body = B.point_body.get(U) if U == Ap else ri
    pin = B.axes.get(U)
    if pin is None:
        raise SpecError([(f"joints.{U}", "a universal joint needs the axis of its pin on the crank "
                                         "side: { kind = \"universal\", axis = [x, y, z] }")])
    ex = _unit(B.sk(U) - B.sk(other))
    n = np.cross(_vec(pin), ex)
    if np.linalg.norm(n) <= B.tolerances.axis_offset:
        raise SpecError([(f"joints.{U}.axis", f"the pin axis is parallel to the coupler {coupler.name} "
                                              "in the sketch: its frame (29) is undetermined")])
    ez = _unit(n)
    Cm = np.stack([ex, np.cross(ez, ex), ez], axis=-1)
    if pin_body not in B.hinge_local:
        raise SpecError([(f"joints.{U}", "the pin of a universal joint must be on a hinged link "
                                         "(a crank or a rocker)")])
    pin_local = B.hinge_local[pin_body].T @ _vec(pin)
    c_extra = B.further_points(coupler, {Ap, Bp}, Cm, B.sk(U))
    B.body_frames[ci] = ("coupler", U, other, pin_body, tuple(float(c) for c in pin_local))
    return c_extra


def _fix_branches(plan: SpatialPlan, tol) -> SpatialPlan:
    """Each dyad's branch s = sign det[A − D, e, B − D] from the sketch, once."""
    steps = list(plan.steps)
    q0 = [Jet(np.asarray(q)) for q in plan.sketch_inputs]
    for i, st in enumerate(steps):
        if st.kind != "RSS":
            continue
        D, Ap, Bp = st.pivot, st.start, st.joint
        ctx = run(plan, plan.defaults, q0, 0, tol, steps=steps[:i])
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
            c2 = run(plan, plan.defaults, q0, 0, tol, steps=steps[: i + 1])
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
        steps[i] = replace(st, branch=ok[int(np.argmin(dev))][0], sketch_v3x=float(np.cross(v1, e)[0]),
                           sketch_v1_norm=float(np.linalg.norm(v1)))
    return plan.with_steps(steps)
