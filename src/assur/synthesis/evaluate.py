"""Vectorised evaluation of a synthesis problem over a population: ``(n, n_vars) → (n,)``.

``Evaluator(problem)(X)`` maps every design vector (SI) to the mechanism's parameters, solves the
target positions (and, where the problem needs it, the whole input cycle) with the batched engine,
and returns an :class:`Evaluation`: the objective ``f`` in the problem file's units (NaN for an
infeasible design: an infeasible design never gets an objective value), the total constraint
violation ``V`` (0 exactly when feasible) and its parts, and the scalar ``F`` an optimiser minimises
(``f`` when feasible, ``infeasible_offset + violation_weight·V`` otherwise, which orders designs by
Deb's feasibility rules). No Python loop over designs; the population is processed in chunks so
memory stays bounded; nothing is mutated.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..analysis.gait import population_gait, resolve_gait
from ..errors import SpecError, float_array
from ..tolerances import DEFAULT
from . import fourbar as fb
from .defects import defect_measures, nearest_inputs
from .design import expression_env, fourbar_lengths, parameters, target_inputs
from .problem import Problem
from .targets import target_offsets

TWO_PI = 2.0 * np.pi


@dataclass
class Evaluation:
    """Per-design results, each (n,) unless noted."""
    objective: np.ndarray            # f in file units; NaN where infeasible
    violation: np.ndarray            # V ≥ 0
    feasible: np.ndarray             # bool
    penalised: np.ndarray            # F (the optimiser's scalar)
    violations: dict = field(default_factory=dict)   # constraint name → (n,)
    quantities: dict = field(default_factory=dict)   # quantity → (n,) (file units); 'distances' → (n, N)
    x: np.ndarray | None = None      # (n, n_vars) the design vectors evaluated (wrapped), with the free timing
                                     # solved inside the evaluation filled in; None when nothing was solved

    def __len__(self) -> int:
        return len(self.objective)

    @staticmethod
    def concatenate(parts: list["Evaluation"]) -> "Evaluation":
        if len(parts) == 1:
            return parts[0]
        cat = lambda key: np.concatenate([getattr(p, key) for p in parts])  # noqa: E731
        keys_v = parts[0].violations.keys()
        keys_q = parts[0].quantities.keys()
        return Evaluation(cat("objective"), cat("violation"), cat("feasible"), cat("penalised"),
                          {k: np.concatenate([p.violations[k] for p in parts]) for k in keys_v},
                          {k: np.concatenate([p.quantities[k] for p in parts]) for k in keys_q},
                          None if parts[0].x is None else cat("x"))

    def row(self, i: int) -> dict:
        """One design's results as plain Python values."""
        def py(v):
            v = v[i]
            return v.tolist() if isinstance(v, np.ndarray) else (bool(v) if isinstance(v, np.bool_) else float(v))
        return {"objective": None if not self.feasible[i] else float(self.objective[i]),
                "feasible": bool(self.feasible[i]), "violation": float(self.violation[i]),
                "violations": {k: py(v) for k, v in self.violations.items()},
                "quantities": {k: py(v) for k, v in self.quantities.items()}}


def default_backend() -> str:
    """The engine backend every evaluation uses, fixed once so results never depend on chunking."""
    from ..engine.planar.numba_backend import available
    return "numba" if available() else "numpy"


#: the compiled kernels cost several seconds to compile for a new mechanism (``benchmarks/first_use.py``) and then
#: evaluate a design in 1–20 µs; numpy takes about NUMPY_SECONDS_PER_UNIT per solved sample and plan step (18 µs for
#: C2's 5 targets, 0.2–2 ms for the problems that solve a whole cycle), and NUMPY_SECONDS_PER_NEWTON_GROUP per solved
#: sample and Newton-solved group (a class-III triad, say: Newton's iterations continued along the turn; 0.4 ms
#: measured on the triad six-bar's populations, benchmarks/newton.py). A run that names no backend compiles when its
#: numpy evaluations would take at least PAYBACK_SECONDS by that estimate (or, without a budget, when its time limit
#: is at least PAYBACK_SECONDS), and runs numpy otherwise
NUMPY_SECONDS_PER_UNIT = 0.5e-6
NUMPY_SECONDS_PER_NEWTON_GROUP = 300e-6
PAYBACK_SECONDS = 10.0


