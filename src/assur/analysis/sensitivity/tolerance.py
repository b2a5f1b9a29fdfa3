"""Tolerance stack-ups over the cycle: per-parameter tolerances, worst-case and RSS envelopes, bands around a path.

A tolerance is a symmetric zone ±t about the nominal parameter (SI). By default every length parameter (a link's
length, a placement distance, a frame coordinate, a slide's offset, a follower's start) gets ±IT/2 of an ISO 286
grade on its own nominal size (IT9 unless asked; :mod:`.iso286`), and every angle parameter of a placement or a slide
±(IT/2)/ℓ for the length ℓ it turns (the placement's distance, else the mechanism's size); the phase of a driver and
of a gear or cam follower (timing, not a machined size) is held. A given tolerance (file units) or grade overrides.

With the exact derivatives D_k = ∂y/∂p_k of an output over the run (:mod:`.outputs`):

- worst case (linear): Σ_k |D_k|·t_k — the zone no combination of tolerances leaves, to first order;
- statistical (root sum square, each tolerance a ±3σ zone): √Σ_k (D_k·t_k)², the ±3σ zone of the output;
- a point's path: the same along the path's normal n: Σ_k |n·∂P/∂p_k|·t_k (the band drawn round a coupler or foot
  path).

The Monte Carlo (:mod:`.montecarlo`) shows where the first-order envelope fails (near toggles, where the output is
not linear over the tolerance zone).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import SpecError
from .iso286 import parse_grade, tolerance as it_tolerance

#: the default ISO grade of every length and placement
DEFAULT_GRADE = 9


@dataclass(frozen=True)
class Tolerances:
    """Per parameter of ``names`` its half-width ``half`` (P,) (SI: m or rad) and how it was set (``source``)."""
    names: tuple[str, ...]
    half: np.ndarray
    source: tuple[str, ...]

    def as_rows(self, plan) -> list[dict]:
        from ...io.units import ANGLE, LENGTH
        u = plan.mechanism.units
        out = []
        for k, name in enumerate(self.names):
            angle = plan.param_kind_of(name) == "angle"
            f = ANGLE[u.angle] if angle else LENGTH[u.length]
            out.append({"parameter": name, "tolerance": float(self.half[k] / f),
                        "unit": u.angle if angle else u.length, "source": self.source[k]})
        return out


def _kind(name: str) -> str:
    """'zero' (a phase: held), 'angle' or 'length' from a parameter's name (docs/format.md)."""
    tail = name.rsplit(".", 1)[-1]
    if tail == "zero":
        return "zero"
    if tail == "angle":
        return "angle"
    return "length"


def _arm(plan, name: str, params) -> float:
    """The length an angle parameter turns: a placement's distance, else the mechanism's size (m)."""
    if name.count(".") == 2:
        d = name.rsplit(".", 1)[0] + ".distance"
        if d in plan.param_names:
            return max(abs(float(params[plan.param_index(d)])), 1e-9)
    return float(plan.length_scale)


def default_tolerances(plan, params=None, grade: int = DEFAULT_GRADE) -> Tolerances:
    """ISO ``grade`` on every length parameter's own size, its angular equivalent on every angle, phases held."""
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    half, source = [], []
    for k, name in enumerate(plan.param_names):
        kind = _kind(name)
        if kind == "zero":
            half.append(0.0)
            source.append("held (a phase)")
        elif kind == "length":
            size = abs(float(params[k])) * 1e3
            t = it_tolerance(grade, size) * 1e-6
            half.append(0.5 * t)
            source.append(f"IT{grade} on {size:.4g} mm")
        else:
            arm = _arm(plan, name, params)
            t = it_tolerance(grade, arm * 1e3) * 1e-6
            half.append(0.5 * t / arm)
            source.append(f"IT{grade} over {arm * 1e3:.4g} mm")
    return Tolerances(plan.param_names, np.array(half), tuple(source))


