"""Compile a planar mechanism description into a :class:`~assur.engine.plan.PlanarPlan`.

Compilation validates the structure (mobility equals the number of drivers, every body is
determined by an Assur group), builds the parameter map (names and sketch defaults) and fixes
each group's assembly branch from the sketch (or from an explicit ``[branches]`` hint), once.
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from dataclasses import replace

from ...errors import SpecError, StructureError
from ...model.mechanism import FRAME, Mechanism
from ...structure.assur import GroupKind, Structure, analyse
from ...tolerances import DEFAULT
from ..plan import (BRANCHED, PARAM_KINDS, CrankStep, FrameStep, GearSlot, GearStep, NewtonStep, PlanarPlan,
                    PPRStep, PRPStep, RPRStep, RRPStep, RRRStep, Side)
from .cam_steps import cam_step
from .newton_group import sketch_branch_sign, sketch_misfit
from .continuation import context_at, run_steps


def _c(xy) -> complex:
    return complex(xy[0], xy[1])


def _unit(z: complex) -> complex:
    return z / abs(z)


class _Builder:
    def __init__(self, m: Mechanism, s: Structure):
        self.m, self.s, self.g = m, s, s.graph
        self.names: list[str] = []
        self.values: list[float] = []
        self.kinds: list[int] = []
        self.recipes: list[tuple] = []
        self.lines: list[tuple] = []
        self.line_of: dict[str, int] = {}
        self.problems: list[tuple[str, str]] = []

    def param(self, name: str, value: float, kind: str = "length") -> int:
        self.names.append(name)
        self.values.append(float(value))
        self.kinds.append(PARAM_KINDS.index(kind))
        return len(self.names) - 1

    def sketch(self, p) -> complex:
        return _c(self.m.sketch(p))

    def sketch_angle(self, body: int) -> float:
        """Orientation of a body's local frame in the sketch (rad)."""
        b = self.g.bodies[body]
        if b.kind == "frame":
            return 0.0
        if b.kind == "link" and len(b.points) >= 2:
            return cmath.phase(self.sketch(b.points[1]) - self.sketch(b.points[0]))
        if b.kind == "link":
            return 0.0
        if b.kind == "block":
            pr = next(p for p in self.m.prismatic if p.name == b.source)
            return self.sketch_line_angle(pr)
        ac = next(a for a in self.m.actuators if a.name == b.source)
        return cmath.phase(self.sketch(ac.between[1]) - self.sketch(ac.between[0]))

    def sketch_line_angle(self, pr) -> float:
        gb = self.g.index(pr.guide)
        return pr.angle + (self.sketch_angle(gb) if pr.guide != FRAME else 0.0)

    def build_geometry(self):
        m = self.m
        for bi, b in enumerate(self.g.bodies):
            if b.kind == "frame":
                rec = []
                for p in b.points:
                    x, y = m.sketch(p)[:2]
                    rec.append((p, self.param(f"{p}.x", x), self.param(f"{p}.y", y)))
                self.recipes.append(("frame", rec))
            elif b.kind == "link":
                lk = m.link(b.name)
                pts = lk.points
                if len(pts) == 1:
                    self.recipes.append(("point", pts[0]))
                    continue
                p0, p1 = self.sketch(pts[0]), self.sketch(pts[1])
                length = lk.length if lk.length is not None else abs(p1 - p0)
                if length <= 0:
                    self.problems.append((f"links.{lk.name}", f"points {pts[0]} and {pts[1]} coincide in the sketch; give 'length'"))
                il = self.param(f"{lk.name}.length", length)
                placed = []
                for p in pts[2:]:
                    pl = lk.placement(p)
                    if pl is None:
                        z = self.sketch(p)
                        rel = (z - p0) / (p1 - p0) if p1 != p0 else 0j
                        org, tow, dist, ang = pts[0], pts[1], abs(z - p0), cmath.phase(rel) if rel else 0.0
                    else:
                        org, tow, dist, ang = pl.origin, pl.toward, pl.distance, pl.angle
                    placed.append((p, org, tow, self.param(f"{lk.name}.{p}.distance", dist),
                                   self.param(f"{lk.name}.{p}.angle", ang, "angle")))
                self.recipes.append(("link", pts[0], pts[1], il, tuple(placed)))
            else:  # block, cylinder, rod: the body's own point at its origin
                self.recipes.append(("point", b.points[0]))
        for pr in m.prismatic:
            gb = self.g.index(pr.guide)
            slider = self.g.index(f"{pr.name}.block") if pr.point is not None else self.g.index(pr.link)
            ia = self.param(f"{pr.name}.angle", pr.angle, "angle")
            io = self.param(f"{pr.name}.offset", pr.offset)
            if pr.point is not None:
                ref, u_slider = pr.point, 1 + 0j
            else:
                lk = m.link(pr.link)
                ref = lk.points[0]
                u_slider = cmath.exp(1j * (self.sketch_line_angle(pr) - self.sketch_angle(slider)))
            self.line_of[pr.name] = len(self.lines)
            self.lines.append(("prismatic", pr.name, gb, slider, pr.through, ia, io, ref, u_slider))
        for ac in m.actuators:
            cyl, rod = self.g.index(f"{ac.name}.cylinder"), self.g.index(f"{ac.name}.rod")
            self.line_of[ac.name] = len(self.lines)
            self.lines.append(("actuator", ac.name, cyl, rod, ac.between[0], None, None, ac.between[1], 1 + 0j))
        for d in m.drivers:
            if d.kind == "rotary":
                self.param(f"{d.name}.zero", d.zero, "angle")


