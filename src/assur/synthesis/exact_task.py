"""Exact synthesis of a problem file's task (``assur synth PROBLEM --exact``): the closed-form four-bars of
:mod:`assur.synthesis.exact` for the problem's targets, in the problem's units.

- ``function`` targets (input/output angle pairs of a link): Freudenstein's four-bars with the template's ground
  length. A relative output (``output = "relative"``) or a uniform timing (a free start ``start``) leaves the start
  angles free: every pair (φ0, ψ0) of a grid of ``START_GRID`` × ``START_GRID`` start angles over a turn is a fit
  (one candidate each), so the table ranks fits of different starts.
- ``poses`` targets (3, 4 or 5 poses of a link at a point): Burmester's four-bars, in the poses' order.

Any other task (path points, six-bar templates …) has no exact method here: SpecError naming the targets.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from .exact_results import Candidates

#: start angles per turn scanned for a task whose start angles are free (a relative output, a uniform timing)
START_GRID = 12


@dataclass(frozen=True)
class ExactTask:
    """The exact synthesis of a problem: ``kind`` ("function" or "motion"), ``method`` (what ran, in words),
    ``candidates`` (:class:`~assur.synthesis.exact_results.Candidates`), ``length_unit`` and ``angle_unit``
    (the problem's: lengths and the motion residual in ``length_unit``)."""
    kind: str
    method: str
    candidates: Candidates
    length_unit: str
    angle_unit: str

    def __repr__(self) -> str:
        return f"ExactTask({self.kind}: {self.method}; {len(self.candidates)} kept)"


def exact_task(problem, *, grashof: str | None = None, limit: int = 20) -> ExactTask:
    """The closed-form four-bars for ``problem``'s targets (see the module docstring)."""
    from ..io.units import LENGTH
    from . import exact
    t = problem.targets
    kind = getattr(t, "kind", None) if t is not None else None
    u = problem.length_unit
    L = LENGTH[u]
    if kind == "poses":
        if not 3 <= t.n <= 5:
            raise SpecError([("targets.poses", f"exact motion generation takes 3, 4 or 5 poses: the problem has "
                                               f"{t.n} (run the optimisers instead: assur synth without --exact)")])
        poses = np.column_stack([np.asarray(t.xy) / L, t.angles])
        c = exact.motion_candidates(poses, grashof=grashof, units=u, limit=limit)
        return ExactTask("motion", f"Burmester motion generation through {t.n} poses of {t.link} at {t.point}", c,
                         u, problem.angle_unit)
    if kind == "function":
        from .seeding import _roles
        roles = _roles(problem.plan.mechanism)
        if roles is None:
            raise SpecError([("mechanism", "exact function generation needs a four-bar template (one crank, a "
                                           "coupler and a rocker on the frame)")])
        sk = {n: np.asarray(xy, float) / L for n, xy in problem.plan.mechanism.points}
        ground = float(np.hypot(*(sk[roles[2]] - sk[roles[0]])))
        x, y = np.asarray(t.xy, float).T
        free_in = t.timing in ("uniform", "free")
        grid = np.linspace(0.0, 2 * math.pi, START_GRID, endpoint=False)
        starts = [(a, b) for a in (grid if free_in else [0.0]) for b in (grid if t.relative else [0.0])]
        c = exact.function_candidates(x, y, ground=ground, starts=starts, grashof=grashof, units=u, limit=limit)
        fit = "exact" if t.n == 3 else "least squares"
        free = " and ".join(w for w, f in (("input", free_in), ("output", t.relative)) if f)
        return ExactTask("function", f"Freudenstein function generation, {t.n} input/output pairs of {t.link} "
                                     f"({fit}; ground {ground:g} {u}"
                                     + (f"; {free} start angles free: {len(starts)} starts" if free else "") + ")",
                         c, u, problem.angle_unit)
    raise SpecError([("targets.kind", f"exact synthesis takes function or poses targets (four-bars): this problem "
                                      f"has {kind or 'no'} targets (run assur synth without --exact)")])


def table_rows(task: ExactTask, *, rejected: int = 5) -> tuple[list[str], list[tuple]]:
    """The ranked table of a task: (header, rows) with rank, residual, Grashof class, whether the crank turns
    fully, the worst transmission angle (°), the lengths (ground, crank, coupler, rocker in the length unit) and the
    defects; the kept candidates first, then up to ``rejected`` rejected ones (rank "–")."""
    unit = "rad" if task.kind == "function" else task.length_unit
    head = ["rank", f"residual [{unit}]", "Grashof class", "crank", "worst μ [°]",
            f"ground, crank, coupler, rocker [{task.length_unit}]", "defects"]
    rows = []
    for s in list(task.candidates) + task.candidates.rejected[:rejected]:
        rows.append((s.rank or "–", f"{s.residual:.3g}", s.grashof, "turns fully" if s.rotatable else "rocks",
                     f"{math.degrees(s.transmission):.1f}" if math.isfinite(s.transmission) else "–",
                     ", ".join(f"{v:.4g}" for v in s.lengths), "; ".join(s.defects) or "none"))
    return head, rows


def as_dict(task: ExactTask) -> dict:
    """JSON-ready (the problem's units; angles in degrees)."""
    def one(s):
        return {"rank": s.rank, "residual": s.residual, "grashof": s.grashof, "rotatable": s.rotatable,
                "transmission_deg": math.degrees(s.transmission) if math.isfinite(s.transmission) else None,
                "lengths": dict(zip(("ground", "crank", "coupler", "rocker"), map(float, s.lengths))),
                "defects": list(s.defects)}
    c = task.candidates
    return {"kind": task.kind, "method": task.method, "length_unit": task.length_unit,
            "residual_unit": "rad" if task.kind == "function" else task.length_unit, "criterion": c.criterion,
            "candidates": [one(s) for s in c], "rejected": [one(s) for s in c.rejected], "counts": c.counts,
            "reason": c.reason}


__all__ = ["ExactTask", "START_GRID", "as_dict", "exact_task", "table_rows"]
