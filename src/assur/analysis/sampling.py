"""Sampling a single-input mechanism over one input cycle; roots and runs on the samples."""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..solve import solve

TWO_PI = 2.0 * math.pi


class Cycle:
    """Evaluates one point (or any function of a state) of a one-input plan at arbitrary inputs.

    ``fn(state) -> array (...,)`` is any scalar function of a state; ``at(q)`` evaluates it.
    """

    def __init__(self, plan, params=None, order: int = 2):
        if plan.n_inputs != 1:
            from ..errors import StructureError
            raise StructureError(f"this analysis needs one input; the mechanism has {plan.n_inputs} "
                                 f"({', '.join(plan.input_names)})")
        self.plan = plan
        self.params = plan.defaults if params is None else np.asarray(params, dtype=float)
        self.order = order

    def state(self, q, order=None):
        return solve(self.plan, self.params, np.asarray(q, dtype=float)[..., None],
                     order=self.order if order is None else order)

    def grid(self, n: int, start: float = 0.0, stop: float = TWO_PI, endpoint: bool = False):
        q = np.linspace(start, stop, n, endpoint=endpoint)
        return q, self.state(q)


def sign_changes(q, values):
    """Indices i where values changes sign between q[i] and q[i+1] (cyclic)."""
    v = np.asarray(values)
    nxt = np.roll(v, -1)
    return np.nonzero(np.isfinite(v) & np.isfinite(nxt) & (np.sign(v) != np.sign(nxt)) & (v != 0))[0]


def root_between(f, a, b):
    fa, fb = f(a), f(b)
    if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0:
        return 0.5 * (a + b)
    return brentq(f, a, b, xtol=1e-13)


def intervals(mask):
    """Cyclic runs of True in a boolean array: list of (first, last) index pairs."""
    m = np.asarray(mask, dtype=bool)
    n = len(m)
    if m.all():
        return [(0, n - 1)]
    if not m.any():
        return []
    start = int(np.argmin(m))  # a False sample: runs begin after it
    runs, cur = [], None
    for k in range(1, n + 1):
        i = (start + k) % n
        if m[i] and cur is None:
            cur = i
        if not m[i] and cur is not None:
            runs.append((cur, (i - 1) % n))
            cur = None
    if cur is not None:
        runs.append((cur, (start - 1) % n))
    return runs