def parse_tolerances(plan, specs=(), grade: int | str = DEFAULT_GRADE, params=None) -> Tolerances:
    """The default tolerances (``grade``) with ``specs`` applied: ``"NAME=VALUE"`` (± in the file's length or angle
    unit), ``"NAME=IT7"``, ``"NAME=0"`` (held); SpecError (located ``--tolerance``) for an unknown name or value."""
    from ...io.units import ANGLE, LENGTH
    g = parse_grade(grade) if isinstance(grade, str) else int(grade)
    tol = default_tolerances(plan, params, g)
    half, source = tol.half.copy(), list(tol.source)
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    u = plan.mechanism.units
    for spec in specs:
        name, sep, value = str(spec).partition("=")
        name, value = name.strip(), value.strip()
        if not sep or name not in plan.param_names:
            raise SpecError([("--tolerance", f"{spec!r}: give NAME=VALUE for a parameter of the plan "
                                             f"(e.g. {plan.param_names[min(1, plan.n_params - 1)]}=0.05, or =IT7)")])
        k = plan.param_index(name)
        if value.upper().startswith("IT"):
            gk = parse_grade(value)
            one = default_tolerances(plan, params, gk)
            half[k], source[k] = one.half[k], one.source[k] if _kind(name) != "zero" else "held (a phase)"
            continue
        try:
            v = float(value)
        except ValueError:
            raise SpecError([("--tolerance", f"{spec!r}: the tolerance must be a number or an IT grade")]) from None
        if not (v >= 0 and math.isfinite(v)):
            raise SpecError([("--tolerance", f"{spec!r}: the tolerance must be ≥ 0")])
        f = ANGLE[u.angle] if plan.param_kind_of(name) == "angle" else LENGTH[u.length]
        half[k], source[k] = v * f, "given"
    return Tolerances(plan.param_names, half, tuple(source))


@dataclass(frozen=True)
class Envelope:
    """An output's tolerance envelope over the run: ``value`` (n,), ``worst`` (n,) the worst-case half-width,
    ``rss`` (n,) the ±3σ half-width, ``contributions`` (n, P) |D_k|·t_k (what each tolerance adds to the worst case)."""
    name: str
    value: np.ndarray
    worst: np.ndarray
    rss: np.ndarray
    contributions: np.ndarray


def envelope(output, tol: Tolerances) -> Envelope:
    """The worst-case and RSS envelopes of an :class:`~.outputs.Output` under ``tol``."""
    c = np.abs(np.asarray(output.derivative)) * tol.half
    return Envelope(output.name, np.asarray(output.value), c.sum(axis=-1), np.sqrt(np.sum(c * c, axis=-1)), c)


@dataclass(frozen=True)
class PathBand:
    """The tolerance band round a point's path over the run: ``path`` (n,) complex, ``normal`` (n,) unit, and the
    half-widths along it: ``worst`` (n,) and ``rss`` (n,) (m)."""
    point: str
    path: np.ndarray
    normal: np.ndarray
    worst: np.ndarray
    rss: np.ndarray

    def edges(self, which: str = "worst"):
        """(inner, outer) (n,) complex: the band's two edges."""
        w = getattr(self, which)
        return self.path - w * self.normal, self.path + w * self.normal


def path_band(sens, point: str, tol: Tolerances) -> PathBand:
    """The band round ``point``'s path (its normal from the exact velocity) under the tolerances ``tol``."""
    x, y = sens[f"{point}.x"], sens[f"{point}.y"]
    vx, vy = sens[f"{point}.vx"], sens[f"{point}.vy"]
    v = vx.value + 1j * vy.value
    with np.errstate(invalid="ignore", divide="ignore"):
        n = 1j * v / np.abs(v)
    D = x.derivative + 1j * y.derivative                         # (n, P) complex
    c = np.abs(np.real(np.conj(n)[:, None] * D)) * tol.half
    return PathBand(point, x.value + 1j * y.value, n, c.sum(axis=-1), np.sqrt(np.sum(c * c, axis=-1)))
