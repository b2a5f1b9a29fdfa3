"""The engine: a mechanism description compiles into a frozen plan, and a plan solves batches into
states (layer 2; see docs/architecture.md).

``compile(m)`` → :class:`PlanarPlan` or :class:`SpatialPlan`; ``solve(plan, params, inputs)`` →
:class:`State` or :class:`SpatialState`.
"""
from .api import assemblies, compile, solve  # noqa: A004 - the public verbs
from .plan import STEP_KINDS, PARAM_KINDS, PlanarPlan, PlanBase, SpatialPlan
from .planar.geometry import geometry
from .state import PointView, SpatialState, State

__all__ = ["assemblies", "compile", "solve", "geometry", "PlanBase", "PlanarPlan", "SpatialPlan", "State",
           "SpatialState", "PointView", "STEP_KINDS", "PARAM_KINDS"]


def __getattr__(name):
    if name == "SolvePlan":         # the former name of PlanarPlan
        import warnings
        warnings.warn("assur.engine.SolvePlan is deprecated: use PlanarPlan", DeprecationWarning, stacklevel=2)
        return PlanarPlan
    raise AttributeError(f"module 'assur.engine' has no attribute {name!r}")
