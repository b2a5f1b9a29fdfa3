"""Co-design of a walking leg and its non-circular gear drive: the linkage's dimensions and the transfer law
optimised together (assur issue 15, part 3; the law's transfer alone: :mod:`assur.codesign.transfer`).

The problem. A leg (one crank, a ``[gait]`` foot) is driven from a uniform motor through a gear pair whose law
makes the foot's horizontal speed exactly constant over the central fraction f of the stride (the window); the
transfer phase closes the cycle with a C² law (bumps c_j over the smoothest bridge). Varied together:

- the leg's dimensions named in ``vary`` (default :func:`default_vary`: every length and angle parameter of the
  file except the crank's length, its pivot and its zero, each within ±``spread`` of its file value; a frame
  coordinate within ±spread of the mechanism's size), and
- the offsets δ_j of the transfer coefficients from the smoothest bridge of that leg, c = c_smooth + δ.

Constraints: the leg assembles over a whole turn; step ≥ ``step_min``; lift ≥ ``lift_min``; sag ≤ ``sag_max``
(defaults: 95 % of the file's step and lift, its sag); the gear pair's margins
(:data:`assur.codesign.margins.MARGIN_NAMES`: both pitch curves convex, centrode pressure angle ≤
``max_pressure_angle``, ratio g within ``ratio_bounds``, no undercut for ``module``) and, with ``max_torque``
(N·m), the peak motor torque within it (:mod:`assur.codesign.torque`, the leg's crank torque solved once per
candidate). Objective, for a feasible
design: the foot's horizontal-speed spread over the central ``target`` fraction of the stride (default 0.9; the
window's own speed is exact, so this measures the transfer law just beyond the window: |v_x| ∝ |x′|/g on the
law's samples) minus a small reward for the worst gear margin. An infeasible design scores 1 + its total scaled
violation. Search: scipy's differential evolution, seeded, from the file's design with the transfer that
:func:`~assur.codesign.transfer.optimize_transfer` finds for it first (half the first population about it),
``budget`` evaluations, then a local Powell polish of the best (a fifth of the budget more).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError, UnbuildableError
from ..kernels.arcs import in_arc
from .checks import gear_checks
from .law import CodesignLaw, foot_law, geared_vx_spread
from .transfer import DEFAULT_RATIO_BOUNDS, CodesignProblem, optimize_transfer

#: the scale that makes each gear margin dimensionless (κ·L, κ·L, rad, ratio, ratio, 1, 1), in the order of
#: :data:`~assur.codesign.margins.MARGIN_NAMES`
MARGIN_SCALES = (1.0, 1.0, 0.1, 0.1, 0.1, 1.0, 1.0)
#: the scale of the torque margin 1 − peak/limit (already dimensionless) when a torque limit is given
TORQUE_SCALE = 1.0
#: weight of the worst (scaled) gear margin in the objective of a feasible design
MARGIN_REWARD = 0.01


def default_vary(plan) -> list[tuple[str, float, float]]:
    """(name, low, high) of every length or angle parameter except the crank's (its length, pivot and zero):
    lengths ±25 %, frame coordinates ±25 % of the mechanism's size, angles ±20°."""
    d = plan.mechanism.drivers[0]
    skip = {f"{d.link}.length", f"{d.pivot}.x", f"{d.pivot}.y", f"{d.name}.zero"}
    out = []
    for name, value, kind in zip(plan.param_names, plan.defaults, plan.param_kind):
        if name in skip or name.endswith(".zero"):
            continue
        if name.endswith((".x", ".y")):
            half = 0.25 * plan.length_scale
        elif kind == 1:                 # angle
            half = math.radians(20.0)
        else:
            half = 0.25 * abs(value)
        out.append((name, float(value - half), float(value + half)))
    return out


@dataclass
class JointDesign:
    """The result of :func:`optimize_codesign`: the leg's params (n_params,), the law, its gear checks, the gait
    (step, lift, sag) of the leg, the measured vx spreads of the geared leg, and how the search went."""
    params: np.ndarray
    law: object
    checks: object
    gait: dict
    vx_spread: dict
    feasible: bool
    objective: float
    evaluations: int
    message: str
    vary: list = field(default_factory=list)


