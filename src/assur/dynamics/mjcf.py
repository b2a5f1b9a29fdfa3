"""A planar mechanism as a MuJoCo model (MJCF): bodies with the file's masses and inertias, hinge and slide joints
along a spanning tree of the mechanism, every other loop closed by an equality ``connect`` constraint, circular gear
pairs as joint equalities, the driver as a velocity servo or as the file's motor, and for a walking leg a base that
carries the legs of its module, with the feet on a ground plane (docs/dynamics.md).

The model is built at the mechanism's assembled sketch (the solve at the sketch's inputs, so every constraint
holds at qpos = 0). The plane of the mechanism is MuJoCo's x–z plane: a point (x, y) goes to (x·g, 0, x·u) with g
the gait's stride direction and u its up (the file's x and y without a gait), every hinge turns about −y (so a
hinge angle is counter-clockwise positive, as in the file) and gravity is the file's. What MuJoCo cannot hold is
refused with an error naming the element: a spatial mechanism, a prismatic pair that would close a loop (MuJoCo has
no equality that keeps a slide), a non-circular gear pair or a cam pair (their laws are not polynomials of the
joint angles).

MuJoCo is needed only to load the model (:func:`mjcf_model`); writing the text needs nothing beyond the standard
library.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..kinetostatics import kernel as K
from ..kinetostatics.groups import body_rows
from ..kinetostatics.program import program_of

#: the simulation's time step (s) and the equality constraints' reference (time constant, damping ratio) and
#: impedance (d0, d_width, width, midpoint, power): stiff enough to hold the loops within 1e-4 of the size
TIMESTEP = 2e-4
STEPS_PER_TURN = 10000
SOLREF = (None, 1.0)
SOLIMP = (0.9999, 0.9999, 0.001, 0.5, 2.0)
#: the drawn links' radius and a foot's, relative to the mechanism's size; the density of a body the file gives
#: no mass (its capsules' volume at steel's density)
LINK_RADIUS, FOOT_RADIUS, DENSITY = 0.01, 0.015, 7850.0


@dataclass
class _Body:
    index: int
    name: str
    parent: int
    pair: object            # the structure pair joining it to its parent (None for the frame)
    origin: np.ndarray      # (3,) world position of the body's frame at the sketch
    joint: tuple | None     # ("hinge" | "slide", world pos (3,), axis (3,))


def _tree(plan):
    """(parent pair of each body, loop pairs): a spanning tree of the bodies with the drivers' pairs and the
    prismatic pairs in it first; SpecError for a prismatic pair, a non-circular gear pair or a cam pair it cannot
    hold."""
    g = plan.structure.graph
    m = plan.mechanism
    parent = list(range(len(g.bodies)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    drivers = set()
    for d in m.drivers:
        if d.kind == "rotary":
            drivers.add(("R", d.pivot, frozenset((0, g.index(d.link)))))
        else:
            drivers.add(("P", d.actuator, None))

    def key(p):
        is_driver = ("R", p.point, frozenset(p.bodies)) in drivers or ("P", p.name, None) in drivers
        return (0 if is_driver else 1 if p.kind == "P" else 2)
    tree, loops = [], []
    for p in sorted((p for p in g.pairs if p.kind in "RP"), key=key):
        a, b = find(p.bodies[0]), find(p.bodies[1])
        if a != b:
            parent[a] = b
            tree.append(p)
        elif p.kind == "P":
            raise SpecError([(f"prismatic.{p.name}", "this slide would close a loop of the MuJoCo model, and MuJoCo "
                                                     "has no equality constraint that keeps a slide: not exported")])
        else:
            loops.append(p)
    for gp, p in zip(m.gears, (p for p in g.pairs if p.kind == "G")):
        if gp.law.kind != "ratio":
            raise SpecError([(f"gears.{gp.name}", "a non-circular gear pair's law is not a polynomial of the joint "
                                                  "angles, which is all a MuJoCo joint equality holds: not exported")])
    for cp in m.cams:
        raise SpecError([(f"cams.{cp.name}", "a cam pair's follower law is a table of the cam's profile, not a "
                                             "polynomial of the joint angles, which is all a MuJoCo joint equality "
                                             "holds: not exported")])
    return tree, loops


def _reference(plan, params, q, speeds=None):
    """(positions (n_points, 2), velocities (n_points, 2), orientations (n_bodies,) complex, angular velocities
    (n_bodies,)) at the inputs q (n_inputs,) and input rates ``speeds`` (default 0)."""
    from ..engine import solve
    speeds = np.zeros(plan.n_inputs) if speeds is None else np.asarray(speeds, dtype=float)
    st = solve(plan, params, np.asarray(q, dtype=float)[None, :], speeds=speeds, order=1, backend="numpy")
    if not bool(np.asarray(st.valid)[0]):
        raise SpecError([("q0", f"the mechanism cannot be assembled at its start {np.degrees(q)} (deg)")])
    pos, vel = np.asarray(st.pos[0], dtype=float), np.asarray(st.vel[0], dtype=float)
    z = (pos[:, 0] + 1j * pos[:, 1])[:, None]
    v = (vel[:, 0] + 1j * vel[:, 1])[:, None]
    p = np.asarray(params, dtype=float)[:, None]
    orient, omega, _ = body_rows(program_of(plan), z, v, np.zeros_like(z), p)
    return pos, vel, orient[:, 0], omega[:, 0]


class _Frame:
    """The map of the mechanism's plane into MuJoCo's x–z plane (module docstring)."""

    def __init__(self, ground=(1.0, 0.0), up=(0.0, 1.0)):
        self.g, self.u = np.asarray(ground, float), np.asarray(up, float)
        self.spin = -1.0 if self.g[0] * self.u[1] - self.g[1] * self.u[0] > 0 else 1.0

    def point(self, xy):
        xy = np.asarray(xy, dtype=float)
        return np.array([xy @ self.g, 0.0, xy @ self.u])

    @property
    def hinge_axis(self):
        return np.array([0.0, self.spin, 0.0])


def _fmt(v) -> str:
    return " ".join(f"{float(x):.12g}" for x in np.atleast_1d(v))


@dataclass(frozen=True)
class MJCFOptions:
    """What :func:`mjcf_text` writes: ``actuator`` ('auto': the file's motor when MuJoCo can hold it exactly
    (constant torque, DC), else a velocity servo; 'velocity'; 'motor'), the velocity servo's gain ``kv``
    (N·m·s/rad or N·s/m; default from the mechanism's inertia), ``legs`` (a walking leg's module on a ground
    plane: default when the file has a ``[gait]``), the time step and the equality constraints' soft parameters."""
    actuator: str = "auto"
    kv: float | None = None
    legs: bool | None = None
    timestep: float | None = None
    solref: tuple = SOLREF
    solimp: tuple = SOLIMP

    def step(self, plan, move: int) -> float:
        """The time step: given, else the smaller of :data:`TIMESTEP` and a turn (or a second of a linear input's
        travel at its speed over the size) over :data:`STEPS_PER_TURN`."""
        if self.timestep is not None:
            return float(self.timestep)
        w = abs(float(plan.speeds[move]))
        period = 2 * math.pi / w if plan.input_kinds[move] == "rotary" else plan.length_scale / w if w else 1.0
        return min(TIMESTEP, period / STEPS_PER_TURN)