def numpy_seconds(problem, evaluations: int) -> float:
    """The estimated numpy time (s) of ``evaluations`` evaluations of ``problem``: the solved samples of one (its
    targets, a whole cycle's samples when a term or constraint needs one, and with free timing solved per design
    the turn it is assigned on and the most refinements of each target, ``timing.MAX_ITERATIONS``, or
    ``timing.GOLDEN_STEPS`` and three for poses) times the plan's
    steps' cost (:data:`NUMPY_SECONDS_PER_UNIT` a step, :data:`NUMPY_SECONDS_PER_NEWTON_GROUP` a Newton-solved group). A
    deterministic estimate: it depends on the problem, never on the machine."""
    t = problem.targets
    samples = (t.n if t is not None else 0) + (problem.cycle_samples if problem.needs_cycle() else 0)
    if t is not None and t.timing == "free" and t.free_timing == "inner":
        from .timing import GOLDEN_STEPS, MAX_ITERATIONS   # free timing solved per design: a turn, then each
        steps = GOLDEN_STEPS + 3 if t.kind == "poses" else MAX_ITERATIONS   # target refined
        samples += problem.cycle_samples + t.n * steps
    newton = len(problem.plan.newton_steps())
    per_sample = (len(problem.plan.steps) - newton) * NUMPY_SECONDS_PER_UNIT + newton * NUMPY_SECONDS_PER_NEWTON_GROUP
    return evaluations * max(samples, 1) * per_sample


def run_backend(problem, budget: int | None, time_limit: float | None) -> str:
    """The backend of a synthesis run that names none: numba (when installed) for a run whose numpy evaluations
    would take long enough to win back the first compile of its kernels, numpy for a shorter one. Decided from the
    problem and the run's settings alone, so a seeded run gives the same design whether or not the kernels are in
    the cache already."""
    if budget is not None:
        short = numpy_seconds(problem, budget) < PAYBACK_SECONDS
    else:
        short = time_limit is not None and time_limit < 6 * PAYBACK_SECONDS
    return "numpy" if short else default_backend()


