"""Widening a walking leg's constant-speed window: the second stage of the atlas's ranking by window
(``rank = "window"`` in :mod:`assur.synthesis.legs`; docs/codesign.md, "The widest window in the atlas").

The gait search (:func:`assur.synthesis.legs.leg_problem`) minimises the support's sag and the foot's speed spread
under a uniform crank; a co-designed gear drive needs something else of the leg: a stride coordinate x(q) whose
window law g = k·x′ gives convex pitch curves with a small pressure angle out to the widest window
(:mod:`assur.codesign.screen`). :func:`widen_window` starts from the gait search's best design and runs a seeded
differential evolution (scipy) on the same variables, bounds and gait constraints (step, lift, the foot under the
body, transmission angle, a full crank turn: the problem's own :class:`~assur.synthesis.evaluate.Evaluator`) and one
more, the support's sag no larger than the start's (a window bought with a sagging stride is no leg), maximising the
screen's slack at a fraction ``push`` just beyond the start's widest window. Each design's foot law is sampled at
:data:`SAMPLES` crank angles and screened on :data:`POINTS` window samples and :data:`KS` values of k (a coarse
screen for the search; the result is judged by the exact :func:`~assur.codesign.widest.widest_window` of each design
as it is written, on its own plan, the plan the ranking measures). The result is the start itself unless a design
with a wider exact window is found.
"""
from __future__ import annotations

import numpy as np

__all__ = ["POINTS", "SAMPLES", "KS", "widen_window"]

#: crank angles of a searched design's foot law, window samples and k values of its screen
SAMPLES, POINTS, KS = 512, 401, 49
#: the penalised objective of a design that breaks a gait constraint (plus its violation) or has no window
INFEASIBLE = 1.0e3


def _own_plan(plan, params):
    """The plan of the design ``params`` (n_params,) of the leg ``plan`` as written: its file's, sketched in its own
    assembly (for a Newton-solved group, continuing ``plan`` to other parameters may reach another assembly or
    none)."""
    from ..engine import compile as compile_plan
    from .design import mechanism_with_params
    return compile_plan(mechanism_with_params(plan, params))


def _slack(plan, params, fraction: float) -> float | None:
    """The coarse screen's slack of one design at ``fraction`` (None: no foot law or no window there).

    A leg with a Newton-solved group is measured on the design's own plan (:func:`_own_plan`, as
    :func:`widen_window` judges its result): the template's plan continued to other parameters may reach another
    assembly or none, and walks every refining solve of the gait from the template's sketch, both ways round (on an
    eight-link class-IV leg about 30 s a design, against 1.5 s on its own plan)."""
    from ..codesign.law import foot_law
    from ..codesign.screen import window_screen
    from ..errors import AssurError
    try:
        if plan.has_newton_groups:
            plan, params = _own_plan(plan, params), None
        return window_screen(foot_law(plan, params, samples=SAMPLES), fraction, points=POINTS, ks=KS).slack
    except AssurError:
        return None


def widen_window(problem, x0, *, budget: int, seed: int, spread: float = 0.02) -> dict:
    """Search the leg ``problem``'s variables from the design ``x0`` (n_vars,) SI (feasible) for a wider window.

    Differential evolution (``budget`` designs in all, population 15 or the variables' count if larger, started
    around ``x0``: ``x0`` itself and Gaussian steps of ``spread`` times each variable's range), minimising minus the
    coarse screen's slack at ``push`` = min(0.95, widest window of ``x0`` + 0.03), infeasible designs (a gait
    constraint broken, or a sampled sag above ``x0``'s) at :data:`INFEASIBLE` + their violation. Returns ``x``
    (n_vars,) SI (``x0`` unless a design with a wider exact window was found), ``window`` (its exact widest window,
    None if none; each design's measured on its own plan, :func:`~assur.synthesis.design.mechanism_with_params`
    compiled, as the ranking measures the file it writes), ``start_window`` (``x0``'s), ``push``, ``evaluations``
    and ``sag_limit`` (``x0``'s sampled sag, mm)."""
    from scipy.optimize import differential_evolution

    from ..codesign.law import foot_law
    from ..codesign.widest import widest_window
    from ..errors import AssurError
    from .evaluate import Evaluator

    evaluator = Evaluator(problem)
    plan = problem.plan
    x0 = np.asarray(x0, dtype=float)
    sag_limit = float(evaluator(x0[None]).quantities["gait.sag"][0])     # the search's own sampled sag (mm)

    def exact(x):
        """The exact widest window of the design x as written (:func:`_own_plan`)."""
        try:
            return widest_window(foot_law(_own_plan(plan, evaluator.params(x[None])[0]))).window
        except AssurError:
            return None

    start = exact(x0)
    push = min(0.95, (start or 0.5) + 0.03)
    bounds = problem.bounds
    lo, hi = bounds[:, 0], bounds[:, 1]
    rng = np.random.default_rng(seed)
    size = max(15, problem.n_vars)
    init = np.clip(x0 + spread * (hi - lo) * rng.standard_normal((size, problem.n_vars)), lo, hi)
    init[0] = np.clip(x0, lo, hi)
    count = [0]

    def objective(X):                        # X (n_vars, S): scipy's vectorised layout
        X = np.atleast_2d(X.T)
        count[0] += len(X)
        ev = evaluator(X)
        params = evaluator.params(X)
        out = np.empty(len(X))
        sag_excess = np.nan_to_num(ev.quantities["gait.sag"] - sag_limit, nan=1.0e6)
        for i in range(len(X)):
            if not ev.feasible[i] or sag_excess[i] > 0:
                out[i] = INFEASIBLE + float(ev.violation[i]) + max(float(sag_excess[i]), 0.0)
                continue
            s = _slack(plan, params[i], push)
            out[i] = INFEASIBLE if s is None else -s
        return out

    generations = max(1, budget // size - 1)
    with np.errstate(invalid="ignore", divide="ignore"):     # degenerate trial designs are judged, not warned of
        res = differential_evolution(objective, list(zip(lo, hi)), init=init, maxiter=generations, seed=seed,
                                     vectorized=True, updating="deferred", polish=False, tol=0.0, atol=0.0)
    best = np.asarray(res.x, dtype=float)
    found = exact(best) if float(res.fun) < INFEASIBLE else None
    check = evaluator(best[None])
    if found is not None and (start is None or found > start) and bool(check.feasible[0]) \
            and float(check.quantities["gait.sag"][0]) <= sag_limit:
        return {"x": best, "window": found, "start_window": start, "push": push, "evaluations": count[0],
                "sag_limit": sag_limit}
    return {"x": x0, "window": start, "start_window": start, "push": push, "evaluations": count[0],
            "sag_limit": sag_limit}
