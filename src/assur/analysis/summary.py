"""The JSON form of a :class:`~assur.analysis.study.Study` (what ``assur analyze --json`` prints).

:func:`summary_dict` formats the Study's typed fields (structure, buildability, transmission, dead centres,
links, output link, gait, walking module; a spatial mechanism's dyads; a linear driver's stroke) into the one
JSON-ready dict at the edge. All numbers SI.
"""
from __future__ import annotations

import math

import numpy as np

from .overview import finite_or_none, structure_summary

__all__ = ["structure_summary", "summary_dict"]


def summary_dict(study) -> dict:
    """The JSON-ready summary of a Study (SI), without the force summary (see :meth:`Study.as_dict`)."""
    plan = study.plan
    out = dict(study.header)
    if plan.n_inputs != 1:
        return out
    if plan.dimension == 3:
        if study.turn:
            from .spatial import spatial_summary
            spatial_summary(study, out)
            out["links"] = {k: v.as_dict() for k, v in study.links.items()}
        return out
    if not study.turn:
        act = study.actuators
        if "note" in act:
            return {**out, "unbuildable": None, "note": act["note"]}
        return {**out, "actuators": act, "unbuildable": act["unbuildable"]}
    b = study.buildable
    out["unbuildable"] = b.unbuildable
    out["ambiguous"] = b.ambiguous
    out["buildable_ranges"] = [{"start": s, "end": e} for s, e in b.ranges]
    out["full_rotation"] = b.full_rotation
    out["toggle_positions"] = b.toggle_positions
    out["transmission_angles"] = {
        k: {"min": finite_or_none(np.nanmin(v)), "max": finite_or_none(np.nanmax(v)),
            "worst_deviation_from_90": finite_or_none(np.nanmax(np.abs(v - math.pi / 2)))}
        for k, v in study.transmission.items()}
    out["dead_centres"] = [{"angle": d.angle, "kind": d.kind, "link": d.link, "crank": d.crank}
                           for d in study.dead_centres]
    out["links"] = {k: v.as_dict() for k, v in study.links.items()}
    out["output_link"] = None if study.output_link is None else study.output_link.as_dict()
    out["four_bars"] = [loop.as_dict() for loop in study.four_bars]
    if plan.mechanism.gait is None:
        return out
    if study.gait is None:
        out["gait"] = None
        out["gait_error"] = study.gait_error
        return out
    out["gait"] = study.gait.as_dict()
    if study.module is not None:
        out["module"] = study.module.as_dict()
    return out