def compile_planar(m: Mechanism, *, tolerances=DEFAULT, structure: Structure | None = None) -> PlanarPlan:
    """Compile a planar mechanism into a solve plan. Raises StructureError / SpecError.

    ``structure``: ``analyse(m)`` when the caller already has it (it depends on the topology only: names, links'
    points, pairs and drivers, never a number), so that a caller compiling many drawings of one topology (the
    designer during a drag) decomposes it once."""
    frame_points = set(m.frame.points)
    for k, d in enumerate(m.drivers):
        ac = next((a for a in m.actuators if a.name == d.actuator), None) if d.kind == "linear" else None
        if ac is not None and set(ac.between) <= frame_points:
            raise SpecError([(f"drivers[{k}].actuator", f"the driven actuator {ac.name} joins two frame points "
                                                        f"({', '.join(ac.between)}): its length cannot change")])
    s = analyse(m) if structure is None else structure
    n_drivers = len(m.drivers)
    if s.mobility != n_drivers:
        p4 = s.pair_counts["p4"]
        raise StructureError(
            f"mobility W = 3·{s.n_moving} − 2·{s.pair_counts['p5']}{f' − {p4}' if p4 else ''} = {s.mobility} "
            f"but {n_drivers} driver(s) "
            f"are given ({', '.join(d.name for d in m.drivers) or 'none'}); each degree of freedom needs one driver")
    if s.undetermined:
        raise StructureError(
            f"cannot decompose into Assur groups: {', '.join(s.undetermined)} are not determined by the drivers "
            f"(W = {s.mobility}, drivers: {', '.join(d.name for d in m.drivers) or 'none'})")
    B = _Builder(m, s)
    B.build_geometry()
    g = s.graph
    steps: list = [FrameStep()]
    input_names, input_kinds, sketch_inputs, speeds = [], [], [], []
    actuator_input: dict[str, int] = {}
    for k, d in enumerate(m.drivers):
        input_names.append(d.name)
        input_kinds.append(d.kind)
        speeds.append(d.speed)
        if d.kind == "rotary":
            pivot, arm = B.sketch(d.pivot), B.sketch(d.arm)
            theta = cmath.phase(arm - pivot)
            q = (d.sense * (theta - d.zero)) % (2 * math.pi)
            sketch_inputs.append(q)
            steps.append(CrankStep((g.index(d.link),), d.pivot, d.arm, k, B.names.index(f"{d.name}.zero"), d.sense))
        else:
            ac = next(a for a in m.actuators if a.name == d.actuator)
            sketch_inputs.append(abs(B.sketch(ac.between[1]) - B.sketch(ac.between[0])))
            actuator_input[d.actuator] = k
    gear_slots: list = []
    cam_slots: list = []
    for grp in s.groups:
        if grp.kind == GroupKind.GEAR:
            steps.append(_gear_step(m, B, grp, steps, gear_slots, sketch_inputs))
        elif grp.kind == GroupKind.CAM:
            steps.append(cam_step(m, B, grp, steps, gear_slots, cam_slots, sketch_inputs))
        else:
            steps.append(_group_step(m, s, B, grp, actuator_input))
    # which body places each point
    solved_order = [b for st in steps for b in st.bodies]
    point_body = []
    for p in m.point_names:
        at = g.bodies_at(p)
        first = min(at, key=lambda b: solved_order.index(b) if b in solved_order else 10**9)
        point_body.append(first)
    plan = PlanarPlan(
        mechanism=m, structure=s, steps=tuple(steps), param_names=tuple(B.names),
        defaults=np.array(B.values, dtype=float), point_names=m.point_names,
        body_names=tuple(b.name for b in g.bodies), input_names=tuple(input_names),
        input_kinds=tuple(input_kinds), sketch_inputs=np.array(sketch_inputs, dtype=float),
        speeds=np.array(speeds, dtype=float), point_body=tuple(point_body), param_kind=np.array(B.kinds),
        geometry_program=tuple(B.recipes), lines=tuple(B.lines), length_scale=m.length_scale,
        sketch_poses=_sketch_frames(B, g), gear_slots=tuple(gear_slots), cam_slots=tuple(cam_slots))
    if B.problems:
        raise SpecError(B.problems)
    sketch_e = [cmath.exp(1j * th) for _, _, th in plan.sketch_poses]
    return _fix_branches(plan, tolerances, sketch_e)