class Evaluator:
    """Pure vectorised objective of a :class:`Problem`. Picklable (for worker processes)."""

    #: designs per chunk: the general route holds (chunk, cycle samples, points) arrays, the fused
    #: compiled reduction only a few numbers per design
    CHUNK, FUSED_CHUNK = 512, 8192

    def __init__(self, problem: Problem, *, chunk: int | None = None, backend: str | None = None):
        if not isinstance(problem, Problem):
            from ..errors import ArgumentTypeError
            raise ArgumentTypeError([("problem", f"must be a Problem (assur.synthesis.load_problem(path)), not "
                                                 f"{type(problem).__name__}")])
        self.problem = problem
        self.backend = backend or default_backend()
        p = problem
        self._periodic = np.array([v.periodic for v in p.variables], dtype=bool)
        self._index = {v.name: i for i, v in enumerate(p.variables)}
        quantities = {t.quantity for t in p.terms} | {lim.quantity for lim in p.limits}
        self._order = 2 if "acceleration" in quantities else 0
        # forces.* need the accelerations (d'Alembert loads), gait speeds the first derivatives
        self._cycle_order = (2 if any(q.startswith(("forces.", "dynamics.")) for q in quantities)
                             else 1 if any(_speed_term(q) for q in quantities) else 0)
        self._quantities = quantities
        from ..engine.planar.numba_backend import covers, cycle_covers
        t = p.targets
        self._needs_cycle = p.needs_cycle()
        # the whole-cycle quantities of the compiled cycle reduction (`_cycle_compiled`): buildability, gait
        # terms, the worst transmission angle, path distances of point targets
        self._cycle_fast = (self.backend == "numba" and self._needs_cycle and "defects" not in p.constraints
                            and not any(q.startswith(("forces.", "dynamics.")) for q in quantities)
                            and (t is None or t.timing != "path" or getattr(t, "kind", "points") == "points")
                            and cycle_covers(p.plan, "transmission.min" in quantities))
        cycle_quantities = ({q for q in quantities if q.startswith("gait.")} | {"transmission.min"}
                            if self._cycle_fast else set())
        self._fusable = (self.backend == "numba" and t is not None and t.timing != "path" and t.kind == "points"
                         and "defects" not in p.constraints
                         and quantities - cycle_quantities <= {"deviation", "unbuildable"} | {q for q in quantities if q.startswith("expression:")}
                         and covers(p.plan))
        fast = self._fusable or (self._cycle_fast and (t is None or t.timing == "path"))
        self.chunk = int(chunk) if chunk else (self.FUSED_CHUNK if fast else self.CHUNK)
        self._cycle_q = np.linspace(0.0, TWO_PI, p.cycle_samples, endpoint=False)   # (M,) whole-cycle inputs
        # free timing solved per design (synthesis.timing): the timing variables are outputs of the evaluation
        self._inner = t is not None and t.timing == "free" and t.free_timing == "inner"
        self._timing_cols = [self._index[n] for n in t.input_variables] if self._inner else []
        self._placement = p.placement              # synthesis.placement: each design placed in closed form

    def __reduce__(self):
        return (_rebuild_evaluator, (self.problem, self.chunk, self.backend))

    # -- public --------------------------------------------------------------------------------------
    def recheck(self, X) -> Evaluation:
        """``self(X, detail=True)`` for a run's result (a design, once). A plan with Newton-solved groups then solves
        on numpy: the detailed route's compiled solve kernels are not the search's (its cycle reduction) and would
        first compile, 9–17 s each, for this one call, where numpy takes 25–150 ms per design and cycle (the
        numbers agree to round-off). Any other plan as ``self(X, detail=True)``."""
        if self.backend != "numba" or not self.problem.plan.has_newton_groups:
            return self(X, detail=True)
        return Evaluator(self.problem, backend="numpy")(X, detail=True)

    def __call__(self, X, detail: bool = False) -> Evaluation:
        """X: (n, n_vars) design vectors in SI (angles in rad) → Evaluation. ``detail`` adds the
        per-target ``distances``/``offsets`` (the general route; without it the fused compiled
        reduction is used where it applies, which gives the same f and V to round-off)."""
        X = np.atleast_2d(float_array(X, "X", "design vectors of numbers (n, n_vars)"))
        if X.shape[-1] != self.problem.n_vars:
            raise SpecError([("X", f"design vectors must have {self.problem.n_vars} entries: shape {X.shape}")])
        size = self.CHUNK if detail else self.chunk          # the detailed route keeps per-target arrays
        parts = [self._chunk(X[i:i + size], detail) for i in range(0, len(X), size)] or [self._chunk(X, detail)]
        return Evaluation.concatenate(parts)

    def wrap(self, X) -> np.ndarray:
        """Periodic angles wrapped into [0, 2π)."""
        X = np.array(X, dtype=float, copy=True)
        X[..., self._periodic] = np.mod(X[..., self._periodic], TWO_PI)
        return X

    def params(self, X) -> np.ndarray:
        """Mechanism parameters (n, n_params) of design vectors X (n, n_vars), SI."""
        return self._params(self.wrap(np.atleast_2d(X)))

    def target_inputs(self, X) -> np.ndarray:
        """(n, N) input values at the targets (rad or m); with free timing solved inside the evaluation, each design's
        best inputs (:mod:`assur.synthesis.timing`)."""
        Xw = self.wrap(np.atleast_2d(X))
        if self._inner:
            return self._solve_timing(self._params(Xw))
        return self._target_inputs(Xw)

    def _solve_timing(self, params) -> np.ndarray:
        """Each design's best inputs at the targets (n, N) (free timing solved inside the evaluation)."""
        from .timing import order_of, solve_timing
        prob = self.problem
        t = prob.targets
        pose = {"link": t.link, "angles": t.angles, "angle_weight": t.angle_weight} if t.kind == "poses" else {}
        return solve_timing(prob.plan, params, t.point, t.xy, self._cycle_q, order_of(prob.constraints),
                            1 if prob.deviation == "distance" else 2, self.backend, **pose)

    def _params(self, X) -> np.ndarray:
        """params() of already wrapped design vectors."""
        return parameters(self.problem, X)

    def _target_inputs(self, X) -> np.ndarray:
        """target_inputs() of already wrapped design vectors."""
        return target_inputs(self.problem, X)

    # -- one chunk -----------------------------------------------------------------------------------
    def _place(self, Xw, detail: bool):
        """(the designs Xw (n, n_vars) at their best placement (:mod:`.placement`), the placed fused reduction
        (n, 9) where the compiled route computed it, else None). The fit is made at each design's reference
        placement; the compiled route also reduces the objective of the placed points there."""
        from .placement import fit, limits, place, points, reference
        prob, pl = self.problem, self._placement
        R = reference(pl, Xw)
        lim = limits(pl, Xw, prob.bounds)
        rotate = pl.angle is not None
        if self._fusable and not detail:
            params = self._params(R)
            params = np.where(np.all(np.isfinite(params), axis=1)[:, None], params, prob.plan.defaults)
            out = self._fused(self._target_inputs(R), params, lim, rotate)
            return place(pl, R, prob.bounds, *out[:, 5:9].T), out
        q, ok = points(prob, R, self.backend)
        return place(pl, R, prob.bounds, *fit(q, ok, prob.targets.xy, lim, rotate)), None

    def _fused(self, theta, params, limits=None, rotate=False):
        """The compiled reduction (D, 5) of ``engine.planar.numba_backend.path_objective`` where it covers the
        problem (timed targets, deviation and buildability only), else None. theta: (n, N) target inputs. With
        ``limits`` (D, 6) the designs' placements solved too (``params`` at their reference placement): (D, 9)."""
        if not self._fusable:
            return None
        from ..engine.planar.numba_backend import path_objective
        prob = self.problem
        cycle = self._cycle_q if self._needs_cycle and not self._cycle_fast else None
        q = theta[:1] if prob.targets.timing == "prescribed" else theta
        return path_objective(prob.plan, params, q, prob.targets.xy, prob.targets.point, cycle,
                              DEFAULT.radicand, limits, rotate)

    def _chunk(self, X, detail: bool = False) -> Evaluation:
        from ..engine import solve
        prob, plan = self.problem, self.problem.plan
        n = len(X)
        Xw = self.wrap(X)
        placed = None
        if self._placement is not None:                   # each design at its best placement, then as given
            Xw, placed = self._place(Xw, detail)
        lo, hi = prob.bounds.T
        out_of_box = np.where(self._periodic, 0.0, np.maximum(0.0, lo - Xw) + np.maximum(0.0, Xw - hi)).sum(axis=1)
        params = self._params(Xw)
        finite = np.all(np.isfinite(params), axis=1)
        params = np.where(finite[:, None], params, plan.defaults)   # NaN parameters: infeasible, not solved
        V = {"bounds": out_of_box, "parameters": np.where(finite, 0.0, 1.0)}
        Q: dict[str, np.ndarray] = {}
        ls = prob.length_scale
        f = np.zeros(n)
        t = prob.targets
        x_out = Xw if self._placement is not None else None      # the placement is an output
        if self._inner:                                   # the best inputs of each design, then as if explicit
            theta = self._solve_timing(params)
            Xw[:, self._timing_cols] = theta
            x_out = Xw
        else:
            theta = self._target_inputs(Xw) if t is not None and t.timing != "path" else None   # (n, N)
        fused = placed if placed is not None else None if detail else self._fused(theta, params)
        if fused is not None:
            V["assembly"] = fused[:, 2] / t.n
            Q["deviation"] = fused[:, 0 if prob.deviation == "squared" else 1] * (ls * ls if prob.deviation == "squared" else ls)
            if prob.deviation != "none":
                f = f + prob.deviation_weight * Q["deviation"]
            if self._needs_cycle and not self._cycle_fast:
                Q["unbuildable"] = fused[:, 3] / prob.cycle_samples
                V["buildable"] = _buildable_violation(Q["unbuildable"], fused[:, 4] / prob.cycle_samples)
        elif theta is not None:
            st = solve(plan, params[:, None, :], theta[..., None], order=self._order, backend=self.backend)
            valid = st.valid & finite[:, None]
            V["assembly"] = np.count_nonzero(~valid, axis=1) / t.n
            from ..io.units import ANGLE
            with np.errstate(all="ignore"):                                       # (n, N, k), (n, N)
                Q["offsets"], Q["distances"] = target_offsets(t, plan, st, theta, ls, 1.0 / ANGLE[prob.angle_unit])
            if self._order == 2:
                Q["acceleration"] = np.sum((st.d2pos_dq2[:, :, plan.point_index(t.point), 0, 0, 0] * ls) ** 2, axis=1)
        if self._needs_cycle and self._cycle_fast and not detail:
            self._cycle_compiled(params, finite, V, Q)
        elif self._needs_cycle and (fused is None or self._cycle_fast):
            self._cycle(params, finite, V, Q)
        if "defects" in prob.constraints:
            from ..io.units import ANGLE
            order, stretch = defect_measures(theta if theta is not None else Q.pop("_path_inputs"),
                                             Q.pop("_cycle_valid"), self._cycle_q)
            V["defects"] = order + stretch
            Q["defects.order"], Q["defects.stretch"] = order / ANGLE[prob.angle_unit], stretch
        if t is not None and t.timing == "path":
            Q["distances"] = Q.pop("_path_distances")
        if "distances" in Q:
            d = Q["distances"]
            Q["deviation"] = (d * d).sum(axis=1) if prob.deviation == "squared" else d.sum(axis=1)
            if prob.deviation != "none":
                f = f + prob.deviation_weight * Q["deviation"]
        env = expression_env(prob, params, Xw)             # for the expressions
        if prob.fourbar:
            self._fourbar(env, theta, n, V)
        for c in ("cyclic_order", "cyclic_order_any", "ascending"):
            if c in prob.constraints:
                V[c] = getattr(fb, c)(theta)
        for term in prob.terms:
            v = self._quantity(term.quantity, term.expression, n, Q, env)
            f = f + term.weight * (v if term.target is None else np.abs(v - term.target))
        for i, lim in enumerate(prob.limits):
            v = self._quantity(lim.quantity, lim.expression, n, Q, env)
            viol = np.zeros(n)
            if lim.low is not None:
                viol = viol + np.maximum(0.0, lim.low - v)
            if lim.high is not None:
                viol = viol + np.maximum(0.0, v - lim.high)
            V[f"limit[{i}] {lim.quantity}"] = np.where(np.isfinite(v), viol, 1.0)
        total = sum(V.values())
        # a measure that cannot be computed (0/0 on a degenerate design) or overflows: infeasible, with a finite
        # penalty (the polish's residuals must stay finite)
        total = np.where(np.isnan(total), 1.0, np.minimum(total, 1e30))
        bad_f = ~np.isfinite(f)
        total = np.where(bad_f & (total == 0), 1.0, total)        # an objective that cannot be computed
        feasible = total == 0
        objective = np.where(feasible, f, np.nan)
        penalised = np.where(feasible, f, prob.infeasible_offset + prob.violation_weight * total)
        return Evaluation(objective, total, feasible, penalised, V, Q, x_out)

    def _cycle(self, params, finite, V, Q):
        """Whole-cycle samples: buildability, gait quantities, transmission, path distances. Newton-solved groups
        are swept through the turn sample after sample (``solve(..., sweep=True)``): a continuous crank motion
        from each design's own assembly at the sketch's angle, and far fewer solves."""
        from ..engine import solve
        prob, plan = self.problem, self.problem.plan
        M, q = prob.cycle_samples, self._cycle_q
        st = solve(plan, params[:, None, :], q[:, None], order=self._cycle_order, backend=self.backend, sweep=True)
        valid = st.valid & finite[:, None]
        share = np.count_nonzero(~valid, axis=1) / M
        Q["unbuildable"] = share
        if "defects" in prob.constraints:
            Q["_cycle_valid"] = valid
        if "buildable" in prob.constraints:
            shortfall = None
            if self.backend == "numba" and share.any():
                from ..engine.planar.numba_backend import path_objective
                r = path_objective(plan, params, np.zeros((1, 0)), np.zeros((0, 2)), plan.point_names[0], q,
                                   DEFAULT.radicand)
                shortfall = None if r is None else r[:, 4] / M
            V["buildable"] = share if shortfall is None else _buildable_violation(share, shortfall)
        ls = prob.length_scale
        if prob.targets is not None and prob.targets.timing == "path":
            path = st.pos[:, :, plan.point_index(prob.targets.point), :]        # (n, M, 2)
            Q["_path_distances"] = _polyline_distance(path, prob.targets.xy) * ls
            if "defects" in prob.constraints:
                Q["_path_inputs"] = nearest_inputs(path, prob.targets.xy, q)
        if any(k.startswith("gait.") for k in self._quantities):
            Q.update(_sampled_gait(plan, st, ls))
        if any(k.startswith("forces.") for k in self._quantities):
            Q.update(_sampled_forces(plan, st, valid, self.backend))
        if any(k.startswith("dynamics.") for k in self._quantities):
            Q.update(_sampled_dynamics(plan, params, st, valid, prob.angle_unit, self.backend))
        if "transmission.min" in self._quantities:
            from ..analysis.transmission import transmission_angles
            from ..io.units import ANGLE
            angles = transmission_angles(plan, st, params[:, None, :])
            if angles:
                stack = np.stack([np.broadcast_to(a, valid.shape) for a in angles.values()], axis=0)
                acute = np.minimum(stack, np.pi - stack)          # RRR's μ ∈ [0, π] folded: worst side
                with np.errstate(all="ignore"):
                    worst = np.nanmin(np.where(valid, acute, np.inf), axis=(0, 2))
                Q["transmission.min"] = np.where(np.isfinite(worst), worst, np.nan) / ANGLE[prob.angle_unit]
            else:
                Q["transmission.min"] = np.full(len(params), np.nan)

    def _cycle_compiled(self, params, finite, V, Q):
        """What :meth:`_cycle` computes (buildability, gait terms, the worst transmission angle, path distances),
        from the compiled cycle reduction (``engine.planar.numba_backend.cycle_objective``): the same sampled
        definitions, the same numbers to round-off, only a few numbers per design stored."""
        from ..engine.planar.numba_backend import cycle_objective
        from ..kernels.codegen import CYCLE_COLUMNS, PATH_COLUMN
        prob, plan = self.problem, self.problem.plan
        M, ls = prob.cycle_samples, prob.length_scale
        gait = {k for k in self._quantities if k.startswith("gait.")}
        kw = {}
        if gait:
            foot, ground, up = resolve_gait(plan)
            kw = dict(foot=foot, ground=ground, up=up, scale=ls,
                      omega=abs(float(plan.speeds[0])) if len(plan.speeds) else 1.0)
        t = prob.targets
        if t is not None and t.timing == "path":
            kw.update(path=t.point, target_xy=t.xy)
        r = cycle_objective(plan, params, self._cycle_q, DEFAULT.radicand,
                            transmission="transmission.min" in self._quantities, **kw)
        share = np.where(finite, r[:, 0] / M, 1.0)      # a design with NaN parameters: nothing assembles
        Q["unbuildable"] = share
        if "buildable" in prob.constraints:
            V["buildable"] = _buildable_violation(share, np.where(finite, r[:, 1] / M, 0.0))
        if "path" in kw:
            Q["_path_distances"] = r[:, PATH_COLUMN:] * ls
        if gait:      # every gait term, as the general route gives them (the speeds where a speed is named)
            speeds = any(_speed_term(k) for k in gait)
            Q.update({k: r[:, i] for i, k in enumerate(CYCLE_COLUMNS)
                      if k.startswith("gait.") and (speeds or not _speed_term(k))})
            Q["gait.clearance"] = Q["gait.lift"] - Q["gait.sag"]
        if "transmission.min" in self._quantities:
            from ..io.units import ANGLE
            Q["transmission.min"] = np.where(finite, r[:, 2], np.nan) / ANGLE[prob.angle_unit]

    def _fourbar(self, env, theta, n, V):
        """The four-bar constraint measures; env: the expressions' names → (n,), theta (n, N) or None."""
        prob = self.problem
        L = fourbar_lengths(prob, env, n)
        L = np.where(np.isfinite(L), L, 0.0)
        safe = np.where(L > 0, L, 1e-300)
        for c, measure in (("grashof", fb.grashof), ("nondegenerate", fb.nondegenerate),
                           ("r2_shortest", fb.crank_shortest), ("cidetec_order", fb.cidetec_order)):
            if c in prob.constraints:
                V[c] = measure(L)
        t = prob.targets
        if theta is not None:
            with np.errstate(all="ignore"):
                V["assembly"] = V.get("assembly", 0.0) + fb.assembly(safe, theta)
            if "continuous_motion" in prob.constraints:
                if t.timing == "free":
                    start, width = theta[:, 0], fb.gaps(theta).sum(axis=1)
                elif t.timing == "uniform":
                    start = theta[:, 0]
                    whole = abs(t.step) * t.n >= TWO_PI - DEFAULT.full_turn
                    width = np.full(n, abs(t.step) * (t.n if whole else t.n - 1))
                    if t.step < 0:
                        start = theta[:, -1]
                else:
                    start, width = theta.min(axis=1), np.ptp(theta, axis=1)
                with np.errstate(all="ignore"):
                    V["continuous_motion"] = fb.continuous_motion(safe, start, width)

    @staticmethod
    def _quantity(name, expression, n, Q, env):
        if expression is not None:
            with np.errstate(all="ignore"):
                return np.broadcast_to(np.asarray(expression(env), dtype=float), (n,))
        return Q[name]


