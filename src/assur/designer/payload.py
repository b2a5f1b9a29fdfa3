"""What the designer's page draws: one solve of the whole cycle of a document, as named float64 arrays and a
small JSON description (the protocol of ``docs/designer.md``).

:func:`describe` compiles a document and solves its cycle once (positions, velocities and accelerations in
time at the driver's speed), then derives everything the page shows from that one state: the links' angular
rates and instant centres, the groups' transmission angles, the dead centres, the gait of a walking leg, the
feet on the ground of a module and, when the file has masses, the driving torque and power.
"""
from __future__ import annotations

import copy
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..errors import AssurError

#: samples of the input's cycle the page receives (one turn of a crank, or a linear driver's stroke)
DESIGNER_STEPS = 360


@dataclass
class Description:
    """A described document: ``meta`` (JSON-ready: ``model``, ``cycle``, ``diagnostics``), ``arrays`` (name →
    float64 array, SI), the compiled ``plan`` (None when the document is not a mechanism yet) and the
    ``params`` the cycle was solved with."""
    meta: dict
    arrays: dict = field(default_factory=dict)
    plan: object = None
    params: object = None
    mechanism: object = None


def _diagnostic(level: str, code: str, message: str, where: str = "") -> dict:
    return {"level": level, "code": code, "message": message, "where": where}


def _model_of_doc(doc: dict) -> dict:
    """The names and topology the page needs, read from the document itself (so a document that is not a
    mechanism yet still draws)."""
    from ..io.units import parse_speed
    from ..model.mechanism import Units
    from .document import angle_factor, link_points, locks
    from .motor_job import motor_hint
    links = doc.get("links", {})
    lp, ll = locks(doc)
    try:
        units = Units(**{k: v for k, v in doc.get("units", {}).items() if k in ("length", "angle")})
        fA = angle_factor(doc)
    except (TypeError, KeyError):
        units, fA = Units(), math.pi / 180
    drivers = []
    for d in doc.get("drivers", []):
        rec = {k: d.get(k) for k in ("name", "kind", "link", "pivot", "arm", "actuator", "speed")}
        try:    # SI (rad/s or m/s) by the file reader's own rule: the page never parses "27 rpm"
            rec["speed_si"] = parse_speed(d.get("speed", 1.0 if d.get("kind", "rotary") == "rotary" else 0.0),
                                          d.get("kind", "rotary"), units)
        except (AssurError, ValueError, TypeError, KeyError):
            rec["speed_si"] = None
        drivers.append(rec)
    gait = doc.get("gait", {})
    return {
        "dimension": int(doc.get("dimension", 2)),
        "points": list(doc.get("points", {})),
        "frame_points": link_points(links.get("frame", [])),
        "links": [{"name": n, "points": link_points(e)} for n, e in links.items()],
        "sliders": [{k: s.get(k) for k in ("name", "guide", "through", "point", "link")}
                    | {"angle_si": float(s["angle"]) * fA if isinstance(s.get("angle"), (int, float)) else 0.0}
                    for s in doc.get("prismatic", [])],
        "actuators": [{"name": n, "between": list(t.get("between", []))} for n, t in doc.get("actuators", {}).items()],
        "drivers": drivers,
        "locks": {"points": lp, "links": ll},
        "foot": gait.get("foot"),
        "motor": copy.deepcopy(doc["motor"]) if isinstance(doc.get("motor"), dict) else None,
        "motor_hint": motor_hint(doc),
        "groups": [], "mobility": None, "formula": None, "params": [], "newton_groups": 0, "chooser": False,
    }


def branched_steps(plan) -> list:
    """The steps with an assembly branch, in solve order: (step index, step)."""
    return [(i, st) for i, st in enumerate(plan.steps) if st.key_point is not None]