def _check_key_point_drawn_apart(plan: PlanarPlan, st, tol) -> None:
    """SpecError where the sketch puts a branched step's point on top of another point of its own bodies:
    the sketch then cannot tell the assembly branch (it would be chosen arbitrarily)."""
    m, g = plan.mechanism, plan.structure.graph
    J = np.array(m.sketch(st.key_point)[:2], dtype=float)
    for b in st.bodies:
        for p in g.bodies[b].points:
            if p != st.key_point and np.hypot(*(np.array(m.sketch(p)[:2], dtype=float) - J)) \
                    <= tol.branch_separation * plan.length_scale:
                raise SpecError([(f"points.{st.key_point}",
                                  f"the sketch puts {st.key_point} on {p}, a point of the same link: it cannot tell "
                                  f"the assembly branch; draw {st.key_point} where it belongs, or set "
                                  f"[branches.{st.key_point}]")])


def _check_sketch_closes(plan: PlanarPlan, params, q0, tol) -> None:
    """SpecError unless the drawn sketch closes the loop equations of every Newton-solved group (it seeds
    the solver, so a sketch off the dimensions could seed another assembly mode): names the joint or slide
    that is off and by how much."""
    for i, st in enumerate(plan.steps):
        if st.kind != "newton":
            continue
        c = context_at(plan, plan.steps[:i], params, q0, tol)
        off, where = sketch_misfit(c, st, plan.sketch_poses)
        if not off <= tol.sketch_fit * plan.length_scale:
            names = ", ".join(plan.body_names[b] for b in st.bodies)
            path = f"points.{where}" if where in plan.point_names else f"prismatic.{where}"
            raise SpecError([(path, f"the sketch does not fit the dimensions of the group {names} (solved by Newton "
                                    f"iterations seeded by the sketch): at {where} it is {off:.4g} m off "
                                    f"({100 * off / plan.length_scale:.2g} % of the mechanism's size); correct the "
                                    f"sketch or the lengths")])


def newton_branch_signs(plan: PlanarPlan) -> dict[int, int]:
    """The assembly of each Newton-solved group as the sketch draws it: {step index: the sign of its
    equilibrated Jacobian determinant at the sketch} (what the solver keeps every sample on)."""
    out = {}
    for i, st in enumerate(plan.steps):
        if st.kind == "newton":
            c = context_at(plan, plan.steps[:i], plan.defaults, plan.sketch_inputs)
            out[i] = sketch_branch_sign(c, st, plan.sketch_poses)
    return out


def _sketch_frames(B: _Builder, g) -> tuple:
    """(x, y, θ) of every body's local frame as drawn in the sketch (the frame at the origin; every
    other body's first point is its local origin)."""
    out = [(0.0, 0.0, 0.0)]
    for b in range(1, len(g.bodies)):
        z0 = B.sketch(g.bodies[b].points[0])
        out.append((z0.real, z0.imag, B.sketch_angle(b)))
    return tuple(out)