def mjcf_text(plan, params=None, *, options: MJCFOptions | None = None, q0=None) -> str:
    """The MJCF text of ``plan`` (see the module docstring)."""
    o = options or MJCFOptions()
    if plan.dimension != 2:
        raise SpecError([("dimension", "the MuJoCo export covers planar mechanisms (dimension = 2)")])
    moving = [k for k in range(plan.n_inputs) if plan.speeds[k] != 0] or [0]
    if len(moving) != 1:
        raise SpecError([("drivers", f"the MuJoCo export drives one input and holds the others (speed 0) at their "
                                     f"sketch values; the mechanism moves {len(moving)}: "
                                     f"{', '.join(plan.input_names[k] for k in moving)}")])
    move = moving[0]
    if o.actuator not in ("auto", "velocity", "motor"):
        raise SpecError([("actuator", f"must be auto, velocity or motor: {o.actuator!r}")])
    m = plan.mechanism
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    tree, loops = _tree(plan)
    legs = (m.gait is not None) if o.legs is None else bool(o.legs)
    if legs and m.gait is None:
        raise SpecError([("gait", "a walking leg's export needs a [gait] table naming its foot")])
    frame = _Frame(m.gait.ground, m.gait.up_vector) if legs else _Frame()
    q0 = np.asarray(plan.sketch_inputs if q0 is None else np.atleast_1d(q0), dtype=float)
    size = plan.length_scale
    root = ET.Element("mujoco", model=m.name or "mechanism")
    ET.SubElement(root, "compiler", angle="radian", inertiafromgeom="auto")
    gravity = m.dynamics.gravity if m.dynamics is not None else (0.0, 0.0)
    if legs and not any(gravity):
        gravity = tuple(-9.81 * np.asarray(m.gait.up_vector))
    dt = o.step(plan, move)
    solref = (2.0 * dt if o.solref[0] is None else o.solref[0], o.solref[1])
    ET.SubElement(root, "option", timestep=f"{dt:.6g}", integrator="implicitfast", gravity=_fmt(frame.point(gravity)))
    default = ET.SubElement(root, "default")
    ET.SubElement(default, "geom", contype="0", conaffinity="0", density=f"{DENSITY:g}", rgba="0.3 0.5 0.8 1")
    ET.SubElement(default, "equality", solref=_fmt(solref), solimp=_fmt(o.solimp))
    world = ET.SubElement(root, "worldbody")
    equality = ET.SubElement(root, "equality")
    phases = tuple(m.gait.phases) if legs else (0.0,)
    joints = []
    if legs:
        base = _base(world, plan, frame, [q0 + phase * np.eye(plan.n_inputs)[move] for phase in phases], params,
                     size)
        parent_el = base
    else:
        parent_el = world
    shift = np.eye(plan.n_inputs)[move]
    rates, masses = {}, []
    for k, phase in enumerate(phases):
        suffix = "" if k == 0 else f"_leg{k + 1}"
        joints.append(_leg(parent_el, equality, plan, params, q0 + phase * shift, plan.speeds[move] * shift, tree,
                           loops, frame, suffix, size, legs, rates, masses))
    for k in range(1, len(phases)):          # the legs' cranks turn together, each at its phase
        ET.SubElement(equality, "joint", name=f"phase_leg{k + 1}", joint1=joints[k][move], joint2=joints[0][move],
                      polycoef="0 1 0 0 0")
    for leg in joints:                       # the settings (drivers of speed 0) hold their sketch values
        for k, name in leg.items():
            if k != move:
                ET.SubElement(equality, "joint", name=f"hold_{name}", joint1=name, polycoef="0 0 0 0 0")
    for gp in m.gears:                       # circular gear pairs: the driven link turns mesh/ratio of the driving
        ratio = float(gp.law.ratio)
        ET.SubElement(equality, "joint", name=f"gear_{gp.name}", joint1=_hinge_of(plan, gp.b),
                      joint2=_hinge_of(plan, gp.a), polycoef=f"0 {gp.mesh_sign / ratio!r} 0 0 0")
    if legs:
        masses.append(float(base.find("inertial").get("mass")))
    key = _actuator(root, plan, params, joints[0][move], move, o, sum(masses) * size * size, dt)
    key.set("qvel", _fmt([rates.get(el.get("name"), 0.0) for el in world.iter("joint")]))
    return ET.tostring(_indent(root), encoding="unicode")