def group_records(plan, structure) -> list[dict]:
    """One record per branched step: its label, kind, point, branch sign and whether the page may flip it (an RPR
    group also names its ``slide``: the prismatic pair or actuator it slides on)."""
    labels = {}
    if structure is not None:
        from ..structure.assur import roman
        for g in structure.groups:
            names = ", ".join(dict.fromkeys(structure.graph.bodies[b].source or structure.body_label(b)
                                            for b in g.bodies))
            for b in g.bodies:
                labels[b] = f"{roman(g.group_class)}({names})"
    out = []
    for k, (i, st) in enumerate(branched_steps(plan)):
        label = next((labels[b] for b in st.bodies if b in labels), f"{st.kind}({st.key_point})")
        out.append({"index": k, "step": i, "label": label, "kind": st.kind, "point": st.key_point,
                    "points_in": list(st.points_in()), "branch": int(st.branch),
                    "flippable": plan.dimension == 2}
                   | ({"slide": plan.lines[st.line][1]} if st.kind == "RPR" else {}))
    return out


def _instant_centres(plan, state) -> np.ndarray:
    """(n, B, 2): each link's instant centre relative to the frame, I = P + k×v_P/ω from one of its points
    (NaN for the frame, bodies without a named point, and where |ω| is below round-off)."""
    pos, vel, omega = state.pos, state.vel, state.body_omega
    n, B = omega.shape[0], omega.shape[-1]
    out = np.full((n, B, 2), np.nan)
    index = {p: i for i, p in enumerate(plan.point_names)}
    by_name = {lk.name: lk.points for lk in plan.mechanism.links}
    scale = max(1e-12, float(np.nanmax(np.abs(vel)))) if np.isfinite(vel).any() else 1.0
    for b, name in enumerate(plan.body_names):
        pts = by_name.get(name)
        if b == 0 or not pts:
            continue
        i = index[pts[0]]
        w = omega[:, b]
        with np.errstate(divide="ignore", invalid="ignore"):
            ok = np.abs(w) * max(1.0, float(np.nanmax(np.abs(pos)))) > 1e-9 * scale
            out[:, b, 0] = np.where(ok, pos[:, i, 0] - vel[:, i, 1] / w, np.nan)
            out[:, b, 1] = np.where(ok, pos[:, i, 1] + vel[:, i, 0] / w, np.nan)
    return out


def _all_centres(study, meta: dict, arrays: dict) -> None:
    """Every relative instant centre over the run (the Study's field): ``centres`` (n, pairs, 2) (NaN at infinity),
    the model's ``centre_pairs`` [[i, j]] (body indices) and ``kennedy`` [[ij, jk, ik]] (pair indices per triple of
    bodies: the three centres Kennedy's theorem puts on one line), for the page's "all centres" view."""
    ic = study.instant_centres
    pts = ic.points
    arrays["centres"] = np.stack([np.where(np.isfinite(pts), pts.real, np.nan),
                                  np.where(np.isfinite(pts), pts.imag, np.nan)], axis=-1)
    meta["model"]["centre_pairs"] = [list(p) for p in ic.pairs]
    meta["model"]["kennedy"] = [list(t) for _, t in ic.kennedy_lines(0)] if len(pts) else []


def _cycle_meta(plan, k: int, turn: bool, valid) -> dict:
    """The ``cycle`` description of a solved cycle of input ``k`` (the analyses fill in their entries)."""
    return {"n": int(len(valid)), "turn": bool(turn),
            "input": {"name": plan.input_names[k], "kind": plan.input_kinds[k], "index": int(k),
                      "speed": float(plan.speeds[k]), "sketch": float(plan.sketch_inputs[k])},
            "assembled": int(valid.sum()), "driver": plan.mechanism.drivers[k].name,
            "dead_centres": [], "gait": None, "module": None, "forces": None}


