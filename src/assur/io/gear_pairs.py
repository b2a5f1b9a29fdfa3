"""The ``[[gears]]`` entries of a mechanism file: gear pairs between links turning about frame pivots.

::

    [[gears]]
    name = "drive"
    a = "motor"            # the driving link (turns about a frame pivot)
    b = "crank"            # the driven link (turns about a frame pivot)
    law = 2                # a number: circular gears, the driving link turns `law` times per driven turn
    # law = "phi + 0.2*sin(phi)"             an expression: the driven rotation θ of the driving rotation phi (rad)
    # law = { phi = [...], theta = [...] }   a table over one driving turn (file angle units; phi from 0 to
    #                                         below 360, or to 360 with θ closing there)
    # law = "walker_gears.toml"              a gear design file (assur-gears/1), relative to this file
    driving_turns = 1      # driving turns per driven turn of a non-circular law (default 1; a design file's own)
    mesh = "external"      # or "internal"
    phase = 0              # the law's driving angle at the sketch (file angle unit)
    pressure_angle = 20    # the teeth's (file angle unit; default a design file's, else 20°)

A non-circular law is sampled at :data:`LAW_SAMPLES` points per driving turn and held as a periodic quintic
spline (:class:`~assur.model.gearing.GearLaw`). A law must increase, start at θ(0) = 0 and close
(θ(φ + 2π) = θ(φ) + 2π/n); a law with corners (a ratio that jumps) is refused: the driven link's acceleration
would be unbounded there. Every problem is reported with its field path (``gears[0].law`` …).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import ExpressionError, SpecError
from ..model.gearing import MESH_SIGNS, TWO_PI, GearLaw, GearPair
from ..model.mechanism import FRAME

#: samples per driving turn of a non-circular law held by a mechanism file
LAW_SAMPLES = 4096
#: a law's ratio dθ/dφ may differ from its spline's by this fraction before the law counts as cornered
CORNER_TOLERANCE = 1e-6
_KEYS = ("a", "b", "driving_turns", "law", "mesh", "name", "phase", "pressure_angle")


def read_gear_pairs(data: dict, P, *, angle_factor: float, link_points: dict, frame_points: set,
                    source: str | None) -> tuple[GearPair, ...]:
    """The gear pairs of a parsed mechanism file (problems go to ``P``, a :class:`~assur.io.problems.Problems`).
    ``link_points``: link name → its points; ``frame_points``: the frame's points."""
    gdata = P.section(data, "gears", "must be an array of tables [[gears]]", list)
    out, seen = [], set()
    for i, spec in enumerate(gdata):
        path = f"gears[{i}]"
        if not isinstance(spec, dict):
            P.add(path, "must be a table")
            continue
        P.unknown_keys(spec, _KEYS, path)
        name = spec.get("name", f"gears{i + 1}")
        if not isinstance(name, str) or not name or name in seen:
            P.add(f"{path}.name", f"must be a unique name: {name!r}")
        seen.add(str(name))
        ends = []
        for key in ("a", "b"):
            link = spec.get(key)
            if not isinstance(link, str) or link not in link_points or link == FRAME:
                known = ", ".join(sorted(set(link_points) - {FRAME}))
                P.add(f"{path}.{key}", f"must be a moving link (known: {known}): {link!r}")
            elif not set(link_points[link]) & frame_points:
                P.add(f"{path}.{key}", f"link '{link}' must turn about a frame pivot (share a point with the frame)")
            ends.append(link)
        if len(ends) == 2 and ends[0] == ends[1] and isinstance(ends[0], str):
            P.add(f"{path}.b", f"must differ from a: {ends[1]!r}")
        mesh = spec.get("mesh", "external")
        if not isinstance(mesh, str) or mesh not in MESH_SIGNS:
            P.add(f"{path}.mesh", f"must be 'external' or 'internal': {mesh!r}")
            mesh = "external"
        phase = _angle(spec, "phase", 0.0, angle_factor, path, P)
        law, design, alpha = _law(spec, angle_factor, path, P, source)
        if "pressure_angle" in spec:
            alpha = _angle(spec, "pressure_angle", 20.0, angle_factor, path, P)
            if not 0 < alpha < math.pi / 2:
                P.add(f"{path}.pressure_angle", "must be between 0 and 90°")
        if law is not None and all(isinstance(e, str) for e in ends):
            out.append(GearPair(str(name), ends[0], ends[1], law, mesh, phase, alpha, design))
    return tuple(out)


def _angle(spec, key, default, factor, path, P) -> float:
    v = spec.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or abs(v) > 1e9:
        P.add(f"{path}.{key}", f"must be a finite angle: {v!r}")
        return 0.0
    return float(v) * (factor if key in spec else math.pi / 180.0)


def _turns(spec, path, P, default=1) -> int:
    n = spec.get("driving_turns", default)
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        P.add(f"{path}.driving_turns", f"must be a whole number ≥ 1: {n!r}")
        return 1
    return n


