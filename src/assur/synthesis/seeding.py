"""Seeds for the optimisers from the exact methods: design vectors of a problem that reproduce exact
four-bar solutions (docs/synthesis.md, "Exact methods: function and motion generation").

``seed_designs(problem)`` reads the problem's targets: poses (3 to 5, kind ``poses``) go to
``exact.motion_candidates``, input/output angle pairs (kind ``function``) to ``exact.function_candidates``;
any other problem gets no seeds (an empty (0, n_vars) array). ``seed_rows(problem, solutions)`` fits the
problem's variables to each solution: the template's crank pivot, crank pin, rocker pivot, rocker pin (and
the target point) must sit where the solution puts A0, A, B0, B (and P) at every precision point, at the
problem's own target inputs (least squares within the bounds from a few starts). Solutions the template
cannot represent within ``tol`` (of the task's size) give no row. The rows are SI design vectors, ready to
be put into an initial population.
"""
from __future__ import annotations

import numpy as np

from ..errors import SpecError
from ..model.mechanism import FRAME


def _roles(mechanism) -> list[str] | None:
    """The template's four-bar points [crank pivot, crank pin, rocker pivot, rocker pin], or None."""
    rotary = [d for d in mechanism.drivers if d.kind == "rotary"]
    if len(rotary) != 1:
        return None
    d = rotary[0]
    links = {lk.name: lk for lk in mechanism.links if lk.name != FRAME}
    frame = set(mechanism.frame.points)
    arm = d.arm
    coupler = [lk for lk in links.values() if arm in lk.points and lk.name != d.link]
    if len(coupler) != 1:
        return None
    for lk in links.values():
        if lk.name in (d.link, coupler[0].name):
            continue
        pivots = [p for p in lk.points if p in frame and p != d.pivot]
        joints = [p for p in lk.points if p in coupler[0].points and p != arm]
        if pivots and joints:
            return [d.pivot, arm, pivots[0], joints[0]]
    return None


def seed_rows(problem, solutions, *, tol: float = 1e-6, starts: int = 6, seed: int = 0) -> np.ndarray:
    """Design vectors (m, n_vars) SI of ``problem`` reproducing exact solutions (``exact.ExactSolution``)."""
    from scipy.optimize import least_squares
    from scipy.stats import qmc

    from ..engine import compile as compile_
    from ..engine import solve
    from .evaluate import Evaluator
    roles = _roles(problem.plan.mechanism)
    if roles is None:
        raise SpecError([("problem.mechanism", "seeds from the exact methods need a four-bar template (one crank, "
                                               "a coupler and a rocker on the frame)")])
    t = problem.targets
    point = getattr(t, "point", None) if t is not None else None
    ev = Evaluator(problem, backend="numpy")
    plan = problem.plan
    lo, hi = problem.bounds.T
    rows = []
    for s in solutions:
        names = ["A0", "A", "B0", "B"] + (["P"] if point and "P" in {n for n, _ in s.mechanism.points} else [])
        mine = roles + ([point] if len(names) == 5 else [])
        cplan = compile_(s.mechanism)
        want = solve(cplan, inputs=np.asarray(s.inputs)[:, None], order=0, backend="numpy").pos
        want = want[:, [cplan.point_index(n) for n in names]]
        if getattr(t, "kind", "points") == "function":
            want = _onto_ground(want, plan, roles)
        n = len(s.inputs) if t is not None and t.n == len(s.inputs) else None
        if t is not None and n is None:
            continue
        idx = [plan.point_index(p) for p in mine]
        size = float(np.ptp(want.reshape(-1, 2), axis=0).max()) or 1.0

        def residual(x):
            X = x[None]
            q = ev.target_inputs(X)[0] if t is not None else plan.sketch_inputs
            st = solve(plan, ev.params(X)[0], np.asarray(q, float).reshape(-1, 1), order=0, on_unbuildable="nan",
                       backend="numpy")
            r = ((st.pos[:, idx] - want) / size).ravel()
            return np.where(np.isfinite(r), r, 10.0)

        rng = np.random.default_rng(seed)
        x0s = [(lo + hi) / 2] + list(lo + qmc.LatinHypercube(d=len(lo), rng=rng).random(starts - 1) * (hi - lo))
        best = None
        for x0 in x0s:
            sol = least_squares(residual, np.clip(x0, lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo)),
                                bounds=(lo, hi), xtol=1e-14, ftol=1e-14, gtol=1e-14)
            if best is None or sol.cost < best.cost:
                best = sol
            if np.max(np.abs(sol.fun)) < tol:
                break
        if best is not None and np.max(np.abs(best.fun)) < tol:
            rows.append(best.x)
    return np.array(rows, dtype=float).reshape(-1, problem.n_vars)


def _onto_ground(want, plan, roles):
    """A function generator (ground A0 → B0 along x from the origin) moved onto the template's ground line."""
    sk = {n: complex(*xy) for n, xy in plan.mechanism.points}
    g0, g1 = sk[roles[0]], sk[roles[2]]
    z = want[..., 0] + 1j * want[..., 1]
    a0, b0 = z[0, 0], z[0, 2]
    w = (z - a0) * (g1 - g0) / (b0 - a0) + g0
    return np.stack([w.real, w.imag], axis=-1)


def seed_designs(problem, *, limit: int = 5, **options) -> np.ndarray:
    """Initial design vectors (m, n_vars) SI from the exact methods for a problem with poses (3–5) or function
    targets on a four-bar template; (0, n_vars) for any other problem. ``options`` go to the exact method."""
    from . import exact
    t = problem.targets
    kind = getattr(t, "kind", "points") if t is not None else None
    empty = np.zeros((0, problem.n_vars))
    roles = _roles(problem.plan.mechanism)
    if roles is None or kind not in ("poses", "function"):
        return empty
    if kind == "poses":
        if not 3 <= t.n <= 5:
            return empty
        poses = np.column_stack([t.xy, t.angles])
        sols = exact.motion_candidates(poses, limit=limit, **options)
    else:
        sk = {n: np.array(xy, float) for n, xy in problem.plan.mechanism.points}
        ground = float(np.hypot(*(sk[roles[2]] - sk[roles[0]])))
        x, y = t.xy[:, 0], t.xy[:, 1]
        starts = ([(0.0, s) for s in np.linspace(0, 2 * np.pi, 12, endpoint=False)]
                  if getattr(t, "relative", False) else None)
        sols = exact.function_candidates(x, y, ground=ground, starts=starts, limit=limit, **options)
    return seed_rows(problem, sols) if sols else empty


__all__ = ["seed_designs", "seed_rows"]