def _hinge_of(plan, link: str) -> str:
    return f"hinge_{link}"


def _indent(root):
    ET.indent(root, space="  ")
    return root


def _base(world, plan, frame, starts, params, size):
    """The body that carries the legs (free to move along the stride and up), the ground plane under the lowest
    foot, and the base's mass (the gait's weight over g, else the legs' mass)."""
    m = plan.mechanism
    foot = m.gait.foot
    lowest = math.inf
    for q in starts:
        pos = _reference(plan, params, q)[0]
        lowest = min(lowest, frame.point(pos[plan.point_index(foot)])[2])
    r = FOOT_RADIUS * size
    friction = m.gait.friction if m.gait.friction is not None else 1.0
    ET.SubElement(world, "geom", name="ground", type="plane", size=_fmt([20 * size, 2 * size, 0.1]),
                  pos=_fmt([0, 0, lowest - r]), contype="1", conaffinity="1", friction=_fmt([friction, 0.005, 1e-4]),
                  rgba="0.8 0.8 0.75 1")
    base = ET.SubElement(world, "body", name="base", pos="0 0 0")
    ET.SubElement(base, "joint", name="base_x", type="slide", axis="1 0 0")
    ET.SubElement(base, "joint", name="base_z", type="slide", axis="0 0 1")
    weight = m.gait.weight
    mass = weight / 9.81 if weight else 4.0 * _links_mass(m)
    ET.SubElement(base, "inertial", pos="0 0 0", mass=f"{max(mass, 1e-3):.12g}", diaginertia=_fmt([1e-3] * 3))
    return base


