"""One-line figures from Python: ``assur.plot.mechanism(plan)``.

Takes a compiled plan, a :class:`~assur.model.mechanism.Mechanism` or the path of a mechanism file and returns the
figure ``assur plot`` draws: for a planar mechanism the point paths, the kinematic diagram in several positions
and the velocity and acceleration against the input; for a spatial one the 3D view with the rocker angle and the
transmission angles.
"""
from __future__ import annotations

import os

from ..analysis.sampling import CYCLE_STEPS
from ..engine import compile as compile_plan
from ..engine.plan import PlanBase
from ..errors import SpecError
from ..io.mechanism_file import load
from ..model.mechanism import Mechanism


def as_plan(source) -> PlanBase:
    """A compiled plan from a plan, a Mechanism or a mechanism file's path (SpecError for anything else)."""
    if isinstance(source, PlanBase):
        return source
    if isinstance(source, Mechanism):
        return compile_plan(source)
    if isinstance(source, (str, os.PathLike)):
        return compile_plan(load(source))
    raise SpecError([("plot", f"needs a plan, a Mechanism or a mechanism file's path, not {type(source).__name__}")])


def mechanism(source, steps: int = CYCLE_STEPS, *, params=None, ranges=None, positions: int = 6, dpi: int = 100):
    """The figure of one turn (or of ``ranges``) of ``source`` (a Study: its run, nothing solved again; a plan, a
    Mechanism or a file path), as a matplotlib Figure: what ``assur plot FILE -o OUT.png`` writes. ``params``: a
    design (default: the file's)."""
    from ..analysis.study import Study
    from .draw import close
    study = source if isinstance(source, Study) else Study(as_plan(source), params, steps, ranges=ranges)
    if study.plan.dimension == 3:
        from .spatial import figure
        fig = figure(study, positions=positions, dpi=dpi)
    else:
        from .figures import mechanism_figure
        fig = mechanism_figure(study, positions=positions, dpi=dpi)
    close(fig)   # pyplot lets it go: the caller owns it (a notebook shows it once, as the cell's value)
    return fig
