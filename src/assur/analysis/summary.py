"""One summary of a mechanism: structure, buildability, transmission, dead centres and gait (planar),
the dyads' branches, swings and dead centres (spatial), or a linear driver's working stroke.

:func:`summarize` solves one input turn once (a :class:`~assur.analysis.sampling.Cycle` of
:data:`~assur.analysis.sampling.CYCLE_STEPS` samples unless told otherwise) and derives every quantity
from it; it returns the JSON-ready summary together with the solved cycle and the gait objects, so that
a report's figures use the same solve. :func:`analyze` is the summary alone: what
``assur analyze --json`` prints and what the report shows. All numbers SI.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError, UnbuildableError
from .gait import GaitCurves, GaitMetrics, gait_metrics_and_curves, module_metrics
from .links import link_motions, output_link
from .overview import finite_or_none, structure_summary, summary_header
from .sampling import CYCLE_STEPS, Cycle, cycle_source
from .spatial import analyze_spatial
from .transmission import buildable_ranges, dead_centres, transmission_angles

__all__ = ["Analysis", "analyze", "structure_summary", "summarize"]


@dataclass(frozen=True)
class Analysis:
    """A mechanism's analysis: ``summary``, the JSON-ready dict of :func:`analyze`; ``cycle``, the solved turn
    it was derived from (None without a single rotary input); for a walking leg that turns fully, its
    ``gait`` metrics and ``gait_curves`` (sampled on the cycle's grid), else None."""
    summary: dict
    cycle: Cycle | None = None
    gait: GaitMetrics | None = None
    gait_curves: GaitCurves | None = None

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        return html_table("Analysis (SI)", self.summary.items())


def summarize(plan, params=None, steps: int = CYCLE_STEPS) -> Analysis:
    """The :class:`Analysis` of a compiled mechanism, planar or spatial, from one solved turn.

    plan: a plan (its turn sampled here at ``steps`` inputs and ``params`` (n_params,), default its
    defaults) or a :class:`~assur.analysis.sampling.Cycle` (its own grid and parameters)."""
    source = plan
    plan, params, steps = cycle_source(source, params, steps)
    cycle = (Cycle.of(source, params, steps) if plan.n_inputs == 1 and plan.input_kinds[0] == "rotary" else None)
    if plan.dimension == 3:
        out = analyze_spatial(cycle or plan, params, steps)
        if cycle is not None:
            out["links"] = link_motions(cycle)
        return Analysis(out, cycle)
    out = summary_header(plan, params, steps)
    if plan.n_inputs != 1:
        return Analysis(out)
    if cycle is None:
        out.update(_stroke(plan, params, steps))
        return Analysis(out)
    ranges, bad, _ = buildable_ranges(cycle)
    out["unbuildable"] = bad
    out["buildable_ranges"] = [{"start": a, "end": b} for a, b in ranges]
    out["full_rotation"] = bad == 0
    out["toggle_positions"] = [] if bad == 0 else sorted({a for r in ranges for a in r})
    _, st = cycle.grid()
    mu = transmission_angles(plan, st, cycle.params)
    out["transmission_angles"] = {
        k: {"min": finite_or_none(np.nanmin(v)), "max": finite_or_none(np.nanmax(v)),
            "worst_deviation_from_90": finite_or_none(np.nanmax(np.abs(v - math.pi / 2)))} for k, v in mu.items()}
    out["dead_centres"] = [{"angle": d.angle, "kind": d.kind, "link": d.link} for d in dead_centres(cycle)]
    out["links"] = link_motions(cycle)
    out["output_link"] = output_link(cycle)
    g = plan.mechanism.gait
    if g is None:
        return Analysis(out, cycle)
    try:
        gm, gc = gait_metrics_and_curves(cycle, steps=cycle.steps)
    except UnbuildableError as exc:
        out["gait"] = None
        out["gait_error"] = str(exc)
        return Analysis(out, cycle)
    out["gait"] = gm.as_dict()
    if len(g.phases) > 1:
        out["module"] = module_metrics(gm, g.phases, steps).as_dict()
    return Analysis(out, cycle, gm, gc)


def analyze(plan, params=None, steps: int = CYCLE_STEPS) -> dict:
    """A JSON-ready summary of a compiled mechanism (see :func:`summarize` and the module docstring)."""
    return summarize(plan, params, steps).summary


def _stroke(plan, params, steps: int) -> dict:
    """The summary entries of a linear driver's working stroke (at most :data:`CYCLE_STEPS` samples)."""
    from .actuators import stroke_summary
    try:
        act = stroke_summary(plan, params, steps=min(int(steps), CYCLE_STEPS))
    except SpecError as exc:
        return {"unbuildable": None,
                "note": f"a linear input has no natural cycle ({exc}); use 'assur solve' with a stroke range"}
    return {"actuators": act, "unbuildable": act["unbuildable"]}