def _cycle_planar(plan, params, meta: dict, arrays: dict, steps: int, exact: bool) -> None:
    """The page's arrays and cycle description from one :class:`~assur.analysis.study.Study` of the document: its
    run, transmission angles, dead centres, gait and forces (``exact``: dead centres and gait refined to their
    roots, as ``assur analyze``; else read off the run's samples, for the previews of a drag)."""
    from ..analysis.study import Study
    from ..analysis.transmission import dead_centres
    study = Study(plan, params, steps)
    k, turn, state = study.moving, study.cyclic, study.state
    valid = np.asarray(state.valid, dtype=bool)
    arrays.update(q=study.q, valid=valid.astype(float), pos=state.pos, vel=state.vel, acc=state.acc,
                  omega=state.body_omega, alpha=state.body_alpha, ic=_instant_centres(plan, state))
    _all_centres(study, meta, arrays)
    mu = study.transmission
    groups = meta["model"]["groups"]
    arrays["transmission"] = np.stack([mu.get(g["point"], np.full(valid.shape, np.nan)) for g in groups], axis=-1) \
        if groups else np.zeros((len(valid), 0))
    c = meta["cycle"] = _cycle_meta(plan, k, turn, valid)
    if study.turn:
        centres = study.dead_centres if exact else dead_centres(study, refine=False)
        c["dead_centres"] = [{"q": float(dc.angle), "kind": dc.kind, "link": dc.link, "crank": dc.crank}
                             for dc in centres]
    if c["assembled"] < len(valid):
        meta["diagnostics"].append(_diagnostic(
            "warning", "unbuildable",
            f"the mechanism cannot be assembled at {len(valid) - c['assembled']} of {len(valid)} samples "
            f"of the input {plan.input_names[k]} (drawn as gaps)", plan.input_names[k]))
    if study.turn and plan.mechanism.gait is not None:
        _gait(study, meta, arrays, exact)
    if plan.n_inputs == 1:
        _forces(study, meta, arrays)


def _gait(study, meta, arrays, exact: bool) -> None:
    """The gait of the foot: the Study's exact gait (refined to its roots, as ``assur analyze``) or its sampled one
    (for previews during a drag). Both give the same keys."""
    from ..analysis.gait import arc_mask, population_contact
    plan, state = study.plan, study.state
    g = plan.mechanism.gait
    i = plan.point_index(g.foot)
    valid = np.asarray(state.valid, dtype=bool)
    if not valid.all():
        meta["diagnostics"].append(_diagnostic("warning", "gait", "no gait: the leg does not assemble over the "
                                                                  "whole turn", g.foot))
        return
    if exact:
        # the committed document's gait is what `assur analyze` reports: its Study of CYCLE_STEPS samples
        from ..analysis.study import Study
        from ..analysis.sampling import CYCLE_STEPS
        exact_study = study if study.steps == CYCLE_STEPS else Study(plan, study.params)
        m = exact_study.gait
        if m is None:
            meta["diagnostics"].append(_diagnostic("warning", "gait", exact_study.gait_error or "no gait", g.foot))
            return
        gait = {"step_length": m.step_length, "lift": m.lift, "sag": m.sag, "duty_factor": m.duty_factor,
                "support_speed_mean": m.support_speed.mean,
                "support_speed_spread": (m.support_speed.max - m.support_speed.min) / m.support_speed.mean,
                "support": m.support}
    else:
        pg = study.population_gait
        gait = {"step_length": pg["step"], "lift": pg["lift"], "sag": pg["sag"], "duty_factor": pg["duty"],
                "support_speed_mean": pg["speed_mean"], "support_speed_spread": pg["speed_spread"], "support": None}
    meta["cycle"]["gait"] = {k: (float(v) if k != "support" else v) for k, v in gait.items()} | \
        {"foot": g.foot, "exact": bool(exact)}
    if len(g.phases) > 1:
        M = len(valid)
        start, width = population_contact(state.pos[None, :, i], ground=g.ground, up=g.up_vector)
        contact = arc_mask(start, width, M)[0]
        shifts = np.rint(np.asarray(g.phases) / (2 * math.pi) * M).astype(int)
        feet = sum(np.roll(contact, -k) for k in shifts).astype(float)
        arrays["feet"] = feet
        meta["cycle"]["module"] = {"phases": [float(p) for p in g.phases], "min_feet": int(feet.min()),
                                   "max_feet": int(feet.max())}


