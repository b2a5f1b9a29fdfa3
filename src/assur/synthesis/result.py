"""The result of a synthesis run (:class:`SynthesisResult`: the best design, its re-check, the run's record) and
:func:`bounds_reached`."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .evaluate import Evaluator
from .problem import Problem


@dataclass
class SynthesisResult:
    """The best design of a run, its re-check and the run's record."""
    problem: Problem
    x: np.ndarray                      # (n_vars,) SI, periodic angles wrapped
    objective: float | None            # f in file units; None if no feasible design was found
    feasible: bool
    violation: float
    details: dict                      # Evaluation.row of the best design
    evaluations: int
    seconds: float
    stopped: str                       # 'converged' | 'target' | 'budget' | 'time' | 'interrupted'
    method: str
    seed: int | None
    starts: list = field(default_factory=list)       # per start: seed, F, evaluations, seconds, stopped
    history: list = field(default_factory=list)      # (evaluations, seconds, best F) over the run
    executor: str = "in-process"
    #: seconds: ``first_batch`` from the run's start to the last of its starts' first evaluated populations (each
    #: start begun before the limit evaluates one), ``longest_batch`` the longest evaluation of one population,
    #: ``finish`` from the last start's end to the result (the best design's re-check in this process); a time limit
    #: holds within ``longest_batch`` + ``finish`` of the limit or of ``first_batch`` (docs/synthesis.md)
    timing: dict = field(default_factory=dict)
    settings: dict = field(default_factory=dict)     # the resolved settings and where each came from
    on_bounds: list = field(default_factory=list)    # variables of the best design that sit on a bound

    @property
    def x_file(self) -> np.ndarray:
        return self.problem.to_file(self.x)

    @property
    def variables(self) -> dict:
        return {n: float(v) for n, v in zip(self.problem.names, self.x_file)}

    def params(self) -> np.ndarray:
        return Evaluator(self.problem).params(self.x[None, :])[0]

    def mechanism(self):
        """The best design as a Mechanism (write it with ``assur.dump``)."""
        from .design import mechanism_with_params
        base = self.problem.plan.mechanism
        note = (f"Synthesised by assur synth from {self.problem.source or 'a problem'}: "
                f"objective {self.objective!r} ({self.problem.deviation}), method {self.method}, seed {self.seed}, "
                f"{self.evaluations} evaluations.")
        return mechanism_with_params(self.problem.plan, self.params(), name=f"{base.name} (synthesised)",
                                     description=(base.description.rstrip() + "\n\n" + note).lstrip())

    def design_plan(self, mechanism=None):
        """The best design's own plan: :meth:`mechanism` (the design sketched in its own assembly; pass it when it
        is made already) compiled, what every command reads from the file it writes; None when it does not
        assemble at its sketch."""
        from ..engine import compile as compile_plan
        from ..errors import AssurError
        try:
            return compile_plan(self.mechanism() if mechanism is None else mechanism)
        except AssurError:
            return None

    def study(self, plan=None):
        """The :class:`~assur.analysis.study.Study` of the best design (one turn, solved on first use): of
        :meth:`design_plan` (``plan``, when the caller has made it already), else of the template's plan at the
        design's numbers. (The template continued to a design far from it, a Newton-solved group's assembly, need
        not reach it along a straight path.)"""
        from ..analysis.study import Study
        plan = self.design_plan() if plan is None else plan
        return Study(self.problem.plan, self.params()) if plan is None else Study(plan)

    def gait(self, plan=None):
        """Exact gait metrics of the best design (None if the template has no [gait] or it cannot walk); ``plan``:
        its :meth:`design_plan` when made already."""
        from ..errors import AssurError
        if self.problem.plan.mechanism.gait is None:
            return None
        try:
            return self.study(plan).gait
        except AssurError:
            return None

    def __repr__(self) -> str:
        what = (f"objective {self.objective:.6g} ({self.problem.deviation})" if self.feasible
                else f"no feasible design (violation {self.violation:.4g})")
        xs = ", ".join(f"{n} = {v:.6g}" for n, v in list(self.variables.items())[:8])
        more = ", …" if len(self.variables) > 8 else ""
        return (f"SynthesisResult({self.problem.name or 'problem'}: {what}; {self.evaluations} evaluations in "
                f"{self.seconds:.2f} s, stopped: {self.stopped}, method {self.method}, seed {self.seed}; "
                f"{xs}{more} [{self.problem.length_unit}, {self.problem.angle_unit}])")

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        unit = self.problem.length_unit
        rows = [("problem", self.problem.name), ("objective", self.objective), ("feasible", self.feasible),
                ("violation", self.violation), ("method", self.method), ("seed", self.seed),
                ("evaluations", self.evaluations), ("seconds", self.seconds), ("stopped", self.stopped),
                ("executor", self.executor)] + [(f"x: {n}", v) for n, v in self.variables.items()]
        return html_table(f"Synthesis result ({unit}, {self.problem.angle_unit})", rows)

    def as_dict(self) -> dict:
        g = self.gait()
        return {"problem": self.problem.name, "source": self.problem.source, "method": self.method,
                "seed": self.seed, "executor": self.executor, "objective": self.objective,
                "feasible": self.feasible, "violation": self.violation, "length_unit": self.problem.length_unit,
                "angle_unit": self.problem.angle_unit, "variables": self.variables,
                "evaluations": self.evaluations, "seconds": self.seconds, "stopped": self.stopped,
                "timing": self.timing,
                "constraints": list(self.problem.constraints), "details": self.details,
                "gait": None if g is None else g.as_dict(), "starts": self.starts,
                "settings": self.settings, "on_bounds": self.on_bounds,
                "history": [list(h) for h in self.history]}

    def bound_warning(self) -> str | None:
        """One line naming the variables of the best design that sit on a bound, or None."""
        if not self.on_bounds:
            return None
        shown = ", ".join(f"{b['variable']} = {b['value']:.6g} ({b['bound']} bound)" for b in self.on_bounds)
        return (f"warning: the best design sits on a variable bound: {shown}; the optimum may lie outside "
                "[variables] — widen the bound if the design allows it")


def bounds_reached(problem, x, rtol: float = 1e-6) -> list:
    """The non-periodic variables of ``x`` (SI) within ``rtol`` of the bound width from their low or high bound,
    as ``{"variable", "bound": "low" | "high", "value"}`` in file units."""
    out = []
    xf = problem.to_file(np.asarray(x, dtype=float))
    for v, xi, vf in zip(problem.variables, x, xf):
        if v.periodic:
            continue
        tol = rtol * (v.high - v.low)
        for bound, edge in (("low", v.low), ("high", v.high)):
            if abs(xi - edge) <= tol:
                out.append({"variable": v.name, "bound": bound, "value": float(vf)})
    return out


# -- one start -----------------------------------------------------------------------------------------