class JointProblem:
    """The scalar objective of (leg dimensions, transfer offsets) for one window fraction; see the module doc."""

    def __init__(self, plan, fraction: float, *, centre_distance: float, module: float, vary=None,
                 step_min: float | None = None, lift_min: float | None = None, n_bumps: int = 6,
                 sag_max: float | None = None, max_pressure_angle: float = math.radians(30.0), ratio_bounds=None,
                 samples: int = 1024, offset: float = 2.0, target: float = 0.9, max_torque: float | None = None):
        self.plan = plan
        self.gears = CodesignProblem(plan, fraction, centre_distance=centre_distance, module=module,
                                     n_bumps=n_bumps, max_pressure_angle=max_pressure_angle,
                                     ratio_bounds=ratio_bounds or DEFAULT_RATIO_BOUNDS, samples=samples,
                                     max_torque=max_torque)
        self.scales = np.asarray(MARGIN_SCALES + ((TORQUE_SCALE,) if max_torque is not None else ()))
        self.vary = list(default_vary(plan) if vary is None else vary)
        names = set(plan.param_names)
        bad = [v[0] for v in self.vary if v[0] not in names]
        if bad:
            raise SpecError([("vary", f"unknown parameter {bad[0]!r} (parameters: {', '.join(plan.param_names)})")])
        self.index = [plan.param_index(v[0]) for v in self.vary]
        base = self.gears.prepared(plan.defaults)["foot"].metrics
        self.step_min = 0.95 * base.step_length if step_min is None else float(step_min)
        self.lift_min = 0.95 * base.lift if lift_min is None else float(lift_min)
        self.sag_max = base.sag if sag_max is None else float(sag_max)
        self.target = float(target)
        self._foot_key, self._foot = None, None
        self.offset = float(offset)
        self.start_from(np.zeros(self.gears.n_bumps))
        self.evaluations = 0

    def start_from(self, offsets) -> None:
        """Start the transfer at these offsets δ (n_bumps,) from the smoothest bridge, searching δ ± ``offset``."""
        self.start_offsets = np.asarray(offsets, dtype=float).reshape(self.gears.n_bumps)
        self.bounds = [(lo, hi) for _, lo, hi in self.vary] + [(d - self.offset, d + self.offset)
                                                               for d in self.start_offsets]

    def split(self, z):
        """(params (n_params,), transfer coefficients c (n_bumps,)) of a search vector z."""
        z = np.asarray(z, dtype=float)
        p = self.plan.defaults.copy()
        p[self.index] = z[:len(self.index)]
        return p, self.gears.default_coefficients(p) + z[len(self.index):]

    def start(self) -> np.ndarray:
        """The file's design with the starting transfer offsets (default: its smoothest bridge)."""
        return np.concatenate([self.plan.defaults[self.index], self.start_offsets])

    def terms(self, z):
        """(violation ≥ 0, objective of a feasible design, gait metrics, gear margins) of z; UnbuildableError or
        SpecError (a window that does not exist) for a leg that is no candidate."""
        p, c = self.split(z)
        metrics = self.gears.prepared(p)["foot"].metrics
        margins = self.gears.margins(c, p)
        scaled = margins / self.scales
        violation = float(np.sum(np.maximum(0.0, -scaled)))
        violation += max(0.0, (self.step_min - metrics.step_length) / self.step_min)
        violation += max(0.0, (self.lift_min - metrics.lift) / self.lift_min)
        violation += max(0.0, (metrics.sag - self.sag_max) / max(self.sag_max, 1e-9))
        value = self.spread(c, p) - MARGIN_REWARD * min(1.0, float(np.min(scaled)))
        return violation, value, metrics, margins

    def spread(self, c, p) -> float:
        """(max − min)/mean of |v_x| ∝ |x′|/g over the law's samples on the ground in the central ``target``
        fraction of the stride, for coefficients c and params p."""
        prep = self.gears.prepared(p)
        key = p.tobytes()
        if key != self._foot_key:
            foot, q = prep["foot"], prep["q"]
            x, xp = foot.x_at(q), np.abs(foot.dx(q))
            on = in_arc(q, foot.contact_start, foot.contact_end - foot.contact_start)
            mid, half = 0.5 * (foot.x_min + foot.x_max), 0.5 * self.target * foot.stride
            self._foot, self._foot_key = (xp, on & (np.abs(x - mid) <= half)), key
        xp, mask = self._foot
        _, (g, _, _) = self.gears.ratio_samples(c, p)
        v = xp[mask] / g[mask]
        return float((v.max() - v.min()) / v.mean()) if v.size else math.inf

    def __call__(self, z) -> float:
        self.evaluations += 1
        try:
            violation, value, _, _ = self.terms(z)
        except (UnbuildableError, SpecError, ValueError, FloatingPointError):
            return 1e3
        if not math.isfinite(violation + value):
            return 1e3
        return 1.0 + violation if violation > 0 else value