def _links_mass(m) -> float:
    d = m.dynamics
    return sum(mp.mass for _, mp in d.bodies) if d is not None else 1.0


def _leg(parent_el, equality, plan, params, q, speeds, tree, loops, frame, suffix, size, legs, rates, masses):
    """One copy of the mechanism under ``parent_el`` at the inputs q moving at ``speeds``; returns {driver index: the
    name of its joint}, adds each joint's rate at the start to ``rates`` and each body's mass to ``masses``."""
    g = plan.structure.graph
    m = plan.mechanism
    pos, vel, orient, omega = _reference(plan, params, q, speeds)
    pidx = {n: i for i, n in enumerate(plan.point_names)}
    moving = {0: (np.zeros(2), np.zeros(2))}     # body → (its origin (2,), the velocity of its point there)
    xyz = {n: frame.point(pos[i]) for i, n in enumerate(plan.point_names)}
    children = {b: [] for b in range(len(g.bodies))}
    for p in tree:
        children[p.bodies[0]].append((p.bodies[1], p))
        children[p.bodies[1]].append((p.bodies[0], p))
    prog = program_of(plan)
    z = (pos[:, 0] + 1j * pos[:, 1])[:, None]
    placed = {0: np.zeros(3)}
    elements = {0: parent_el}
    driver_joints = {}
    order = [0]
    seen = {0}
    while order:
        b = order.pop(0)
        for c, p in children[b]:
            if c in seen:
                continue
            seen.add(c)
            order.append(c)
            name = g.bodies[c].name + suffix
            if p.kind == "R":
                origin = xyz[p.point]
                jtype, axis = "hinge", frame.hinge_axis
                jname = f"hinge_{g.bodies[c].name}" if g.bodies[c].kind == "link" and b == 0 and not suffix else \
                    f"{p.point}_{g.bodies[c].name}{suffix}"
                rates[jname] = float(omega[c] - omega[b])
                moving[c] = (pos[pidx[p.point]], vel[pidx[p.point]])
            else:
                origin, axis, ref, u = _slide(plan, prog, z, params, orient, p, frame, pos)
                jtype, jname = "slide", f"slide_{p.name}{suffix}"
                o_b, v_b = moving[b]
                r = pos[ref] - o_b
                v_guide = v_b + omega[b] * np.array([-r[1], r[0]])
                rates[jname] = float(np.dot(u, vel[ref] - v_guide))
                moving[c] = (pos[ref], vel[ref])
            body = ET.SubElement(elements[b], "body", name=name, pos=_fmt(origin - placed[b]))
            ET.SubElement(body, "joint", name=jname, type=jtype, pos="0 0 0", axis=_fmt(axis))
            for k, d in enumerate(m.drivers):
                if (d.kind == "rotary" and p.kind == "R" and b == 0 and g.bodies[c].name == d.link) or \
                        (d.kind == "linear" and p.kind == "P" and p.name == d.actuator):
                    driver_joints[k] = jname
            masses.append(_inertial_and_geoms(body, plan, prog, c, z, params, orient, xyz, origin, frame, size))
            placed[c], elements[c] = origin, body
    for p in loops:
        a, b = p.bodies
        ET.SubElement(equality, "connect", name=f"loop_{p.point}_{g.bodies[b].name}{suffix}",
                      body1=g.bodies[a].name + suffix if a else ("base" if legs else "world"),
                      body2=g.bodies[b].name + suffix, anchor=_fmt(xyz[p.point] - placed[a]))
    for i, n in enumerate(plan.point_names):      # a site at every point, on the body the force analysis loads
        b = min(g.bodies_at(n), key=lambda k: (k != 0, k))
        parent = elements[b] if b else parent_el
        ET.SubElement(parent, "site", name=n + suffix, pos=_fmt(xyz[n] - placed[b]), size=_fmt(0.3 * LINK_RADIUS *
                                                                                          size))
    if legs:
        foot = m.gait.foot
        b = max(g.bodies_at(foot))
        ET.SubElement(elements[b], "geom", name=f"foot{suffix}", type="sphere", size=_fmt(FOOT_RADIUS * size),
                      pos=_fmt(xyz[foot] - placed[b]), contype="1", conaffinity="1", mass="0", rgba="0.8 0.3 0.2 1")
    return driver_joints


