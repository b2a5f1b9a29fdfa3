"""assur — structural and kinematic analysis and dimensional synthesis of mechanisms.

The data flow is description → compiled plan → batched state::

    import assur
    mech = assur.load("examples/walker_fourbar.toml")     # frozen description (SI inside)
    plan = assur.compile(mech)                              # Assur groups, branches, parameter map
    state = assur.solve(plan, inputs=angles)                # positions, velocities, accelerations
"""
from __future__ import annotations

from .engine import PlanarPlan, SolvePlan, SpatialPlan, SpatialState, State, compile, solve  # noqa: A004
from .errors import AssurError, SpecError, StructureError, SynthesisError, UnbuildableError, UnbuildableWarning
from .io.mechanism_file import dump, dumps, load, loads
from .model.mechanism import Mechanism
from .structure.assur import AssurGroup, GroupKind, Structure, analyse

#: the structure of a description (mobility, Assur groups); ``analyse`` is its former name
analyse_structure = analyse

__version__ = "0.1.0"

_LAZY = {
    "summarize": ("assur.analysis.summary", "analyze"),
    "analyze": ("assur.analysis.summary", "analyze"),     # the former name of summarize
    "gait_metrics": ("assur.analysis.gait", "gait_metrics"),
    "gait_curves": ("assur.analysis.gait", "gait_curves"),
    "transmission_angles": ("assur.analysis.transmission", "transmission_angles"),
    "dead_centres": ("assur.analysis.transmission", "dead_centres"),
}


def __getattr__(name):
    """Analysis functions load on first use (they pull in scipy.optimize)."""
    if name in _LAZY:
        import importlib
        module, attr = _LAZY[name]
        return getattr(importlib.import_module(module), attr)
    raise AttributeError(f"module 'assur' has no attribute {name!r}")

__all__ = ["AssurError", "AssurGroup", "GroupKind", "Mechanism", "PlanarPlan", "SolvePlan", "SpatialPlan", "SpecError",
           "SpatialState", "State", "Structure", "StructureError", "SynthesisError", "UnbuildableError",
           "UnbuildableWarning", "analyse", "analyse_structure", "compile", "dump",
           "dumps", "load", "loads", "solve", "__version__", *_LAZY]
