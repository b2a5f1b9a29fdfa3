"""Forces of the papers' mechanisms: a section of docs/reproduction.md.

The papers print no forces. Every number here is computed by ``assur.forces`` from the example files, whose
mass properties and loads are ASSUMPTIONS stated in the files (steel bars of 30 × 10 mm section, stated body
weights and loads). Each row is checked in this script against the virtual-power value −Σ(F·v + M·ω)/ω computed
from the solved velocities alone (the column "virtual power check": the largest relative difference over the
cycle). ``docs/reproduction.py`` includes ``section()``.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import assur
from assur.kinetostatics.design import drive_summary

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
STEPS = 720


def _g(x, digits=4):
    return f"{x:.{digits}g}"


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _rotating(pos, vel, acc, i0, i1):
    """(d, d', d'', ω, α) of the direction P[i1] − P[i0]: ω = d × d'/|d|², α = d × d''/|d|² − 2ω (d·d')/|d|²."""
    d, dv, da = pos[:, i1] - pos[:, i0], vel[:, i1] - vel[:, i0], acc[:, i1] - acc[:, i0]
    L2 = np.sum(d * d, -1)
    w = _cross(d, dv) / L2
    return d, dv, da, w, _cross(d, da) / L2 - 2 * w * np.sum(d * dv, -1) / L2


def _virtual_power_check(plan, f, point_loads=()):
    """The largest relative difference between the driving effort and −Σ(F·v + M·ω)/q̇ of the applied loads
    (gravity, d'Alembert forces and couples, the file's loads), from the solved positions, velocities and
    accelerations of the points and the files' mass properties alone."""
    st = f.state
    m, g = plan.mechanism, plan.structure.graph
    dyn = m.dynamics
    grav = np.asarray(dyn.gravity[:2], dtype=float)
    pos, vel, acc = st.pos, st.vel, st.acc
    P = np.zeros(st.shape)
    for bi, body in enumerate(g.bodies):
        mp = dyn.mass_of(body.name)
        if bi == 0 or mp.mass == 0:
            continue
        if body.kind == "block":
            k = plan.point_index(body.points[0])
            vc, ac, w, al, inertia = vel[:, k], acc[:, k], 0.0, 0.0, mp.inertia or 0.0
        elif body.kind in ("cylinder", "rod"):
            act = next(a for a in m.actuators if a.name == body.source)
            i0, i1 = plan.point_index(act.between[0]), plan.point_index(act.between[1])
            d, dv, da, w, al = _rotating(pos, vel, acc, i0, i1)
            L = np.sqrt(np.sum(d * d, -1))[:, None]
            u = d / L
            L1 = np.sum(u * dv, -1)[:, None]
            u1 = (dv - u * L1) / L
            L2 = np.sum(u1 * dv, -1)[:, None] + np.sum(u * da, -1)[:, None]
            u2 = (da - 2 * u1 * L1 - u * L2) / L
            sign, base = (1.0, i0) if body.kind == "cylinder" else (-1.0, i1)
            dist = sign * (mp.com or 0.0)
            vc, ac = vel[:, base] + dist * u1, acc[:, base] + dist * u2
            inertia = mp.inertia or 0.0
        else:
            i0, i1 = (plan.point_index(p) for p in body.points[:2])
            d, dv, da, w, al = _rotating(pos, vel, acc, i0, i1)
            if mp.com == "mid":
                a_, b_ = 0.5, 0.0
            else:           # sketch coordinates: com = P0 + a·d + b·rot90(d), fixed to the body
                sk = np.array([m.sketch(p)[:2] for p in body.points[:2]])
                rel, base = np.array(mp.com) - sk[0], sk[1] - sk[0]
                a_ = np.dot(rel, base) / np.dot(base, base)
                b_ = float(base[0] * rel[1] - base[1] * rel[0]) / np.dot(base, base)
            rot = lambda x: np.stack([-x[:, 1], x[:, 0]], -1)  # noqa: E731
            vc = vel[:, i0] + a_ * dv + b_ * rot(dv)
            ac = acc[:, i0] + a_ * da + b_ * rot(da)
            L2 = np.sum(d * d, -1)
            inertia = mp.inertia if mp.inertia is not None else mp.mass * L2 / 12.0
        P += np.sum(mp.mass * (grav - ac) * vc, -1) - inertia * al * w
    for load in dyn.loads:
        v = vel[:, plan.point_index(load.point)]
        if load.opposes == "velocity":
            force = -np.linalg.norm(load.force) * v / np.linalg.norm(v, axis=-1, keepdims=True)
        else:
            force = np.asarray(load.force)
        P += np.sum(force * v, -1)
    for point, F in point_loads:
        P += np.sum(F * vel[:, plan.point_index(point)], -1)
    T_vp = -P / float(st.qdot[0])
    return float(np.nanmax(np.abs(f.driver[:, 0] - T_vp)) / np.nanmax(np.abs(f.driver[:, 0])))


def _noise(x, scale):
    """0 for rounding noise (below 1e-9 of the scale)."""
    return 0.0 if abs(x) <= 1e-9 * scale else x


def legs():
    rows = []
    for name, paper in (("walker_crank_slider.toml", "000"), ("walker_fourbar.toml", "004 (a)"),
                        ("walker_sixbar.toml", "004 (c)")):
        plan = assur.compile(assur.load(EX / name))
        q = np.linspace(0, 2 * math.pi, STEPS, endpoint=False)
        f = assur.forces(plan, inputs=q)
        s = drive_summary(f, q)
        gf = assur.Study(plan, steps=STEPS).force_cycle.gait
        mod = gf.module_driver
        check = _virtual_power_check(plan, f)
        rows.append((paper, name, _g(s.peak), _g(s.rms), _g(gf.weight), len(gf.phases), _g(np.max(np.abs(mod))),
                     _g(np.sqrt(np.mean(mod ** 2))), _g(_noise(np.mean(mod), np.max(np.abs(mod)))), f"{check:.1e}"))
    out = ["| paper | file | leg alone: peak torque (N·m) | RMS (N·m) | body weight (N) | legs | module: peak shaft "
           "torque (N·m) | RMS (N·m) | mean (N·m) | virtual power check (leg alone) |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def manipulator():
    plan = assur.compile(assur.load(EX / "lever_manipulator.toml"))
    s = np.linspace(0.5, 1.0, 501)
    f = assur.forces(plan, inputs=s)
    d = drive_summary(f, s)
    check = _virtual_power_check(plan, f)
    i = int(np.nanargmax(np.abs(f.driver[:, 0])))
    return [f"- Cylinder force over the working stroke 500 → 1000 mm at 100 mm/s: peak {_g(d.peak)} N (at a driving-rod "
            f"length of {_g(s[i] * 1000)} mm), mean {_g(d.mean)} N, work {_g(d.energy)} J; peak load on the driving "
            f"cylinder's hinge A {_g(_peak(d, 'A'))} N. Virtual power check: {check:.1e}."]


def _peak(d, point):
    return max(v for k, v in d.joint_peaks.items() if k.split(" ")[0] == point)


def rssr():
    """Paper 003's RSSR against a constant resisting torque on the rocker; checked against the kinematic ratio
    T = τ·dψ/dφ (virtual power with massless links: T·ω1 + τ·ω_rocker = 0)."""
    plan = assur.compile(assur.load(EX / "rssr.toml"))
    q = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    f = assur.forces(plan, inputs=q)
    st = f.state
    e2 = np.array([1.0, 0.0, 0.0])           # the rocker axis of examples/rssr.toml (gamma1 = 90°, gamma2 = 0)
    D, B = st.pos[:, plan.point_index("P4")], st.pos[:, plan.point_index("P3")]
    vB = st.vel[:, plan.point_index("P3")]
    r = B - D
    w_rocker = np.sum(np.cross(r, vB) * e2, -1) / np.sum(np.cross(e2, r) ** 2, -1)   # ω about e2
    tau = next(ld.torque for ld in plan.mechanism.dynamics.loads if ld.link == "rocker")
    T_vp = -tau * w_rocker / float(st.qdot[0])
    T = f.driver[:, 0]
    check = float(np.max(np.abs(T - T_vp)) / np.max(np.abs(T)))
    i = int(np.argmax(np.abs(T)))
    return [f"- Paper 003's RSSR (`examples/rssr.toml`; assumed: massless links, a constant resisting torque of "
            f"{_g(-tau)} N·m about the rocker axis): driving torque peak {_g(abs(T[i]), 5)} N·m at "
            f"φ = {math.degrees(q[i]):.2f}°, RMS {_g(np.sqrt(np.mean(T ** 2)), 5)} N·m, mean "
            f"{_g(_noise(np.mean(T), np.max(np.abs(T))))} N·m over a turn (3 600 samples); the smallest condition "
            f"measure (sin μ_T) {_g(np.nanmin(f.condition), 3)}. Check against τ·dψ/dφ from the velocities: "
            f"{check:.1e}."]


def section() -> str:
    return "\n".join([
        "## Forces of the papers' mechanisms (computed; the papers print none)",
        "",
        "Computed by `assur.forces` (docs/forces.md) from the example files. The mass properties and loads are "
        "assumptions written in each file: steel bars of 30 × 10 mm section (7850 kg/m³, 2.355 kg/m; a bent lever as "
        "two bars), each file's driver speed, gravity towards the ground. Walking legs: the leg alone carries its own "
        "weight and inertia; the module carries the stated body weight, shared equally by the feet on the ground "
        "(each foot only in its contact arc), and its shaft torque is the sum over the legs (antiphase for paper 004; "
        "one leg for paper 000). A mean module torque that is not zero is the work of the weight on feet whose "
        "height changes over the contact arc (the sag).",
        "",
        legs(),
        "",
        "Paper 002's manipulator (`examples/lever_manipulator.toml`; assumed: a 20 kg carriage, 8 kg barrels and 3 kg "
        "rods, a 500 N process resistance against the carriage's motion):",
        "",
        *manipulator(),
        *rssr(),
        "",
    ])
