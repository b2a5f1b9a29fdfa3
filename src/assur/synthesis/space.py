"""The variables an optimiser searches: all of a problem's design variables but those each evaluation finds for
itself — the timing variables of free timing solved inside the evaluation (``[targets] free_timing = "inner"``,
:mod:`assur.synthesis.timing`) and the translation and angle of a placement solved in closed form
(:mod:`assur.synthesis.placement`)."""
from __future__ import annotations

import numpy as np


class SearchSpace:
    """``index`` (k,) the searched variables of the problem (k ≤ n_vars); ``bounds`` (k, 2) SI; ``periodic`` (k,);
    :meth:`expand` maps search vectors (n, k) to design vectors (n, n_vars), :meth:`reduce` back."""

    def __init__(self, problem):
        t = problem.targets
        solved = (set(t.input_variables) if t is not None and t.timing == "free" and t.free_timing == "inner"
                  else set())
        if problem.placement is not None:
            solved |= {problem.variables[i].name for i in problem.placement.solved}
        self.problem = problem
        self.index = np.array([i for i, v in enumerate(problem.variables) if v.name not in solved], dtype=int)
        self.variables = tuple(problem.variables[i] for i in self.index)
        self.bounds = problem.bounds[self.index]
        self.periodic = np.array([v.periodic for v in self.variables], dtype=bool)
        self.n_vars = len(self.index)
        self.full = self.n_vars == problem.n_vars
        self.names = tuple(v.name for v in self.variables)

    def __getattr__(self, name):
        """The problem's other members (targets, constraints, deviation, terms, …)."""
        if name == "problem":
            raise AttributeError(name)
        return getattr(self.problem, name)

    def expand(self, Z) -> np.ndarray:
        """Search vectors (..., k) → design vectors (..., n_vars); the solved variables are 0 (the evaluation fills
        them in)."""
        Z = np.asarray(Z, dtype=float)
        if self.full:
            return Z
        X = np.zeros(Z.shape[:-1] + (self.problem.n_vars,))
        X[..., self.index] = Z
        return X

    def reduce(self, X) -> np.ndarray:
        """Design vectors (..., n_vars) → search vectors (..., k)."""
        X = np.asarray(X, dtype=float)
        return X if self.full else X[..., self.index]


def solved_per_design(problem) -> dict:
    """The variables each evaluation finds for itself, by reason: ``{"free timing": [names], "placement": [names],
    "size": [names]}`` (a reason only where it applies; "size": the lengths whose common factor the placement
    solves, still searched for the shape)."""
    t, out = problem.targets, {}
    if t is not None and t.timing == "free" and t.free_timing == "inner":
        out["free timing"] = list(t.input_variables)
    pl = problem.placement
    if pl is not None:
        out["placement"] = [problem.names[i] for i in pl.solved]
        if pl.scale:
            out["size"] = [problem.names[i] for i in pl.scale]
    return out


__all__ = ["SearchSpace", "solved_per_design"]
