"""A design as a mechanism: design vectors mapped to the template's parameters and to the inputs at the targets
(:func:`parameters`, :func:`target_inputs`), and one parameter vector written into the template.

``mechanism_with_params(plan, params)`` returns a new frozen ``Mechanism`` whose parameters are
``params`` (SI, ``plan.param_names`` order): frame points moved, link lengths and point placements
written explicitly, slide lines and crank zeros set, and the moving points' sketch coordinates
replaced by the design assembled at the sketch input on the plan's branch — so the written file
compiles back to the same parameters and the same assembly branch.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import SpecError
from ..model.mechanism import FRAME, Placement


def parameters(problem, X) -> np.ndarray:
    """Mechanism parameters (n, n_params) SI of wrapped design vectors X (n, n_vars): the template's defaults with
    the problem's ``[parameters]`` expressions evaluated in order (a parameter may use those before it)."""
    plan = problem.plan
    p = np.tile(plan.defaults, (len(X), 1))
    env = expression_env(problem, p, X)        # its parameter columns are views: filled in below, in order
    names = set(problem.names)
    with np.errstate(all="ignore"):
        for name, e in problem.parameters:
            idx = plan.param_index(name)
            p[:, idx] = np.broadcast_to(np.asarray(e(env), dtype=float), (len(X),))
            if name not in names:
                env[name] = p[:, idx]
    return p


def expression_env(problem, params, X) -> dict:
    """The names the problem's expressions read → (n,) columns: the mechanism's parameters ``params``
    (n, n_params) and the design variables of X (n, n_vars), a variable shadowing a parameter of its name."""
    env = {name: params[:, i] for i, name in enumerate(problem.plan.param_names)}
    env.update({v.name: X[:, j] for j, v in enumerate(problem.variables)})
    return env


def fourbar_lengths(problem, env, n: int) -> np.ndarray:
    """(n, 4) the lengths the four-bar constraints read (``[constraints] fourbar``), from :func:`expression_env`;
    NaN where an expression cannot be computed."""
    with np.errstate(all="ignore"):
        return np.stack([np.broadcast_to(np.asarray(e(env), dtype=float), (n,)) for _, e in problem.fourbar], axis=1)


def target_inputs(problem, X) -> np.ndarray:
    """(n, N) input values at the targets (rad or m) of wrapped design vectors X (n, n_vars) as they stand: the
    prescribed inputs, the timing variables of free timing, or uniform timing's start plus its steps."""
    t = problem.targets
    names = problem.names
    if t.timing == "prescribed":
        return np.broadcast_to(t.inputs, (len(X), t.n))
    if t.timing == "free":
        return X[:, [names.index(n) for n in t.input_variables]]
    return X[:, [names.index(t.start)]] + t.step * np.arange(t.n)


def mechanism_with_params(plan, params, *, name: str | None = None, description: str | None = None):
    """params: (n_params,) SI → Mechanism (the template's structure, this design's dimensions)."""
    from ..engine import solve
    m = plan.mechanism
    params = np.asarray(params, dtype=float)
    if params.shape != (plan.n_params,):
        raise SpecError([("params", f"must have shape ({plan.n_params},): {params.shape}")])
    value = {n: float(v) for n, v in zip(plan.param_names, params)}
    st = solve(plan, params, plan.sketch_inputs[None, :], order=0, backend="numpy")
    assembled = bool(np.all(st.valid))
    pos = st.pos.reshape(-1, plan.n_points, st.pos.shape[-1])[0]
    if not assembled and plan.n_inputs == 1 and plan.input_kinds[0] == "rotary":
        # a design that cannot reach the sketch's input (a rocker-crank working over a range, say): sketch it
        # at the nearest crank angle where it assembles, on the same branch
        turn = np.linspace(-np.pi, np.pi, 721)
        turn = turn[np.argsort(np.abs(turn), kind="stable")]
        tried = solve(plan, params, (plan.sketch_inputs[0] + turn)[:, None], order=0, backend="numpy")
        ok = np.flatnonzero(tried.valid)
        if len(ok):
            assembled, pos = True, tried.pos[ok[0]]
    frame_points = set(m.frame.points)
    points = []
    for i, (p, xy) in enumerate(m.points):
        if p in frame_points and f"{p}.x" in value:
            xy = (value[f"{p}.x"], value[f"{p}.y"])
        elif assembled and p in plan.point_names:
            xy = tuple(float(c) for c in pos[plan.point_index(p)])
        points.append((p, tuple(xy)))
    links = []
    for lk in m.links:
        if lk.name == FRAME or len(lk.points) < 2 or f"{lk.name}.length" not in value:
            links.append(lk)
            continue
        place = []
        for p in lk.points[2:]:
            old = lk.placement(p)
            origin, toward = (old.origin, old.toward) if old is not None else (lk.points[0], lk.points[1])
            place.append((p, Placement(origin, toward, value[f"{lk.name}.{p}.distance"],
                                       value[f"{lk.name}.{p}.angle"])))
        links.append(dataclasses.replace(lk, length=value[f"{lk.name}.length"], place=tuple(place)))
    prismatic = tuple(dataclasses.replace(pr, angle=value.get(f"{pr.name}.angle", pr.angle),
                                          offset=value.get(f"{pr.name}.offset", pr.offset)) for pr in m.prismatic)
    drivers = tuple(dataclasses.replace(d, zero=value[f"{d.name}.zero"]) if d.kind == "rotary"
                    and f"{d.name}.zero" in value else d for d in m.drivers)
    return dataclasses.replace(m, points=tuple(points), links=tuple(links), prismatic=prismatic, drivers=drivers,
                               name=m.name if name is None else name,
                               description=m.description if description is None else description)


__all__ = ["expression_env", "fourbar_lengths", "mechanism_with_params", "parameters", "target_inputs"]
