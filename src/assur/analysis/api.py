"""The public analysis functions of a plan: thin wrappers that build one
:class:`~assur.analysis.study.Study` (one solved turn) and read its fields, for callers that hold a plan rather than
a Study. Each also takes a Study, whose own run is used (``params`` and ``steps`` are then not used).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

from .sampling import CYCLE_STEPS
from .study import Study
from .summary import summary_dict

__all__ = ["Analysis", "analyze", "summarize", "buildable_ranges", "dead_centres", "dyad_summaries", "gait_curves", "gait_metrics",
           "gait_metrics_and_curves", "link_motions", "output_link"]


def dead_centres(plan, params=None, steps: int = CYCLE_STEPS) -> list:
    """The dead centres of every crank over one turn (:attr:`Study.dead_centres`): the input angles where a crank is
    collinear with the link hinged at its arm, in the motor's angle for a crank driven through gears."""
    return list(Study.of(plan, params, steps).dead_centres)


def buildable_ranges(plan, params=None, steps: int = CYCLE_STEPS):
    """(ranges [(start, end)] rad, unbuildable samples, steps) of one turn (:attr:`Study.buildable`)."""
    from .transmission import buildable_ranges as ranges_of
    return ranges_of(Study.of(plan, params, steps))


def link_motions(plan, params=None, steps: int = CYCLE_STEPS) -> dict:
    """Per moving link: angle range, turns per input turn, largest |ω| and |α| (:attr:`Study.links`)."""
    return Study.of(plan, params, steps).links


def output_link(plan, params=None, steps: int = CYCLE_STEPS):
    """The output link's swing, extremes and time ratio (:attr:`Study.output_link`), or None."""
    return Study.of(plan, params, steps).output_link


def gait_metrics_and_curves(plan, params=None, *, steps: int = CYCLE_STEPS, **options):
    """:func:`~assur.analysis.gait.gait_metrics_and_curves` on one turn of a plan (or a Study's run). ``options``:
    ``foot``, ``ground``, ``up``, ``support``, ``band`` (default: the file's ``[gait]`` and the contact arc)."""
    from .gait import gait_metrics_and_curves as of_cycle
    return of_cycle(Study.of(plan, params, steps), **options)


def gait_metrics(plan, params=None, *, steps: int = CYCLE_STEPS, **options):
    """The :class:`~assur.analysis.gait.GaitMetrics` of one leg over one turn (see :func:`gait_metrics_and_curves`).
    With the file's own definition (no options) it is :attr:`Study.gait`; UnbuildableError if the crank cannot turn
    fully."""
    return gait_metrics_and_curves(plan, params, steps=steps, **options)[0]


def gait_curves(plan, params=None, *, steps: int = CYCLE_STEPS, **options):
    """The sampled gait curves of one leg over one turn (see :func:`gait_metrics_and_curves`)."""
    return gait_metrics_and_curves(plan, params, steps=steps, **options)[1]


def dyad_summaries(plan, params=None, steps: int = CYCLE_STEPS) -> list:
    """Every R–S–S dyad's outputs over one crank turn of a spatial plan (:attr:`Study.spatial`)."""
    return Study.of(plan, params, steps).spatial


@dataclass(frozen=True)
class Analysis:
    """The former result of :func:`summarize`: ``summary`` (the JSON-ready dict), ``cycle`` (the Study),
    ``gait`` and ``gait_curves``. Deprecated: use :class:`~assur.analysis.study.Study`."""
    summary: dict
    cycle: Study | None = None
    gait: object = None
    gait_curves: object = None

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        return html_table("Analysis (SI)", self.summary.items())


def summarize(plan, params=None, steps: int = CYCLE_STEPS) -> Analysis:
    """Deprecated: ``Study(plan, params, steps)``; its ``as_dict(forces=False)`` is this ``summary``."""
    warnings.warn("assur.summarize is deprecated: use assur.Study(plan, params, steps) and its fields or "
                  "as_dict()", DeprecationWarning, stacklevel=2)
    study = Study.of(plan, params, steps)
    return Analysis(summary_dict(study), study if study.turn else None, study.gait, study.gait_curves)


def analyze(plan, params=None, steps: int = CYCLE_STEPS) -> dict:
    """Deprecated: ``Study(plan, params, steps).as_dict(forces=False)``."""
    warnings.warn("assur.analyze is deprecated: use assur.Study(plan, params, steps).as_dict()",
                  DeprecationWarning, stacklevel=2)
    return summary_dict(Study.of(plan, params, steps))
