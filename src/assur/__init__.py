"""assur — structural and kinematic analysis and dimensional synthesis of mechanisms.

The data flow is description → compiled plan → batched state::

    import assur
    mech = assur.load("examples/walker_fourbar.toml")     # frozen description (SI inside)
    plan = assur.compile(mech)                              # Assur groups, branches, parameter map
    state = assur.solve(plan, inputs=angles)                # positions, velocities, accelerations

``import assur`` itself imports nothing heavy: every name below loads its module on first use (so the
command line can answer Ctrl-C cleanly from its first instruction, and analysis functions do not pull in
scipy.optimize until they are called).
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the same names, for type checkers and editors
    from .engine import PlanarPlan, SpatialPlan, SpatialState, State, assemblies, compile, solve  # noqa: A004
    from .errors import (AssurError, SpecError, StructureError, SynthesisError, UnbuildableError,
                         UnbuildableWarning)
    from .io.builder import Builder
    from .kinetostatics.api import forces
    from .dynamics.api import simulate
    from .io.mechanism_file import dump, dumps, load, loads
    from .model.mechanism import Mechanism
    from .structure.assur import AssurGroup, GroupKind, Structure
    from .structure.assur import analyse as analyse_structure
    from .analysis.study import Study

from .version import __version__

_LAZY = {
    **{name: ("assur.engine", name) for name in ("PlanarPlan", "SpatialPlan", "SpatialState", "State", "compile",
                                                  "solve", "assemblies")},
    **{name: ("assur.errors", name) for name in ("AssurError", "SpecError", "StructureError", "SynthesisError",
                                                  "UnbuildableError", "UnbuildableWarning")},
    **{name: ("assur.io.mechanism_file", name) for name in ("dump", "dumps", "load", "loads")},
    "Builder": ("assur.io.builder", "Builder"),
    "Mechanism": ("assur.model.mechanism", "Mechanism"),
    **{name: ("assur.structure.assur", name) for name in ("AssurGroup", "GroupKind", "Structure")},
    #: the structure of a description (mobility, Assur groups)
    "analyse_structure": ("assur.structure.assur", "analyse"),
    "Study": ("assur.analysis.study", "Study"),
    "gait_metrics": ("assur.analysis.api", "gait_metrics"),
    "gait_curves": ("assur.analysis.api", "gait_curves"),
    "transmission_angles": ("assur.analysis.transmission", "transmission_angles"),
    "dead_centres": ("assur.analysis.api", "dead_centres"),
    "forces": ("assur.kinetostatics.api", "forces"),
    "simulate": ("assur.dynamics.api", "simulate"),
}

#: former names, still served with a DeprecationWarning naming the replacement: name → (module, attribute, advice)
_DEPRECATED = {
    "SolvePlan": ("assur.engine", "PlanarPlan", "use assur.PlanarPlan"),
    "analyse": ("assur.structure.assur", "analyse", "use assur.analyse_structure"),
    "analyze": ("assur.analysis.api", "analyze", "use assur.Study(plan).as_dict()"),
    "summarize": ("assur.analysis.api", "analyze", "use assur.Study(plan) and its fields, or .as_dict()"),
    "Designer": ("assur.designer.widget", "Designer", "use assur.designer.Designer"),
}


def __getattr__(name):
    """The public names load their module on first use; ``assur.<subpackage>`` imports it."""
    if name in _LAZY:
        module, attr = _LAZY[name]
        value = getattr(importlib.import_module(module), attr)
        globals()[name] = value
        return value
    if name in _DEPRECATED:
        module, attr, advice = _DEPRECATED[name]
        import warnings
        warnings.warn(f"assur.{name} is deprecated: {advice}", DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module(module), attr)
    if not name.startswith("_"):
        try:
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
    raise AttributeError(f"module 'assur' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)


__all__ = ["AssurError", "AssurGroup", "Builder", "GroupKind", "Mechanism", "PlanarPlan", "SpatialPlan", "SpatialState",
           "SpecError", "State", "Structure", "StructureError", "Study", "SynthesisError", "UnbuildableError",
           "UnbuildableWarning", "__version__", "analyse_structure", "assemblies", "compile", "dead_centres", "dump",
           "dumps", "forces", "gait_curves", "gait_metrics", "load", "loads", "simulate", "solve", "transmission_angles"]
