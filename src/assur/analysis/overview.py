"""The part of a mechanism's summary that every dimension shares: the structure (mobility, pairs, Assur
groups, structural formula) and the head of a cycle summary (parameters, inputs, samples). JSON-ready
dicts, SI units.
"""
from __future__ import annotations

import math

from ..structure.assur import analyse


def structure_summary(mech, structure=None) -> dict:
    """Mobility (with its formula), links, kinematic pairs, drivers, Assur groups and the structural formula of
    the mechanism ``mech``; ``idle_freedoms`` and ``mobility_without_idle`` where links spin idly. ``structure``:
    its :class:`~assur.structure.assur.Structure` when already known (a plan's), else decomposed here."""
    s = analyse(mech) if structure is None else structure
    out = {
        "name": mech.name,
        "mobility": s.mobility,
        "mobility_formula": (f"W = 3·{s.n_moving} − 2·{s.pair_counts['p5']} − {s.pair_counts['p4']} = {s.mobility}"
                             if s.formula_name == "Chebyshev" else
                             f"W = 6·{s.n_moving} − 5·{s.pair_counts['p5']} − 4·{s.pair_counts['p4']} − "
                             f"3·{s.pair_counts['p3']} − 2·{s.pair_counts['p2']} − {s.pair_counts['p1']} = {s.mobility}"),
        "formula": s.formula_name,
        "moving_links": s.n_moving,
        "pairs": dict(s.pair_counts),
        "drivers": [d.name for d in mech.drivers],
        "structural_formula": s.structural_formula if s.groups or s.drivers else None,
        "structural_formula_numbered": s.structural_formula_numbered if s.groups or s.drivers else None,
        "groups": s.describe(),
    }
    if s.idle:
        out["idle_freedoms"] = s.idle
        out["mobility_without_idle"] = s.mobility_without_idle
    return out


def summary_header(plan, params, steps: int, structure=None) -> dict:
    """:func:`structure_summary` with the ``parameters`` (at ``params`` (n_params,), default the plan's), the
    ``inputs`` and the number of samples ``steps``; a plan with several inputs gets ``unbuildable`` None and a
    ``note`` instead of a cycle analysis."""
    out = structure_summary(plan.mechanism, structure)
    out["parameters"] = {n: float(v) for n, v in zip(plan.param_names, plan.defaults if params is None else params)}
    out["inputs"] = [{"name": n, "kind": k, "speed": float(s), "sketch": float(q)}
                     for n, k, s, q in zip(plan.input_names, plan.input_kinds, plan.speeds, plan.sketch_inputs)]
    out["steps"] = steps
    if plan.n_inputs != 1:
        out["unbuildable"] = None
        out["note"] = "cycle analysis needs a single input; use 'assur solve' for several inputs"
    return out


def finite_or_none(x):
    """``x`` as a float, None when it is not finite (strict JSON)."""
    x = float(x)
    return None if not math.isfinite(x) else x