def _rebuild_evaluator(problem, chunk, backend):
    return Evaluator(problem, chunk=chunk, backend=backend)


def _speed_term(quantity: str) -> bool:
    """Whether a gait quantity needs the foot's velocity (the cycle solved with first derivatives)."""
    return quantity.startswith("gait.speed") or quantity.startswith("gait.vx_")


def _buildable_violation(share, shortfall):
    """The whole-cycle buildability measure: the mean shortfall of the groups past their toggles
    (smooth: it grows continuously as a design moves away from buildable), or where no radicand
    explains the failure (coincident pivots, say) the unbuildable share of the cycle. 0 exactly
    when every sample assembles."""
    return np.where(shortfall > 0, shortfall, share)


def _polyline_distance(path, targets):
    """Distance of each target (N, 2) to the closed polyline path (n, M, 2) → (n, N)."""
    a = path[:, :, None, :]
    b = np.roll(path, -1, axis=1)[:, :, None, :]
    p = targets[None, None, :, :]
    ab = b - a
    t = np.clip(np.sum((p - a) * ab, axis=-1) / np.maximum(np.sum(ab * ab, axis=-1), 1e-300), 0.0, 1.0)
    d = np.linalg.norm(a + t[..., None] * ab - p, axis=-1)      # (n, M, N)
    return d.min(axis=1)


