"""The targets of a synthesis problem (``[targets]`` of a problem file): what a design must meet.

Three kinds: ``points`` (path generation: positions of a coupler point), ``function`` (function
generation: input/output angle pairs of a link) and ``poses`` (motion generation: positions of a point
and angles of its link), each with the timings of the input: prescribed, free, uniform, or (points only)
none (``path``). Numbers in the file's units; a :class:`Targets` holds SI.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass

import numpy as np

TIMINGS = ("prescribed", "free", "uniform", "path")
#: what [targets] prescribes: coupler points (path generation), input/output angle pairs of a link (function
#: generation) or poses (x, y, angle) of a link (motion generation)
TARGET_KINDS = ("points", "function", "poses")
#: the output of function targets: the link's angle change from its angle at the first input, or its angle
FUNCTION_OUTPUTS = ("relative", "absolute")


@dataclass(frozen=True, slots=True)
class Targets:
    """What the design must meet, N targets. timing 'prescribed': ``inputs`` (N,); 'free':
    ``input_variables`` (N names); 'uniform': ``start`` variable + ``step`` (rad); 'path': no timing
    (distance to the nearest point of the sampled path; points only).

    kind 'points': positions ``xy`` (N, 2) SI of ``point``. kind 'function': ``xy`` (N, 2) the input/output
    angle pairs (rad) of ``link`` (its angle: the line from its first point to its second); ``relative``:
    the output is the angle change from the angle at the first input; uniform timing puts input i at
    ``start + (x_i − x_0)``. kind 'poses': positions ``xy`` (N, 2) SI of ``point`` and the angles ``angles``
    (N,) rad of ``link``; a pose's deviation is |Δp| + ``angle_weight`` (m per rad)·|Δθ|."""
    point: str | None
    xy: np.ndarray
    timing: str
    inputs: np.ndarray | None = None
    input_variables: tuple[str, ...] = ()
    start: str | None = None
    step: float = 0.0
    kind: str = "points"
    link: str | None = None
    angles: np.ndarray | None = None
    relative: bool = True
    angle_weight: float = 0.0
    free_timing: str = "explicit"      # free timing: "inner" (solved per design) or "explicit" (design variables)
    placement: str = "inner"           # point targets: the design's placement solved per design where it can be

    @property
    def n(self) -> int:
        return len(self.xy)


def _did_you_mean(name: str, known) -> str:
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


#: how free timing is solved: "inner" — each design's best input per target, inside the evaluation (the optimiser
#: searches the design variables only); "explicit" — the inputs are design variables the optimiser searches
FREE_TIMINGS = ("inner", "explicit")
#: how the placement of a design (its position, angle and size; :mod:`assur.synthesis.placement`) is found: "inner" —
#: in closed form per design, where the problem allows it; "explicit" — its variables are searched like the others
PLACEMENTS = ("inner", "explicit")
_TARGET_KEYS = {"points": ("point", "xy", "timing", "inputs", "variables", "start", "step", "free_timing",
                           "placement"),
                "function": ("link", "pairs", "output", "timing", "variables", "start"),
                "poses": ("link", "point", "poses", "angle_weight", "timing", "inputs", "variables", "start", "step",
                          "free_timing")}


def _target_link(raw, plan, P) -> str | None:
    """The moving link named by ``targets.link`` (None after reporting a problem)."""
    link = raw.get("link")
    moving = [b for b in plan.body_names if b != "frame"]
    if link not in moving:
        P.add("targets.link", f"unknown link {link!r}{_did_you_mean(str(link), moving)} (moving links: "
                              f"{', '.join(moving)})")
        return None
    return link