def _law(spec, angle_factor, path, P, source):
    """(GearLaw or None, design file or None, pressure angle from a design file or 20°)."""
    alpha = math.radians(20.0)
    v = spec.get("law")
    where = f"{path}.law"
    if v is None:
        P.add(where, "is required: a ratio, an expression in phi, a table {phi, theta} or a gear design file")
        return None, None, alpha
    if isinstance(v, bool):
        P.add(where, f"must be a ratio, an expression, a table or a file: {v!r}")
        return None, None, alpha
    if isinstance(v, (int, float)):
        if not (math.isfinite(v) and 0 < v < 1e9):
            P.add(where, f"a ratio must be a finite number > 0 (driving turns per driven turn): {v!r}")
            return None, None, alpha
        if "driving_turns" in spec:
            P.add(f"{path}.driving_turns", "applies to a non-circular law only (a ratio law's turns are the ratio)")
        return GearLaw("ratio", ratio=float(v), source=f"ratio {v:g}"), None, alpha
    if isinstance(v, dict):
        n = _turns(spec, path, P)
        P.unknown_keys(v, ("phi", "theta"), where)
        phi, theta = v.get("phi"), v.get("theta")
        ok = all(isinstance(x, list) and len(x) >= 8 and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                           and math.isfinite(c) for c in x) for x in (phi, theta))
        if not ok or len(phi) != len(theta):
            P.add(where, "a table needs phi and theta: two lists of the same length, at least 8 finite angles")
            return None, None, alpha
        phi = np.asarray(phi, float) * angle_factor
        theta = np.asarray(theta, float) * angle_factor
        if abs(phi[-1] - phi[0] - TWO_PI) <= 1e-9:       # a table that spans the whole turn (as a gear file's)
            if abs(theta[-1] - theta[0] - TWO_PI / n) > 1e-9:
                P.add(where, f"does not close: θ at phi = 360° is {math.degrees(theta[-1]):.6g}°, must be "
                             f"{360 / n:.6g}°")
                return None, None, alpha
            phi, theta = phi[:-1], theta[:-1]
        return _sampled(phi, theta, n, where, P, "table", table=True), None, alpha
    if not isinstance(v, str):
        P.add(where, f"must be a ratio, an expression, a table or a file: {v!r}")
        return None, None, alpha
    if v.strip().lower().endswith(".toml"):
        return _from_design(v, spec, where, P, source)
    n = _turns(spec, path, P)
    from .expressions import function_of
    try:
        f = function_of(v, "phi")
        phi = np.arange(LAW_SAMPLES) * (TWO_PI / LAW_SAMPLES)
        theta = np.asarray(f(phi), dtype=float) * np.ones_like(phi)
    except (ExpressionError, SpecError) as exc:
        P.add(where, str(exc))
        return None, None, alpha
    except (ArithmeticError, ValueError, TypeError) as exc:
        P.add(where, f"cannot be evaluated over a driving turn: {exc}")
        return None, None, alpha
    ends = np.asarray(f(np.array([0.0, TWO_PI])), dtype=float) * np.ones(2)
    law = _sampled(phi, theta, n, where, P, f"θ = {v}", closure=ends, expression=v)
    return law, None, alpha


def _sampled(phi, theta, n, where, P, description, *, table=False, closure=None, expression=None):
    """A table GearLaw from samples over one driving turn, after checking start, increase and closure."""
    if not np.all(np.isfinite(theta)):
        P.add(where, "is not finite over the driving turn")
        return None
    if table:
        if abs(phi[0]) > 1e-12 or not np.all(np.diff(phi) > 0) or phi[-1] >= phi[0] + TWO_PI:
            P.add(where, "the table's phi must start at 0 and increase strictly within one driving turn (< 360°)")
            return None
        close = theta[0] + TWO_PI / n
    else:
        close = closure[1]
    if abs(theta[0]) > 1e-9:
        P.add(where, f"θ must be 0 at phi = 0 (the sketch): it is {math.degrees(theta[0]):.6g}°")
        return None
    if not np.all(np.diff(np.append(theta, close)) > 0):
        k = int(np.argmax(np.diff(np.append(theta, close)) <= 0))
        P.add(where, f"must increase: it does not after phi = {math.degrees(phi[k]):.4g}°")
        return None
    if not table and abs(close - TWO_PI / n) > 1e-9:
        P.add(where, f"does not close: θ(360°) = {math.degrees(close):.6g}°, must be {360 / n:.6g}° "
                     f"(driving_turns = {n})")
        return None
    return GearLaw("table", phi=tuple(phi.tolist()), theta=tuple(theta.tolist()), driving_turns=n,
                   source=description, expression=expression)


def _from_design(v, spec, where, P, source):
    """A law from an ``assur-gears/1`` design file, sampled and checked for corners."""
    alpha = math.radians(20.0)
    base = Path(source).parent if source else Path.cwd()
    file = (base / v) if not Path(v).is_absolute() else Path(v)
    from ..gears.design import GearDesign
    from .gear_file import load_design
    try:
        design = load_design(file)
    except SpecError as exc:
        P.add(where, f"the gear design file {v!r} cannot be used: {exc}")
        return None, None, alpha
    if not isinstance(design, GearDesign):
        P.add(where, f"{v!r} is a wheel-step file, not a gear design file (format assur-gears/1)")
        return None, None, alpha
    if "driving_turns" in spec:
        P.add(f"{where.rsplit('.', 1)[0]}.driving_turns", "comes from the gear design file; remove it here")
    law = design.law
    n = law.driving_turns
    phi = np.arange(LAW_SAMPLES) * (TWO_PI / LAW_SAMPLES)
    gl = GearLaw("table", phi=tuple(phi.tolist()), theta=tuple(np.asarray(law.theta(phi), float).tolist()),
                 driving_turns=n, source=f"gear design {file.name}")
    mid = phi + 0.5 * TWO_PI / LAW_SAMPLES
    exact = np.asarray(law.ratio(mid), float)
    held = gl.evaluate(mid)[1]
    off = np.abs(held - exact) / np.abs(exact)
    if not np.all(off <= CORNER_TOLERANCE):
        k = int(np.argmax(off))
        P.add(where, f"the law of {v!r} has corners (its ratio jumps near phi = {math.degrees(mid[k]):.3f}°): a "
                     f"driven link's acceleration is unbounded there; smooth it (e.g. law.rounding > 0)")
        return None, None, alpha
    return gl, str(file.resolve()), float(design.pressure_angle)
