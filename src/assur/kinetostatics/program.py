"""The force program of a plan: its force tables as flat arrays for :mod:`.kernel`, built once per plan.

Groups are listed in the order they are solved (the last group of the plan first). A group is a
crank, a dyad with an inner revolute, a dyad with an inner slide (each side one body, or a driven
actuator's cylinder and rod), or 'generic' (triads and other shapes: a linear solve per sample).
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from .kernel import (ANG_LINE, ANG_POINTS, ANG_STILL, DEF_BAR, DEF_GIVEN, DEF_POLYGON, G_CRANK, G_GENERIC,
                     G_INNER_P, G_INNER_R, PAIR_P, PAIR_R, PAIR_T)
from .loads import point_body
from .tables import ForceTables, body_index, force_tables

_KINDS = {"R": PAIR_R, "P": PAIR_P, "T": PAIR_T}


@dataclass(frozen=True)
class Program:
    """Flat tables (read the shapes in the field comments). ``generic`` lists, per generic group, its
    (bodies, pair indices), in the order of the rows of ``gr`` whose code is G_GENERIC."""
    ang_order: np.ndarray   # (n_bodies,) int: bodies in an order where a guide precedes its sliders
    ang: np.ndarray         # (n_bodies, 4) int: how, point a, point b, guide body
    ang_param: np.ndarray   # (n_bodies,) int: the line's angle parameter (ANG_LINE)
    ang_off: np.ndarray     # (n_bodies,) float
    massive: np.ndarray     # (n_massive,) int
    mass: np.ndarray        # (n_bodies,) kg
    inertia: np.ndarray     # (n_bodies,) kg·m² (DEF_GIVEN)
    idef: np.ndarray        # (n_bodies,) int
    ipts: np.ndarray        # (n_bodies, K) int: the bar's two points or the polygon's points, -1 padded
    cpts: np.ndarray        # (n_bodies, K) int: the com's points, -1 padded
    cw: np.ndarray          # (n_bodies, K) float: their weights
    coff: np.ndarray        # (n_bodies,) complex: the com's offset in the body frame
    gravity: complex
    lpts: np.ndarray        # (n_loads, 2) int: body, point of each constant force
    lforce: np.ndarray      # (n_loads,) complex N
    torque: np.ndarray      # (n_bodies,) N·m constant torques
    pr: np.ndarray          # (n_pairs, 7) int: kind, earlier, later, point, line, driven input, first column
    ln: np.ndarray          # (n_lines, 5) int: is actuator, guide body, angle parameter, reference point, through point
    gr: np.ndarray          # (n_groups, 12) int: the group table (kernel.GR_*)
    gb: np.ndarray          # (…,) int: the groups' side bodies
    gd: np.ndarray          # (…,) int: the groups' driven slides
    drv: np.ndarray         # (n_inputs,) int: each input's driver pair
    sense: np.ndarray       # (n_inputs,) float: +1, or a crank's sense
    slide_of: np.ndarray    # (n_pairs,) int: the row of each slide or motor pair in the compact (N, M) output, or -1
    n_unknowns: int
    generic: tuple
    #: True when every load is constant (the kernel applies them); False: some are applied in numpy beforehand
    loads_in_kernel: bool

    @property
    def compiled_ok(self) -> bool:
        """True when the compiled kernel covers the whole program (no generic group)."""
        return not self.generic and not self.geared

    #: True when the plan has gear or cam pairs (their tooth and contact forces are applied by the numpy path)
    geared: bool = False


_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def program_of(plan) -> Program:
    prog = _CACHE.get(plan)
    if prog is None:
        prog = build_program(force_tables(plan))
        _CACHE[plan] = prog
    return prog


def build_program(t: ForceTables) -> Program:
    plan = t.plan
    nb = t.n_bodies
    K = max([2] + [len(b.points) for b in plan.structure.graph.bodies])
    ang = np.zeros((nb, 4), np.int64)
    ang_param = np.zeros(nb, np.int64)
    ang_off = np.zeros(nb)
    order: list[int] = []
    for b, rec in enumerate(t.angles):
        if rec.how == "points":
            ang[b] = (ANG_POINTS, rec.a, rec.b, 0)
        elif rec.how == "line":
            ang[b] = (ANG_LINE, 0, 0, rec.guide)
            ang_param[b], ang_off[b] = rec.angle_param, rec.offset
        else:
            ang[b, 0] = ANG_STILL

    def visit(b):
        if b in order:
            return
        if ang[b, 0] == ANG_LINE:
            visit(int(ang[b, 3]))
        order.append(b)

    for b in range(nb):
        visit(b)
    mass, inertia, idef = np.zeros(nb), np.zeros(nb), np.zeros(nb, np.int64)
    ipts, cpts = np.full((nb, K), -1, np.int64), np.full((nb, K), -1, np.int64)
    cw, coff = np.zeros((nb, K)), np.zeros(nb, complex)
    massive = []
    for b, bm in enumerate(t.masses):
        if bm is None:
            continue
        massive.append(b)
        mass[b] = bm.mass
        cpts[b, :len(bm.points)] = bm.points
        cw[b, :len(bm.weights)] = bm.weights
        coff[b] = bm.offset
        body_pts = [plan.point_index(p) for p in plan.structure.graph.bodies[b].points]
        if bm.inertia is not None or bm.default == "zero":
            idef[b], inertia[b] = DEF_GIVEN, bm.inertia or 0.0
        elif bm.default == "bar":
            idef[b] = DEF_BAR
            ipts[b, :2] = body_pts[:2]
        else:
            idef[b] = DEF_POLYGON
            ipts[b, :len(body_pts)] = body_pts
    dyn = t.dynamics
    lpts, lforce, torque = [], [], np.zeros(nb)
    loads_in_kernel = True
    for i, load in enumerate(dyn.loads):
        if load.law is not None or load.opposes is not None:
            loads_in_kernel = False
        elif load.torque is not None:
            torque[body_index(plan, load.link)] += load.torque
        else:
            lpts.append((point_body(t, load.point, load.link, f"loads[{i}].link"), plan.point_index(load.point)))
            lforce.append(complex(load.force[0], load.force[1]))
    pr = np.array([(_KINDS[fp.kind], fp.earlier, fp.later, fp.point, fp.line, fp.driven, fp.columns[0])
                   for fp in t.pairs], np.int64).reshape(-1, 7)
    ln = np.zeros((len(plan.lines), 5), np.int64)
    for i, rec in enumerate(plan.lines):
        kind, name, gb_, slider, through, ia, io, ref, u_slider = rec
        ln[i] = (kind == "actuator", gb_, -1 if ia is None else ia, plan.point_index(ref), plan.point_index(through))
    gr_rows, gb_list, gd_list, generic = [], [], [], []
    for step, bodies, mine in reversed(t.groups):
        row = _group_row(t, bodies, mine, gb_list, gd_list)
        if row is None:
            row = [G_GENERIC] + [0] * 11
            generic.append((bodies, mine))
        gr_rows.append(row)
    sense = np.ones(plan.n_inputs)
    for st in plan.crank_steps():
        sense[st.input] = st.sense
    slide_of = np.full(len(t.pairs), -1, np.int64)
    slide_rows = [k for k, fp in enumerate(t.pairs) if fp.kind != "R"]
    slide_of[slide_rows] = np.arange(len(slide_rows))
    return Program(np.array(order, np.int64), ang, ang_param, ang_off, np.array(massive, np.int64), mass, inertia,
                   idef, ipts, cpts, cw, coff, complex(*dyn.gravity[:2]), np.array(lpts, np.int64).reshape(-1, 2),
                   np.array(lforce, complex), torque, pr, ln, np.array(gr_rows, np.int64).reshape(-1, 12),
                   np.array(gb_list, np.int64), np.array(gd_list, np.int64), np.array(t.driver_pairs, np.int64),
                   sense, slide_of, t.n_unknowns, tuple(generic), loads_in_kernel,
                   geared=bool(getattr(plan, "gear_slots", ())) or bool(getattr(plan, "cam_slots", ())))


def _group_row(t: ForceTables, bodies, mine, gb_list, gd_list):
    """The row of a crank or a dyad, appending its sides to ``gb_list`` and its driven slides to ``gd_list``;
    None for any other shape."""
    pairs = [t.pairs[k] for k in mine]
    if len(bodies) == 1 and sorted(fp.kind for fp in pairs) == ["R", "T"]:
        r = next(k for k in mine if t.pairs[k].kind == "R")
        tt = next(k for k in mine if t.pairs[k].kind == "T")
        a0 = len(gb_list)
        gb_list.append(bodies[0])
        return [G_CRANK, a0, 1, 0, 0, r, 0, tt, 0, 0, 0, 0]
    unit = {b: b for b in bodies}
    driven = [k for k in mine if t.pairs[k].kind == "P" and t.pairs[k].driven >= 0 and t.pairs[k].earlier in unit]
    for k in driven:
        fp = t.pairs[k]
        lo, hi = sorted((unit[fp.earlier], unit[fp.later]))
        for b in bodies:
            if unit[b] == hi:
                unit[b] = lo
    sides: dict[int, list[int]] = {}
    for b in bodies:
        sides.setdefault(unit[b], []).append(b)
    if len(sides) != 2:
        return None
    (ua, side_a), (ub, side_b) = sides.items()
    inner = [k for k in mine if t.pairs[k].earlier in unit and k not in driven]
    outer = [k for k in mine if t.pairs[k].earlier not in unit]
    if len(inner) != 1 or len(outer) != 2 or any(t.pairs[k].kind == "T" or t.pairs[k].driven >= 0 for k in outer):
        return None
    side = [0 if unit[t.pairs[k].later] == ua else 1 for k in outer]
    if sorted(side) != [0, 1]:
        return None
    oa, ob = (outer[0], outer[1]) if side[0] == 0 else (outer[1], outer[0])
    ik = inner[0]
    later_b = 1 if unit[t.pairs[ik].later] == ub else 0
    kinds = (t.pairs[oa].kind, t.pairs[ob].kind)
    if t.pairs[ik].kind == "R":
        code, r_side = G_INNER_R, 0
    else:
        if kinds == ("R", "R"):
            r_side = 2
        elif kinds == ("R", "P"):
            r_side = 0
        elif kinds == ("P", "R"):
            r_side = 1
        else:
            return None
        code = G_INNER_P
    a0 = len(gb_list)
    gb_list.extend(side_a)
    b0 = len(gb_list)
    gb_list.extend(side_b)
    d0 = len(gd_list)
    gd_list.extend(driven)
    return [code, a0, len(side_a), b0, len(side_b), oa, ob, ik, d0, len(driven), later_b, r_side]