def _sampled_gait(plan, st, ls):
    """Gait quantities ``gait.*`` of every design from the cycle samples st (n, M): the sampled form
    (:func:`assur.analysis.gait.population_gait`) of the exact per-design definitions of ``analysis.gait``."""
    foot, ground, up = resolve_gait(plan)
    i = plan.point_index(foot)
    dpos = None if st.dpos_dq is None else st.dpos_dq[:, :, i, :, 0]
    w = abs(float(plan.speeds[0])) if len(plan.speeds) else 1.0
    out = population_gait(st.pos[:, :, i, :], st.valid, dpos, ground=ground, up=up, omega=w, scale=ls)
    return {f"gait.{k}": v for k, v in out.items()}


def _sampled_dynamics(plan, params, st, valid, angle_unit, backend) -> dict:
    """``dynamics.*`` of every design from rest on the template's motor (:mod:`assur.dynamics.quantities`), on the
    cycle samples st (D, M) solved with order 2; a design with an unassembled sample does not turn fully, so it does
    not start (0, NaN). The mean speed in the file's angle unit per second."""
    from ..dynamics.quantities import population_quantities
    from ..io.units import ANGLE
    out = population_quantities(plan, params, st, compiled=backend == "numba")
    bad = ~np.all(valid, axis=1)
    for k in out:
        out[k] = np.where(bad, 0.0 if k == "dynamics.starts" else np.nan, out[k])
    out["dynamics.mean_speed"] = out["dynamics.mean_speed"] / ANGLE[angle_unit]
    return out