def _forces(study, meta, arrays) -> None:
    """The driving torque and power over the run when the file has masses or loads (the Study's forces)."""
    plan = study.plan
    if not study.has_loads:
        return
    try:
        f = study.forces
    except AssurError as exc:
        meta["diagnostics"].append(_diagnostic("warning", "forces", str(exc)))
        return
    arrays["torque"] = np.asarray(f.driver)[..., 0]
    arrays["power"] = np.asarray(f.power)
    unit = "N·m" if plan.input_kinds[0] == "rotary" else "N"
    meta["cycle"]["forces"] = {"effort_unit": unit, "peak_effort": float(np.nanmax(np.abs(arrays["torque"]))),
                               "peak_power": float(np.nanmax(np.abs(arrays["power"]))),
                               "mean_power": float(np.nanmean(arrays["power"]))}


def _cycle_spatial(plan, params, meta, arrays, steps: int) -> None:
    from ..analysis.study import Study
    study = Study(plan, params, steps)
    state = study.state
    valid = np.asarray(state.valid, dtype=bool)
    arrays.update(q=study.q, valid=valid.astype(float), pos=state.pos, vel=state.vel, acc=state.acc)
    meta["cycle"] = _cycle_meta(plan, study.moving, study.cyclic, valid)


def parameter_records(plan, params) -> list[dict]:
    """The sliders of the spatial view: every parameter with its value and a range around it (SI): a link's
    length from half to one and a half times its value, a coordinate or offset ± half the mechanism's size around
    its value, an angle ± 45°."""
    out = []
    scale = float(plan.length_scale)
    for i, name in enumerate(plan.param_names):
        v = float(params[i])
        kind = plan.param_kind_of(name)
        if kind == "length" and name.endswith(".length"):
            lo, hi = 0.5 * v, 1.5 * v
        elif kind == "length":
            lo, hi = v - 0.5 * scale, v + 0.5 * scale
        else:
            lo, hi = v - math.pi / 4, v + math.pi / 4
        out.append({"name": name, "kind": kind, "value": v, "min": lo, "max": hi})
    return out


def describe(doc: dict, overrides: dict | None = None, steps: int = DESIGNER_STEPS, exact: bool = True,
             compiled=None) -> Description:
    """Compile and solve a document (see the module docstring). Never raises for a document that is not a
    mechanism: the reason is a diagnostic and ``cycle`` is None. ``exact``: gait metrics refined to their roots
    (else on the samples, for the previews of a drag). ``compiled``: the document's ``(mechanism, structure, plan,
    warnings)`` or the AssurError that stops it, when already known (:meth:`.compiled.Compiled.described`)."""
    meta = {"model": _model_of_doc(doc), "cycle": None, "diagnostics": []}
    arrays: dict = {}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            if isinstance(compiled, AssurError):
                raise compiled
            if compiled is None:
                from .compiled import StructureCache, compile_doc
                compiled = compile_doc(doc, StructureCache()).described()
                if isinstance(compiled, AssurError):
                    raise compiled
            mech, structure, plan, warned = compiled
        except AssurError as exc:
            meta["diagnostics"].append(_diagnostic("error", "structure", str(exc)))
            _sketch(doc, arrays)
            return Description(meta, arrays)
        for w in warned:
            meta["diagnostics"].append(_diagnostic("warning", type(w.message).__name__, str(w.message)))
        m = meta["model"]
        m["mobility"], m["formula"] = int(structure.mobility), structure.structural_formula
        m["groups"] = group_records(plan, structure)
        m["newton_groups"] = len(plan.newton_steps())
        if m["newton_groups"]:
            from .choosing import available
            m["chooser"] = available()
        m["point_order"] = list(plan.point_names)
        m["body_names"] = list(plan.body_names)
        m["gears"] = gear_records(mech)
        m["cams"] = cam_records(plan) if plan.dimension == 2 else []
        params = plan.defaults.copy()
        for name, value in (overrides or {}).items():
            if name in plan.param_names:
                params[plan.param_index(name)] = float(value)
        if plan.dimension == 3:
            m["params"] = parameter_records(plan, params)
        try:
            if plan.dimension == 2:
                _cycle_planar(plan, params, meta, arrays, steps, exact)
            else:
                _cycle_spatial(plan, params, meta, arrays, steps)
        except AssurError as exc:
            meta["diagnostics"].append(_diagnostic("error", "cycle", str(exc)))
        arrays["sketch"] = np.array([mech.sketch(p) for p in plan.point_names], dtype=float)
    for w in caught:
        meta["diagnostics"].append(_diagnostic("warning", type(w.message).__name__, str(w.message)))
    return Description(meta, arrays, plan, params, mech)