def _slide(plan, prog, z, params, orient, pair, frame, pos):
    """(origin (3,), axis (3,), the slider's reference point (index), the line's direction (2,)) of a slide at the
    sketch: the origin at the reference point."""
    i = next(k for k, rec in enumerate(plan.lines) if rec[1] == pair.name)
    rec = plan.lines[i]
    ref = plan.point_index(rec[7])
    if rec[0] == "actuator":
        u = pos[ref] - pos[plan.point_index(rec[4])]
        u = u / np.linalg.norm(u)
        return frame.point(pos[ref]), frame.point(u), ref, u
    p = np.asarray(params, dtype=float)[:, None]
    u, _ = K.line_uq(prog.ln, i, z, p, orient[:, None])
    u = complex(np.ravel(u)[0])
    return frame.point(pos[ref]), frame.point([u.real, u.imag]), ref, np.array([u.real, u.imag])


def _inertial_and_geoms(body, plan, prog, b, z, params, orient, xyz, origin, frame, size):
    """The body's capsules between its points (a box for a slider block) and, when the file gives it a mass, its
    inertial (com and inertia about the axis of the plane) from the force analysis' mass recipe."""
    g = plan.structure.graph
    gb = g.bodies[b]
    r = LINK_RADIUS * size
    pts = [xyz[n] - origin for n in gb.points]
    if gb.kind == "block":
        ET.SubElement(body, "geom", type="box", size=_fmt([2 * r, r, r]), pos=_fmt(pts[0]))
    elif gb.kind in ("cylinder", "rod"):
        ac = next(a for a in plan.mechanism.actuators if a.name == gb.source)
        other = xyz[ac.between[1] if gb.kind == "cylinder" else ac.between[0]] - origin
        ET.SubElement(body, "geom", type="capsule", fromto=_fmt(np.concatenate([pts[0], pts[0] + 0.6 * (other -
                                                                                                    pts[0])])),
                      size=_fmt(r * (1.5 if gb.kind == "cylinder" else 1.0)))
    elif len(pts) == 1:
        ET.SubElement(body, "geom", type="sphere", size=_fmt(r), pos=_fmt(pts[0]))
    else:
        ring = pts + ([pts[0]] if len(pts) > 2 else [])
        for a, c in zip(ring, ring[1:]):
            if np.linalg.norm(c - a) > 1e-9 * size:
                ET.SubElement(body, "geom", type="capsule", fromto=_fmt(np.concatenate([a, c])), size=_fmt(r))
    if b not in set(int(x) for x in prog.massive):     # MuJoCo weighs the geoms: about this much (kg)
        return DENSITY * sum(np.pi * r * r * _capsule_length(el) + 4 / 3 * np.pi * r ** 3
                             for el in body.findall("geom"))
    o = orient[:, None]
    zero = np.zeros_like(o, dtype=float)
    c, _, _ = K.com_motion(b, prog.cpts, prog.cw, prog.coff, z, np.zeros_like(z), np.zeros_like(z), o, zero, zero)
    inertia = float(np.ravel(K.body_inertia(b, prog.mass, prog.inertia, prog.idef, prog.ipts, z, c))[0])
    c = complex(np.ravel(c)[0])
    mass = float(prog.mass[b])
    inertia = max(inertia, 1e-12 * max(mass, 1e-9) * size * size)
    ET.SubElement(body, "inertial", pos=_fmt(frame.point([c.real, c.imag]) - origin), mass=f"{max(mass, 1e-9):.12g}",
                  diaginertia=_fmt([inertia] * 3))
    return mass