def _target_array(raw, key, width, P) -> np.ndarray | None:
    """targets.<key> as an (N, width) finite array (None after reporting a problem)."""
    try:
        a = np.array(raw.get(key), dtype=float)
    except (TypeError, ValueError):
        a = None
    if a is None or a.ndim != 2 or a.shape[1] != width or len(a) < 1 or not np.all(np.isfinite(a)):
        shape = "[x, y]" if width == 2 and key == "xy" else "[input, output]" if key == "pairs" else "[x, y, angle]"
        got = "" if a is None else f" (got shape {a.shape})"
        P.add(f"targets.{key}", f"must be a list of {shape} rows of finite numbers{got}")
        return None
    return a


def parse_targets(raw, plan, L, A, number, P) -> Targets | None:
    """The [targets] table → Targets in SI (L, A: the file's length and angle units in SI; ``number``
    reads a finite number; every problem goes to ``P`` with its location); None when absent or invalid."""
    if raw is None:
        return None
    if not isinstance(raw, dict):
        P.add("targets", "must be a table")
        return None
    kind = raw.get("kind", "points")
    if kind not in TARGET_KINDS:
        P.add("targets.kind", f"must be one of {', '.join(TARGET_KINDS)}: {kind!r}")
        return None
    P.unknown_keys(raw, ("kind", *_TARGET_KEYS[kind]), "targets")
    extra = {"kind": kind}
    if kind == "points":
        placement = raw.get("placement", "inner")
        if placement not in PLACEMENTS:      # reported; the rest of the targets is still read
            P.add("targets.placement", f"must be one of {', '.join(PLACEMENTS)}: {placement!r}")
            placement = "explicit"
        extra["placement"] = placement
    point = None
    if kind != "function":
        point = raw.get("point")
        if point not in plan.point_names:
            P.add("targets.point", f"unknown point {point!r} (known: {', '.join(plan.point_names)})")
            return None
    if kind != "points":
        link = _target_link(raw, plan, P)
        if link is None:
            return None
        extra["link"] = link
        if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
            P.add("targets.kind", f"{kind} targets need a mechanism with one rotary input")
            return None
    if kind == "poses":
        members = next((lk.points for lk in plan.mechanism.links if lk.name == extra["link"]), ())
        if point not in members:
            P.add("targets.point", f"point {point!r} is not on link {extra['link']!r} (its points: "
                                   f"{', '.join(members)})")
            return None
        poses = _target_array(raw, "poses", 3, P)
        if poses is None:
            return None
        xy, extra["angles"] = poses[:, :2], poses[:, 2] * A
        spread = max((float(np.hypot(*(a - b))) for a in xy for b in xy), default=0.0)
        w = raw.get("angle_weight", spread if spread > 0 else 1.0)
        w = number("targets.angle_weight", w)
        if w is None or w < 0:
            if w is not None:
                P.add("targets.angle_weight", f"must not be negative: {w:g}")
            return None
        extra["angle_weight"] = w * L
    elif kind == "function":
        pairs = _target_array(raw, "pairs", 2, P)
        if pairs is None:
            return None
        output = raw.get("output", "relative")
        if output not in FUNCTION_OUTPUTS:
            P.add("targets.output", f"must be one of {', '.join(FUNCTION_OUTPUTS)}: {output!r}")
            return None
        extra["relative"] = output == "relative"
        xy = pairs * (A / L)        # the angle pairs, scaled back by L below (SI: rad)
    else:
        xy = _target_array(raw, "xy", 2, P)
        if xy is None:
            return None
    n = len(xy)
    timing = raw.get("timing", "prescribed" if "inputs" in raw or kind == "function" else
                     "path" if kind == "points" else None)
    if timing not in TIMINGS or (timing == "path" and kind != "points"):
        allowed = TIMINGS if kind == "points" else TIMINGS[:3]
        P.add("targets.timing", f"must be one of {', '.join(allowed)}" + (f" for {kind} targets" if kind != "points"
                                                                          else "") + f": {timing!r}")
        return None
    if "free_timing" in raw and timing != "free":
        P.add("targets.free_timing", f"applies to free timing only (timing = \"free\"), not {timing!r}")
        return None
    unit = A if plan.input_kinds[0] == "rotary" else L
    if timing == "prescribed":
        if kind == "function":
            return Targets(point, xy * L, timing, inputs=pairs[:, 0] * A, **extra)
        try:
            q = np.array(raw.get("inputs"), dtype=float)
        except (TypeError, ValueError):
            q = None
        if q is None or q.shape != (n,) or not np.all(np.isfinite(q)):
            P.add("targets.inputs", f"must list one input value per target ({n})")
            return None
        return Targets(point, xy * L, timing, inputs=q * unit, **extra)
    if timing == "free":
        names = raw.get("variables")
        if not (isinstance(names, list) and len(names) == n and all(isinstance(s, str) for s in names)):
            P.add("targets.variables", f"free timing needs one design variable name per target ({n})")
            return None
        ft = raw.get("free_timing", "explicit" if kind == "function" else "inner")
        if ft not in FREE_TIMINGS:
            P.add("targets.free_timing", f"must be one of {', '.join(FREE_TIMINGS)}: {ft!r}")
            return None
        return Targets(point, xy * L, timing, input_variables=tuple(names), free_timing=ft, **extra)

    if timing == "uniform":
        start = raw.get("start")
        if not isinstance(start, str):
            P.add("targets.start", "uniform timing needs the design variable of the first input")
            return None
        if kind == "function":   # the inputs keep the pairs' spacing: input i = start + (x_i − x_0)
            step = (pairs[-1, 0] - pairs[0, 0]) / max(n - 1, 1)
        else:
            step = number("targets.step", raw.get("step"))
            if step is None or step == 0:
                P.add("targets.step", "uniform timing needs a non-zero step")
                return None
        return Targets(point, xy * L, timing, start=start, step=step * unit, **extra)
    return Targets(point, xy * L, timing, **extra)