def _sampled_forces(plan, st, valid, backend) -> dict:
    """``forces.*`` of every design from the cycle samples st (D, M) solved with order 2 (SI: N·m or N, N).

    One leg (no ``[gait]``, or one phase): its driving effort. A walking module (``[gait] phases``): the
    common shaft's, Σ over the legs of the leg's effort at q + phase. With ``[gait] weight`` each foot carries
    its share of the weight on the design's sampled contact arc
    (:func:`assur.kinetostatics.gait.population_foot_loads`). NaN for a design with an unassembled or
    singular sample."""
    from ..kinetostatics import forces
    from ..kinetostatics.gait import phase_shifts, population_foot_loads
    g = plan.mechanism.gait
    D, M = valid.shape
    phases = g.phases if g is not None else (0.0,)
    shifts = phase_shifts(phases, M)
    legs = [(int(s), None) for s in shifts]
    if g is not None and g.weight is not None:
        foot, ground, up = resolve_gait(plan)
        pos = st.pos[:, :, plan.point_index(foot), :]
        loads = population_foot_loads(pos, valid, phases, g.weight, up, ground)       # (D, M, legs, 2)
        # leg k at its own sample i = j + s_k carries the load of module sample j
        legs = [(int(s), np.roll(loads[:, :, k], s, axis=1)) for k, s in enumerate(shifts)]
    torque, reaction, unloaded = np.zeros((D, M)), np.full(D, -np.inf), None
    with np.errstate(all="ignore"):
        for s, load in legs:
            if load is None and unloaded is not None:
                f = unloaded
            else:
                f = forces(plan, state=st, point_loads=None if load is None else [(foot, load)], backend=backend)
                unloaded = f if load is None else None
            torque = torque + np.roll(f.driver[..., 0], -s, axis=1)                  # module sample j
            reaction = np.maximum(reaction, np.max(f.magnitudes[..., f.joint_pairs], axis=(1, 2)))
        bad = ~np.all(valid, axis=1)
        out = {"forces.torque_peak": np.max(np.abs(torque), axis=1),
               "forces.torque_rms": np.sqrt(np.mean(torque * torque, axis=1)),
               "forces.reaction_peak": reaction}
    return {k: np.where(bad, np.nan, v) for k, v in out.items()}


__all__ = ["Evaluation", "Evaluator", "NUMPY_SECONDS_PER_NEWTON_GROUP", "NUMPY_SECONDS_PER_UNIT", "PAYBACK_SECONDS",
           "default_backend", "numpy_seconds", "run_backend"]
