"""Solver settings: the defaults of ``synthesize`` and ``assur synth``, and the ``[solver]`` table a problem
file may carry.

The settings of a run are resolved in this order, each level overriding the one before it:

1. the built-in defaults (:data:`DEFAULTS`);
2. the problem file's ``[solver]`` table;
3. what the command line (or the Python call) gives explicitly.

    [solver]
    method = "restart"        # restart | de | cmaes | local | lshade
    budget = 300000           # objective evaluations in all
    target = 1e-20            # stop at the first feasible design with objective ≤ target
    starts = 1
    popsize = 15
    strategy = "best1bin"
    polish = "auto"
    maxiter = 1000
    time = 60                 # seconds
"""
from __future__ import annotations

import math

#: the global methods: 'restart' is the default (differential evolution restarted on stagnation, each
#: restart's best polished, until the budget, the time limit or the target ends the run)
METHODS = ("restart", "de", "cmaes", "local", "lshade")
DE_STRATEGIES = ("best1bin", "best1exp", "rand1bin", "rand1exp", "rand2bin", "rand2exp", "randtobest1bin",
                 "randtobest1exp", "currenttobest1bin", "currenttobest1exp", "best2exp", "best2bin")
POLISHES = ("auto", "least_squares", "nelder-mead", "l-bfgs-b", "none")

#: the default evaluation budget of a run when neither the file nor the caller gives a budget or a time limit
DEFAULT_BUDGET = 300_000

#: built-in defaults (level 1); for the 'restart' method ``budget`` None means DEFAULT_BUDGET unless a time limit
#: is given
DEFAULTS = {"method": "restart", "budget": None, "time": None, "target": None, "starts": 1, "popsize": 15,
            "strategy": "best1bin", "polish": "auto", "maxiter": 1000}

#: what each key of [solver] holds
KEYS = {
    "method": f"global method: {' | '.join(METHODS)}",
    "budget": "objective evaluations in all (integer ≥ 1)",
    "time": "wall-time limit in seconds (> 0)",
    "target": "stop at the first feasible design with objective ≤ target (file units)",
    "starts": "independent starts (integer ≥ 1)",
    "popsize": "population per variable (integer ≥ 2)",
    "strategy": "scipy differential-evolution strategy",
    "polish": f"local refinement: {' | '.join(POLISHES)}",
    "maxiter": "generations per start or restart (integer ≥ 1)",
}


def read_solver(raw, P) -> dict:
    """Validate a parsed ``[solver]`` table; every problem goes to ``P`` (an ``io.problems.Problems``) with its
    location (``solver.KEY``). Returns the valid settings (only the keys the file gives)."""
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        P.add("solver", "must be a table of solver settings (method, budget, target, starts, …)")
        return {}
    P.unknown_keys(raw, tuple(KEYS), "solver")
    out = {}
    for key, v in raw.items():
        if key not in KEYS:
            continue
        value, problem = check_setting(key, v)
        if problem:
            P.add(f"solver.{key}", problem)
        else:
            out[key] = value
    return out


def check_setting(key: str, v):
    """(the setting ``key`` as its type, None) when ``v`` is a valid value, else (None, what is wrong)."""
    import numpy as np
    if key in ("method", "strategy", "polish"):
        choices = {"method": METHODS, "strategy": DE_STRATEGIES, "polish": POLISHES}[key]
        if not isinstance(v, str) or v not in choices:
            return None, f"must be one of {', '.join(choices)}: {v!r:.60}"
        return v, None
    if key in ("budget", "starts", "popsize", "maxiter"):
        low = 2 if key == "popsize" else 1
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            return None, f"must be an integer ≥ {low}: {v!r:.60}"
        return int(v), None
    # time, target
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not math.isfinite(v):
        return None, f"must be a finite number: {v!r:.60}"
    if key == "time" and not v > 0:
        return None, f"must be positive: {v!r}"
    return float(v), None


def resolve(file_settings: dict | None, given: dict) -> dict:
    """The settings of a run: DEFAULTS ← the file's [solver] ← the caller's explicit (non-None) values. A run with
    neither a budget nor a time limit gets DEFAULT_BUDGET with the 'restart' method. Adds ``sources``: key → 'default' | 'file' | 'given'."""
    from ..errors import SettingError
    problems = []
    for k, v in given.items():           # the caller's values, checked as the file's are (named as the arguments)
        if v is not None and k in KEYS:
            _, problem = check_setting(k, v)
            if problem:
                problems.append(("time_limit" if k == "time" else k, problem))
    if problems:
        raise SettingError(problems)
    settings, sources = dict(DEFAULTS), {k: "default" for k in DEFAULTS}
    for level, values in (("file", file_settings or {}), ("given", given)):
        for k, v in values.items():
            if v is not None and k in settings:
                settings[k], sources[k] = v, level
    if settings["method"] in ("restart", "lshade") and settings["budget"] is None and settings["time"] is None:
        settings["budget"] = DEFAULT_BUDGET        # restarts go on until something ends them
    settings["sources"] = sources
    return settings


__all__ = ["DEFAULTS", "DEFAULT_BUDGET", "DE_STRATEGIES", "KEYS", "METHODS", "POLISHES", "check_setting", "read_solver",
           "resolve"]