__all__ = ["FREE_TIMINGS", "FUNCTION_OUTPUTS", "TARGET_KINDS", "TIMINGS", "Targets", "parse_targets"]


# -- deviations -------------------------------------------------------------------------------------------
def wrap_angle(a):
    """Angles wrapped into [−π, π)."""
    return np.mod(np.asarray(a) + np.pi, 2.0 * np.pi) - np.pi


def target_offsets(t: Targets, plan, st, theta, length_scale: float, angle_scale: float):
    """(offsets (n, N, k), distances (n, N)) of a population's solved target states ``st`` (n, N) at the inputs
    ``theta`` (n, N), in the file's units; a squared deviation is Σ |offsets|², a plain one Σ distances.

    points: the offsets (x, y) of the point from its targets, distance their length. function: the output
    error ε = ψ_i − ψ_0 − (y_i − y_0) (relative) or ψ_i − y_i (absolute), wrapped into [−π, π), in the angle
    unit; with free timing also the input error (θ_i − θ_0) − (x_i − x_0) as a second offset. poses: distance
    |Δp| + w·|Δθ| (Δθ wrapped), kept as the one offset."""
    if t.kind == "points":
        off = (st.pos[:, :, plan.point_index(t.point), :] - t.xy) * length_scale
        return off, np.linalg.norm(off, axis=-1)
    psi = st.body_angle[:, :, plan.body_names.index(t.link)]                     # (n, N)
    if t.kind == "function":
        x, y = t.xy[:, 0], t.xy[:, 1]
        out = wrap_angle(psi - psi[:, :1] - (y - y[0])) if t.relative else wrap_angle(psi - y)
        parts = [out]
        if t.timing == "free":
            parts.insert(0, wrap_angle(theta - theta[:, :1] - (x - x[0])))
        off = np.stack(parts, axis=-1) * angle_scale
        return off, np.linalg.norm(off, axis=-1)
    dp = np.linalg.norm(st.pos[:, :, plan.point_index(t.point), :] - t.xy, axis=-1)
    d = (dp + t.angle_weight * np.abs(wrap_angle(psi - t.angles))) * length_scale
    return d[..., None], d