def _gear_step(m, B, grp, steps, gear_slots, sketch_inputs) -> GearStep:
    """The step of a link driven through a gear pair, appending the pair's slot to ``gear_slots``: the driving
    link must be a driven crank or the driven link of an earlier gear pair (a turning link whose whole rotation
    the solver knows)."""
    g = B.g
    pair = g.pairs[grp.outer[1][1]]
    k = next(i for i, gp in enumerate(m.gears) if gp.name == pair.name)
    gp = m.gears[k]
    a, b = pair.bodies
    source = None
    for st in steps:
        if st.bodies == (a,) and st.kind == "crank":
            d = m.drivers[st.input]
            source = (st.input, float(d.sense), float(sketch_inputs[st.input]))
        elif st.bodies == (a,) and st.kind == "gear":
            source = (st.input, 1.0, 0.0)
    if source is None:
        cammed = any(st.bodies == (a,) and st.kind == "cam" for st in steps)
        raise StructureError(f"gear pair '{gp.name}': its driving link '{gp.a}' must be a driven crank or the "
                             f"driven link of another gear pair (a link the drive turns directly)"
                             + ("; a gear driven by a cam's follower is not supported" if cammed else ""))
    pivot = g.pairs[grp.outer[0][1]].point
    arm = next(p for p in g.bodies[b].points if p != pivot)
    zero = B.param(f"{gp.name}.zero", cmath.phase(B.sketch(arm) - B.sketch(pivot)), "angle")
    slot = len(m.drivers) + len(gear_slots)
    gear_slots.append(GearSlot(k, *source))
    return GearStep((b,), pivot, arm, slot, zero, 1, k)


def _side(g, body, actuator_input):
    b = g.bodies[body]
    if b.kind in ("cylinder", "rod") and b.source in actuator_input:
        cyl, rod = g.index(f"{b.source}.cylinder"), g.index(f"{b.source}.rod")
        return Side(cyl, (cyl, rod, actuator_input[b.source]))
    return Side(body)


def _group_step(m, s, B, grp, actuator_input):
    """The step record that solves one Assur group."""
    g = s.graph
    kind = grp.kind
    if kind in (GroupKind.TRIAD, GroupKind.GENERAL):
        return NewtonStep(grp.bodies, grp)
    # sides: the two units of the dyad, each with its outer pair
    (ba, pa), (bb, pb) = grp.outer
    sa, sb = _side(g, ba, actuator_input), _side(g, bb, actuator_input)
    pair_a, pair_b = g.pairs[pa], g.pairs[pb]
    inner = g.pairs[grp.inner[0]] if grp.inner else None
    if kind == GroupKind.RRR:
        J = _inner_point(g, grp, sa, sb)
        return RRRStep(grp.bodies, sa, pair_a.point, sb, pair_b.point, J)
    if kind == GroupKind.RRP:
        J = _inner_point(g, grp, sa, sb)
        return RRPStep(grp.bodies, sa, pair_a.point, sb.body, B.line_of[pair_b.name], J)
    if kind == GroupKind.RPR:
        line = B.line_of[inner.name]
        guide = B.lines[line][2]
        if guide in (sa.body,) or (sa.actuator and guide in sa.actuator[:2]):
            g_pt, s_pt = pair_a.point, pair_b.point
        else:
            g_pt, s_pt = pair_b.point, pair_a.point
        slider = B.lines[line][3]
        return RPRStep(grp.bodies, B.lines[line][2], g_pt, slider, s_pt, line)
    if kind == GroupKind.PRP:
        J = _inner_point(g, grp, sa, sb)
        return PRPStep(grp.bodies, sa.body, B.line_of[pair_a.name], sb.body, B.line_of[pair_b.name], J)
    if kind == GroupKind.PPR:
        # sa: revolute outer, sb: prismatic outer (classified so)
        return PPRStep(grp.bodies, sa.body, pair_a.point, sb.body, B.line_of[pair_b.name], B.line_of[inner.name])
    raise StructureError(f"group of kind {kind} is not supported")


def _inner_point(g, grp, sa, sb) -> str:
    ua = set(g.bodies[sa.body].points) | (set(g.bodies[sa.actuator[1]].points) if sa.actuator else set())
    ub = set(g.bodies[sb.body].points) | (set(g.bodies[sb.actuator[1]].points) if sb.actuator else set())
    common = sorted(ua & ub)
    for i in grp.inner:
        p = g.pairs[i]
        if p.kind == "R" and p.point in common:
            return p.point
    if common:
        return common[0]
    raise StructureError("dyad without an inner revolute")