def optimize_codesign(plan, fraction: float, *, centre_distance: float, module: float, vary=None,
                      step_min: float | None = None, lift_min: float | None = None, sag_max: float | None = None,
                      n_bumps: int = 6, max_pressure_angle: float = math.radians(30.0), ratio_bounds=None,
                      budget: int = 4000, seed: int = 1, popsize: int = 12, target: float = 0.9,
                      progress=None, max_torque: float | None = None) -> JointDesign:
    """Optimise the leg's dimensions and the transfer law together (see the module doc). ``budget``: objective
    evaluations at most; ``progress(text)``: told after each generation. Returns a :class:`JointDesign` whose
    ``feasible`` says whether every constraint holds (the torque limit, with ``max_torque`` in N·m, included: its
    peak refined between samples on the final law); its law is rebuilt on the full 4096-sample foot law."""
    from scipy.optimize import differential_evolution
    if isinstance(budget, bool) or not isinstance(budget, (int, np.integer)) or budget < 50:
        raise SpecError([("budget", f"must be a whole number ≥ 50: {budget!r}")])
    if progress is not None:
        progress("the transfer law of the file's leg first …")
    problem = JointProblem(plan, fraction, centre_distance=centre_distance, module=module, vary=vary,
                           step_min=step_min, lift_min=lift_min, sag_max=sag_max, n_bumps=n_bumps,
                           max_pressure_angle=max_pressure_angle, ratio_bounds=ratio_bounds, target=target,
                           max_torque=max_torque)
    first = optimize_transfer(plan, fraction, centre_distance=centre_distance, module=module, n_bumps=n_bumps,
                              max_pressure_angle=max_pressure_angle, ratio_bounds=problem.gears.ratio_bounds,
                              seed=seed, measure=False, max_torque=max_torque)
    problem.start_from(first.coefficients - problem.gears.default_coefficients(plan.defaults))
    dims = len(problem.bounds)
    pop = max(5, int(popsize)) * dims
    maxiter = max(1, int(budget) // pop - 1)
    rng = np.random.default_rng(seed)
    lo, hi = (np.array(b) for b in zip(*problem.bounds))
    init = lo + rng.random((pop, dims)) * (hi - lo)
    near = pop // 2                  # half about the file's design and its smoothest bridge
    init[:near] = np.clip(problem.start() + 0.05 * (hi - lo) * rng.standard_normal((near, dims)), lo, hi)
    init[0] = np.clip(problem.start(), lo, hi)
    generation = [0]

    def told(xk, convergence=0.0):
        generation[0] += 1
        if progress is not None:
            progress(f"generation {generation[0]}/{maxiter}: best {problem(xk):.5g} "
                     f"({problem.evaluations} evaluations)")
        return problem.evaluations >= budget

    res = differential_evolution(problem, problem.bounds, init=init, maxiter=maxiter, seed=seed, polish=False,
                                 tol=1e-12, callback=told, updating="immediate")
    best = res.x if res.fun <= problem(problem.start()) else problem.start()
    # a local polish of the best (Powell, in units of the search box), a fifth of the budget
    from scipy.optimize import minimize
    span = hi - lo
    polish = minimize(lambda u: problem(np.clip(best + u * span, lo, hi)), np.zeros(dims), method="Powell",
                      options={"maxfev": max(50, int(budget) // 5), "xtol": 1e-4, "ftol": 1e-7})
    if polish.fun < problem(best):
        best = np.clip(best + polish.x * span, lo, hi)
    if progress is not None:
        progress(f"polished: best {problem(best):.5g} ({problem.evaluations} evaluations)")
    params, c = problem.split(best)
    try:
        violation, _, metrics, _ = problem.terms(best)
    except (UnbuildableError, SpecError) as exc:
        raise SpecError([("codesign", f"no leg of the search assembles with a window of {fraction:g}: {exc}")]) \
            from None
    law = CodesignLaw(foot_law(plan, params), fraction, c, n_bumps=n_bumps)
    checks = gear_checks(law, centre_distance, module=module, max_pressure_angle=max_pressure_angle,
                         ratio_bounds=problem.gears.ratio_bounds, max_torque=max_torque)
    gait = {"step": metrics.step_length, "lift": metrics.lift, "sag": metrics.sag,
            "step_min": problem.step_min, "lift_min": problem.lift_min, "sag_max": problem.sag_max}
    return JointDesign(params, law, checks, gait, geared_vx_spread(law), violation == 0 and checks.ok,
                       float(problem(best)), problem.evaluations, str(res.message), problem.vary)