def gear_records(mech, samples: int = 180) -> list[dict]:
    """Each gear pair's two pitch curves for the page to draw turning with their links: per curve its link's
    ``pivot`` and ``arm`` points, the sketch angle ``angle0`` of pivot → arm (rad) and ``xy`` (samples, 2), the
    curve relative to the pivot in the sketch orientation (m; :func:`assur.model.gearing.pitch_points`)."""
    from ..model.gearing import gear_ends, pitch_points
    out = []
    for gp in mech.gears:
        ends = []
        for pivot, arm in gear_ends(mech, gp):
            z0, z1 = (complex(*mech.sketch(p)[:2]) for p in (pivot, arm))
            ends.append((pivot, arm, z0, float(np.angle(z1 - z0))))
        curves = pitch_points(gp, ends[0][2], ends[1][2], samples=samples)
        out.append({"name": gp.name, "curves": [
            {"pivot": pivot, "arm": arm, "angle0": angle0,
             "xy": np.round(np.column_stack([c.real, c.imag]), 12).tolist()}
            for (pivot, arm, _, angle0), c in zip(ends, curves)]})
    return out


def cam_records(plan, samples: int = 240) -> list[dict]:
    """Each cam pair's profile for the page to draw turning with its cam, as a gear's pitch curve: the cam's
    ``pivot`` and ``arm`` points, the sketch angle ``angle0`` of pivot → arm (rad), ``xy`` (samples, 2) the profile
    relative to the pivot in the sketch orientation (m), and the follower's ``point`` and ``roller`` radius (m)."""
    from ..cams.followers import from_plan
    from ..model.camming import cam_ends
    out = []
    for k, cp in enumerate(plan.mechanism.cams):
        try:
            g = from_plan(plan, k)
        except AssurError:
            continue
        pivot, arm = cam_ends(plan.mechanism, cp)
        z = g.orientation * g.profile(samples)
        out.append({"name": cp.name, "pivot": pivot, "arm": arm, "angle0": float(np.angle(g.orientation)),
                    "xy": np.round(np.column_stack([z.real, z.imag]), 12).tolist(), "point": cp.point,
                    "roller": cp.roller_radius if cp.contact == "roller" else 0.0})
    return out


def _sketch(doc: dict, arrays: dict) -> None:
    from .document import length_factor
    fL = length_factor(doc)
    pts = list(doc.get("points", {}).values())
    if pts:
        arrays["sketch"] = np.array([[c * fL for c in p] for p in pts], dtype=float)


def pack(arrays: dict) -> tuple[dict, bytes]:
    """(index, blob): every array as little-endian float64 in one blob; ``index`` maps a name to
    ``[offset, length, shape]`` in float64 elements."""
    index, parts, offset = {}, [], 0
    for name, a in arrays.items():
        a = np.ascontiguousarray(a, dtype="<f8")
        index[name] = [offset, int(a.size), list(a.shape)]
        parts.append(a.tobytes())
        offset += a.size
    return index, b"".join(parts)


def unpack(index: dict, blob: bytes) -> dict:
    """The arrays of :func:`pack` back: name → read-only float64 array of its shape (views on ``blob``)."""
    return {name: np.frombuffer(blob, dtype="<f8", count=length, offset=8 * offset).reshape(shape)
            for name, (offset, length, shape) in index.items()}