def _sketch_deviations(plan: PlanarPlan, st, candidates, sketch_e) -> list[float]:
    """How far each candidate assembly ``(sign, pos, poses, valid)`` of step ``st`` lies from the sketch: the sum
    of its points' distances to their sketch positions plus the size times its bodies' turns off the sketch."""
    m, scale = plan.mechanism, plan.length_scale
    group_points = {p for b in st.bodies for p in plan.structure.graph.bodies[b].points}
    return [sum(abs(c[1][p] - _c(m.sketch(p))) for p in group_points)
            + scale * sum(abs(c[2][b] - sketch_e[b]) for b in st.bodies) for c in candidates]


def sketch_branch_signs(plan: PlanarPlan, tolerances=DEFAULT) -> dict[int, int | None]:
    """The branch of each closed-form branched step as the sketch draws it, ``[branches]`` hints set aside:
    {step index: the sign of the assembly nearest the sketch (the rule compilation uses without a hint), or None
    where the sketch does not tell (both assemblies as near, or neither assembles)}. Later steps are placed on
    the branches the sketch shows for the earlier ones. One solve of the sketch input per sign and step, no
    compilation: what the designer compares before and after a drag."""
    tol = tolerances
    steps = list(plan.steps)
    sketch_e = [cmath.exp(1j * th) for _, _, th in _sketch_poses_of(plan)]
    out: dict[int, int | None] = {}
    for i, st in enumerate(steps):
        if st.kind not in BRANCHED:
            continue
        cands = []
        for sign in (1, -1):
            trial = steps[:i] + [st.with_branch(sign)]
            pos, poses, valid = run_steps(plan, trial, plan.defaults, plan.sketch_inputs, order=0, upto=i + 1,
                                          tol=tol)
            if bool(np.all(valid)):
                cands.append((sign, pos, poses, True))
        if len(cands) == 1:
            out[i] = cands[0][0]
        elif cands:
            dev = _sketch_deviations(plan, st, cands, sketch_e)
            out[i] = None if abs(dev[0] - dev[1]) <= tol.branch_separation * plan.length_scale \
                else cands[int(np.argmin(dev))][0]
        else:
            out[i] = None
        steps[i] = st.with_branch(out[i] if out[i] is not None else st.branch)
    return out


def _sketch_poses_of(plan: PlanarPlan) -> tuple:
    """(x, y, θ) of every body's local frame as drawn in the sketch (``_sketch_frames`` of the plan's own
    mechanism; ``plan.sketch_poses`` may hold the assembled seeds instead)."""
    B = _Builder(plan.mechanism, plan.structure)
    return _sketch_frames(B, plan.structure.graph)