def _capsule_length(el) -> float:
    """The length of a capsule geom's segment (0 for any other geom)."""
    ft = el.get("fromto")
    if ft is None:
        return 0.0
    a = np.array([float(x) for x in ft.split()])
    return float(np.linalg.norm(a[3:] - a[:3]))


def _affine_motor(plan, motor):
    """(gain, bias on velocity, armature) of a motor MuJoCo holds exactly as a general actuator at the input
    (force = gain·ctrl + bias·q̇, ctrl = 1 the full supply), or None."""
    from .motors import drive_train
    if motor is None or motor.kind not in ("torque", "force", "dc"):
        return None
    t = drive_train(motor, plan)
    if motor.kind == "dc":
        stall, free = t.dc_constants()
        return t.ratio * motor.efficiency * stall, -t.ratio * t.ratio * motor.efficiency * stall / free, t.inertia
    value = motor.torque if motor.kind == "torque" else motor.force
    return t.ratio * motor.efficiency * value, 0.0, t.inertia


def _actuator(root, plan, params, joint, move, o, inertia, dt):
    """The driver's actuator and a keyframe ``run`` whose ctrl starts it: the file's motor (ctrl = 1) or a velocity
    servo (ctrl = the driver's file speed)."""
    m = plan.mechanism
    sense = float(next((st.sense for st in plan.crank_steps() if st.input == move), 1))
    motor = _affine_motor(plan, m.motor) if o.actuator in ("auto", "motor") else None
    if o.actuator == "motor" and motor is None:
        what = "none" if m.motor is None else f"a {m.motor.kind!r} motor"
        raise SpecError([("motor", f"MuJoCo holds a constant-torque or DC motor exactly; the file has {what}: "
                                   "export with the velocity actuator")])
    act = ET.SubElement(root, "actuator")
    if motor is not None:
        gain, bias, armature = motor
        ET.SubElement(act, "general", name="motor", joint=joint, gear=f"{sense:g}", gaintype="fixed",
                      gainprm=f"{gain!r}", biastype="affine", biasprm=f"0 0 {bias!r}", ctrlrange="-1 1",
                      ctrllimited="true")
        if armature:
            for el in root.iter("joint"):
                if el.get("name") == joint:
                    el.set("armature", f"{armature!r}")
        ctrl = 1.0
    else:
        kv = o.kv if o.kv is not None else inertia / (200.0 * dt)
        ET.SubElement(act, "velocity", name="drive", joint=joint, gear=f"{sense:g}", kv=f"{kv:.6g}")
        ctrl = float(plan.speeds[move])
    keys = ET.SubElement(root, "keyframe")
    return ET.SubElement(keys, "key", name="run", ctrl=f"{ctrl!r}")


def write_mjcf(plan, path, params=None, *, options: MJCFOptions | None = None, q0=None):
    """Write the MJCF of ``plan`` to ``path`` atomically (nothing is written when the export is refused)."""
    from pathlib import Path

    from ..io.output import atomic_file
    text = mjcf_text(plan, params, options=options, q0=q0)
    with atomic_file(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return Path(path)


def write(mechanism, path):
    """``assur export FILE --to mjcf OUT``: the MJCF of a mechanism (compiled here), written atomically; returns
    nothing to print."""
    from ..engine import compile as compile_
    write_mjcf(compile_(mechanism), path)
    return None


def mjcf_model(plan, params=None, *, options: MJCFOptions | None = None, q0=None):
    """The loaded ``mujoco.MjModel`` of the MJCF (needs the ``sim`` extra)."""
    from ..errors import require
    mujoco = require("mujoco", "the MuJoCo model", "pip install 'assur[sim]'")
    return mujoco.MjModel.from_xml_string(mjcf_text(plan, params, options=options, q0=q0))


__all__ = ["MJCFOptions", "mjcf_model", "mjcf_text", "write", "write_mjcf"]