def _fix_branches(plan: PlanarPlan, tol, sketch_e) -> PlanarPlan:
    """Choose each branched step's sign once, at compile time, at the sketch input.

    With a ``[branches]`` hint: the assembly that puts the point on the stated side (decided a little
    off the sketch input when the sketch itself lies on the line); an RPR group's ``slide`` hint: the sign that
    puts its slider's hinge ahead of (+1) or behind (−1) its guide's hinge along the slide line
    (``kernels.planar.rotation_from_slide``). Otherwise: the assembly nearest the
    sketch — the group's points and its bodies' orientations (a cylinder's direction, say).
    ``sketch_e`` (n_bodies,) complex: each body's orientation in the sketch.
    """
    m = plan.mechanism
    hints = {h.point: h for h in m.branches if h.side is not None}
    slide_hints = {(h.point, h.on): h for h in m.branches if h.slide is not None}
    steps = list(plan.steps)
    params = plan.defaults
    q0 = plan.sketch_inputs
    scale = plan.length_scale
    nudge = np.array([tol.branch_nudge if k == "rotary" else tol.branch_nudge * scale for k in plan.input_kinds])
    used_hints, used_slides = set(), set()

    def candidates(i, st, inputs):
        out = []
        for sign in (1, -1):
            trial = steps[: i] + [st.with_branch(sign)]
            pos, poses, valid = run_steps(plan, trial, params, inputs, order=0, upto=i + 1, tol=tol)
            out.append((sign, pos, poses, bool(np.all(valid))))
        return out

    for i, st in enumerate(steps):
        if st.kind not in BRANCHED:
            continue
        cands = candidates(i, st, q0)
        if not any(c[3] for c in cands):
            raise SpecError([(f"points.{st.key_point}",
                              f"the group solving '{st.key_point}' cannot be assembled in the sketch position "
                              f"(check the dimensions and the sketch)")])
        allowed = [c for c in cands if c[3]]
        slid = slide_hints.get((st.key_point, plan.lines[st.line][1])) if st.kind == "RPR" else None
        if slid is not None:
            used_slides.add((slid.point, slid.on))
            allowed = [c for c in allowed if c[0] == (1 if slid.slide == "ahead" else -1)]
            if not allowed:
                raise SpecError([(f"branches.{st.key_point}.slide",
                                  f"the RPR group on '{slid.on}' cannot be assembled with {st.key_point} {slid.slide} "
                                  f"of {st.guide_point} in the sketch position")])
        hint = hints.get(st.key_point)
        if hint is not None:
            used_hints.add(hint.point)
            want = 1 if hint.side == "left" else -1

            def side(pos):
                a, b, z = pos[hint.of[0]], pos[hint.of[1]], pos[st.key_point]
                c = np.imag(np.conj(b - a) * (z - a))
                return 0 if abs(c) <= tol.collinear * scale * scale else int(np.sign(c))

            matches = [c for c in allowed if side(c[1]) == want]
            if not matches or len({side(c[1]) for c in allowed}) == 1:
                # on the line in the sketch: decide just off the sketch input
                for dq in (nudge, -nudge):
                    near = [c for c in candidates(i, st, q0 + dq) if c[3]]
                    ok_signs = {c[0] for c in near if side(c[1]) == want}
                    if ok_signs and len(ok_signs) < len(near):
                        matches = [c for c in allowed if c[0] in ok_signs]
                        break
            if not matches:
                raise SpecError([(f"branches.{st.key_point}",
                                  f"no assembly puts {st.key_point} on the {hint.side} of {hint.of[0]} → {hint.of[1]}")])
            allowed = matches
        if len(allowed) == 1 or slid is not None:
            chosen = allowed[0][0]
        else:
            _check_key_point_drawn_apart(plan, st, tol)
            dev = _sketch_deviations(plan, st, allowed, sketch_e)
            if abs(dev[0] - dev[1]) <= tol.branch_separation * scale:
                raise SpecError([(f"points.{st.key_point}",
                                  f"the sketch does not tell the assembly branch of '{st.key_point}' (both branches "
                                  f"coincide); move it off the line or set [branches.{st.key_point}]")])
            chosen = allowed[int(np.argmin(dev))][0]
        steps[i] = st.with_branch(chosen)
    unused_slides = sorted(set(slide_hints) - used_slides)
    if unused_slides:
        p, on = unused_slides[0]
        rpr = [f"{s.key_point} on {plan.lines[s.line][1]}" for s in steps if s.kind == "RPR"]
        raise SpecError([(f"branches.{p}.on", f"no RPR group slides on '{on}' with its slider hinged at '{p}' (RPR "
                                              f"groups: {', '.join(rpr) or 'none'})")])
    unused = set(hints) - used_hints
    if unused:
        p = sorted(unused)[0]
        raise SpecError([(f"branches.{p}", f"'{p}' is not the point a branched group solves "
                          f"(branched points: {', '.join(s.key_point for s in steps if s.kind in BRANCHED)})")])
    fixed = plan.with_steps(steps)
    _check_sketch_closes(fixed, params, q0, tol)
    # the assembled sketch pose of every body: the seed of the Newton solver (honours the branches)
    pos, poses, valid = run_steps(fixed, fixed.steps, params, q0, order=0, origins=True, tol=tol)
    seeds = []
    for b in range(len(fixed.body_names)):
        o, e = poses.get(b, (np.nan, np.nan))
        if not (np.all(valid) and np.isfinite(o) and np.isfinite(e)):
            seeds = None
            break
        seeds.append((float(np.real(o)), float(np.imag(o)), float(np.angle(e))))
    # an unassemblable sketch keeps the sketch's own frames as the seed
    return fixed if seeds is None else replace(fixed, sketch_poses=tuple(seeds))
